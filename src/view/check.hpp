#pragma once
// Internal: the checks a figure and a track pass before the page or a video
// is written from them (view.hpp: write_animation, write_video).

#include "lagrangian/view/view.hpp"

namespace lagrangian::view::detail {

/// Throws std::invalid_argument "animation: <field>: <what>" naming the field
/// and the value: sizes that do not match, non-finite or decreasing times,
/// non-finite positions or fixed parts, radii out of range, body indices
/// out of range, series of the wrong length.
void check(const Figure& figure, const Track& track);

}  // namespace lagrangian::view::detail
