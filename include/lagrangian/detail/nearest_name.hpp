#pragma once
// Internal: the nearest name by edit distance, for "did you mean" hints
// (the scene reader's keys and values, the expressions' names and
// functions; compiled once in src/core/nearest_name.cpp).

#include <cstddef>
#include <string>
#include <vector>

namespace lagrangian::detail {

/// The candidate nearest to `word` by edit distance (Levenshtein: one
/// insertion, deletion or substitution each), at most `max_distance` edits
/// away, the first of equally near ones; "" when none is. A pair whose table
/// would exceed 65 536 cells gives no hint rather than a slow one.
std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates,
                         std::size_t max_distance);

}  // namespace lagrangian::detail
