#pragma once
/// \file text/expression.hpp
/// Expressions of a model stated as text: T, V, Q, D written in a scene file
/// or handed to the library as strings. `parse()` reads one expression once
/// into an `Expression`, a list of nodes in evaluation order (each node after
/// the nodes it reads, equal subexpressions stored once); `evaluate()`
/// (text/evaluate.hpp) computes it on any number type the library derives
/// with, so the equations of motion of a text model come from the same
/// automatic differentiation as those of a C++ model.
///
/// The language: numbers (`2`, `0.5`, `1e-3`), the coordinates, their
/// velocities (`<coordinate>_dot`), the time `t`, the parameters, `pi`;
/// `+ - * /`, `^` (or `**`, right-associative, binding tighter than unary
/// minus: `-x^2` is −(x²)), parentheses, and the functions `sin cos tan asin
/// acos atan sinh cosh tanh exp log sqrt abs` (one argument), `atan2 pow min
/// max` (two). A parse error is an ExpressionError naming the column and,
/// for an unknown name, every name the expression may use.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/errors.hpp"

namespace lagrangian::text {

/// An expression that cannot be read: the message names the field (as given
/// to parse()), the 1-based column and what is wrong.
class ExpressionError : public Error {
 public:
  ExpressionError(std::string field, int column, const std::string& what);
  /// The field named by the caller of parse(), e.g. "model.kinetic".
  const std::string& field() const noexcept { return field_; }
  /// 1-based column of the offending character in the expression (0: the
  /// expression as a whole).
  int column() const noexcept { return column_; }
  /// What is wrong, without the field and the column.
  const std::string& message() const noexcept { return message_; }

 private:
  std::string field_;
  int column_;
  std::string message_;
};

/// What a node computes. a and b are the indices of its operands.
enum class Op : std::uint8_t {
  constant,    ///< value
  coordinate,  ///< q[index]
  velocity,    ///< q̇[index]
  time,        ///< t
  parameter,   ///< parameters[index]
  add,
  sub,
  mul,
  div,
  neg,
  pow_const,  ///< a^value, value a constant (integers exact at a = 0)
  pow,        ///< a^b, both varying
  sin,
  cos,
  tan,
  asin,
  acos,
  atan,
  sinh,
  cosh,
  tanh,
  exp,
  log,
  sqrt,
  abs,
  atan2,  ///< atan2(a, b): the angle of the point (b, a)
  min,
  max,
};

/// One node of an expression.
struct Node {
  Op op = Op::constant;
  int a = -1;          ///< first operand (node index), −1 if none
  int b = -1;          ///< second operand, −1 if none
  int index = -1;      ///< coordinate, velocity or parameter index
  double value = 0.0;  ///< constant, or the exponent of pow_const
  friend bool operator==(const Node&, const Node&) = default;
};

/// The names an expression may use.
struct Symbols {
  std::vector<std::string> coordinates;  ///< q_i; their velocities are `<name>_dot`
  std::vector<std::string> parameters;   ///< named constants
};

/// A parsed expression: nodes in evaluation order, the result the last one.
/// Subexpressions that are equal node for node are stored once.
struct Expression {
  std::vector<Node> nodes;
  /// The index of the result (the last node).
  int root() const { return static_cast<int>(nodes.size()) - 1; }
  /// True when the expression reads q̇ (false for V, true for a T that is not constant).
  bool reads_velocities() const;
  /// True when the expression reads t.
  bool reads_time() const;
};

/// Parses `source`; throws ExpressionError (with `field` in its message) on
/// a syntax error, an unknown name or function, or a wrong argument count.
Expression parse(std::string_view source, const Symbols& symbols, const std::string& field);

/// The expression with each parameter replaced by its value and every
/// subexpression of constants folded into one constant (what is evaluated);
/// parameter number `keep`, when given, stays a parameter (its sensitivity).
Expression bind_parameters(const Expression& e, const std::vector<double>& parameter_values, int keep = -1);

/// ∂e/∂v, v the coordinate (`variable` = Op::coordinate) or velocity
/// (Op::velocity) of index `index`, as an expression over the same names,
/// folded as parse() folds (for display: `inspect` prints p = ∂T/∂q̇ with
/// it; the equations of motion come from automatic differentiation).
/// Throws ExpressionError for min or max of v, which have no formula.
Expression derivative(const Expression& e, Op variable, int index);

/// `e` as text, which parse() reads back to an expression of the same value
/// (products regrouped), with the names of `symbols` and numbers to 12
/// significant digits.
std::string to_text(const Expression& e, const Symbols& symbols);

/// Where `e` is undefined at (q, q̇, t) with the parameter values
/// `parameters` (in the order of symbols.parameters): "" when no operation
/// makes a non-finite value of finite operands, else one sentence naming the
/// first that does and its operand, in the names `e` was written with, e.g.
/// "log of a number <= 0: log(x - a) with x - a = -1".
std::string undefined_at(const Expression& e, const Symbols& symbols, const double* q, const double* qd, double t,
                         const double* parameters);

/// True when `name` can name a coordinate or a parameter: a letter or `_`
/// first, then letters, digits and `_`; not a function name, `t` or `pi`.
bool valid_name(std::string_view name);

}  // namespace lagrangian::text
