#pragma once
// Internal: formatting of values and "did you mean" hints for the scene's
// error messages (definitions in scene_messages.cpp).

#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "text.hpp"

namespace lagrangian::scene::detail {

std::string quote_text(std::string_view s, char quote = '\'');
using text::join;

std::string format_value(double v);

std::string format_derived(double v);

std::string format_vec(const Vec3& v);

std::string unknown_hint(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace lagrangian::scene::detail
