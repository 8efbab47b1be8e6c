// CSS/SVG colour values: #rgb, #rrggbb (and #rgba/#rrggbbaa), rgb()/rgba() with numbers
// or percentages, and the 147 SVG named colours.
#pragma once

#include "character/character.h"

#include <optional>
#include <string_view>

namespace mar {

std::optional<Rgba> parse_color(std::string_view text);

/// "#rrggbb" of the colour (alpha dropped).
std::string color_hex(const Rgba& c);

}  // namespace mar
