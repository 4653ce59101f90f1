#pragma once
// Internal: JSON strings and files written through `<path>.partial`, shared
// by the run report and the scene runner (compiled in src/integrate/report.cpp).

#include <sstream>
#include <string>

namespace lagrangian::detail {

/// Appends s to os as a JSON string literal (quotes, backslashes and
/// control characters escaped; <, > and & as \u003c, \u003e, \u0026, so that
/// the JSON can sit inside an HTML <script> element).
void json_string(std::ostringstream& os, const std::string& s);

/// Writes `text` to `<path>.partial` and renames it to `path` when complete;
/// throws OptionError naming the path ("cannot write <what> '…'") otherwise.
void write_text_file(const std::string& path, const std::string& text, const std::string& what);

}  // namespace lagrangian::detail
