// CSS/SVG colour values: #rgb, #rrggbb (and #rgba/#rrggbbaa), rgb()/rgba() with numbers
// or percentages, and the 147 SVG named colours.
#pragma once

#include "character/character.h"

#include <optional>
#include <string_view>

namespace mar {

/// `s` without leading and trailing white space (std::isspace).
std::string_view trim_space(std::string_view s);

std::optional<Rgba> parse_color(std::string_view text);

/// A stage background: "transparent", a chroma-key preset ("chroma-green" #00ff00,
/// "chroma-blue" #0000ff, "chroma-magenta" #ff00ff) or any colour parse_color() reads.
std::optional<Rgba> parse_background_color(std::string_view text);

/// "#rrggbb" of the colour (alpha dropped).
std::string color_hex(const Rgba& c);

}  // namespace mar
