// Parameter sweeps and ensembles of a scene (include/lagrangian/sweep.hpp):
// the points, the changed TOML documents, the thread pool, the gathering of
// results by point index and the CSV.

#include "lagrangian/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <thread>
#include <variant>

#include <toml++/toml.h>

#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/plots.hpp"
#include "lagrangian/progress.hpp"
#include "lagrangian/scene.hpp"
#include "lagrangian/scene_io.hpp"
#include "lagrangian/scene_models.hpp"
#include "lagrangian/scene_run.hpp"
#include "text.hpp"
#include "toml_document.hpp"

namespace lagrangian::scene {
namespace {

namespace fs = std::filesystem;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A finite number written in full (no trailing text); false otherwise.
bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  const char* begin = s.data();
  const char* end = begin + s.size();
  if (*begin == '+') ++begin;
  const auto r = std::from_chars(begin, end, v);
  return r.ec == std::errc() && r.ptr == end && std::isfinite(v);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  if (!s.empty() && s.back() == sep) out.emplace_back();
  return out;
}

std::string q(const std::string& s) { return text::quoted(s, '\''); }

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
      throw OptionError("--vary " + key + ": " + what + " must be a finite number, got " + q(s) + " in " +
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

std::vector<std::string> SweepOptions::output_groups() { return {"final", "events", "energy", "error", "cost", "wall"}; }

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

namespace {

// -- changing the document ------------------------------------------------------

using PathPart = std::variant<std::string, std::size_t>;

std::vector<PathPart> parse_path(const std::string& option, const std::string& key) {
  std::vector<PathPart> parts;
  std::size_t i = 0;
  auto bad = [&](const std::string& why) {
    throw OptionError(option + " " + key + ": not a scene key: " + why +
                      " (write keys as in the scene file, e.g. model.parameters.e or bodies[0].velocity[2])");
  };
  while (i < key.size()) {
    if (key[i] == '[') {
      const std::size_t close = key.find(']', i);
      if (close == std::string::npos) bad("'[' without ']'");
      std::size_t v = 0;
      const auto r = std::from_chars(key.data() + i + 1, key.data() + close, v);
      if (r.ec != std::errc() || r.ptr != key.data() + close) bad("the index in '[]' must be an integer >= 0");
      if (parts.empty()) bad("it starts with an index");
      parts.emplace_back(v);
      i = close + 1;
      if (i < key.size() && key[i] == '.') {
        ++i;
        if (i == key.size()) bad("it ends with '.'");
      }
    } else {
      std::size_t end = key.find_first_of(".[", i);
      if (end == std::string::npos) end = key.size();
      if (end == i) bad("an empty name");
      parts.emplace_back(key.substr(i, end - i));
      i = end;
      if (i < key.size() && key[i] == '.') {
        ++i;
        if (i == key.size()) bad("it ends with '.'");
      }
    }
  }
  return parts;
}

std::string type_of(const toml::node& n) {
  std::ostringstream os;
  os << n.type();
  return os.str();
}

/// Writes `value` at `path` in `root`: an integral value is an integer where
/// the file has an integer or no value; missing tables and keys are created
/// (the reader refuses unknown ones with its own message), missing array
/// elements are not.
void assign(toml::table& root, const std::string& option, const std::string& key, const std::vector<PathPart>& path,
            double value) {
  toml::node* cur = &root;
  std::string where;
  auto fail = [&](const std::string& why) { throw OptionError(option + " " + key + ": " + why); };
  auto numeric = [&](const toml::node* old, auto&& put) {
    if (old && !old->is_number())
      fail("the scene has " + where + " = " + type_of(*old) + ", not a number; only numbers can be varied");
    // Integral values go in as TOML integers where the file has an integer or
    // nothing (the reader takes an integer for a float key, not the reverse).
    if ((!old || old->is_integer()) && std::nearbyint(value) == value && std::abs(value) < 9.2e18)
      put(toml::value<std::int64_t>(static_cast<std::int64_t>(value)));
    else
      put(toml::value<double>(value));
  };
  for (std::size_t k = 0; k < path.size(); ++k) {
    const bool last = k + 1 == path.size();
    if (const auto* name = std::get_if<std::string>(&path[k])) {
      where += (where.empty() ? "" : ".") + *name;
      toml::table* t = cur->as_table();
      if (!t) fail("the scene has " + where.substr(0, where.rfind('.')) + " as " + type_of(*cur) + ", not a table");
      toml::node* child = t->get(*name);
      if (last) {
        numeric(child, [&](auto&& v) { t->insert_or_assign(*name, std::move(v)); });
        return;
      }
      if (!child) {
        if (std::holds_alternative<std::size_t>(path[k + 1]))
          fail("the scene file does not write " + where + "; write it in the scene to vary one of its elements");
        child = &t->insert_or_assign(*name, toml::table{}).first->second;
      }
      cur = child;
    } else {
      const std::size_t i = std::get<std::size_t>(path[k]);
      toml::array* a = cur->as_array();
      if (!a) fail("the scene has " + where + " as " + type_of(*cur) + ", not an array");
      if (i >= a->size())
        fail("index " + std::to_string(i) + " is out of range: the scene's " + where + " has " +
             std::to_string(a->size()) + " element" + (a->size() == 1 ? "" : "s"));
      where += "[" + std::to_string(i) + "]";
      toml::node* child = a->get(i);
      if (last) {
        numeric(child, [&](auto&& v) { a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(i), std::move(v)); });
        return;
      }
      cur = child;
    }
  }
}

/// Everything a worker needs to build the scene of a point.
struct Plan {
  std::string file;
  /// The scene file's text, parsed again for every point: a parsed document
  /// keeps the source lines that error messages cite, a copy of one does not.
  std::string text;
  std::vector<std::vector<PathPart>> vary_paths;  // empty for variables
  std::vector<std::vector<PathPart>> set_paths;
  std::vector<Expression> set_expressions;
  std::vector<std::string> variables;             // names of the variables, in --vary order
  std::vector<std::size_t> variable_slots;        // their index in SweepOptions::vary
};

/// The document of one point, with its values written in; `values` gets the
/// varied then the set values.
Scene point_scene(const Plan& plan, const SweepOptions& o, toml::table& doc, std::vector<double>& values) {
  std::vector<double> vars;
  for (std::size_t slot : plan.variable_slots) vars.push_back(values[slot]);
  for (std::size_t k = 0; k < o.vary.size(); ++k)
    if (!plan.vary_paths[k].empty()) assign(doc, "--vary", o.vary[k].key, plan.vary_paths[k], values[k]);
  for (std::size_t k = 0; k < o.set.size(); ++k) {
    const double v = plan.set_expressions[k].evaluate(vars.data());
    values.push_back(v);
    if (!std::isfinite(v))
      throw OptionError("--set " + o.set[k].key + ": the expression " + q(o.set[k].expression) + " gives " +
                        (std::isnan(v) ? "NaN" : "an infinite value") + " at this point");
    assign(doc, "--set", o.set[k].key, plan.set_paths[k], v);
  }
  return detail::scene_from_document(doc, plan.file);
}

/// Names a --first-time expression may use for `scene`: t, the coordinates
/// and their rates as in trajectory.csv, energy and total_energy.
std::vector<std::string> trajectory_names(const Scene& scene) {
  std::vector<std::string> coords;
  if (scene.model) {
    if (const ModelInfo* info = find_model(scene.model->name)) coords = info->coordinates;
  } else {
    Scene expanded = scene;
    expanded.expand_gas();
    for (const Body& b : expanded.bodies)
      for (const char* axis : {".x", ".y", ".z"}) coords.push_back(b.name + axis);
  }
  std::vector<std::string> names{"t"};
  names.insert(names.end(), coords.begin(), coords.end());
  for (const auto& c : coords) names.push_back(c + "_dot");
  names.emplace_back("energy");
  names.emplace_back("total_energy");
  return names;
}

/// The first times of the --first-time expressions from the run's
/// trajectory.csv (see FirstTimeSpec).
void first_times(const std::string& path, const SweepOptions& o, SweepRecord& rec) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) throw OptionError("cannot read the trajectory '" + path + "'");
  const std::vector<std::string> names = split(line, ',');
  std::vector<Expression> exprs;
  for (const FirstTimeSpec& f : o.first_times) exprs.emplace_back(f.expression, names, "--first-time " + f.name);
  rec.first_times.assign(exprs.size(), kNaN);
  std::vector<double> prev_val(exprs.size(), kNaN);
  double prev_t = kNaN;
  std::vector<double> row(names.size());
  std::size_t open = exprs.size();
  while (open > 0 && std::getline(in, line)) {
    const std::vector<std::string> cells = split(line, ',');
    for (std::size_t c = 0; c < row.size(); ++c)
      row[c] = c < cells.size() ? std::strtod(cells[c].c_str(), nullptr) : kNaN;
    const double t = row[0];
    for (std::size_t k = 0; k < exprs.size(); ++k) {
      if (!std::isnan(rec.first_times[k])) continue;
      const double v = exprs[k].evaluate(row.data());
      if (v > 0) {
        // Linear interpolation of the zero between the previous sample and this one.
        rec.first_times[k] = std::isfinite(prev_val[k]) && prev_val[k] <= 0 && v != prev_val[k]
                                 ? prev_t + (t - prev_t) * (0 - prev_val[k]) / (v - prev_val[k])
                                 : t;
        --open;
      }
      prev_val[k] = v;
    }
    prev_t = t;
  }
}

SweepRecord run_point(const Plan& plan, const SweepOptions& o, std::uint64_t index, const std::string& work_dir) {
  SweepRecord rec;
  rec.values = point_values(o, index);
  try {
    toml::table doc = toml::parse(plan.text, plan.file);  // the worker's own document
    Scene scene = point_scene(plan, o, doc, rec.values);
    RunControls controls;
    controls.write_outputs = !o.first_times.empty();
    if (controls.write_outputs) {
      scene.output.directory = work_dir;
      scene.output.trajectory = true;
      scene.output.plots = false;
    }
    const RunResult r = run(scene, controls);
    const RunReport& rep = r.report;
    rec.coordinates = rep.coordinates;
    rec.q = r.q_final;
    rec.qd = r.qd_final;
    rec.t_final = rep.t_final;
    rec.energy_drift_max = rep.energy_drift_max;
    rec.energy_drift_final = rep.energy_drift_final;
    rec.impact_energy_loss = rep.impact_energy_loss;
    rec.has_reference = rep.has_reference;
    rec.reference_error_final = rep.reference_error_final;
    rec.steps = rep.steps;
    rec.rejected_steps = rep.rejected_steps;
    rec.rhs_evaluations = rep.rhs_evaluations;
    rec.wall_time_s = rep.wall_time_s;
    for (const EventRecord& e : rep.events) {
      SweepRecord::EventGroup& g = rec.events[e.kind == EventKind::watched ? e.name : to_string(e.kind)];
      if (g.count == 0) g.first = e.t;
      g.last = e.t;
      ++g.count;
    }
    if (!o.first_times.empty()) first_times((fs::path(work_dir) / "trajectory.csv").string(), o, rec);
  } catch (const std::exception& e) {
    std::string msg = e.what();
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    rec.status = "failed: " + msg;
    rec.values.resize(o.vary.size() + o.set.size(), kNaN);
  }
  return rec;
}

// -- serialization between ranks ---------------------------------------------------

constexpr char kField = '\x1f', kRecord = '\x1e';

void put(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back exactly
  out.append(buf, r.ptr);
  out += kField;
}
void put(std::string& out, std::uint64_t v) {
  out += std::to_string(v);
  out += kField;
}
void put(std::string& out, std::string s) {
  std::replace(s.begin(), s.end(), kField, ' ');
  std::replace(s.begin(), s.end(), kRecord, ' ');
  out += s;
  out += kField;
}

std::string serialize(std::uint64_t index, const SweepRecord& r) {
  std::string out;
  put(out, index);
  put(out, r.status);
  put(out, static_cast<std::uint64_t>(r.values.size()));
  for (double v : r.values) put(out, v);
  put(out, static_cast<std::uint64_t>(r.coordinates.size()));
  for (std::size_t k = 0; k < r.coordinates.size(); ++k) {
    put(out, r.coordinates[k]);
    put(out, k < r.q.size() ? r.q[k] : kNaN);
    put(out, k < r.qd.size() ? r.qd[k] : kNaN);
  }
  for (double v : {r.t_final, r.energy_drift_max, r.energy_drift_final, r.impact_energy_loss,
                   r.reference_error_final, r.wall_time_s})
    put(out, v);
  put(out, static_cast<std::uint64_t>(r.has_reference));
  for (std::uint64_t v : {r.steps, r.rejected_steps, r.rhs_evaluations}) put(out, v);
  put(out, static_cast<std::uint64_t>(r.events.size()));
  for (const auto& [name, g] : r.events) {
    put(out, name);
    put(out, g.count);
    put(out, g.first);
    put(out, g.last);
  }
  put(out, static_cast<std::uint64_t>(r.first_times.size()));
  for (double v : r.first_times) put(out, v);
  out += kRecord;
  return out;
}

class Reader {
 public:
  explicit Reader(const std::string& s) : s_(s) {}
  bool more() const { return pos_ < s_.size(); }
  std::string text() {
    const std::size_t end = s_.find(kField, pos_);
    if (end == std::string::npos) throw std::runtime_error("sweep: malformed results from a rank");
    std::string out = s_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return out;
  }
  double number() {
    const std::string t = text();
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc()) {
      if (t.find("nan") != std::string::npos) return kNaN;
      if (t.find("inf") != std::string::npos) return t[0] == '-' ? -INFINITY : INFINITY;
      throw std::runtime_error("sweep: malformed number from a rank: " + t);
    }
    return v;
  }
  std::uint64_t count() { return std::stoull(text()); }
  void end_record() {
    if (pos_ >= s_.size() || s_[pos_] != kRecord) throw std::runtime_error("sweep: malformed record from a rank");
    ++pos_;
  }

 private:
  const std::string& s_;
  std::size_t pos_ = 0;
};

void deserialize(const std::string& text, std::vector<SweepRecord>& slots, std::vector<bool>& filled) {
  Reader in(text);
  while (in.more()) {
    const std::uint64_t index = in.count();
    if (index >= slots.size()) throw std::runtime_error("sweep: a rank sent point " + std::to_string(index));
    SweepRecord r;
    r.status = in.text();
    r.values.resize(in.count());
    for (double& v : r.values) v = in.number();
    const std::uint64_t n = in.count();
    for (std::uint64_t k = 0; k < n; ++k) {
      r.coordinates.push_back(in.text());
      r.q.push_back(in.number());
      r.qd.push_back(in.number());
    }
    for (double* v : {&r.t_final, &r.energy_drift_max, &r.energy_drift_final, &r.impact_energy_loss,
                      &r.reference_error_final, &r.wall_time_s})
      *v = in.number();
    r.has_reference = in.count() != 0;
    for (std::uint64_t* v : {&r.steps, &r.rejected_steps, &r.rhs_evaluations}) *v = in.count();
    const std::uint64_t groups = in.count();
    for (std::uint64_t k = 0; k < groups; ++k) {
      const std::string name = in.text();
      SweepRecord::EventGroup& g = r.events[name];
      g.count = in.count();
      g.first = in.number();
      g.last = in.number();
    }
    r.first_times.resize(in.count());
    for (double& v : r.first_times) v = in.number();
    in.end_record();
    // Coordinates that a run without a final state left empty: q, qd stay empty.
    if (n == 0) {
      r.q.clear();
      r.qd.clear();
    }
    slots[index] = std::move(r);
    filled[index] = true;
  }
}

// -- the table ------------------------------------------------------------------------

std::string cell(double v) {
  if (std::isnan(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string csv_text(std::string s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

bool wants(const SweepOptions& o, const char* group) {
  return std::find(o.outputs.begin(), o.outputs.end(), group) != o.outputs.end();
}

/// Event groups in a fixed order: impact, rest, release, stop (a watched
/// event that ended the run), then the watched events' names in
/// alphabetical order.
std::vector<std::string> event_groups(const std::vector<SweepRecord>& records) {
  std::vector<std::string> names;
  for (const SweepRecord& r : records)
    for (const auto& [name, g] : r.events)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  auto rank = [](const std::string& n) {
    return n == "impact" ? 0 : n == "rest" ? 1 : n == "release" ? 2 : n == "stop" ? 3 : 4;
  };
  std::sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) {
    return rank(a) != rank(b) ? rank(a) < rank(b) : a < b;
  });
  return names;
}

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

Table make_table(const SweepOptions& o, const std::vector<SweepRecord>& records) {
  Table t;
  t.header.emplace_back("point");
  for (const VarySpec& v : o.vary) t.header.push_back(v.key);
  for (const SetSpec& s : o.set) t.header.push_back(s.key);
  t.header.emplace_back("status");
  std::vector<std::string> coords;
  for (const SweepRecord& r : records)
    if (r.ok()) {
      coords = r.coordinates;
      break;
    }
  const std::vector<std::string> groups = event_groups(records);
  if (wants(o, "final")) {
    t.header.emplace_back("t_final");
    for (const auto& c : coords) t.header.push_back("q_" + c);
    for (const auto& c : coords) t.header.push_back("qd_" + c);
  }
  if (wants(o, "events"))
    for (const auto& g : groups)
      for (const char* p : {"n_", "first_", "last_"}) t.header.push_back(p + g);
  for (const FirstTimeSpec& f : o.first_times) t.header.push_back("t_" + f.name);
  if (wants(o, "energy"))
    for (const char* c : {"energy_drift_max", "energy_drift_final", "impact_energy_loss"}) t.header.emplace_back(c);
  if (wants(o, "error")) t.header.emplace_back("reference_error_final");
  if (wants(o, "cost"))
    for (const char* c : {"steps", "rejected_steps", "rhs_evaluations"}) t.header.emplace_back(c);
  if (wants(o, "wall")) t.header.emplace_back("wall_time_s");

  for (std::size_t i = 0; i < records.size(); ++i) {
    const SweepRecord& r = records[i];
    const bool ok = r.ok();
    std::vector<std::string> row;
    row.push_back(std::to_string(i));
    for (std::size_t k = 0; k < o.vary.size() + o.set.size(); ++k)
      row.push_back(k < r.values.size() ? cell(r.values[k]) : "");
    row.push_back(csv_text(r.status));
    auto num = [&](double v) { row.push_back(ok ? cell(v) : ""); };
    auto count = [&](std::uint64_t v) { row.push_back(ok ? std::to_string(v) : ""); };
    if (wants(o, "final")) {
      num(r.t_final);
      for (std::size_t k = 0; k < coords.size(); ++k) num(k < r.q.size() ? r.q[k] : kNaN);
      for (std::size_t k = 0; k < coords.size(); ++k) num(k < r.qd.size() ? r.qd[k] : kNaN);
    }
    if (wants(o, "events"))
      for (const auto& g : groups) {
        const auto it = r.events.find(g);
        count(it == r.events.end() ? 0 : it->second.count);
        num(it == r.events.end() ? kNaN : it->second.first);
        num(it == r.events.end() ? kNaN : it->second.last);
      }
    for (std::size_t k = 0; k < o.first_times.size(); ++k) num(k < r.first_times.size() ? r.first_times[k] : kNaN);
    if (wants(o, "energy")) {
      num(r.energy_drift_max);
      num(r.energy_drift_final);
      num(r.impact_energy_loss);
    }
    if (wants(o, "error")) num(r.has_reference ? r.reference_error_final : kNaN);
    if (wants(o, "cost")) {
      count(r.steps);
      count(r.rejected_steps);
      count(r.rhs_evaluations);
    }
    if (wants(o, "wall")) num(r.wall_time_s);
    t.rows.push_back(std::move(row));
  }
  return t;
}

std::string to_csv(const Table& t) {
  std::string out;
  for (std::size_t k = 0; k < t.header.size(); ++k) out += (k ? "," : "") + t.header[k];
  out += "\n";
  for (const auto& row : t.rows) {
    for (std::size_t k = 0; k < row.size(); ++k) out += (k ? "," : "") + row[k];
    out += "\n";
  }
  return out;
}

/// The columns drawn by default: t_final, the final coordinates, the impact
/// energy loss, the first time of each event group and each --first-time.
std::vector<std::string> default_plot_columns(const Table& t) {
  std::vector<std::string> cols;
  for (std::size_t k = 0; k < t.header.size(); ++k) {
    const std::string& h = t.header[k];
    // Columns that are the same in every row say nothing as a curve.
    bool varies = false;
    for (const auto& row : t.rows) varies = varies || row[k] != t.rows.front()[k];
    if (!varies) continue;
    if (h == "t_final" || h.rfind("q_", 0) == 0 || h == "impact_energy_loss" || h.rfind("first_", 0) == 0 ||
        (h.rfind("t_", 0) == 0 && h != "t_final"))
      cols.push_back(h);
  }
  if (cols.size() > 12) cols.resize(12);
  return cols;
}

void plot(const SweepOptions& o, const Table& t, const std::string& scene_name, SweepResult& result) {
  std::vector<std::size_t> axes;
  for (std::size_t k = 0; k < o.vary.size(); ++k)
    if (o.vary[k].count > 1) axes.push_back(k);
  if (o.monte_carlo > 0) {
    result.plot_note = "Monte Carlo sweeps are not plotted (the points are in sweep.csv)";
    return;
  }
  if (axes.empty() || axes.size() > 2) {
    result.plot_note = "plots are drawn for sweeps along one or two keys; this one varies " +
                       std::to_string(axes.size());
    return;
  }
  std::vector<std::string> columns = o.plot_columns.empty() ? default_plot_columns(t) : o.plot_columns;
  if (columns.empty()) {
    result.plot_note = "nothing plotted: no default column (t_final, q_*, impact_energy_loss, first_*, t_*) varies "
                       "across the points; name columns with --plot";
    return;
  }
  SweepPlotSpec spec;
  spec.title = scene_name;
  spec.out_dir = o.out_dir;
  spec.png = o.png;
  spec.svg = o.svg;
  for (std::size_t a : axes) {
    spec.axes.push_back(o.vary[a].key);
    spec.axis_counts.push_back(o.vary[a].count);
    spec.log_axes.push_back(o.vary[a].kind == VarySpec::Kind::log);
  }
  auto index_of = [&](const std::string& name) {
    const auto it = std::find(t.header.begin(), t.header.end(), name);
    if (it == t.header.end()) {
      const std::string near = nearest(name, t.header);
      throw OptionError("--plot: no column " + q(name) +
                        (near.empty() ? " in sweep.csv" : "; did you mean '" + near + "'?"));
    }
    return static_cast<std::size_t>(it - t.header.begin());
  };
  std::vector<std::size_t> x_cols;
  for (std::size_t a : axes) x_cols.push_back(1 + a);
  for (const std::string& c : columns) {
    const std::size_t ci = index_of(c);
    SweepPlotSpec::Series s;
    s.name = c;
    for (const auto& row : t.rows) {
      std::vector<double> x;
      for (std::size_t xc : x_cols) x.push_back(row[xc].empty() ? kNaN : std::strtod(row[xc].c_str(), nullptr));
      s.x.push_back(std::move(x));
      s.y.push_back(row[ci].empty() ? kNaN : std::strtod(row[ci].c_str(), nullptr));
    }
    spec.series.push_back(std::move(s));
  }
  // Axis values come from the grid (a failed run has no values in its row).
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const std::vector<double> values = point_values(o, i);
    for (auto& s : spec.series)
      for (std::size_t a = 0; a < axes.size(); ++a) s.x[i][a] = values[axes[a]];
  }
  collect_plots([&] { return make_sweep_plots(spec); }, result.files, result.plot_note);
}

}  // namespace

SweepResult sweep(const std::string& scene_path, const SweepOptions& o) {
  o.validate();
  const auto start = std::chrono::steady_clock::now();
  // The scene as it is must load: its own errors come first, with its lines.
  const Scene base = load_scene(scene_path);
  Plan plan;
  plan.file = scene_path;
  {
    std::ifstream in(scene_path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    plan.text = text.str();
  }
  for (std::size_t k = 0; k < o.vary.size(); ++k) {
    if (o.vary[k].variable()) {
      plan.vary_paths.emplace_back();
      plan.variables.push_back(o.vary[k].key);
      plan.variable_slots.push_back(k);
    } else {
      plan.vary_paths.push_back(parse_path("--vary", o.vary[k].key));
    }
  }
  for (const SetSpec& s : o.set) {
    plan.set_paths.push_back(parse_path("--set", s.key));
    plan.set_expressions.emplace_back(s.expression, plan.variables, "--set " + s.key);
  }

  // Point 0 decides what is bad input rather than a failed run: a key the
  // scene cannot take (unknown key, unknown model parameter, an element the
  // scene does not write). Values that are merely invalid fail their run.
  const std::uint64_t n = point_count(o);
  {
    toml::table doc = toml::parse(plan.text, plan.file);
    std::vector<double> values = point_values(o, 0);
    try {
      const Scene s = point_scene(plan, o, doc, values);
      for (const FirstTimeSpec& f : o.first_times)  // names checked here, against the scene's coordinates
        Expression(f.expression, trajectory_names(s), "--first-time " + f.name);
      (void)inspect(s);
    } catch (const SceneError& e) {
      const std::string m = e.message();
      if (m.find("unknown key") != std::string::npos || m.find("unknown parameter") != std::string::npos ||
          m.find("has no parameter") != std::string::npos)
        throw;
    } catch (const OptionError& e) {
      const std::string m = e.what();
      if (m.rfind("--vary", 0) == 0 || m.rfind("--set", 0) == 0 || m.rfind("--first-time", 0) == 0) {
        if (m.find("gives NaN") == std::string::npos && m.find("infinite value") == std::string::npos) throw;
      }
    } catch (const Error&) {
    }
  }

  // This rank's points: i = rank, rank + ranks, ... (cyclic, so that points
  // whose cost grows along the grid spread evenly).
  std::vector<std::uint64_t> mine;
  for (std::uint64_t i = static_cast<std::uint64_t>(o.rank); i < n; i += static_cast<std::uint64_t>(o.ranks))
    mine.push_back(i);
  int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = static_cast<int>(
      std::min<std::uint64_t>(static_cast<std::uint64_t>(threads), std::max<std::size_t>(1, mine.size())));

  const fs::path out_dir = o.out_dir;
  const fs::path csv_path = out_dir / "sweep.csv";
  if (o.rank == 0) {
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec || !fs::is_directory(out_dir))
      throw OptionError("--out: cannot create the directory '" + o.out_dir + "'" + (ec ? ": " + ec.message() : ""));
    fs::remove(csv_path, ec);  // an earlier sweep's table must not look like this one's
  }
  const fs::path work_root = out_dir / (".work-rank" + std::to_string(o.rank));

  std::vector<SweepRecord> local(mine.size());
  std::atomic<std::size_t> next{0}, done{0};
  auto worker = [&](int id) {
    const std::string work_dir = (work_root / ("thread" + std::to_string(id))).string();
    for (;;) {
      const std::size_t k = next.fetch_add(1);
      if (k >= mine.size()) return;
      local[k] = run_point(plan, o, mine[k], work_dir);
      done.fetch_add(1);
    }
  };
  {
    Progress progress(0, static_cast<double>(mine.size()), o.progress && o.rank == 0 && Progress::stderr_is_terminal());
    progress.set_format("run %.0f");
    std::vector<std::thread> pool;
    for (int id = 0; id < threads; ++id) pool.emplace_back(worker, id);
    if (o.progress && o.rank == 0) {
      while (done.load() < mine.size()) {
        progress.update(static_cast<double>(done.load()));
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
    for (auto& t : pool) t.join();
    progress.finish();
  }
  std::error_code ignore;
  fs::remove_all(work_root, ignore);
  const auto computed = std::chrono::steady_clock::now();

  SweepResult result;
  result.points = n;
  result.threads = threads;
  result.ranks = o.ranks;
  std::vector<SweepRecord> all(n);
  std::vector<bool> filled(n, false);
  if (o.ranks > 1) {
    std::string text;
    for (std::size_t k = 0; k < mine.size(); ++k) text += serialize(mine[k], local[k]);
    const std::string gathered = o.gather(text);
    result.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.rank != 0) {
      result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    }
    deserialize(gathered, all, filled);
    for (std::uint64_t i = 0; i < n; ++i)
      if (!filled[i]) throw std::runtime_error("sweep: no result for point " + std::to_string(i) + " from its rank");
  } else {
    result.run_time_s = std::chrono::duration<double>(computed - start).count();
    for (std::size_t k = 0; k < mine.size(); ++k) all[mine[k]] = std::move(local[k]);
  }
  for (const SweepRecord& r : all) result.failed += r.ok() ? 0 : 1;
  const Table table = make_table(o, all);
  lagrangian::detail::write_text_file(csv_path.string(), to_csv(table), "sweep table");
  result.files.push_back(csv_path.string());
  result.header = table.header;
  if (o.plots) plot(o, table, base.name, result);
  result.records = std::move(all);
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace lagrangian::scene
