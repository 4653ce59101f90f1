#include "lagrangian/detail/nearest_name.hpp"

#include <algorithm>

namespace lagrangian::detail {

std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates,
                         std::size_t max_distance) {
  constexpr std::size_t kMaxCells = 1u << 16;
  std::string best;
  std::size_t best_d = max_distance + 1;
  std::vector<std::size_t> prev, cur;
  for (const auto& c : candidates) {
    // (The difference of the lengths is a lower bound of the distance.)
    const std::size_t diff = c.size() > word.size() ? c.size() - word.size() : word.size() - c.size();
    if (diff >= best_d || (word.size() + 1) * (c.size() + 1) > kMaxCells) continue;
    prev.resize(c.size() + 1);
    cur.resize(c.size() + 1);
    for (std::size_t j = 0; j <= c.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      cur[0] = i;
      for (std::size_t j = 1; j <= c.size(); ++j) {
        const std::size_t sub = prev[j - 1] + (word[i - 1] == c[j - 1] ? 0 : 1);
        cur[j] = std::min({sub, prev[j] + 1, cur[j - 1] + 1});
      }
      std::swap(prev, cur);
    }
    if (prev[c.size()] < best_d) {
      best_d = prev[c.size()];
      best = c;
    }
  }
  return best_d <= max_distance ? best : std::string();
}

}  // namespace lagrangian::detail
