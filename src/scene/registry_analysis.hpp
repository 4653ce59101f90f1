#pragma once
// Internal: the analyses (analysis.hpp) of a built-in model, reached through
// the registry like run and inspect. Only the models that suit an analysis
// instantiate it; the others refuse with the reason.

#include <cmath>
#include <string>
#include <vector>

#include <cstdio>

#include "lagrangian/analysis/analysis.hpp"
#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace lagrangian::scene::detail {

/// Halton radical inverse of i in base b, in [0, 1).
inline double halton(int i, int b) {
  double f = 1, r = 0;
  for (int k = i; k > 0; k /= b) {
    f /= b;
    r += f * (k % b);
  }
  return r;
}

/// The starts of the equilibrium search (see AnalysisRequest::starts).
inline std::vector<Eigen::VectorXd> equilibrium_starts(const Eigen::VectorXd& q0, const std::vector<std::string>& units,
                                                       int count) {
  static constexpr int primes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};
  constexpr double pi = 3.141592653589793;
  std::vector<Eigen::VectorXd> starts{q0};
  for (int s = 1; s < count; ++s) {
    Eigen::VectorXd q(q0.size());
    for (int i = 0; i < q.size(); ++i) {
      const double u = halton(s, primes[i % 16]);
      const bool angle = static_cast<std::size_t>(i) < units.size() && units[static_cast<std::size_t>(i)] == "rad";
      q[i] = angle ? -pi + 2 * pi * u : q0[i] + std::max(1.0, 2 * std::abs(q0[i])) * (2 * u - 1);
    }
    starts.push_back(q);
  }
  return starts;
}

inline std::vector<double> periods_of(const std::vector<std::string>& units) {
  std::vector<double> p;
  for (const auto& u : units) p.push_back(u == "rad" ? 6.283185307179586 : 0.0);
  return p;
}

template <class M>
std::string analyse_model(const M& model, const ModelInfo& info, const State<coordinate_count_v<M>>& initial, double t0,
                          const AnalysisRequest& request) {
  constexpr int n = coordinate_count_v<M>;
  if constexpr (pfaffian_count_v<M> > 0 || unilateral_count_v<M> > 0) {
    (void)model;
    (void)initial;
    (void)t0;
    (void)request;
    throw AnalysisError("model '" + info.name + "': equilibria and modes need a model without " +
                        (pfaffian_count_v<M> > 0 ? std::string("Pfaffian constraints")
                                                 : std::string("unilateral constraints (contacts)")) +
                        "; this one declares them");
  } else {
    if (pfaffian_count(model) > 0 || unilateral_count(model) > 0)
      throw AnalysisError("model '" + info.name + "': equilibria and modes need a model without " +
                          (pfaffian_count(model) > 0 ? std::string("Pfaffian constraints")
                                                     : std::string("unilateral constraints (contacts)")) +
                          "; this one declares them");
    if (uses_generalized_forces(model))
      throw AnalysisError("model '" + info.name +
                          "': equilibria and modes need a model without generalized forces; this one declares them");
    const std::vector<std::string> names = coordinate_names(model);
    std::string out;
    if (uses_dissipation(model))
      out += "note: the model declares a dissipation function; it does not move equilibria, and the modes below are "
             "those of the undamped system\n";
    if (!is_autonomous(model, initial, t0)) {
      char when[40];
      std::snprintf(when, sizeof when, "%.12g", t0);
      out += "note: L depends explicitly on t; equilibria and modes are those of the system frozen at t0 = " +
             std::string(when) + " s\n";
    }
    std::vector<Equilibrium> eq;
    if (request.equilibria || (request.modes && !request.modes_at_initial)) {
      EquilibriumOptions opt;
      opt.t = t0;
      opt.periods = periods_of(info.units);
      opt.starts = equilibrium_starts(initial.q, info.units, request.starts);
      eq = find_equilibria(model, opt);
      if (request.equilibria) {
        out += "\n" + format_equilibria(eq, names, info.units);
        out += "  (from " + std::to_string(request.starts) +
               " starts: minimisation finds minima, Newton's method on dU/dq = G^T lambda also saddles and maxima)\n"
               "  A search from finitely many starts can miss equilibria: this list may be incomplete (--starts N "
               "searches from more).\n";
      }
    }
    if (request.modes) {
      std::vector<Vec<double, n>> about;
      if (request.modes_at_initial) {
        about.push_back(initial.q);
      } else {
        for (const Equilibrium& e : eq)
          if (e.stable || e.kind == EquilibriumKind::degenerate) about.push_back(e.q);
        if (about.empty()) out += "\nNo stable equilibrium found: no normal modes (use --at-initial-state)\n";
      }
      for (const auto& q : about) out += "\n" + format_modes(small_oscillations(model, q, t0), names, info.units);
    }
    return out;
  }
}

/// The OptionError of a scene whose model (`model`: "model 'NAME'" or "the
/// model stated as text") the tangent flow is not derived for (Lyapunov
/// exponents, Floquet multipliers; `what` names the analysis): `why` says
/// what is derived and what this model has.
inline OptionError no_tangent_flow(const char* what, const std::string& model, const std::string& why) {
  return OptionError(std::string(what) + ": " + model + ": " + why);
}

/// The reasons of no_tangent_flow().
inline std::string too_many_coordinates(const std::string& count) {
  return "the tangent flow is derived for models with at most " + std::to_string(kMaxTangentFlowCoordinates) +
         " coordinates; this one has " + count;
}
inline const char* const kNoRestitution =
    "the tangent flow crosses impacts of contacts with restitution coefficients; this model's contacts have none";

/// `run(model)` for the models the tangent flow is derived for (contacts
/// crossed at their impacts, analysis/saltation.hpp; holonomic and
/// Pfaffian constraints kept on their manifold and through the impacts), the OptionError of no_tangent_flow() for the others (the
/// scene asks for what its model cannot give, as solve-bvp's refusals do),
/// which never instantiate it. (Text models, whose size is known at run
/// time, are seen at their size by text/tangent_flow.hpp.)
template <class Result, class M, class Run>
Result with_tangent_flow(const M& model, const ModelInfo& info, const char* what, Run&& run) {
  constexpr int n = coordinate_count_v<M>;
  constexpr int u = unilateral_count_v<M>;
  constexpr bool contacts_crossed = u == 0 || has_restitution_v<M>;
  if constexpr (n == Dynamic || n > kMaxTangentFlowCoordinates || !contacts_crossed) {
    (void)model, (void)run;
    throw no_tangent_flow(what, "model '" + info.name + "'",
                          n == Dynamic                       ? too_many_coordinates("a run-time number")
                          : n > kMaxTangentFlowCoordinates ? too_many_coordinates(std::to_string(n))
                                                           : std::string(kNoRestitution));
  } else {
    return run(model);
  }
}

template <class M>
BvpResult solve_model_bvp(const M& model, const ModelInfo& info, const BvpRequest& request, DiscreteRule rule) {
  constexpr int n = coordinate_count_v<M>;
  auto refuse = [&](const std::string& what) {
    return OptionError("solve-bvp: model '" + info.name + "' declares " + what +
                       "; boundary-value problems by stationary action are solved for unconstrained conservative "
                       "models only");
  };
  if constexpr (has_constraints_v<M> && !runtime_constraint_counts_v<M>) {
    (void)model;
    (void)request;
    (void)rule;
    throw refuse("constraints");
  } else {
    if (has_constraints(model)) throw refuse("constraints");
    if (uses_generalized_forces(model)) throw refuse("generalized forces");
    if (uses_dissipation(model)) throw refuse("a dissipation function");
    const int size = model_size(model);
    const std::string coords = std::to_string(size) + (size == 1 ? " coordinate" : " coordinates");
    auto vec = [&](const std::vector<double>& v, const char* flag) {
      if (v.size() != static_cast<std::size_t>(size))
        throw OptionError(std::string("command line: ") + flag + ": " + std::to_string(v.size()) +
                          " values given; model '" + info.name + "' has " + coords);
      Vec<double, n> out(size);
      for (int i = 0; i < size; ++i) out[i] = v[static_cast<std::size_t>(i)];
      return out;
    };
    BvpOptions opt;
    opt.steps = request.steps;
    opt.rule = rule;
    return lagrangian::solve_bvp(model, vec(request.from, "--from"), vec(request.to, "--to"), request.t0, request.t1,
                                 opt);
  }
}

}  // namespace lagrangian::scene::detail
