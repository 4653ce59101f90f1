#pragma once
// Internal: a model with contacts (and no holonomic or Pfaffian rows) that
// can hold its contacts shut, for the tangent flow's resting contacts
// (TangentModel::rest, analysis/lyapunov.hpp). A held contact's gap
// φ_j(q, t) = 0 becomes a holonomic row counted at run time, so the tangent
// passes of HoldingContacts<M> give the motion that keeps it shut,
//   M q̈ = r + G_jᵀ λ_j,   G_j q̈ + γ_j = 0,   G_j = ∂φ_j/∂q,
// and with nothing held the free motion of M. Everything else (energies,
// forces, gaps, restitution, names) is the model's own, inherited.

#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_names.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

template <class M>
class HoldingContacts;

/// HoldingContacts of M's twin with parameters of type Q (instantiated only
/// where a parameter's seeded twin is asked for).
template <class M, class Q>
struct HoldingTwin {
  using type = HoldingContacts<typename M::template with_parameter_type<Q>>;
};

template <class M>
class HoldingContacts : public M {
 public:
  static constexpr int n = coordinate_count_v<M>;
  static_assert(holonomic_count_v<M> == 0 && pfaffian_count_v<M> == 0 && unilateral_count_v<M> != 0,
                "HoldingContacts: a model with contacts and no holonomic or Pfaffian rows");

  explicit HoldingContacts(const M& model) : M(model) {}
  /// The model with its parameters of type Q holding the same contacts
  /// (held_like()): a parameter's seeded twin (analysis/sensitivity.hpp).
  template <class Q>
  using with_parameter_type = typename HoldingTwin<M, Q>::type;

  /// Contact j held shut (`shut`), or opened again.
  void hold(int j, bool shut) const {
    const auto at = std::find(held_.begin(), held_.end(), j);
    if (shut == (at != held_.end())) return;
    if (shut) {
      held_.push_back(j);
    } else {
      held_.erase(at);
    }
  }
  /// Holds the contacts `other` holds, in its order, from now on whatever it
  /// holds later (its list is read, not copied: `other` outlives this).
  template <class Other>
  void held_like(const Other& other) const {
    like_ = &other.held();
  }
  /// The contacts held shut, in the order they were held.
  const std::vector<int>& held() const { return like_ != nullptr ? *like_ : held_; }
  /// Contacts held shut, each one holonomic row.
  int held_count() const { return static_cast<int>(held().size()); }
  int holonomic_count() const { return held_count(); }

  /// The held contacts' gaps φ_j(q, t) (m or rad), in the order they were
  /// held, into a per-thread vector for each number type S (sized once per
  /// count; the values hold until the next call with the same S on this
  /// thread).
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> holonomic(const Vec<S, n>& q, const S& t) const {
    thread_local Vec<S, Dynamic> rows;
    const int count = held_count();
    if (rows.size() != count) rows.resize(count);
    if (count > 0) {
      const auto gaps = M::unilateral(q, t);
      for (int k = 0; k < count; ++k) rows[k] = gaps[held()[static_cast<std::size_t>(k)]];
    }
    return Eigen::Map<const Vec<S, Dynamic>>(rows.data(), count);
  }
  /// A held row is named after its contact.
  std::vector<std::string> holonomic_names() const {
    const std::vector<std::string> contacts = constraint_names(static_cast<const M&>(*this));
    std::vector<std::string> names;
    for (int j : held()) names.push_back(contacts[static_cast<std::size_t>(j)]);
    return names;
  }

 private:
  mutable std::vector<int> held_;
  mutable const std::vector<int>* like_ = nullptr;  // held_like()'s list, read in place of held_
};

/// True for a model whose tangent flow holds its resting contacts through
/// HoldingContacts<M>: contacts, no holonomic or Pfaffian rows, and no
/// hold() of its own (a text model's FixedSizeModel has one).
template <class M>
concept held_by_wrapper = holonomic_count_v<M> == 0 && pfaffian_count_v<M> == 0 && unilateral_count_v<M> != 0 &&
                          !requires(const M& m) { m.hold(0, true); };

}  // namespace lagrangian::detail
