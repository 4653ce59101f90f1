// What a sweep varies and sets (include/lagrangian/scene/sweep.hpp): the arithmetic
// expressions of --set and --first-time, the options --vary, --set and
// --first-time parsed and checked, and the points (grid or Monte Carlo).

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <random>
#include <sstream>

#include "lagrangian/scene/sweep.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/scene/scene.hpp"
#include "sweep_detail.hpp"
#include "text.hpp"

namespace lagrangian::scene {
namespace {

using detail::kNaN;
using detail::q;

// -- expressions ------------------------------------------------------------------

enum OpCode { kConst, kVar, kAdd, kSub, kMul, kDiv, kPow, kNeg, kFunc1, kFunc2 };
constexpr const char* kFunctions1[] = {"sin", "cos", "tan", "asin", "acos", "atan", "sqrt", "exp", "log", "abs"};
constexpr const char* kFunctions2[] = {"atan2", "min", "max", "pow"};

double apply1(int f, double x) {
  switch (f) {
    case 0: return std::sin(x);
    case 1: return std::cos(x);
    case 2: return std::tan(x);
    case 3: return std::asin(x);
    case 4: return std::acos(x);
    case 5: return std::atan(x);
    case 6: return std::sqrt(x);
    case 7: return std::exp(x);
    case 8: return std::log(x);
    default: return std::abs(x);
  }
}

double apply2(int f, double x, double y) {
  switch (f) {
    case 0: return std::atan2(x, y);
    case 1: return std::min(x, y);
    case 2: return std::max(x, y);
    default: return std::pow(x, y);
  }
}

}  // namespace

namespace detail_expr {

/// Recursive descent: sum := product (('+'|'-') product)*; product := unary
/// (('*'|'/') unary)*; unary := '-' unary | power; power := atom ('^' unary)?;
/// atom := number | name | name '(' args ')' | '(' sum ')'.
class Parser {
 public:
  Parser(const std::string& text, const std::vector<std::string>& vars, const std::string& what,
         std::vector<std::pair<int, double>>& out)
      : s_(text), vars_(vars), what_(what), out_(out) {}
  void parse() {
    sum();
    skip();
    if (pos_ != s_.size()) fail("unexpected " + q(s_.substr(pos_, 1)));
  }

 private:
  const std::string& s_;
  const std::vector<std::string>& vars_;
  const std::string& what_;
  std::vector<std::pair<int, double>>& out_;
  std::size_t pos_ = 0;

  [[noreturn]] void fail(const std::string& why) const {
    throw OptionError(what_ + ": cannot read the expression " + q(s_) + " at character " + std::to_string(pos_ + 1) +
                      ": " + why);
  }
  void skip() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  bool eat(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  /// operand ((op1 | op2) operand)*, left-associative.
  void chain(void (Parser::*operand)(), char op1, int code1, char op2, int code2) {
    (this->*operand)();
    for (;;) {
      const int code = eat(op1) ? code1 : eat(op2) ? code2 : -1;
      if (code < 0) return;
      (this->*operand)();
      out_.emplace_back(code, 0);
    }
  }
  void sum() { chain(&Parser::product, '+', kAdd, '-', kSub); }
  void product() { chain(&Parser::unary, '*', kMul, '/', kDiv); }
  void unary() {
    if (eat('-')) {
      unary();
      out_.emplace_back(kNeg, 0);
    } else if (eat('+')) {
      unary();
    } else {
      power();
    }
  }
  void power() {
    atom();
    if (eat('^')) {
      unary();
      out_.emplace_back(kPow, 0);
    }
  }
  void atom() {
    skip();
    if (pos_ >= s_.size()) fail("expected a number, a name or '('");
    const char c = s_[pos_];
    if (eat('(')) {
      sum();
      if (!eat(')')) fail("expected ')'");
      return;
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      double v = 0;
      const auto r = std::from_chars(s_.data() + pos_, s_.data() + s_.size(), v);
      if (r.ec != std::errc()) fail("malformed number");
      pos_ = static_cast<std::size_t>(r.ptr - s_.data());
      out_.emplace_back(kConst, v);
      return;
    }
    if (!(std::isalpha(static_cast<unsigned char>(c)) || c == '_')) fail("unexpected " + q(std::string(1, c)));
    const std::size_t start = pos_;
    while (pos_ < s_.size() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    const std::string name = s_.substr(start, pos_ - start);
    if (eat('(')) {
      for (std::size_t f = 0; f < std::size(kFunctions1); ++f)
        if (name == kFunctions1[f]) {
          sum();
          if (!eat(')')) fail(name + " takes one argument; expected ')'");
          out_.emplace_back(kFunc1, static_cast<double>(f));
          return;
        }
      for (std::size_t f = 0; f < std::size(kFunctions2); ++f)
        if (name == kFunctions2[f]) {
          sum();
          if (!eat(',')) fail(name + " takes two arguments; expected ','");
          sum();
          if (!eat(')')) fail("expected ')'");
          out_.emplace_back(kFunc2, static_cast<double>(f));
          return;
        }
      fail("unknown function " + q(name));
    }
    for (std::size_t k = 0; k < vars_.size(); ++k)
      if (vars_[k] == name) {
        out_.emplace_back(kVar, static_cast<double>(k));
        return;
      }
    if (name == "pi") {
      out_.emplace_back(kConst, 3.141592653589793);
      return;
    }
    std::vector<std::string> names = vars_;
    names.emplace_back("pi");
    const std::string near = nearest(name, names);
    pos_ = start;
    fail("unknown name " + q(name) +
         (near.empty() ? "; known names: " + text::join(names) : "; did you mean '" + near + "'?"));
  }
};

}  // namespace detail_expr

Expression::Expression(const std::string& text, const std::vector<std::string>& variables, const std::string& what) {
  std::vector<std::pair<int, double>> ops;
  if (text.find_first_not_of(" \t") == std::string::npos) throw OptionError(what + ": empty expression");
  detail_expr::Parser(text, variables, what, ops).parse();
  for (const auto& [code, value] : ops) ops_.push_back({code, value});
}

bool Expression::uses(std::size_t k) const {
  for (const Op& op : ops_)
    if (op.code == kVar && static_cast<std::size_t>(op.value) == k) return true;
  return false;
}

std::vector<std::string> sweep_warnings(const SweepOptions& o) {
  std::vector<std::string> variables;
  for (const VarySpec& v : o.vary)
    if (v.variable()) variables.push_back(v.key);
  std::vector<Expression> exprs;
  for (const SetSpec& s : o.set) exprs.emplace_back(s.expression, variables, "--set " + s.key);
  std::vector<std::string> out;
  for (std::size_t k = 0; k < variables.size(); ++k) {
    bool used = false;
    for (const Expression& e : exprs) used = used || e.uses(k);
    if (!used)
      out.push_back("--vary " + variables[k] + ": no --set expression uses the variable '" + variables[k] +
                    "', so its values change nothing and points that differ only in it run the same scene; use "
                    "it in --set KEY=EXPRESSION, or vary a scene key (a name with '.' or '[', such as "
                    "model.parameters." + variables[k] + ")");
  }
  return out;
}

double Expression::evaluate(const double* values) const {
  double stack[64];
  int top = 0;
  for (const Op& op : ops_) {
    switch (op.code) {
      case kConst: stack[top++] = op.value; break;
      case kVar: stack[top++] = values[static_cast<std::size_t>(op.value)]; break;
      case kNeg: stack[top - 1] = -stack[top - 1]; break;
      case kFunc1: stack[top - 1] = apply1(static_cast<int>(op.value), stack[top - 1]); break;
      default: {
        const double y = stack[--top];
        double& x = stack[top - 1];
        switch (op.code) {
          case kAdd: x += y; break;
          case kSub: x -= y; break;
          case kMul: x *= y; break;
          case kDiv: x /= y; break;
          case kPow: x = std::pow(x, y); break;
          default: x = apply2(static_cast<int>(op.value), x, y); break;
        }
      }
    }
    if (top >= 63) throw OptionError("expression nested too deeply");
  }
  return top == 1 ? stack[0] : kNaN;
}

}  // namespace lagrangian::scene

namespace lagrangian::scene {
namespace detail {

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

std::string q(const std::string& s) { return text::quoted(s, '\''); }

}  // namespace detail

namespace {

using detail::q;
using detail::split;

/// A finite number written in full (no trailing text); false otherwise.
bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  const char* begin = s.data();
  const char* end = begin + s.size();
  if (*begin == '+') ++begin;
  const auto r = std::from_chars(begin, end, v);
  return r.ec == std::errc() && r.ptr == end && std::isfinite(v);
}

/// "key=rest": the key (non-empty, no spaces) and the rest; throws OptionError "<option>: …".
std::pair<std::string, std::string> key_and_value(const std::string& option, const std::string& text,
                                                  const char* form) {
  const auto eq = text.find('=');
  if (eq == std::string::npos)
    throw OptionError(option + ": expected " + form + ", got " + q(text) + " (no '=')");
  std::string key = text.substr(0, eq);
  if (key.empty()) throw OptionError(option + ": expected " + form + ", got " + q(text) + " (no key before '=')");
  if (key.find_first_of(" \t\n,\"") != std::string::npos)
    throw OptionError(option + ": the key " + q(key) + " contains a space, comma or quote");
  return {key, text.substr(eq + 1)};
}

bool is_name(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(),
                     [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace

// -- options ----------------------------------------------------------------------

bool VarySpec::variable() const { return key.find_first_of(".[") == std::string::npos; }

double VarySpec::grid_value(int k) const {
  if (count <= 1) return a;
  if (k == count - 1) return b;  // the end point exactly
  const double f = static_cast<double>(k) / (count - 1);
  if (kind == Kind::log) return a * std::pow(b / a, f);
  return a + (b - a) * f;
}

VarySpec parse_vary(const std::string& text) {
  constexpr const char* form = "KEY=START:STOP:COUNT[:log], KEY=uniform:A:B or KEY=normal:MU:SIGMA";
  auto [key, rest] = key_and_value("--vary", text, form);
  VarySpec v;
  v.key = key;
  if (v.variable() && !is_name(key))
    throw OptionError("--vary: " + q(key) +
                      " is neither a scene key (with '.' or '[') nor a variable name (letters, digits, '_')");
  const std::vector<std::string> parts = split(rest, ':');
  auto number = [&](const std::string& s, const char* what) {
    double x = 0;
    if (!parse_number(s, x))
      throw OptionError("--vary " + v.key + ": " + what + " must be a finite number, got " + q(s) + " in " +
                        q(text));
    return x;
  };
  if (!parts.empty() && (parts[0] == "uniform" || parts[0] == "normal")) {
    const bool uniform = parts[0] == "uniform";
    if (parts.size() != 3)
      throw OptionError("--vary " + key + ": expected " + (uniform ? "uniform:A:B" : "normal:MU:SIGMA") + ", got " +
                        q(text));
    v.kind = uniform ? VarySpec::Kind::uniform : VarySpec::Kind::normal;
    v.a = number(parts[1], uniform ? "A" : "MU");
    v.b = number(parts[2], uniform ? "B" : "SIGMA");
    if (uniform && !(v.a < v.b))
      throw OptionError("--vary " + key + ": uniform:A:B needs A < B, got " + q(text));
    if (!uniform && !(v.b > 0)) throw OptionError("--vary " + key + ": normal:MU:SIGMA needs SIGMA > 0, got " + q(text));
    return v;
  }
  if (parts.size() != 3 && !(parts.size() == 4 && parts[3] == "log"))
    throw OptionError("--vary: expected " + std::string(form) + ", got " + q(text));
  v.a = number(parts[0], "START");
  v.b = number(parts[1], "STOP");
  long long count = 0;
  const auto r = std::from_chars(parts[2].data(), parts[2].data() + parts[2].size(), count);
  if (r.ec != std::errc() || r.ptr != parts[2].data() + parts[2].size() || count < 1 || count > 100'000'000)
    throw OptionError("--vary " + key + ": COUNT must be an integer >= 1, got " + q(parts[2]) + " in " +
                      q(text));
  v.count = static_cast<int>(count);
  if (parts.size() == 4) {
    v.kind = VarySpec::Kind::log;
    if (!(v.a > 0 && v.b > 0))
      throw OptionError("--vary " + key + ": a log grid needs START and STOP > 0, got " + q(text));
  }
  return v;
}

SetSpec parse_set(const std::string& text) {
  auto [key, rest] = key_and_value("--set", text, "KEY=EXPRESSION");
  if (key.find_first_of(".[") == std::string::npos)
    throw OptionError("--set: " + q(key) + " is not a scene key (keys have '.' or '[', e.g. model.qd[0])");
  return {key, rest};
}

FirstTimeSpec parse_first_time(const std::string& text) {
  auto [name, rest] = key_and_value("--first-time", text, "NAME=EXPRESSION");
  if (!is_name(name)) throw OptionError("--first-time: the name " + q(name) + " must be letters, digits and '_'");
  return {name, rest};
}

std::vector<std::string> SweepOptions::output_groups() {
  return {"final", "events", "energy", "error", "cost", "wall", "chaos"};
}

bool SweepOptions::wants(const std::string& group) const {
  return std::find(outputs.begin(), outputs.end(), group) != outputs.end();
}

void SweepOptions::validate() const {
  if (vary.empty()) throw OptionError("--vary: at least one is needed (KEY=START:STOP:COUNT)");
  for (std::size_t i = 0; i < vary.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (vary[i].key == vary[j].key) throw OptionError("--vary: the key " + q(vary[i].key) + " is varied twice");
  for (const SetSpec& s : set)
    for (const VarySpec& v : vary)
      if (s.key == v.key) throw OptionError("--set: the key " + q(s.key) + " is also varied");
  const bool any_grid = std::any_of(vary.begin(), vary.end(), [](const VarySpec& v) { return v.grid(); });
  const bool any_random = std::any_of(vary.begin(), vary.end(), [](const VarySpec& v) { return !v.grid(); });
  if (monte_carlo > 0 && any_grid) {
    const auto it = std::find_if(vary.begin(), vary.end(), [](const VarySpec& v) { return v.grid(); });
    throw OptionError("--monte-carlo: every --vary must be a distribution (uniform:A:B or normal:MU:SIGMA); " +
                      q(it->key) + " is a grid");
  }
  if (monte_carlo == 0 && any_random) {
    const auto it = std::find_if(vary.begin(), vary.end(), [](const VarySpec& v) { return !v.grid(); });
    throw OptionError("--vary " + it->key + ": a distribution needs --monte-carlo N");
  }
  if (monte_carlo == 0) {
    double n = 1;
    for (const VarySpec& v : vary) n *= v.count;
    if (n > 1e9) throw OptionError("--vary: the grid has " + std::to_string(n) + " points, more than 1e9");
  } else if (monte_carlo > 1'000'000'000) {
    throw OptionError("--monte-carlo: at most 1e9 points, got " + std::to_string(monte_carlo));
  }
  if (threads < 0) throw OptionError("--threads: must be >= 1, got " + std::to_string(threads));
  const auto groups = output_groups();
  for (const std::string& o : outputs)
    if (std::find(groups.begin(), groups.end(), o) == groups.end()) {
      const std::string near = nearest(o, groups);
      throw OptionError("--output: unknown column group " + q(o) +
                        (near.empty() ? "; expected some of: " + text::join(groups) : "; did you mean '" + near + "'?"));
    }
  if (out_dir.empty()) throw OptionError("--out: the output directory is empty");
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw OptionError("sweep: rank " + std::to_string(rank) + " of " + std::to_string(ranks));
  if (ranks > 1 && !gather) throw OptionError("sweep: several ranks need a gather function");
}

}  // namespace lagrangian::scene

namespace lagrangian::scene {

std::uint64_t point_seed(std::uint64_t seed, std::uint64_t i) {
  std::uint64_t z = seed + (i + 1) * 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::uint64_t point_count(const SweepOptions& o) {
  if (o.monte_carlo > 0) return o.monte_carlo;
  std::uint64_t n = 1;
  for (const VarySpec& v : o.vary) n *= static_cast<std::uint64_t>(v.count);
  return n;
}

std::vector<double> point_values(const SweepOptions& o, std::uint64_t index) {
  std::vector<double> values(o.vary.size());
  if (o.monte_carlo > 0) {
    std::mt19937_64 engine(point_seed(o.seed, index));
    // (0, 1]: the 53 high bits, shifted off zero so that log() is finite.
    auto uniform = [&] { return (static_cast<double>(engine() >> 11) + 1.0) * 0x1.0p-53; };
    for (std::size_t k = 0; k < o.vary.size(); ++k) {
      const VarySpec& v = o.vary[k];
      if (v.kind == VarySpec::Kind::uniform) {
        values[k] = v.a + (v.b - v.a) * (uniform() - 0x1.0p-53);  // [a, b)
      } else {
        const double u1 = uniform(), u2 = uniform();
        values[k] = v.a + v.b * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.141592653589793 * u2);
      }
    }
    return values;
  }
  // The first --vary varies slowest.
  std::uint64_t rest = index;
  for (std::size_t k = o.vary.size(); k-- > 0;) {
    const auto n = static_cast<std::uint64_t>(o.vary[k].count);
    values[k] = o.vary[k].grid_value(static_cast<int>(rest % n));
    rest /= n;
  }
  return values;
}

}  // namespace lagrangian::scene
