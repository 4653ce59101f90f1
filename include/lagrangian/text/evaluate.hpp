#pragma once
/// \file text/evaluate.hpp
/// Evaluation of a text Expression (text/expression.hpp) on any number type
/// S the library computes with: double, and the AD numbers (ad::Jet,
/// ad::EomJet), so derivatives of a text model are taken exactly as for a
/// C++ model. Functions of S are found as a C++ model's are: `using std::sin;
/// sin(x)`.

#include <cmath>
#include <new>
#include <type_traits>
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
/// Leaves are read where they are (q, q̇, t: no copy), numbers (constants and
/// parameters) enter the operations as doubles (a·c costs what scaling
/// costs), and integer and half powers are products and square roots.
/// Parameters given as numbers of type S (P = S: carrying derivatives with
/// respect to parameters) are read where they are, as the leaves are.
template <class S, class QVec, class QdVec, class P = double>
S evaluate(const Expression& e, const QVec& q, const QdVec& qd, const S& t, std::vector<S>& slots,
           const P* parameters = nullptr) {
  static_assert(std::is_same_v<P, double> || std::is_same_v<P, S>, "text::evaluate: parameters of type double or S");
  using std::pow, std::sqrt;
  const std::size_t count = e.nodes.size();
  if (slots.size() < count) slots.resize(count);
  const Node* nodes = e.nodes.data();
  auto is_number = [&](int k) {
    return nodes[k].op == Op::constant || (std::is_same_v<P, double> && nodes[k].op == Op::parameter);
  };
  auto number = [&](int k) -> double {
    if constexpr (std::is_same_v<P, double>) {
      return nodes[k].op == Op::constant ? nodes[k].value : parameters[nodes[k].index];
    } else {
      return nodes[k].value;  // (constants only)
    }
  };
  // Node k as an S: a leaf in place, a number in `scratch`, else its slot.
  // (A vector whose elements come by value, such as an Eigen::Map of
  // constants, is read into `scratch`.)
  auto element = [&](const auto& v, int index, S& scratch) -> const S& {
    if constexpr (std::is_reference_v<decltype(v[index])>) {
      return v[index];
    } else {
      scratch = S(v[index]);
      return scratch;
    }
  };
  auto operand = [&](int k, S& scratch) -> const S& {
    switch (nodes[k].op) {
      case Op::coordinate: return element(q, nodes[k].index, scratch);
      case Op::velocity: return element(qd, nodes[k].index, scratch);
      case Op::time: return t;
      case Op::parameter:
        if constexpr (!std::is_same_v<P, double>) return parameters[nodes[k].index];
        [[fallthrough]];
      case Op::constant: scratch = S(number(k)); return scratch;
      default: return slots[static_cast<std::size_t>(k)];
    }
  };
  S sa{}, sb{};
  for (std::size_t i = 0; i < count; ++i) {
    const Node& n = nodes[i];
    // The node's value made straight into its slot (no copy of a number of
    // derivatives where S allows it).
    auto put = [&](auto&& make) {
      if constexpr (std::is_trivially_destructible_v<S>) {
        ::new (static_cast<void*>(&slots[i])) S(make());
      } else {
        slots[i] = make();
      }
    };
    switch (n.op) {
      case Op::constant:
      case Op::coordinate:
      case Op::velocity:
      case Op::time:
      case Op::parameter: break;  // read where they are
      case Op::add:
      case Op::sub:
      case Op::mul:
      case Op::div: {
        const bool na = is_number(n.a), nb = is_number(n.b);
        if (na && !nb) {
          const double x = number(n.a);
          const S& y = operand(n.b, sb);
          put([&]() -> S { return n.op == Op::add ? x + y : n.op == Op::sub ? x - y : n.op == Op::mul ? x * y : x / y; });
        } else if (nb && !na) {
          const S& x = operand(n.a, sa);
          const double y = number(n.b);
          put([&]() -> S { return n.op == Op::add ? x + y : n.op == Op::sub ? x - y : n.op == Op::mul ? x * y : x / y; });
        } else {
          put([&] { return apply(n, operand(n.a, sa), operand(n.b, sb)); });
        }
        break;
      }
      case Op::pow_const: {
        const S& x = operand(n.a, sa);
        if (n.value == 2.0) {
          put([&]() -> S { return x * x; });
        } else if (n.value == 3.0) {
          put([&]() -> S { return x * x * x; });
        } else if (n.value == 1.0) {
          put([&]() -> S { return x; });
        } else if (n.value == 0.5) {
          put([&]() -> S { return sqrt(x); });
        } else if (n.value == -1.0) {
          put([&]() -> S { return 1.0 / x; });
        } else {
          put([&]() -> S { return pow(x, n.value); });
        }
        break;
      }
      default: {
        const S& x = operand(n.a, sa);
        put([&] { return apply(n, x, n.b >= 0 ? operand(n.b, sb) : x); });
      }
    }
  }
  S root{};
  return operand(static_cast<int>(count) - 1, root);
}

}  // namespace lagrangian::text
