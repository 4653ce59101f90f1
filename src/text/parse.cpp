// Reading an expression into nodes (text/expression.hpp): a recursive-descent
// parser over a builder that stores equal nodes once and folds constants.
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "builder.hpp"
#include "lagrangian/detail/nearest_name.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::text {

ExpressionError::ExpressionError(std::string field, int column, const std::string& what)
    : Error(field + (column > 0 ? " (column " + std::to_string(column) + ")" : std::string()) + ": " + what),
      field_(std::move(field)),
      column_(column),
      message_(what) {}

namespace {

using detail::Builder;
using detail::reachable;

struct Function {
  std::string_view name;
  Op op;
  int arguments;
};

constexpr std::array<Function, 17> kFunctions{{{"sin", Op::sin, 1},
                                               {"cos", Op::cos, 1},
                                               {"tan", Op::tan, 1},
                                               {"asin", Op::asin, 1},
                                               {"acos", Op::acos, 1},
                                               {"atan", Op::atan, 1},
                                               {"sinh", Op::sinh, 1},
                                               {"cosh", Op::cosh, 1},
                                               {"tanh", Op::tanh, 1},
                                               {"exp", Op::exp, 1},
                                               {"log", Op::log, 1},
                                               {"sqrt", Op::sqrt, 1},
                                               {"abs", Op::abs, 1},
                                               {"atan2", Op::atan2, 2},
                                               {"pow", Op::pow, 2},
                                               {"min", Op::min, 2},
                                               {"max", Op::max, 2}}};

const Function* find_function(std::string_view name) {
  for (const Function& f : kFunctions)
    if (f.name == name) return &f;
  return nullptr;
}

class Parser {
 public:
  Parser(std::string_view s, const Symbols& symbols, const std::string& field)
      : s_(s), symbols_(symbols), field_(field), b_(e_) {}

  Expression run() {
    skip();
    if (pos_ == s_.size()) throw ExpressionError(field_, 0, "the expression is empty");
    const int root = sum();
    skip();
    if (pos_ < s_.size()) fail(pos_, std::string("unexpected '") + s_[pos_] + "'");
    return reachable(e_, root);
  }

 private:
  [[noreturn]] void fail(std::size_t at, const std::string& what) const {
    throw ExpressionError(field_, static_cast<int>(at) + 1, what);
  }

  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  bool accept_power() {
    skip();
    if (pos_ < s_.size() && s_[pos_] == '^') {
      ++pos_;
      return true;
    }
    if (pos_ + 1 < s_.size() && s_[pos_] == '*' && s_[pos_ + 1] == '*') {
      pos_ += 2;
      return true;
    }
    return false;
  }

  /// next (op next)*, left-associative, for the operators of `ops`.
  int left_associative(int (Parser::*next)(), std::initializer_list<std::pair<char, Op>> ops) {
    int x = (this->*next)();
    for (;;) {
      skip();
      if (pos_ + 1 < s_.size() && s_[pos_] == '*' && s_[pos_ + 1] == '*') return x;  // a power: not here
      const auto op = std::find_if(ops.begin(), ops.end(), [&](const auto& o) { return accept(o.first); });
      if (op == ops.end()) return x;
      x = b_.binary(op->second, x, (this->*next)());
    }
  }
  int sum() { return left_associative(&Parser::product, {{'+', Op::add}, {'-', Op::sub}}); }
  int product() { return left_associative(&Parser::signed_factor, {{'*', Op::mul}, {'/', Op::div}}); }

  int signed_factor() {
    if (accept('-')) return b_.unary(Op::neg, signed_factor());
    if (accept('+')) return signed_factor();
    return power();
  }

  int power() {
    const int base = primary();
    if (accept_power()) return b_.binary(Op::pow, base, signed_factor());  // right-associative
    return base;
  }

  int primary() {
    skip();
    if (pos_ == s_.size()) fail(pos_, "the expression ends where a number, a name or '(' was expected");
    const char c = s_[pos_];
    if (c == '(') {
      ++pos_;
      const int x = sum();
      if (!accept(')')) fail(pos_, "')' expected");
      return x;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') return name();
    fail(pos_, std::string("unexpected '") + c + "'");
  }

  int number() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '.')) ++pos_;
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      std::size_t p = pos_ + 1;
      if (p < s_.size() && (s_[p] == '+' || s_[p] == '-')) ++p;
      if (p < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p]))) {
        pos_ = p;
        while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      }
    }
    const std::string text(s_.substr(start, pos_ - start));
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || !std::isfinite(v)) fail(start, "'" + text + "' is not a number");
    return b_.constant(v);
  }

  int name() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    const std::string id(s_.substr(start, pos_ - start));
    if (accept('(')) return call(id, start);
    if (find_function(id)) fail(start, "'" + id + "' is a function: write " + id + "(...)");
    if (id == "t") return b_.leaf(Op::time, -1);
    if (id == "pi") return b_.constant(std::numbers::pi);
    const auto& qs = symbols_.coordinates;
    for (std::size_t i = 0; i < qs.size(); ++i) {
      if (id == qs[i]) return b_.leaf(Op::coordinate, static_cast<int>(i));
      if (id == qs[i] + "_dot") return b_.leaf(Op::velocity, static_cast<int>(i));
    }
    const auto& ps = symbols_.parameters;
    for (std::size_t i = 0; i < ps.size(); ++i)
      if (id == ps[i]) return b_.leaf(Op::parameter, static_cast<int>(i));
    std::vector<std::string> names = {"t", "pi"};
    for (const std::string& q : qs) {
      names.push_back(q);
      names.push_back(q + "_dot");
    }
    names.insert(names.end(), ps.begin(), ps.end());
    fail(start, "unknown name '" + id + "'" + nearest(id, names) + "; " + known_names());
  }

  int call(const std::string& id, std::size_t start) {
    const Function* f = find_function(id);
    if (!f) {
      std::string all;
      for (const Function& g : kFunctions) all += (all.empty() ? "" : " ") + std::string(g.name);
      std::vector<std::string> names;
      for (const Function& g : kFunctions) names.emplace_back(g.name);
      fail(start, "unknown function '" + id + "'" + nearest(id, names) + "; the functions are " + all);
    }
    std::vector<int> args;
    if (!accept(')')) {
      args.push_back(sum());
      while (accept(',')) args.push_back(sum());
      if (!accept(')')) fail(pos_, "')' or ',' expected in the arguments of " + id);
    }
    if (static_cast<int>(args.size()) != f->arguments)
      fail(start, id + " takes " + std::to_string(f->arguments) + " argument" + (f->arguments == 1 ? "" : "s") +
                      ", not " + std::to_string(args.size()));
    return f->arguments == 1 ? b_.unary(f->op, args[0]) : b_.binary(f->op, args[0], args[1]);
  }

  /// ", did you mean 'x'?" for the name of `names` nearest to `id` (at most
  /// two edits away, and fewer than its length), else "".
  static std::string nearest(const std::string& id, const std::vector<std::string>& names) {
    const std::size_t most = id.empty() ? 0 : std::min<std::size_t>(2, id.size() - 1);
    const std::string best = lagrangian::detail::nearest_name(id, names, most);
    return best.empty() ? std::string() : ", did you mean '" + best + "'?";
  }

  std::string known_names() const {
    auto list = [](const std::vector<std::string>& v, const std::string& suffix) {
      std::string out;
      for (const std::string& s : v) out += (out.empty() ? "" : ", ") + s + suffix;
      return out.empty() ? std::string("none") : out;
    };
    return "the names here are the coordinates (" + list(symbols_.coordinates, "") + "), their velocities (" +
           list(symbols_.coordinates, "_dot") + "), the parameters (" + list(symbols_.parameters, "") +
           "), t and pi";
  }

  std::string_view s_;
  const Symbols& symbols_;
  const std::string& field_;
  std::size_t pos_ = 0;
  Expression e_;
  Builder b_;
};

}  // namespace

bool Expression::reads_velocities() const {
  for (const Node& n : nodes)
    if (n.op == Op::velocity) return true;
  return false;
}

bool Expression::reads_time() const {
  for (const Node& n : nodes)
    if (n.op == Op::time) return true;
  return false;
}

Expression parse(std::string_view source, const Symbols& symbols, const std::string& field) {
  return Parser(source, symbols, field).run();
}

Expression bind_parameters(const Expression& e, const std::vector<double>& parameter_values, int keep) {
  Expression out;
  Builder b(out);
  std::vector<int> at(e.nodes.size());
  for (std::size_t i = 0; i < e.nodes.size(); ++i) {
    const Node& n = e.nodes[i];
    const int a = n.a >= 0 ? at[static_cast<std::size_t>(n.a)] : -1;
    const int c = n.b >= 0 ? at[static_cast<std::size_t>(n.b)] : -1;
    at[i] = n.op == Op::parameter && n.index != keep
                ? b.constant(parameter_values.at(static_cast<std::size_t>(n.index)))
                : b.copy(n, a, c);
  }
  return at.empty() ? out : reachable(out, at.back());
}

bool valid_name(std::string_view name) {
  if (name.empty() || !(std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_')) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return name != "t" && name != "pi" && !find_function(name);
}

}  // namespace lagrangian::text
