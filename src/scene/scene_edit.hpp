#pragma once
// Internal: changing a scene file's TOML document before it is read — a
// scene key ("model.parameters.e", "bodies[0].velocity[2]") parsed into a
// path, a number written at it (sweeps' --vary and --set, run --set).

#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include <toml++/toml.h>

namespace lagrangian::scene::detail {

using PathPart = std::variant<std::string, std::size_t>;

/// The path of a scene key; OptionError "<option> <key>: not a scene key: …".
std::vector<PathPart> parse_path(const std::string& option, const std::string& key);

/// Writes `value` at `path` in `root`: an integral value is an integer where
/// the file has an integer or no value; missing tables and keys are created
/// (the reader refuses unknown ones with its own message), missing array
/// elements are not. OptionError "<option> <key>: …" otherwise.
void assign(toml::table& root, const std::string& option, const std::string& key, const std::vector<PathPart>& path,
            double value);

}  // namespace lagrangian::scene::detail
