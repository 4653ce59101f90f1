// Expressions as formulas (text/expression.hpp): the symbolic derivative by
// one variable, for display (the momenta p = ∂T/∂q̇ that inspect prints),
// and the text of an expression. The equations of motion never use these:
// they are derived by automatic differentiation.
#include <cstdio>
#include <string>
#include <vector>

#include "builder.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::text {

namespace {

const char* function_name(Op op) {
  switch (op) {
    case Op::sin: return "sin";
    case Op::cos: return "cos";
    case Op::tan: return "tan";
    case Op::asin: return "asin";
    case Op::acos: return "acos";
    case Op::atan: return "atan";
    case Op::sinh: return "sinh";
    case Op::cosh: return "cosh";
    case Op::tanh: return "tanh";
    case Op::exp: return "exp";
    case Op::log: return "log";
    case Op::sqrt: return "sqrt";
    case Op::abs: return "abs";
    case Op::atan2: return "atan2";
    case Op::pow: return "pow";
    case Op::min: return "min";
    case Op::max: return "max";
    default: return nullptr;
  }
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

/// Precedence of what a node prints as: 1 sums, 2 products, 3 unary
/// minus, 4 powers, 5 atoms (names, numbers, calls).
int precedence(const Expression& e, int i) {
  const Node& n = e.nodes[static_cast<std::size_t>(i)];
  switch (n.op) {
    case Op::add:
    case Op::sub: return 1;
    case Op::mul: {
      const Node& a = e.nodes[static_cast<std::size_t>(n.a)];
      return a.op == Op::constant && a.value < 0 ? 3 : 2;  // −c·x prints with a leading minus
    }
    case Op::div: return 2;
    case Op::neg: return 3;
    case Op::pow_const: return 4;
    case Op::constant: return n.value < 0 ? 3 : 5;
    default: return 5;
  }
}

class Printer {
 public:
  Printer(const Expression& e, const Symbols& s) : e_(e), s_(s) {}

  /// Node i, in parentheses when its precedence is below `at_least`.
  std::string print(int i, int at_least) const {
    const std::string body = bare(i);
    return precedence(e_, i) < at_least ? "(" + body + ")" : body;
  }

 private:
  const Node& node(int i) const { return e_.nodes[static_cast<std::size_t>(i)]; }

  /// A product c·u with c < 0 printed with −c: the text after a minus.
  bool negative_product(int i) const {
    const Node& n = node(i);
    return n.op == Op::mul && node(n.a).op == Op::constant && node(n.a).value < 0;
  }
  std::string without_sign(int i) const {
    const Node& n = node(i);
    const double c = -node(n.a).value;
    return c == 1.0 ? print(n.b, 3) : number_text(c) + "*" + print(n.b, 3);
  }

  std::string bare(int i) const {
    const Node& n = node(i);
    switch (n.op) {
      case Op::constant: return number_text(n.value);
      case Op::coordinate: return s_.coordinates[static_cast<std::size_t>(n.index)];
      case Op::velocity: return s_.coordinates[static_cast<std::size_t>(n.index)] + "_dot";
      case Op::time: return "t";
      case Op::parameter: return s_.parameters[static_cast<std::size_t>(n.index)];
      case Op::add:
        if (negative_product(n.b)) return print(n.a, 1) + " - " + without_sign(n.b);
        if (node(n.b).op == Op::neg) return print(n.a, 1) + " - " + print(node(n.b).a, 2);
        return print(n.a, 1) + " + " + print(n.b, 1);
      case Op::sub: return print(n.a, 1) + " - " + print(n.b, 2);
      case Op::mul:
        if (negative_product(i)) return "-" + without_sign(i);
        return print(n.a, 2) + "*" + print(n.b, 2);  // (a·(b·c) = a·b·c, a·(b/c) = a·b/c)
      case Op::div: return print(n.a, 2) + "/" + print(n.b, 3);
      case Op::neg: return "-" + print(n.a, 3);
      case Op::pow_const: return print(n.a, 5) + "^" + number_text(n.value);
      default:
        if (n.b >= 0) return std::string(function_name(n.op)) + "(" + print(n.a, 0) + ", " + print(n.b, 0) + ")";
        return std::string(function_name(n.op)) + "(" + print(n.a, 0) + ")";
    }
  }

  const Expression& e_;
  const Symbols& s_;
};

}  // namespace

Expression derivative(const Expression& e, Op variable, int index) {
  Expression out;
  detail::Builder b(out);
  const std::size_t count = e.nodes.size();
  std::vector<int> at(count), d(count);  // each node copied, and its derivative
  const int zero = b.constant(0.0), one = b.constant(1.0);
  for (std::size_t i = 0; i < count; ++i) {
    const Node& n = e.nodes[i];
    const int a = n.a >= 0 ? at[static_cast<std::size_t>(n.a)] : -1;
    const int c = n.b >= 0 ? at[static_cast<std::size_t>(n.b)] : -1;
    const int da = n.a >= 0 ? d[static_cast<std::size_t>(n.a)] : zero;
    const int db = n.b >= 0 ? d[static_cast<std::size_t>(n.b)] : zero;
    at[i] = b.copy(n, a, c);
    const int x = at[i];
    auto mul = [&](int p, int q) { return b.binary(Op::mul, p, q); };
    auto div = [&](int p, int q) { return b.binary(Op::div, p, q); };
    auto f = [&](Op op, int p) { return b.unary(op, p); };
    auto sq = [&](int p) { return b.unary(Op::pow_const, p, 2.0); };
    int r = zero;
    switch (n.op) {
      case Op::constant:
      case Op::time:
      case Op::parameter: r = zero; break;
      case Op::coordinate:
      case Op::velocity: r = n.op == variable && n.index == index ? one : zero; break;
      case Op::add: r = b.binary(Op::add, da, db); break;
      case Op::sub: r = b.binary(Op::sub, da, db); break;
      case Op::mul: r = b.binary(Op::add, mul(da, c), mul(a, db)); break;
      case Op::div: r = b.binary(Op::sub, div(da, c), div(mul(a, db), sq(c))); break;
      case Op::neg: r = f(Op::neg, da); break;
      case Op::pow_const:
        r = mul(mul(b.constant(n.value), b.unary(Op::pow_const, a, n.value - 1.0)), da);
        break;
      case Op::pow:  // (a^c)' = a^c (c' log a + c a'/a)
        r = mul(x, b.binary(Op::add, mul(db, f(Op::log, a)), div(mul(c, da), a)));
        break;
      case Op::sin: r = mul(f(Op::cos, a), da); break;
      case Op::cos: r = mul(f(Op::neg, f(Op::sin, a)), da); break;
      case Op::tan: r = div(da, sq(f(Op::cos, a))); break;
      case Op::asin: r = div(da, f(Op::sqrt, b.binary(Op::sub, one, sq(a)))); break;
      case Op::acos: r = f(Op::neg, div(da, f(Op::sqrt, b.binary(Op::sub, one, sq(a))))); break;
      case Op::atan: r = div(da, b.binary(Op::add, one, sq(a))); break;
      case Op::sinh: r = mul(f(Op::cosh, a), da); break;
      case Op::cosh: r = mul(f(Op::sinh, a), da); break;
      case Op::tanh: r = div(da, sq(f(Op::cosh, a))); break;
      case Op::exp: r = mul(x, da); break;
      case Op::log: r = div(da, a); break;
      case Op::sqrt: r = div(da, mul(b.constant(2.0), x)); break;
      case Op::abs: r = mul(div(a, x), da); break;
      case Op::atan2:  // atan2(a, c)' = (c a' − a c')/(a² + c²)
        r = div(b.binary(Op::sub, mul(c, da), mul(a, db)), b.binary(Op::add, sq(a), sq(c)));
        break;
      case Op::min:
      case Op::max: {
        const bool constant_a = out.nodes[static_cast<std::size_t>(da)] == Node{Op::constant, -1, -1, -1, 0.0};
        const bool constant_b = out.nodes[static_cast<std::size_t>(db)] == Node{Op::constant, -1, -1, -1, 0.0};
        if (!constant_a || !constant_b)
          throw ExpressionError("derivative", 0,
                                std::string(function_name(n.op)) + " of the variable has no formula for its derivative");
        r = zero;
        break;
      }
    }
    d[i] = r;
  }
  return detail::reachable(out, d[count - 1]);
}

std::string to_text(const Expression& e, const Symbols& symbols) {
  return Printer(e, symbols).print(e.root(), 0);
}

}  // namespace lagrangian::text
