#pragma once
// Internal: text helpers shared by the scene reader and the validator.

#include <string>
#include <string_view>
#include <vector>

namespace lagrangian::scene::text {

/// s between `quote` characters, with quotes, backslashes and control
/// characters escaped, cut after 80 characters (for error messages).
inline std::string quoted(std::string_view s, char quote) {
  constexpr std::size_t kMax = 80;
  std::string out(1, quote);
  std::size_t n = 0;
  for (const char c : s) {
    if (++n > kMax) {
      out += "...";
      break;
    }
    const auto u = static_cast<unsigned char>(c);
    if (c == quote || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20 || u == 0x7f) {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[u >> 4];
      out += hex[u & 15];
    } else {
      out += c;
    }
  }
  out += quote;
  return out;
}

/// The items separated by ", ".
inline std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

}  // namespace lagrangian::scene::text
