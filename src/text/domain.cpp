// Where an expression is undefined at a state (text/expression.hpp): the
// first operation that makes a non-finite value of finite operands, said
// with its operand as text, so that a model stated as text that cannot
// start is refused with the expression at fault.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::text {

namespace {

/// What goes wrong in an operation of `op` whose value is not finite.
const char* failure(Op op) {
  switch (op) {
    case Op::div: return "division by zero";
    case Op::log: return "log of a number <= 0";
    case Op::sqrt: return "square root of a negative number";
    case Op::pow:
    case Op::pow_const: return "power of a negative number (or of 0 to a negative power)";
    case Op::asin: return "asin of a number outside [-1, 1]";
    case Op::acos: return "acos of a number outside [-1, 1]";
    case Op::tan: return "tan at an odd multiple of pi/2";
    default: return "a value that is not finite";
  }
}

/// The expression whose result is node `k` of `e`.
Expression subexpression(const Expression& e, int k) {
  Expression s;
  s.nodes.assign(e.nodes.begin(), e.nodes.begin() + k + 1);
  return s;
}

}  // namespace

std::string undefined_at(const Expression& e, const Symbols& symbols, const double* q, const double* qd, double t,
                         const double* parameters) {
  const std::size_t n = e.nodes.size();
  std::vector<double> value(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Node& node = e.nodes[i];
    switch (node.op) {
      case Op::constant: value[i] = node.value; break;
      case Op::coordinate: value[i] = q[node.index]; break;
      case Op::velocity: value[i] = qd[node.index]; break;
      case Op::time: value[i] = t; break;
      case Op::parameter: value[i] = parameters[node.index]; break;
      default: {
        const double a = value[static_cast<std::size_t>(node.a)];
        const double b = node.b >= 0 ? value[static_cast<std::size_t>(node.b)] : a;
        value[i] = apply(node, a, b);
        if (std::isfinite(value[i]) || !std::isfinite(a) || !std::isfinite(b)) break;
        // The operand that takes the operation out of its domain: the
        // divisor, the base of a power, else the first.
        const int at = node.op == Op::div ? node.b : node.a;
        std::ostringstream os;
        os.precision(12);
        const Expression whole = subexpression(e, static_cast<int>(i));
        const Expression operand = subexpression(e, at);
        os << failure(node.op) << ": " << to_text(whole, symbols) << " with " << to_text(operand, symbols) << " = "
           << value[static_cast<std::size_t>(at)];
        return os.str();
      }
    }
  }
  return "";
}

}  // namespace lagrangian::text
