#pragma once
/// \file text/evaluate.hpp
/// Evaluation of a text Expression (text/expression.hpp) on any number type
/// S the library computes with: double, and the AD numbers (ad::Jet,
/// ad::EomJet), so derivatives of a text model are taken exactly as for a
/// C++ model. Functions of S are found as a C++ model's are: `using std::sin;
/// sin(x)`.

#include <cmath>
#include <vector>

#include "lagrangian/ad/cmath.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::text {

/// The value of node `n` whose operands have the values a and b (b unused
/// by one-operand nodes). Leaves (constants, coordinates, velocities, time,
/// parameters) are not computed here.
template <class S>
S apply(const Node& n, const S& a, const S& b) {
  using std::abs, std::acos, std::asin, std::atan, std::atan2, std::cos, std::cosh, std::exp, std::log, std::pow,
      std::sin, std::sinh, std::sqrt, std::tan, std::tanh;
  switch (n.op) {
    case Op::add: return a + b;
    case Op::sub: return a - b;
    case Op::mul: return a * b;
    case Op::div: return a / b;
    case Op::neg: return -a;
    case Op::pow_const: return pow(a, n.value);
    case Op::pow: return pow(a, b);
    case Op::sin: return sin(a);
    case Op::cos: return cos(a);
    case Op::tan: return tan(a);
    case Op::asin: return asin(a);
    case Op::acos: return acos(a);
    case Op::atan: return atan(a);
    case Op::sinh: return sinh(a);
    case Op::cosh: return cosh(a);
    case Op::tanh: return tanh(a);
    case Op::exp: return exp(a);
    case Op::log: return log(a);
    case Op::sqrt: return sqrt(a);
    case Op::abs: return abs(a);
    case Op::atan2: return atan2(a, b);
    case Op::min: return b < a ? b : a;
    case Op::max: return a < b ? b : a;
    default: return a;  // (leaves: never asked)
  }
}

/// The value of `e` at (q, q̇, t), with `parameters` for parameter nodes
/// (none are left in a bound expression). `slots` holds one S per node; it
/// is resized only when too small, so a caller that keeps it allocates once.
template <class S, class QVec, class QdVec>
S evaluate(const Expression& e, const QVec& q, const QdVec& qd, const S& t, std::vector<S>& slots,
           const double* parameters = nullptr) {
  const std::size_t count = e.nodes.size();
  if (slots.size() < count) slots.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Node& n = e.nodes[i];
    switch (n.op) {
      case Op::constant: slots[i] = S(n.value); break;
      case Op::coordinate: slots[i] = q[n.index]; break;
      case Op::velocity: slots[i] = qd[n.index]; break;
      case Op::time: slots[i] = t; break;
      case Op::parameter: slots[i] = S(parameters[n.index]); break;
      default: {
        const S& a = slots[static_cast<std::size_t>(n.a)];
        slots[i] = apply(n, a, n.b >= 0 ? slots[static_cast<std::size_t>(n.b)] : a);
      }
    }
  }
  return slots[count - 1];
}

}  // namespace lagrangian::text
