#pragma once
// Eigen's NumTraits and ScalarBinaryOpTraits for the AD number types, so
// that Eigen matrices and vectors of them work (see ad.hpp).

#include <Eigen/Core>

#include "lagrangian/ad/eom_jet.hpp"
#include "lagrangian/ad/jet.hpp"

// -- Eigen integration: matrices and vectors of jets ------------------------------
namespace Eigen {
/// Traits shared by the AD number types: Real is the AD type, T its value
/// type, N its number of directions (a cost hint for Eigen).
template <class Real_, class T, int N>
struct LagrangianAdNumTraits : NumTraits<T> {
  using Real = Real_;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum {
    IsComplex = 0,
    IsInteger = 0,
    IsSigned = 1,
    RequireInitialization = 1,
    ReadCost = 1 + N,
    AddCost = 1 + N,
    MulCost = 1 + 3 * N
  };
  static inline Real epsilon() { return Real(NumTraits<T>::epsilon()); }
  static inline Real dummy_precision() { return Real(NumTraits<T>::dummy_precision()); }
  static inline Real highest() { return Real(NumTraits<T>::highest()); }
  static inline Real lowest() { return Real(NumTraits<T>::lowest()); }
  static inline int digits10() { return NumTraits<T>::digits10(); }
};
template <class T, int N, int O>
struct NumTraits<lagrangian::ad::Jet<T, N, O>> : LagrangianAdNumTraits<lagrangian::ad::Jet<T, N, O>, T, N> {};
template <int N, bool R>
struct NumTraits<lagrangian::ad::EomJet<N, R>> : LagrangianAdNumTraits<lagrangian::ad::EomJet<N, R>, double, N> {};
template <int N, bool R, typename BinaryOp>
struct ScalarBinaryOpTraits<lagrangian::ad::EomJet<N, R>, double, BinaryOp> {
  using ReturnType = lagrangian::ad::EomJet<N, R>;
};
template <int N, bool R, typename BinaryOp>
struct ScalarBinaryOpTraits<double, lagrangian::ad::EomJet<N, R>, BinaryOp> {
  using ReturnType = lagrangian::ad::EomJet<N, R>;
};
template <class T, int N, int O, typename BinaryOp>
struct ScalarBinaryOpTraits<lagrangian::ad::Jet<T, N, O>, T, BinaryOp> {
  using ReturnType = lagrangian::ad::Jet<T, N, O>;
};
template <class T, int N, int O, typename BinaryOp>
struct ScalarBinaryOpTraits<T, lagrangian::ad::Jet<T, N, O>, BinaryOp> {
  using ReturnType = lagrangian::ad::Jet<T, N, O>;
};
}  // namespace Eigen
