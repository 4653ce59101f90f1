#pragma once
// Internal: a model definition's registry entry (registry_common.hpp tells
// how a definition is written), with the model's picture for the animation
// page and the plots: its figure and where its bodies are (view.hpp), from
// Def::figure and Def::place or from the model's particles().

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "lagrangian/view/view.hpp"
#include "registry_common.hpp"

namespace lagrangian::scene::detail {

/// Point masses named `names`, nothing drawn between them; `up` against gravity.
inline view::Figure point_masses(std::vector<std::string> names, view::Point up) {
  view::Figure f;
  for (std::string& n : names) f.bodies.push_back({std::move(n), 0.0, -1});
  f.up = up;
  return f;
}

/// Point masses hanging from a pivot at the origin: the first on a rod from
/// the pivot, each next on a rod from the one before.
inline view::Figure pendulum_figure(std::vector<std::string> names, view::Point up) {
  view::Figure f = point_masses(std::move(names), up);
  for (std::size_t b = 0; b < f.bodies.size(); ++b)
    f.rods.push_back({static_cast<int>(b), static_cast<int>(b) - 1, {0, 0, 0}});
  f.pivots = {{0, 0, 0}};
  return f;
}

/// The definition places its bodies itself (Def::place), not by particles().
template <class Def>
inline constexpr bool places_v = requires(const typename Def::Model& m, const double* x, view::Point* c) {
  Def::place(m, x, 0.0, c);
};

template <class Def>
std::vector<std::array<int, 3>> particle_axes_entry(const ModelSpec& spec) {
  using M = typename Def::Model;
  std::vector<std::array<int, 3>> axes;
  if constexpr (has_particles_v<M> && !places_v<Def>) {
    const ModelInfo& info = info_of<Def>();
    const Parameters p(info, spec);
    const M model = build_model<Def>(info, p);
    for (const Particle& part : model.particles()) axes.push_back(part.axes);
  }
  return axes;
}

template <class Def>
view::Figure picture_entry(const ModelSpec& spec, const double* t, const double* q, std::size_t rows,
                           std::vector<double>& xyz) {
  using M = typename Def::Model;
  constexpr bool has_figure = requires(const M& m) { Def::figure(m); };
  constexpr bool has_place = places_v<Def>;
  const ModelInfo& info = info_of<Def>();
  const Parameters p(info, spec);
  const M model = build_model<Def>(info, p);
  view::Figure figure;
  if constexpr (has_figure) figure = Def::figure(model);
  if constexpr (has_particles_v<M>) {
    if (figure.bodies.empty()) {
      int k = 0;
      for (const Particle& part : model.particles()) {
        (void)part;
        figure.bodies.push_back({"particle " + std::to_string(++k), 0.0, -1});
      }
    }
  }
  const std::size_t nb = figure.bodies.size();
  const std::size_t n = info.coordinates.size();
  xyz.assign(rows * nb * 3, 0.0);
  if (nb == 0) return figure;
  std::vector<view::Point> centres(nb);
  for (std::size_t r = 0; r < rows; ++r) {
    const double* qr = q + r * n;
    centres.assign(nb, view::Point{0, 0, 0});
    if constexpr (has_place) {
      Def::place(model, qr, t[r], centres.data());
    } else if constexpr (has_particles_v<M>) {
      std::size_t b = 0;
      for (const Particle& part : model.particles()) {
        for (std::size_t a = 0; a < 3; ++a)
          if (part.axes[a] >= 0) centres[b][a] = qr[part.axes[a]];
        ++b;
      }
    }
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t a = 0; a < 3; ++a) xyz[(r * nb + b) * 3 + a] = centres[b][a];
  }
  return figure;
}

/// The registry entry of a model definition.
template <class Def>
ModelEntry entry() {
  return ModelEntry{std::string(name_of<Def>()), &run_entry<Def>, &inspect_entry<Def>, &analyse_entry<Def>,
                    &bvp_entry<Def>, &picture_entry<Def>, &particle_axes_entry<Def>, &eom_entry<Def>,
                    &lyapunov_entry<Def>, &floquet_entry<Def>, &sensitivity_entry<Def>};
}

}  // namespace lagrangian::scene::detail
