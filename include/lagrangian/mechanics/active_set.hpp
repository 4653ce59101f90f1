#pragma once
/// \file active_set.hpp
/// Which unilateral constraints (contacts) are active.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace lagrangian {

/// Which unilateral constraints (contacts) are active: held shut as
/// constraint rows, while the others carry no force. Contact j is the
/// model's unilateral constraint j; there may be any number. Sets of
/// contacts below 64 are stored inline, so copying them never allocates.
class ActiveSet {
 public:
  /// No contact active: the bilateral rows only.
  ActiveSet() = default;
  /// Every contact active, however many there are.
  static ActiveSet all() {
    ActiveSet s;
    s.all_ = true;
    return s;
  }
  /// Contact j alone.
  static ActiveSet only(int j) {
    ActiveSet s;
    s.insert(j);
    return s;
  }
  bool contains(int j) const {
    if (all_) return true;
    const auto [w, bit] = place(j);
    return w == 0 ? (low_ & bit) != 0 : w <= high_.size() && (high_[w - 1] & bit) != 0;
  }
  /// Whether any of the contacts 0 … count − 1 is active.
  bool any(int count) const {
    if (all_) return count > 0;
    for (int j = 0; j < count; ++j)
      if (contains(j)) return true;
    return false;
  }
  /// Contact j becomes active.
  void insert(int j) {
    if (all_) return;
    const auto [w, bit] = place(j);
    if (w == 0) {
      low_ |= bit;
      return;
    }
    if (high_.size() < w) high_.resize(w, 0);
    high_[w - 1] |= bit;
  }
  /// Contact j becomes inactive (a set made by all() lists no contacts to
  /// remove: std::logic_error).
  void erase(int j) {
    if (all_) throw std::logic_error("ActiveSet::erase on ActiveSet::all(), which does not know its contacts");
    const auto [w, bit] = place(j);
    if (w == 0) {
      low_ &= ~bit;
    } else if (w <= high_.size()) {
      high_[w - 1] &= ~bit;
    }
  }
  /// This set without contact j.
  ActiveSet without(int j) const {
    ActiveSet s = *this;
    s.erase(j);
    return s;
  }

 private:
  /// The word (0: inline) and bit of contact j.
  static std::pair<std::size_t, std::uint64_t> place(int j) {
    const auto u = static_cast<std::size_t>(j);
    return {u / 64, std::uint64_t{1} << (u % 64)};
  }
  bool all_ = false;
  std::uint64_t low_ = 0;
  std::vector<std::uint64_t> high_;
};
/// Every unilateral constraint active.
inline const ActiveSet all_active = ActiveSet::all();

}  // namespace lagrangian
