// Event-driven engine for smooth hard spheres (see hard_spheres.hpp for the
// equations): per-sphere local times, a binary heap of predicted events with
// per-sphere impact counters for invalidation, and a cell grid broad phase.
// The whole engine stays in this one file so that its hot paths inline.
#include "lagrangian/scene/hard_spheres.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "lagrangian/integrate/detail/energy_monitor.hpp"
#include "lagrangian/integrate/detail/momentum_symmetry.hpp"
#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"
#include "lagrangian/errors.hpp"
#include "hard_spheres_common.hpp"

namespace lagrangian {

namespace {

using detail::hard_spheres::Event;
using detail::hard_spheres::Grid;
using detail::hard_spheres::kAxis;
using detail::hard_spheres::kCross;
using detail::hard_spheres::Kind;
using detail::hard_spheres::kPair;
using detail::hard_spheres::kWall;
using detail::hard_spheres::largest_radius;
using detail::hard_spheres::make_grid;
using detail::hard_spheres::num;
using detail::hard_spheres::sphere_name;
using detail::hard_spheres::wall_name;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr const auto& kBoxWall = box_wall_names;

// ---------------------------------------------------------------------------
// The engine.

constexpr std::uint64_t kPurgeEvery = std::uint64_t{1} << 30;

// Heap order: the earliest event on top; ties broken by kind, then spheres,
// so that the sequence does not depend on the order of insertion.
struct Later {
  bool operator()(const Event& x, const Event& y) const {
    if (x.t != y.t) return x.t > y.t;
    if ((x.code >> 30) != (y.code >> 30)) return (x.code >> 30) > (y.code >> 30);
    if (x.a != y.a) return x.a > y.a;
    return x.code > y.code;
  }
};

struct Body {
  Eigen::Vector3d r0;   // position at tref (m)
  Eigen::Vector3d v;    // velocity (m/s)
  double tref;          // reference time of r0 (s)
  double radius, mass;
  double last_impact;   // time of the latest impact (s), for the TC model
  std::uint32_t count;  // impacts so far (mod 2³²)
  std::array<int, 3> cell;
  std::int32_t next, prev;  // doubly linked list of the spheres in a cell

  Eigen::Vector3d at(double t) const { return r0 + v * (t - tref); }
};

struct Plane {
  Eigen::Vector3d n, p;
  double e;
};

class Engine {
 public:
  Engine(const HardSphereSystem& sys, const HardSphereOptions& opt, const HardSphereImpactObserver* on_impact)
      : sys_(sys),
        opt_(opt),
        on_impact_(on_impact),
        t_end_(opt.t_end),
        now_(opt.t0),
        use_grid_(opt.broad_phase == BroadPhase::cell_grid) {
    const std::size_t n = sys.spheres.size();
    names_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) names_.push_back(sphere_name(sys, i));
    for (std::size_t k = 0; k < sys.walls.size(); ++k) {
      const auto& w = sys.walls[k];
      planes_.push_back({w.normal.normalized(), w.point, w.restitution});
      wall_names_.push_back(wall_name(sys, k));
    }
    wall_impulse_.assign((6 + sys.walls.size()) * RunReport::kWallImpulseBlocks, 0.0);
    lo_ = sys.box_min;
    hi_ = sys.box_max;
    grid_ = make_grid(lo_, hi_, 2 * largest_radius(sys), n, !use_grid_);
    head_.assign(grid_.cells(), -1);
    bodies_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& s = sys.spheres[i];
      Body& b = bodies_[i];
      b.r0 = s.position;
      b.v = s.velocity;
      b.tref = opt.t0;
      b.radius = s.radius;
      b.mass = s.mass;
      b.last_impact = -kInf;
      b.count = 0;
      b.cell = grid_.locate(s.position);
      link(static_cast<std::uint32_t>(i));
    }
    purge_base_ = 8 * n + 1024;  // entries; ~2.5 of them per sphere are live at 10 % packing
    purge_at_ = purge_base_;
    heap_.reserve(purge_base_ + 1);
  }

  /// Which components of P and L the system conserves
  /// (integrate/detail/momentum_symmetry.hpp): the spheres fly free between impacts and
  /// impacts between spheres conserve both, so only the walls' impulses
  /// count, judged where a sphere may meet them: at points spread through
  /// the box.
  void judge_momentum_symmetry(RunReport& rep) const {
    const Eigen::Vector3d& r0 = opt_.angular_momentum_point;
    lagrangian::detail::MomentumSymmetry sym({r0[0], r0[1], r0[2]});
    using Source = lagrangian::detail::MomentumSymmetry::Source;
    std::uint64_t seed = 0x2545F4914F6CDD1DULL;
    auto uniform = [&seed] {  // in [0, 1), the same sequence every run
      seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
      return static_cast<double>(seed >> 11) * 0x1.0p-53;
    };
    for (int probe = 0; probe < 5; ++probe) {
      Eigen::Vector3d r;
      for (int k = 0; k < 3; ++k) r[k] = sys_.box_min[k] + uniform() * (sys_.box_max[k] - sys_.box_min[k]);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d n = Eigen::Vector3d::Unit(k);
        sym.add(1.0, r.data(), n.data());  // both faces normal to axis k push along it
        sym.end_probe(Source::contact);
      }
      for (const HardWall& w : sys_.walls) {
        const Eigen::Vector3d n = w.normal.normalized();
        sym.add(1.0, r.data(), n.data());
        sym.end_probe(Source::contact);
      }
    }
    sym.write(rep);
  }

  RunReport run(const HardSphereSampler& sampler, std::chrono::steady_clock::time_point start) {
    RunReport rep;
    rep.model = "hard spheres (event-driven)";
    rep.method = "event_driven";
    rep.adaptive = false;
    rep.t0 = opt_.t0;
    rep.t_end = opt_.t_end;
    rep.coordinates.reserve(3 * names_.size());
    for (const auto& nm : names_)
      for (const char* ax : kAxis) rep.coordinates.push_back(nm + "." + ax);
    bool elastic = sys_.pair_restitution == 1.0 && sys_.box_restitution == 1.0;
    for (const auto& w : sys_.walls) elastic = elastic && w.restitution == 1.0;
    rep.conservative = elastic;
    rep.has_particles = true;
    judge_momentum_symmetry(rep);
    if (sampler) {
      snapshot_ = sys_.spheres;
      for (std::size_t i = 0; i < snapshot_.size(); ++i) snapshot_[i].name = names_[i];
    }

    for (std::uint32_t i = 0; i < bodies_.size(); ++i) {
      predict_walls(i, -1);
      predict_crossing(i);
      for_neighbours(i, [&](std::uint32_t j) {
        if (j > i) predict_pair(i, j);
      });
    }

    std::uint64_t processed = 0;
    std::uint64_t k = 0;
    double ts = opt_.t0;
    for (;;) {
      while (!heap_.empty() && stale(heap_.front())) pop();
      const double te = heap_.empty() ? kInf : heap_.front().t;
      if (ts <= te) {
        sample(ts, sampler, rep);
        if (ts >= t_end_) break;
        ++k;
        ts = sample_time(k);
        continue;
      }
      if (processed >= opt_.max_events)
        throw SimulationError("hard spheres: more than max_events = " + std::to_string(opt_.max_events) +
                                  " events (collisions and cell crossings) at t = " + num(te) + " s, before t_end = " +
                                  num(t_end_) + " s (" + std::to_string(rep.impacts) +
                                  " impacts so far); raise HardSphereOptions::max_events, or look for an inelastic "
                                  "collapse (e < 1 with collapse_time = 0)",
                              te);
      const Event ev = heap_.front();
      pop();
      now_ = ev.t;
      ++processed;
      switch (ev.kind()) {
        case kPair: pair_impact(ev.a, ev.b(), rep); break;
        case kWall: wall_impact(ev.a, ev.b(), rep); break;
        case kCross: cross(ev.a, ev.b()); break;
      }
      if (processed % kPurgeEvery == 0) purge();
    }

    rep.steps = processed;  // collisions (pair and wall) plus cell crossings
    rep.rhs_evaluations = 0;
    rep.impact_energy_loss = loss_;
    constexpr std::size_t kB = RunReport::kWallImpulseBlocks;
    for (std::size_t w = 0; w < wall_impulse_.size() / kB; ++w) {
      const std::string name = w < 6 ? std::string(kBoxWall[w]) : wall_names_[w - 6];
      std::vector<double> blocks(wall_impulse_.begin() + static_cast<std::ptrdiff_t>(w * kB),
                                 wall_impulse_.begin() + static_cast<std::ptrdiff_t>((w + 1) * kB));
      double total = 0;
      for (const double b : blocks) total += b;
      rep.wall_impulses[name] = total;
      rep.wall_impulse_blocks[name] = std::move(blocks);
    }
    if (rep.unlogged_events > 0) {
      std::ostringstream os;
      os << "event log truncated: it holds the first " << rep.events.size() << " of "
         << rep.events.size() + rep.unlogged_events
         << " impacts (max_recorded_events; a scene's output.max_events); the impact count and the dissipated "
            "energy cover them all";
      rep.warnings.push_back(os.str());
    }
    rep.t_final = t_end_;
    energy_.finish(rep, t_end_);
    check_drift(rep, 0.0);  // exact flights: the bound is its floor, 1e-2
    rep.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return rep;
  }

 private:
  // --- cell lists -----------------------------------------------------------
  void link(std::uint32_t i) {
    Body& b = bodies_[i];
    const std::size_t c = grid_.index(b.cell);
    b.prev = -1;
    b.next = head_[c];
    if (b.next >= 0) bodies_[b.next].prev = static_cast<std::int32_t>(i);
    head_[c] = static_cast<std::int32_t>(i);
  }

  void unlink(std::uint32_t i) {
    Body& b = bodies_[i];
    if (b.prev >= 0)
      bodies_[b.prev].next = b.next;
    else
      head_[grid_.index(b.cell)] = b.next;
    if (b.next >= 0) bodies_[b.next].prev = b.prev;
  }

  template <class F>
  void for_cell(std::size_t c, F&& f) {
    for (std::int32_t j = head_[c]; j >= 0; j = bodies_[j].next) f(static_cast<std::uint32_t>(j));
  }

  // Every sphere in the 27 cells around sphere i's (i itself included).
  template <class F>
  void for_neighbours(std::uint32_t i, F&& f) {
    const auto c = bodies_[i].cell;
    for (int z = std::max(c[2] - 1, 0); z <= std::min(c[2] + 1, grid_.n[2] - 1); ++z)
      for (int y = std::max(c[1] - 1, 0); y <= std::min(c[1] + 1, grid_.n[1] - 1); ++y)
        for (int x = std::max(c[0] - 1, 0); x <= std::min(c[0] + 1, grid_.n[0] - 1); ++x) for_cell(grid_.index(x, y, z), f);
  }

  // --- queue ----------------------------------------------------------------
  bool stale(const Event& e) const {
    return e.ca != bodies_[e.a].count || (e.kind() == kPair && e.cb != bodies_[e.b()].count);
  }

  void pop() {
    std::pop_heap(heap_.begin(), heap_.end(), Later{});
    heap_.pop_back();
  }

  void push(double t, std::uint32_t a, std::uint32_t b, Kind kind) {
    t = std::max(t, now_);
    if (!(t < t_end_)) return;  // never reached in this run
    const std::uint32_t cb = kind == kPair ? bodies_[b].count : 0;
    heap_.push_back({t, a, (static_cast<std::uint32_t>(kind) << 30) | b, bodies_[a].count, cb});
    std::push_heap(heap_.begin(), heap_.end(), Later{});
    if (heap_.size() > purge_at_) purge();
  }

  // Drops the entries invalidated since they were predicted; the heap's
  // storage is kept, so the amortized cost per push stays O(1).
  void purge() {
    heap_.erase(std::remove_if(heap_.begin(), heap_.end(), [this](const Event& e) { return stale(e); }), heap_.end());
    std::make_heap(heap_.begin(), heap_.end(), Later{});
    purge_at_ = std::max(purge_base_, 2 * heap_.size());
  }

  // --- predictions ------------------------------------------------------------
  void predict_pair(std::uint32_t i, std::uint32_t j) {
    const Body& p = bodies_[i];
    const Body& q = bodies_[j];
    // Formed at the later reference time: the same numbers whenever the
    // prediction is made.
    const double ts = std::max(p.tref, q.tref);
    const Eigen::Vector3d dv = p.v - q.v;
    const Eigen::Vector3d dr = p.at(ts) - q.at(ts);
    const double b = dr.dot(dv);
    if (b >= 0) return;  // separating or sliding: no contact ahead
    const double sigma = p.radius + q.radius;
    const double c = dr.squaredNorm() - sigma * sigma;
    double t = ts;  // c ≤ 0: touching or overlapping by round-off, approaching: now
    if (c > 0) {
      const double d = b * b - dv.squaredNorm() * c;
      if (d <= 0) return;  // they miss
      t = ts + c / (std::sqrt(d) - b);
    }
    push(t, std::min(i, j), std::max(i, j), kPair);
  }

  void predict_walls(std::uint32_t i, int skip) {
    const Body& p = bodies_[i];
    for (int d = 0; d < 3; ++d) {
      const double v = p.v[d];
      if (v > 0 && skip != 2 * d + 1)
        push(p.tref + (hi_[d] - p.radius - p.r0[d]) / v, i, static_cast<std::uint32_t>(2 * d + 1), kWall);
      else if (v < 0 && skip != 2 * d)
        push(p.tref + (lo_[d] + p.radius - p.r0[d]) / v, i, static_cast<std::uint32_t>(2 * d), kWall);
    }
    for (std::size_t k = 0; k < planes_.size(); ++k) {
      if (static_cast<int>(6 + k) == skip) continue;
      const Plane& w = planes_[k];
      const double vn = w.n.dot(p.v);
      if (vn < 0) push(p.tref + (w.n.dot(p.r0 - w.p) - p.radius) / -vn, i, static_cast<std::uint32_t>(6 + k), kWall);
    }
  }

  void predict_crossing(std::uint32_t i) {
    if (!use_grid_) return;
    const Body& p = bodies_[i];
    double best = kInf;
    std::uint32_t code = 0;
    for (int d = 0; d < 3; ++d) {
      const double v = p.v[d];
      double t = kInf;
      if (v > 0 && p.cell[d] + 1 < grid_.n[d])
        t = p.tref + (lo_[d] + (p.cell[d] + 1) * grid_.width[d] - p.r0[d]) / v;
      else if (v < 0 && p.cell[d] > 0)
        t = p.tref + (lo_[d] + p.cell[d] * grid_.width[d] - p.r0[d]) / v;
      if (t < best) {
        best = t;
        code = static_cast<std::uint32_t>(2 * d + (v > 0 ? 1 : 0));
      }
    }
    if (best < kInf) push(best, i, code, kCross);
  }

  // Walls, the next cell crossing and all neighbours (but `partner`, which
  // has just collided with i and is separating).
  void predict_all(std::uint32_t i, std::int64_t partner, int skip_wall) {
    predict_walls(i, skip_wall);
    predict_crossing(i);
    for_neighbours(i, [&](std::uint32_t j) {
      if (j != i && static_cast<std::int64_t>(j) != partner) predict_pair(i, j);
    });
  }

  // --- events ---------------------------------------------------------------
  double restitution_now(const Body& p, double e) const {
    return now_ - p.last_impact < opt_.collapse_time ? 1.0 : e;  // TC model
  }

  /// Logs an impact; `name()` gives its name ("s1-s2", "s1-wall:z_min"), made only when it is logged or
  /// when its values overflow, which stops the run naming it.
  template <class Name>
  void record(RunReport& rep, const Name& name, double impulse, double u, double sep, double loss) {
    if (!std::isfinite(impulse) || !std::isfinite(loss)) {
      std::ostringstream os;
      os.precision(17);
      os << "hard spheres: the impact " << name() << " at t = " << now_
         << " gave a non-finite impulse or energy loss (J = " << impulse << " N s, loss " << loss
         << " J): its values overflow double precision, so the run was stopped";
      throw SimulationError(os.str(), now_);
    }
    ++rep.impacts;
    if (rep.events.size() < opt_.max_recorded_events) {
      EventRecord r;
      r.t = now_;
      r.kind = EventKind::impact;
      r.name = name();
      r.impulse = impulse;
      r.approach_speed = u;
      r.separation_speed = sep;
      r.kinetic_energy_before = energy0_ - loss_;
      r.kinetic_energy_after = energy0_ - loss_ - loss;
      rep.events.push_back(std::move(r));
    } else {
      ++rep.unlogged_events;
    }
    loss_ += loss;
    energy_.shift(now_, -loss, -loss);
  }


  void pair_impact(std::uint32_t i, std::uint32_t j, RunReport& rep) {
    Body& p = bodies_[i];
    Body& q = bodies_[j];
    const Eigen::Vector3d ri = p.at(now_), rj = q.at(now_);
    const Eigen::Vector3d d = ri - rj;
    const double dist = d.norm();
    if (!(dist > 0)) return;  // coincident centres: no line of centres
    const Eigen::Vector3d n = d / dist;
    const double vn = (p.v - q.v).dot(n);
    if (vn >= 0) return;  // a graze: nothing changes, the other predictions stand
    const double e = std::max(restitution_now(p, sys_.pair_restitution), restitution_now(q, sys_.pair_restitution));
    const double mu = p.mass / (1 + p.mass / q.mass);  // m_p m_q / (m_p + m_q), without overflowing the product
    const double u = -vn;
    const double J = (1 + e) * mu * u;
    p.r0 = ri;
    q.r0 = rj;
    p.tref = q.tref = now_;
    const Eigen::Vector3d vi = p.v, vj = q.v;
    p.v += (J / p.mass) * n;
    q.v -= (J / q.mass) * n;
    if (on_impact_ != nullptr)
      (*on_impact_)({now_, i, static_cast<std::ptrdiff_t>(j), -1, n, dist, e, vi, p.v, vj, q.v});
    ++p.count;
    ++q.count;
    p.last_impact = q.last_impact = now_;
    const double loss = 0.5 * mu * (1 - e * e) * u * u;
    record(rep, [&] { return names_[i] + "-" + names_[j]; }, J, u, (p.v - q.v).dot(n), loss);
    predict_all(i, j, -1);
    predict_all(j, i, -1);
  }

  void wall_impact(std::uint32_t i, std::uint32_t w, RunReport& rep) {
    Body& p = bodies_[i];
    const Eigen::Vector3d r = p.at(now_);
    const Eigen::Vector3d v = p.v;
    double u, sep, e;
    if (w < 6) {
      const int d = static_cast<int>(w / 2);
      const double vn = (w % 2 == 0) ? p.v[d] : -p.v[d];  // along the inward normal
      if (vn >= 0) return;
      e = restitution_now(p, sys_.box_restitution);
      u = -vn;
      p.v[d] = -e * p.v[d];
      sep = e * u;
    } else {
      const Plane& pl = planes_[w - 6];
      const double vn = pl.n.dot(p.v);
      if (vn >= 0) return;
      e = restitution_now(p, pl.e);
      u = -vn;
      p.v -= ((1 + e) * vn) * pl.n;
      sep = pl.n.dot(p.v);
    }
    p.r0 = r;
    p.tref = now_;
    ++p.count;
    p.last_impact = now_;
    if (on_impact_ != nullptr) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      if (w < 6) {
        normal[static_cast<int>(w / 2)] = (w % 2 == 0) ? 1.0 : -1.0;
      } else {
        normal = planes_[w - 6].n;
      }
      (*on_impact_)({now_, i, -1, static_cast<int>(w), normal, 0.0, e, v, p.v, Eigen::Vector3d::Zero(),
                     Eigen::Vector3d::Zero()});
    }
    const double loss = 0.5 * p.mass * (1 - e * e) * u * u;
    // the stretch of [t0, t_end] this impact falls in (RunReport::wall_impulse_blocks)
    constexpr int kB = RunReport::kWallImpulseBlocks;
    const int block = std::clamp(static_cast<int>((now_ - opt_.t0) / (t_end_ - opt_.t0) * kB), 0, kB - 1);
    wall_impulse_[w * kB + static_cast<std::size_t>(block)] += (1 + e) * p.mass * u;
    record(rep, [&] { return names_[i] + "-" + (w < 6 ? std::string(kBoxWall[w]) : wall_names_[w - 6]); },
           (1 + e) * p.mass * u, u, sep, loss);
    predict_all(i, -1, static_cast<int>(w));
  }

  void cross(std::uint32_t i, std::uint32_t code) {
    const int d = static_cast<int>(code / 2);
    const int step = (code % 2) ? 1 : -1;
    unlink(i);
    bodies_[i].cell[d] += step;
    link(i);
    // The layer of 9 cells that has come into range.
    const auto c = bodies_[i].cell;
    const int layer = c[d] + step;
    if (layer >= 0 && layer < grid_.n[d]) {
      const int u = (d + 1) % 3, w = (d + 2) % 3;
      std::array<int, 3> cc{};
      cc[d] = layer;
      for (int a = std::max(c[u] - 1, 0); a <= std::min(c[u] + 1, grid_.n[u] - 1); ++a)
        for (int b = std::max(c[w] - 1, 0); b <= std::min(c[w] + 1, grid_.n[w] - 1); ++b) {
          cc[u] = a;
          cc[w] = b;
          for_cell(grid_.index(cc), [&](std::uint32_t j) { predict_pair(i, j); });
        }
    }
    predict_crossing(i);
  }

  // --- samples --------------------------------------------------------------
  double sample_time(std::uint64_t k) const {
    if (opt_.output_interval > 0) {
      const double t = opt_.t0 + static_cast<double>(k) * opt_.output_interval;
      if (t < t_end_ && t_end_ - t > 1e-9 * opt_.output_interval) return t;
    }
    return t_end_;
  }

  void sample(double t, const HardSphereSampler& sampler, RunReport& rep) {
    double T = 0;
    momenta_.clear();
    for (std::size_t i = 0; i < bodies_.size(); ++i) {
      const Body& b = bodies_[i];
      const Eigen::Vector3d r = b.at(t);
      T += 0.5 * b.mass * b.v.squaredNorm();
      momenta_.add(b.mass, r.data(), b.v.data());
      rep.coordinate_scale = std::max(rep.coordinate_scale, r.cwiseAbs().maxCoeff());
      if (sampler) {
        snapshot_[i].position = r;
        snapshot_[i].velocity = b.v;
      }
    }
    if (rep.samples == 0) {
      energy0_ = T;
      energy_.start(rep, T);
    }
    momenta_.record(rep);
    energy_.sample(rep, t, T);  // T against T₀ less what the impacts took
    ++rep.samples;
    if (sampler) sampler(t, snapshot_);
  }

  const HardSphereSystem& sys_;
  const HardSphereOptions& opt_;
  const HardSphereImpactObserver* on_impact_;  // null: none
  double t_end_, now_;
  bool use_grid_;
  Eigen::Vector3d lo_, hi_;
  Grid grid_;
  std::vector<Body> bodies_;
  std::vector<std::int32_t> head_;
  std::vector<Plane> planes_;
  std::vector<std::string> names_, wall_names_;
  std::vector<double> wall_impulse_;  // N·s received by each wall (the box faces, then the planes), by stretch
  std::vector<Event> heap_;
  std::size_t purge_base_ = 0, purge_at_ = 0;
  std::vector<HardSphere> snapshot_;
  double energy0_ = 0, loss_ = 0;  // J: T at the start, taken by the impacts so far
  lagrangian::detail::EnergyMonitor energy_;
  lagrangian::detail::PointMomenta momenta_{{opt_.angular_momentum_point[0], opt_.angular_momentum_point[1],
                                             opt_.angular_momentum_point[2]}};
};

}  // namespace

RunReport run_hard_spheres(const HardSphereSystem& system, const HardSphereOptions& options,
                           const HardSphereSampler& sampler, const HardSphereImpactObserver& on_impact) {
  validate(system, options);
  const auto start = std::chrono::steady_clock::now();
  Engine engine(system, options, on_impact ? &on_impact : nullptr);
  return engine.run(sampler, start);
}

}  // namespace lagrangian
