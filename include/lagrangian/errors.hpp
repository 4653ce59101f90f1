#pragma once
/// \file errors.hpp
/// Exceptions thrown by the library. Every message names the offending field
/// and value, so a user can fix the input without reading the source.

#include <stdexcept>
#include <string>
#include <utility>

namespace lagrangian {

/// Base of every error the library throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A model parameter is out of its physical range (mass ≤ 0, NaN, …).
class ParameterError : public Error {
 public:
  using Error::Error;
};

/// A simulation option is invalid (t_end < t0, rtol ≤ 0, unknown stepper, …).
class OptionError : public Error {
 public:
  using Error::Error;
};

/// A field of SimulationOptions is out of its range: what() is
/// "simulation option 'FIELD' PROBLEM"; a scene reports the same PROBLEM
/// under its key run.FIELD.
class InvalidOption : public OptionError {
 public:
  InvalidOption(std::string field, std::string problem)
      : OptionError("simulation option '" + field + "' " + problem), field_(std::move(field)),
        problem_(std::move(problem)) {}
  const std::string& field() const { return field_; }      ///< "rtol"
  const std::string& problem() const { return problem_; }  ///< "must be < 1, got 2"

 private:
  std::string field_, problem_;
};

/// The initial state lies beyond an edge of the model's domain, where a
/// watched event that stops the run marks it (a mass above its pulley, a
/// projectile below its plane): the message names the edge and the value.
class DomainError : public OptionError {
 public:
  using OptionError::OptionError;
};

/// The dynamics cannot be evaluated at a state (singular mass matrix, …).
class DynamicsError : public Error {
 public:
  using Error::Error;
};

/// A run failed part-way (non-finite state, step-size underflow, max_steps).
class SimulationError : public Error {
 public:
  SimulationError(const std::string& what, double time) : Error(what), time_(time) {}
  /// Time (s) at which the run stopped.
  double time() const noexcept { return time_; }

 private:
  double time_;
};

/// A constraint cannot be satisfied, or the constraint set is unusable.
class ConstraintError : public Error {
 public:
  using Error::Error;
};

/// An analysis cannot be done: the model does not suit it (non-conservative
/// forces for a stationary-action problem, Pfaffian constraints for
/// equilibria), a boundary-value problem is singular, Newton's method did not
/// converge. The message says which and gives the numbers.
class AnalysisError : public Error {
 public:
  using Error::Error;
};

}  // namespace lagrangian
