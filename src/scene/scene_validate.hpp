#pragma once
// Internal: the scene validator, shared by scene_validate_fields.cpp (values,
// names and references) and scene_validate_initial.cpp (the state at t0).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "scene_gas_fill.hpp"

namespace lagrangian::scene::detail {

std::string idx(const std::string& prefix, std::size_t i);

/// A body as the checks see it: explicit or a molecule of the gas.
struct BodyRef {
  bool gas = false;
  std::int64_t index = -1;  // into bodies, or the gas molecule index
};

class Validator {
 public:
  explicit Validator(const Scene& s) : s_(s) {}

  void run();

 private:
  const Scene& s_;
  std::unordered_map<std::string, std::size_t> by_name_;
  double kinetic_energy_ = 0;  ///< Σ ½ m |v|² of the bodies checked so far (J)
  std::optional<detail::GasLayout> layout_;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  void finite(const std::string& key, double v) const;
  void finite(const std::string& key, const Vec3& v) const;
  void positive(const std::string& key, double v, const std::string& why = "") const;
  void nonnegative(const std::string& key, double v) const;
  void restitution(const std::string& key, double e) const;
  void nonzero_normal(const std::string& key, const Vec3& n) const;

  // -- run and output --
  bool event_driven() const;
  void check_run() const;
  void check_output() const;

  // -- model --
  void check_model() const;
  void check_text_model() const;
  /// q or q̇ (`key`): empty, or one finite value per coordinate.
  void check_state(const std::string& key, const std::vector<double>& v,
                   const std::vector<std::string>& coordinates) const;

  // -- bodies and gas --
  void check_bodies();
  void check_gas();
  std::optional<BodyRef> find(const std::string& name) const;
  BodyRef require_body(const std::string& key, const std::string& name) const;
  void require_bodies(const std::string& key, const std::vector<std::string>& names) const;
  std::string body_name(const BodyRef& r) const;
  Vec3 position(const BodyRef& r) const;
  double radius(const BodyRef& r) const;
  std::string position_key(const BodyRef& r) const;
  std::string velocity_key(const BodyRef& r) const;

  // -- effects, constraints, contacts --
  void check_effects() const;
  void check_constraints() const;
  void check_box_fields() const;
  void check_contacts() const;
  void check_engine() const;

  // -- the initial state (scene_validate_initial.cpp) --
  void check_initial_state() const;
  void check_in_box() const;
  void overlap_failure(const BodyRef& a, const BodyRef& b, double d) const;
  static bool overlapping(double d, double sum);
  void check_pairs(const std::vector<BodyRef>& set) const;
  void check_overlaps() const;
  void check_planes() const;
  void check_links() const;
  void check_surfaces() const;
  void check_gravity_singularity() const;
};

}  // namespace lagrangian::scene::detail
