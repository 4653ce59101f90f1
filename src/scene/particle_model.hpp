#pragma once
// Internal to the particle scenes' engine: a scene of bodies in Cartesian
// coordinates as equations of motion with constraint rows and contacts.
//
// State x = [r; v] with r the 3N Cartesian positions (m) and v = ṙ (m/s).
// Equations of motion with Lagrange multipliers for the active constraint
// rows (links, surfaces, resting contacts), M = diag(m) ⊗ I₃:
//   M a = F(r, v, t) + Cᵀ λ,   C a = −γ − b,
// solved through the Schur complement S = C M⁻¹ Cᵀ (complete orthogonal
// decomposition, so redundant constraints are allowed). F is the sum of the
// declared force kernels only: the kernel list is built once from the scene.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/scene/scene.hpp"
#include "particle_forces.hpp"
#include "particle_rows.hpp"

namespace lagrangian::scene::detail::particles {

// -- the system ----------------------------------------------------------------

class ParticleModel {
 public:
  ParticleModel(const ParticleModel&) = delete;  // contacts are held by address
  ParticleModel& operator=(const ParticleModel&) = delete;
  explicit ParticleModel(const Scene& scene) {
    n_ = static_cast<int>(scene.bodies.size());
    dim_ = 3 * n_;
    std::unordered_map<std::string, int> index;
    for (int i = 0; i < n_; ++i) {
      const Body& b = scene.bodies[static_cast<std::size_t>(i)];
      index[b.name] = i;
      names_.push_back(b.name);
      mass_.push_back(b.mass);
      radius_.push_back(b.radius);
    }
    inv_mass3_.resize(dim_);
    for (int i = 0; i < n_; ++i) inv_mass3_.segment<3>(3 * i).setConstant(1.0 / mass_[static_cast<std::size_t>(i)]);
    add_kernels(scene, index);
    add_rows(scene, index);
    fixed_rows_ = static_cast<int>(rows_.size());
    add_contacts(scene, index);
    has_contacts_ = has_pairs_ || !wall_contacts_.empty();
    for (Contact& c : wall_contacts_) number(c);
    constrained_ = fixed_rows_ > 0 || has_contacts_;  // contacts may come to rest
    resize_rows();
    select_rhs();
  }

  int bodies() const { return n_; }
  int dim() const { return dim_; }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<double>& mass() const { return mass_; }
  /// 1/m of each of the 3N coordinates (1/kg).
  const Eigen::VectorXd& inverse_masses() const { return inv_mass3_; }
  bool has_contacts() const { return has_contacts_; }
  /// True when a declared force depends on the velocities (a drag).
  bool velocity_dependent() const { return linear_drag_ != nullptr || quadratic_drag_ != nullptr; }
  /// The contacts of bodies with fixed planes and the box's walls.
  const std::vector<Contact>& wall_contacts() const { return wall_contacts_; }
  bool dissipative() const {
    return std::any_of(kernels_.begin(), kernels_.end(), [](const auto& k) { return k->dissipative(); });
  }
  /// The bodies that meet each other as spheres ([sphere_contacts]).
  const std::vector<int>& pair_members() const { return pair_members_; }
  const std::vector<Row>& rows() const { return rows_; }
  int fixed_rows() const { return fixed_rows_; }
  std::uint64_t rhs_evaluations = 0;
  double omega = 0;  // Baumgarte rate (1/s); 0: none
  std::uint64_t constraint_solves = 0, contact_sweeps = 0;

  /// ẋ = [v; a], through the right-hand side composed for this scene.
  void rhs(const double* x, double* dx, double t) { rhs_fn_(*this, x, dx, t); }
  /// rhs() for a look at the state (the multipliers at a sample), not
  /// counted among the run's evaluations or its effects'.
  void rhs_uncounted(const double* x, double* dx, double t) {
    const auto evaluations = rhs_evaluations, solves = constraint_solves, sweeps = contact_sweeps;
    kernel_counts_.clear();
    for (const auto& k : kernels_) kernel_counts_.push_back(k->evaluations);
    rhs(x, dx, t);
    rhs_evaluations = evaluations;
    constraint_solves = solves;
    contact_sweeps = sweeps;
    for (std::size_t i = 0; i < kernels_.size(); ++i) kernels_[i]->evaluations = kernel_counts_[i];
  }

  /// The right-hand side for one set of declared kinds (bits: uniform
  /// gravity, Newtonian gravity, springs, linear drag, quadratic drag) and
  /// with or without constraint rows. Undeclared kinds are not in the code.
  /// (force_accelerations() lists the kernels too: a new kind goes into
  /// both.)
  template <unsigned Kinds, bool Constrained>
  static void rhs_for(ParticleModel& s, const double* x, double* dx, double) {
    ++s.rhs_evaluations;
    const int dim = s.dim_;
    const double* r = x;
    const double* v = x + dim;
    double* a = dx + dim;
    if constexpr ((Kinds & 1u) != 0) {
      s.gravity_->start(v, dx, a, dim);  // ṙ = v and a = g in one pass
    } else {
      for (int i = 0; i < dim; ++i) {
        dx[i] = v[i];
        a[i] = 0.0;
      }
    }
    if constexpr ((Kinds & 2u) != 0) s.newton_->add(r, v, a);
    if constexpr ((Kinds & 4u) != 0) s.springs_->add(r, v, a);
    if constexpr ((Kinds & 8u) != 0) s.linear_drag_->add(r, v, a);
    if constexpr ((Kinds & 16u) != 0) s.quadratic_drag_->add(r, v, a);
    if constexpr (Constrained) s.constrain(r, v, a);
  }

  /// a = F(r, v)/m (m/s², 3N values) of the declared force kernels alone,
  /// on numbers of any type S: doubles, or AD numbers for the tangent flow
  /// (particle_tangent.cpp), whose pass may seed one of the scene's
  /// parameters `p`. (The kernels a run calls are listed in rhs_for() too:
  /// a new kind goes into both.)
  template <class S>
  void force_accelerations(const S* r, const S* v, S* a, const Parameter& p = {}) {
    for (int i = 0; i < dim_; ++i) a[i] = S(0.0);
    if (gravity_) gravity_->add(r, v, a, p);
    if (newton_) newton_->add(r, v, a, p);
    if (springs_) springs_->add(r, v, a, p);
    if (linear_drag_) linear_drag_->add(r, v, a, p);
    if (quadratic_drag_) quadratic_drag_->add(r, v, a, p);
  }

  using RhsFn = void (*)(ParticleModel&, const double*, double*, double);
  template <unsigned... K>
  static constexpr std::array<RhsFn, 64> rhs_table(std::integer_sequence<unsigned, K...>) {
    return {rhs_for<(K >> 1), (K & 1u) != 0>...};
  }
  /// Chooses the right-hand side once, from what the scene declares
  /// (defined in particle_system.cpp, which compiles the 64 right-hand
  /// sides once for every file that builds a ParticleModel).
  void select_rhs();


  double kinetic(const double* x) const {
    double T = 0;
    for (int i = 0; i < n_; ++i) T += 0.5 * mass_[static_cast<std::size_t>(i)] * at(x + dim_, i).squaredNorm();
    return T;
  }
  double potential(const double* x) const {
    double V = 0;
    for (const auto& k : kernels_) V += k->potential(x);
    return V;
  }

  std::map<std::string, std::uint64_t> counts() const {
    std::map<std::string, std::uint64_t> out;
    for (const auto& k : kernels_) out[k->kind] = k->evaluations;
    if (has_links_) out["links"] = constraint_solves;
    if (has_surfaces_) out["surfaces"] = constraint_solves;
    if (has_pairs_) out["sphere_contacts"] = contact_sweeps;
    if (has_planes_) out["plane_contacts"] = contact_sweeps;
    if (has_box_) out["box_contacts"] = contact_sweeps;
    return out;
  }

  // -- constraints ----------------------------------------------------------

  void resize_rows() {
    const int m = static_cast<int>(rows_.size());
    C_.setZero(m, dim_);
    MinvCt_.setZero(dim_, m);
    S_.setZero(m, m);
    rhs_m_.setZero(m);
    lambda_.setZero(m);
  }

  void assemble(const double* r) {
    jacobian(rows_, r, dim_, C_);
    MinvCt_ = inv_mass3_.asDiagonal() * C_.transpose();
    S_.noalias() = C_ * MinvCt_;
    cod_.compute(S_);
  }

  /// a ← a + M⁻¹Cᵀλ with S λ = −(C a + γ + b), a the unconstrained accelerations.
  void constrain(const double* r, const double* v, double* a) {
    if (rows_.empty()) return;  // contacts only, none resting now
    ++constraint_solves;
    assemble(r);
    Eigen::Map<const Eigen::VectorXd> vv(v, dim_);
    for (int k = 0; k < static_cast<int>(rows_.size()); ++k) {
      const Row& row = rows_[static_cast<std::size_t>(k)];
      double b = row.gamma(r, v);
      if (omega > 0) b += 2 * omega * C_.row(k).dot(vv) + omega * omega * row.value(r);
      rhs_m_[k] = -b;
    }
    Eigen::Map<Eigen::VectorXd> acc(a, dim_);
    rhs_m_.noalias() -= C_ * acc;
    lambda_ = cod_.solve(rhs_m_);
    acc.noalias() += MinvCt_ * lambda_;
  }

  double position_residual(const double* r) const {
    double g = 0;
    for (const Row& row : rows_) g = std::max(g, std::abs(row.value(r)));
    return g;
  }
  double velocity_residual(const double* x) {
    if (rows_.empty()) return 0;
    jacobian(rows_, x, dim_, C_);  // C only: no factorisation for a residual
    Eigen::Map<const Eigen::VectorXd> vv(x + dim_, dim_);
    return (C_ * vv).lpNorm<Eigen::Infinity>();
  }

  /// Projects r onto g = 0 (M-weighted Gauss–Newton) and v onto C v = 0.
  /// Returns the iterations, or −1 when nothing needed doing.
  int project(double* x, double tolerance) {
    if (rows_.empty()) return -1;
    Eigen::Map<Eigen::VectorXd> r(x, dim_), v(x + dim_, dim_);
    const double scale = 1.0 + r.lpNorm<Eigen::Infinity>();
    int it = 0;
    bool moved = false;
    for (; it < 20; ++it) {
      for (int k = 0; k < static_cast<int>(rows_.size()); ++k) rhs_m_[k] = rows_[static_cast<std::size_t>(k)].value(x);
      if (rhs_m_.lpNorm<Eigen::Infinity>() <= tolerance * scale) break;
      assemble(x);
      r -= MinvCt_ * cod_.solve(rhs_m_);
      moved = true;
    }
    assemble(x);
    rhs_m_.noalias() = C_ * v;
    if (rhs_m_.lpNorm<Eigen::Infinity>() > tolerance * (1.0 + v.lpNorm<Eigen::Infinity>())) {
      v -= MinvCt_ * cod_.solve(rhs_m_);
      moved = true;
    }
    return moved ? it : -1;
  }

  // -- contacts -------------------------------------------------------------

  /// Contacts that may close in a step of length h from positions r0 to r1
  /// with accelerations a0, a1 at its ends: every open wall contact, and
  /// sphere pairs whose x-extents over the step overlap (sweep and prune on
  /// x; a path deviates from its chord by at most h²/8 max|a|).
  void candidates(const double* r0, const double* r1, const double* a0, const double* a1, double h,
                  std::vector<Contact*>& out) {
    ++contact_sweeps;
    out.clear();
    for (auto& c : wall_contacts_)
      if (!c.resting) out.push_back(&c);
    if (!has_pairs_) return;
    spans_.clear();
    for (int i : pair_members_) {
      const int c = 3 * i;
      const double bulge = 0.125 * h * h * std::max(std::abs(a0[c]), std::abs(a1[c])) + 1e-12;
      const double R = radius_[static_cast<std::size_t>(i)];
      spans_.push_back({std::min(r0[c], r1[c]) - R - bulge, std::max(r0[c], r1[c]) + R + bulge, i});
    }
    std::sort(spans_.begin(), spans_.end(), [](const Span& a, const Span& b) { return a.lo < b.lo; });
    for (std::size_t p = 0; p < spans_.size(); ++p)
      for (std::size_t q = p + 1; q < spans_.size() && spans_[q].lo <= spans_[p].hi; ++q) {
        Contact& c = pair_contact(spans_[p].body, spans_[q].body);
        if (!c.resting) out.push_back(&c);
      }
  }

  Contact& pair_contact(int i, int j) {
    if (i > j) std::swap(i, j);
    const std::uint64_t key = static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(n_) + static_cast<std::uint64_t>(j);
    auto it = pairs_.find(key);
    if (it != pairs_.end()) return it->second;
    Contact c;
    c.pair = true;
    c.a = i;
    c.b = j;
    c.R = radius_[static_cast<std::size_t>(i)] + radius_[static_cast<std::size_t>(j)];
    c.e = pair_e_;
    c.name = names_[static_cast<std::size_t>(i)] + "-" + names_[static_cast<std::size_t>(j)];
    return number(pairs_.emplace(key, c).first->second);
  }

  /// The contact numbered `id` (Contact::id): walls and planes first, then
  /// pairs of bodies in the order they were first met.
  Contact& contact(int id) { return *by_id_[static_cast<std::size_t>(id)]; }
  const Contact& contact(int id) const { return *by_id_[static_cast<std::size_t>(id)]; }

  /// All contacts within `tol` of closing at state x (for simultaneous impacts).
  void near_contacts(const double* x, double tol, std::vector<Contact*>& out) {
    out.clear();
    for (auto& c : wall_contacts_)
      if (!c.resting && c.gap(x) <= tol) out.push_back(&c);
    if (!has_pairs_) return;
    for (std::size_t p = 0; p < pair_members_.size(); ++p)
      for (std::size_t q = p + 1; q < pair_members_.size(); ++q) {
        const int i = pair_members_[p], j = pair_members_[q];
        const double dist = (at(x, i) - at(x, j)).norm();
        if (dist - radius_[static_cast<std::size_t>(i)] - radius_[static_cast<std::size_t>(j)] <= tol) {
          Contact& c = pair_contact(i, j);
          if (!c.resting) out.push_back(&c);
        }
      }
  }

  /// d²φ/dt² of a contact at x under the current forces and constraints.
  /// True when the forces press the contact shut: d²φ/dt² < 0 beyond
  /// round-off (1e-9 of the largest acceleration, at least 1e-12 m/s²).
  bool pressed(const double* x, const Contact& c) {
    pressed_dx_.resize(static_cast<std::size_t>(2 * dim_));
    rhs(x, pressed_dx_.data(), 0.0);
    const double* v = x + dim_;
    const double* a = pressed_dx_.data() + dim_;
    double scale = 0;
    for (int k = 0; k < dim_; ++k) scale = std::max(scale, std::abs(a[k]));
    const double tol = 1e-9 * scale + 1e-12;
    if (!c.pair) return c.n.dot(at(a, c.a)) < -tol;
    const Vector3d d = at(x, c.a) - at(x, c.b);
    const Vector3d dv = at(v, c.a) - at(v, c.b);
    const Vector3d da = at(a, c.a) - at(a, c.b);
    const double l = d.norm();
    const double radial = d.dot(dv) / l;
    return d.dot(da) / l + (dv.squaredNorm() - radial * radial) / l < -tol;
  }

  /// Resting contacts that an impulse has set approaching: they leave the
  /// constraint rows and become contacts to resolve.
  void wake_approaching(const double* x, double touch, std::vector<Contact*>& near) {
    bool changed = false;
    for (int k = static_cast<int>(rows_.size()) - 1; k >= fixed_rows_; --k) {
      const std::size_t idx = static_cast<std::size_t>(k - fixed_rows_);
      Contact* c = rest_contacts_[idx];
      if (c->rate(x, x + dim_) < -touch) {
        c->resting = false;
        rest_contacts_.erase(rest_contacts_.begin() + static_cast<std::ptrdiff_t>(idx));
        rows_.erase(rows_.begin() + k);
        if (std::find(near.begin(), near.end(), c) == near.end()) near.push_back(c);
        changed = true;
      }
    }
    if (changed) resize_rows();
  }

  void make_resting(Contact& c) {
    c.resting = true;
    Row row;
    row.kind = c.pair ? Row::Kind::rest_spheres : Row::Kind::rest_plane;
    row.a = c.a;
    row.b = c.pair ? c.b : -1;
    row.p = c.p;
    row.n = c.n;
    row.length = c.R;
    row.name = c.name;
    rest_contacts_.push_back(&c);
    rows_.push_back(row);
    resize_rows();
  }

  /// The resting contacts, in the order of their rows (after the fixed ones).
  const std::vector<Contact*>& resting_contacts() const { return rest_contacts_; }
  /// λ of every current row (fixed rows first) and the rows' Jacobian C,
  /// from the last right-hand side evaluation.
  const Eigen::VectorXd& multipliers() const { return lambda_; }
  const Eigen::MatrixXd& constraint_jacobian() const { return C_; }
  /// λ of the k-th resting contact (N) from the last right-hand side: > 0
  /// pushes the bodies apart, < 0 would pull them together.
  double resting_multiplier(std::size_t k) const { return lambda_[fixed_rows_ + static_cast<Eigen::Index>(k)]; }

  /// The k-th resting contact leaves the constraint rows (it lifts off).
  void release(std::size_t k) {
    rest_contacts_[k]->resting = false;
    rest_contacts_.erase(rest_contacts_.begin() + static_cast<std::ptrdiff_t>(k));
    rows_.erase(rows_.begin() + fixed_rows_ + static_cast<std::ptrdiff_t>(k));
    resize_rows();
  }

 private:
  /// The body named `name` (-1 for none: a fixed end).
  static int body_of(const std::unordered_map<std::string, int>& index, const std::string& name) {
    return name.empty() ? -1 : index.at(name);
  }
  /// The bodies a list names, or all of them when it is empty.
  std::vector<int> members_of(const std::unordered_map<std::string, int>& index,
                              const std::vector<std::string>& list) const {
    std::vector<int> out;
    if (list.empty()) {
      out.resize(static_cast<std::size_t>(n_));
      std::iota(out.begin(), out.end(), 0);
    } else {
      for (const auto& s : list) out.push_back(index.at(s));
    }
    return out;
  }
  /// Only the declared effects become kernels.
  void add_kernels(const Scene& scene, const std::unordered_map<std::string, int>& index) {
    auto body = [&](const std::string& name) { return body_of(index, name); };
    auto members = [&](const std::vector<std::string>& list) { return members_of(index, list); };
    auto inv = [&](int i) { return i < 0 ? 0.0 : 1.0 / mass_[static_cast<std::size_t>(i)]; };
    if (scene.gravity) {
      kernels_.push_back(std::make_unique<GravityKernel>(mass_, scene.gravity->g));
      gravity_ = static_cast<GravityKernel*>(kernels_.back().get());
  }
  if (scene.newtonian_gravity) {
    kernels_.push_back(std::make_unique<NewtonKernel>(mass_, scene.newtonian_gravity->G));
    newton_ = static_cast<NewtonKernel*>(kernels_.back().get());
  }
  if (!scene.springs.empty()) {
    std::vector<SpringData> s;
    for (const auto& sp : scene.springs) {
      const int a = body(sp.a), b = body(sp.b);
      s.push_back({a, b, sp.anchor, sp.stiffness, sp.rest_length, inv(a), inv(b)});
    }
    kernels_.push_back(std::make_unique<SpringKernel>(std::move(s)));
    springs_ = static_cast<SpringKernel*>(kernels_.back().get());
  }
  const auto drag_entries = [&](const auto& tables) {
    DragEntries entries;
    for (std::size_t t = 0; t < tables.size(); ++t)
      for (int i : members(tables[t].bodies))
        entries.push(i, static_cast<int>(t), tables[t].coefficient, mass_[static_cast<std::size_t>(i)]);
    return entries;
  };
  if (!scene.linear_drag.empty()) {
    kernels_.push_back(std::make_unique<LinearDragKernel>(drag_entries(scene.linear_drag)));
    linear_drag_ = static_cast<LinearDragKernel*>(kernels_.back().get());
  }
  if (!scene.quadratic_drag.empty()) {
    kernels_.push_back(std::make_unique<QuadraticDragKernel>(drag_entries(scene.quadratic_drag)));
    quadratic_drag_ = static_cast<QuadraticDragKernel*>(kernels_.back().get());
  }
  }
  /// The constraint rows of the links and surfaces.
  void add_rows(const Scene& scene, const std::unordered_map<std::string, int>& index) {
    auto body = [&](const std::string& name) { return body_of(index, name); };
    for (std::size_t k = 0; k < scene.links.size(); ++k) {
      const Link& l = scene.links[k];
      Row row;
      row.kind = Row::Kind::link;
      row.a = body(l.a);
      row.b = body(l.b);
      row.p = l.anchor;
      const Vector3d d0 = scene.bodies[static_cast<std::size_t>(row.a)].position -
                          (row.b >= 0 ? scene.bodies[static_cast<std::size_t>(row.b)].position : l.anchor);
      row.length = std::isnan(l.length) ? d0.norm() : l.length;
      row.source = static_cast<int>(k);
      row.name = l.name.empty() ? "link" + std::to_string(k) : l.name;
      rows_.push_back(row);
      has_links_ = true;
  }
  for (std::size_t k = 0; k < scene.surfaces.size(); ++k) {
    const Surface& s = scene.surfaces[k];
    Row row;
    row.kind = s.kind == Surface::Kind::plane ? Row::Kind::plane : Row::Kind::sphere;
    row.a = body(s.body);
    row.p = s.point;
    row.n = s.normal.normalized();
    row.length = s.radius;
    row.source = static_cast<int>(k);
    row.name = s.name.empty() ? "surface" + std::to_string(k) : s.name;
    rows_.push_back(row);
    has_surfaces_ = true;
  }
  }
  /// The contacts: sphere pairs, planes and the box's walls.
  void add_contacts(const Scene& scene, const std::unordered_map<std::string, int>& index) {
    auto members = [&](const std::vector<std::string>& list) { return members_of(index, list); };
    if (scene.sphere_contacts) {
      pair_members_ = members(scene.sphere_contacts->bodies);
      pair_e_ = scene.sphere_contacts->restitution;
      has_pairs_ = true;
  }
  for (std::size_t k = 0; k < scene.planes.size(); ++k) {
    const PlaneContact& pc = scene.planes[k];
    const std::string pname = pc.name.empty() ? "plane" + std::to_string(k) : pc.name;
    for (int i : members(pc.bodies)) {
      Contact c;
      c.a = i;
      c.p = pc.point;
      c.n = pc.normal.normalized();
      c.R = radius_[static_cast<std::size_t>(i)];
      c.e = pc.restitution;
      c.plane = static_cast<int>(k);
      c.name = names_[static_cast<std::size_t>(i)] + "-" + pname;
      wall_contacts_.push_back(c);
    }
    has_planes_ = true;
  }
  if (scene.box) {
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < n_; ++i)
      for (int k = 0; k < 3; ++k)
        for (int side = 0; side < 2; ++side) {
          Contact c;
          c.a = i;
          c.n = Vector3d::Zero();
          c.n[k] = side == 0 ? 1.0 : -1.0;
          c.p = side == 0 ? scene.box->min : scene.box->max;
          c.R = radius_[static_cast<std::size_t>(i)];
          c.e = scene.box->restitution;
          c.name = names_[static_cast<std::size_t>(i)] + "-wall:" + axis[k] + (side == 0 ? "_min" : "_max");
          wall_contacts_.push_back(c);
        }
    has_box_ = true;
  }
  }

  struct Span {
    double lo, hi;
    int body;
  };
  int n_ = 0, dim_ = 0;
  std::vector<std::string> names_;
  std::vector<double> mass_, radius_;
  Eigen::VectorXd inv_mass3_;
  std::vector<std::unique_ptr<Kernel>> kernels_;
  std::vector<Row> rows_;
  int fixed_rows_ = 0;
  bool constrained_ = false, has_links_ = false, has_surfaces_ = false;
  bool has_pairs_ = false, has_planes_ = false, has_box_ = false, has_contacts_ = false;
  std::vector<int> pair_members_;
  double pair_e_ = 1;
  std::vector<Contact> wall_contacts_;
  std::unordered_map<std::uint64_t, Contact> pairs_;
  std::vector<Contact*> by_id_;  // every contact made so far, by Contact::id
  Contact& number(Contact& c) {
    c.id = static_cast<int>(by_id_.size());
    by_id_.push_back(&c);
    return c;
  }
  std::vector<Contact*> rest_contacts_;
  std::vector<Span> spans_;
  Eigen::VectorXd rhs_m_, lambda_;
  std::vector<std::uint64_t> kernel_counts_;  ///< rhs_uncounted()'s saved counts
  std::vector<double> pressed_dx_;  ///< ẋ for pressed()
  GravityKernel* gravity_ = nullptr;
  NewtonKernel* newton_ = nullptr;
  SpringKernel* springs_ = nullptr;
  LinearDragKernel* linear_drag_ = nullptr;
  QuadraticDragKernel* quadratic_drag_ = nullptr;
  RhsFn rhs_fn_ = nullptr;
  Eigen::MatrixXd C_, MinvCt_, S_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
};

}  // namespace lagrangian::scene::detail::particles
