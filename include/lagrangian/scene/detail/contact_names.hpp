#pragma once
// Internal: how a logged event names the bodies of a contact. A contact
// between bodies is named "<a>-<b>" ("ball-floor", "m3-m7", "s3-wall:x_max");
// the plots mark an impact on the bodies it names and the animation page
// flashes them.

#include <string_view>

namespace lagrangian::detail {

/// Does the event name `contact` name `body`: the whole name, or a part
/// that begins or ends it, or sits between two dashes? Body names may hold
/// dashes of their own ("left-ball-right-ball" names "left-ball").
inline bool names_body(std::string_view contact, std::string_view body) {
  if (body.empty()) return false;
  if (contact == body) return true;
  const std::size_t n = body.size();
  if (contact.size() <= n) return false;
  if (contact.starts_with(body) && contact[n] == '-') return true;
  if (contact.ends_with(body) && contact[contact.size() - n - 1] == '-') return true;
  for (std::size_t at = contact.find(body, 1); at != std::string_view::npos; at = contact.find(body, at + 1))
    if (contact[at - 1] == '-' && at + n < contact.size() && contact[at + n] == '-') return true;
  return false;
}

}  // namespace lagrangian::detail
