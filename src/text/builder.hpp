#pragma once
// Internal: the node builder shared by the parser (parse.cpp) and the
// symbolic derivative (formula.cpp).

#include <map>
#include <tuple>
#include <vector>

#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::text::detail {

inline bool is_leaf(Op op) {
  return op == Op::constant || op == Op::coordinate || op == Op::velocity || op == Op::time || op == Op::parameter;
}

/// Appends nodes, returning the index of an equal node when there is one,
/// and folding operations on constants (and the identities x + 0, x·1, x·0,
/// x/1, x^1, x^0, −(−x)) as it goes.
class Builder {
 public:
  explicit Builder(Expression& e) : e_(e) {}

  int constant(double v) { return add({Op::constant, -1, -1, -1, v}); }
  int leaf(Op op, int index) { return add({op, -1, -1, index, 0.0}); }

  int unary(Op op, int a, double value = 0.0) {
    const Node& x = e_.nodes[static_cast<std::size_t>(a)];
    if (op == Op::pow_const) {
      if (value == 1.0) return a;
      if (value == 0.0) return constant(1.0);
    }
    if (op == Op::neg && x.op == Op::neg) return x.a;
    if (op == Op::neg && x.op == Op::mul) return product(constant(-1.0), a);
    const Node n{op, a, -1, -1, value};
    if (x.op == Op::constant) return constant(apply(n, x.value, x.value));
    return add(n);
  }

  int binary(Op op, int a, int b) {
    const Node x = e_.nodes[static_cast<std::size_t>(a)], y = e_.nodes[static_cast<std::size_t>(b)];
    const bool xc = x.op == Op::constant, yc = y.op == Op::constant;
    if (xc && yc) return constant(apply(Node{op, a, b, -1, 0.0}, x.value, y.value));
    switch (op) {
      case Op::add:
        if (xc && x.value == 0.0) return b;
        if (yc && y.value == 0.0) return a;
        break;
      case Op::sub:
        if (yc && y.value == 0.0) return a;
        if (xc && x.value == 0.0) return unary(Op::neg, b);
        break;
      case Op::mul:
        if ((xc && x.value == 0.0) || (yc && y.value == 0.0)) return constant(0.0);
        if (xc && x.value == 1.0) return b;
        if (yc && y.value == 1.0) return a;
        return product(a, b);
      case Op::div: {
        if (yc && y.value == 1.0) return a;
        if (xc && x.value == 0.0) return constant(0.0);
        // (c₁u)/(c₂w) = (c₁/c₂)·(u/w) and (c₁u)/w = c₁·(u/w): numbers in front.
        double c1 = 1.0, c2 = 1.0;
        const int u = split(a, c1), w = split(b, c2);
        if (c1 != 1.0 && u >= 0 && w >= 0)
          return product(constant(c2 != 1.0 ? c1 / c2 : c1), add({Op::div, u, c2 != 1.0 ? w : b, -1, 0.0}));
        break;
      }
      case Op::pow:
        if (yc) return unary(Op::pow_const, a, y.value);
        break;
      default:
        break;
    }
    return add({op, a, b, -1, 0.0});
  }

  /// a·b as c·u: the numbers among the factors of a and b multiplied into
  /// one leading constant c (none when it is 1), the rest u in their order.
  int product(int a, int b) {
    double c = 1.0;
    const int u = split(a, c), w = split(b, c);
    const int rest = u < 0 ? w : (w < 0 ? u : add({Op::mul, u, w, -1, 0.0}));
    if (rest < 0) return constant(c);
    if (c == 1.0) return rest;
    if (c == 0.0) return constant(0.0);
    return add({Op::mul, constant(c), rest, -1, 0.0});
  }

  /// Copies node `n` of another expression whose operands are already
  /// copied to `a` and `b` (used by bind_parameters()).
  int copy(const Node& n, int a, int b) {
    if (is_leaf(n.op)) return add(n);
    if (n.b >= 0) return binary(n.op, a, b);
    return unary(n.op, a, n.value);
  }

 private:
  int add(const Node& n) {
    const auto key = std::make_tuple(static_cast<int>(n.op), n.a, n.b, n.index, n.value);
    if (auto it = seen_.find(key); it != seen_.end()) return it->second;
    e_.nodes.push_back(n);
    const int i = static_cast<int>(e_.nodes.size()) - 1;
    seen_.emplace(key, i);
    return i;
  }

  /// Node i as c_i · rest: multiplies c by c_i, returns rest (−1: none).
  int split(int i, double& c) const {
    const Node& n = e_.nodes[static_cast<std::size_t>(i)];
    if (n.op == Op::constant) {
      c *= n.value;
      return -1;
    }
    if (n.op == Op::mul && e_.nodes[static_cast<std::size_t>(n.a)].op == Op::constant) {
      c *= e_.nodes[static_cast<std::size_t>(n.a)].value;
      return n.b;
    }
    if (n.op == Op::neg) {
      c = -c;
      return n.a;
    }
    return i;
  }

  Expression& e_;
  std::map<std::tuple<int, int, int, int, double>, int> seen_;
};

/// The nodes `root` reads, in their order, `root` last: what folding and
/// sharing left unread is dropped.
inline Expression reachable(const Expression& e, int root) {
  std::vector<char> used(e.nodes.size(), 0);
  used[static_cast<std::size_t>(root)] = 1;
  for (int i = root; i >= 0; --i) {
    const Node& n = e.nodes[static_cast<std::size_t>(i)];
    if (!used[static_cast<std::size_t>(i)]) continue;
    if (n.a >= 0) used[static_cast<std::size_t>(n.a)] = 1;
    if (n.b >= 0) used[static_cast<std::size_t>(n.b)] = 1;
  }
  Expression out;
  std::vector<int> at(e.nodes.size(), -1);
  for (int i = 0; i <= root; ++i) {
    if (!used[static_cast<std::size_t>(i)]) continue;
    Node n = e.nodes[static_cast<std::size_t>(i)];
    if (n.a >= 0) n.a = at[static_cast<std::size_t>(n.a)];
    if (n.b >= 0) n.b = at[static_cast<std::size_t>(n.b)];
    at[static_cast<std::size_t>(i)] = static_cast<int>(out.nodes.size());
    out.nodes.push_back(n);
  }
  return out;
}

}  // namespace lagrangian::text::detail
