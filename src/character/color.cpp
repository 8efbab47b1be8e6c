#include "character/color.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <string>

namespace mar {

std::string_view trim_space(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}
namespace {

struct Named {
  const char* name;
  int r, g, b;
};

// SVG 1.1 recognised colour keywords (sorted for binary search).
constexpr std::array<Named, 147> kNamed{{
    {"aliceblue", 240, 248, 255},
    {"antiquewhite", 250, 235, 215},
    {"aqua", 0, 255, 255},
    {"aquamarine", 127, 255, 212},
    {"azure", 240, 255, 255},
    {"beige", 245, 245, 220},
    {"bisque", 255, 228, 196},
    {"black", 0, 0, 0},
    {"blanchedalmond", 255, 235, 205},
    {"blue", 0, 0, 255},
    {"blueviolet", 138, 43, 226},
    {"brown", 165, 42, 42},
    {"burlywood", 222, 184, 135},
    {"cadetblue", 95, 158, 160},
    {"chartreuse", 127, 255, 0},
    {"chocolate", 210, 105, 30},
    {"coral", 255, 127, 80},
    {"cornflowerblue", 100, 149, 237},
    {"cornsilk", 255, 248, 220},
    {"crimson", 220, 20, 60},
    {"cyan", 0, 255, 255},
    {"darkblue", 0, 0, 139},
    {"darkcyan", 0, 139, 139},
    {"darkgoldenrod", 184, 134, 11},
    {"darkgray", 169, 169, 169},
    {"darkgreen", 0, 100, 0},
    {"darkgrey", 169, 169, 169},
    {"darkkhaki", 189, 183, 107},
    {"darkmagenta", 139, 0, 139},
    {"darkolivegreen", 85, 107, 47},
    {"darkorange", 255, 140, 0},
    {"darkorchid", 153, 50, 204},
    {"darkred", 139, 0, 0},
    {"darksalmon", 233, 150, 122},
    {"darkseagreen", 143, 188, 143},
    {"darkslateblue", 72, 61, 139},
    {"darkslategray", 47, 79, 79},
    {"darkslategrey", 47, 79, 79},
    {"darkturquoise", 0, 206, 209},
    {"darkviolet", 148, 0, 211},
    {"deeppink", 255, 20, 147},
    {"deepskyblue", 0, 191, 255},
    {"dimgray", 105, 105, 105},
    {"dimgrey", 105, 105, 105},
    {"dodgerblue", 30, 144, 255},
    {"firebrick", 178, 34, 34},
    {"floralwhite", 255, 250, 240},
    {"forestgreen", 34, 139, 34},
    {"fuchsia", 255, 0, 255},
    {"gainsboro", 220, 220, 220},
    {"ghostwhite", 248, 248, 255},
    {"gold", 255, 215, 0},
    {"goldenrod", 218, 165, 32},
    {"gray", 128, 128, 128},
    {"green", 0, 128, 0},
    {"greenyellow", 173, 255, 47},
    {"grey", 128, 128, 128},
    {"honeydew", 240, 255, 240},
    {"hotpink", 255, 105, 180},
    {"indianred", 205, 92, 92},
    {"indigo", 75, 0, 130},
    {"ivory", 255, 255, 240},
    {"khaki", 240, 230, 140},
    {"lavender", 230, 230, 250},
    {"lavenderblush", 255, 240, 245},
    {"lawngreen", 124, 252, 0},
    {"lemonchiffon", 255, 250, 205},
    {"lightblue", 173, 216, 230},
    {"lightcoral", 240, 128, 128},
    {"lightcyan", 224, 255, 255},
    {"lightgoldenrodyellow", 250, 250, 210},
    {"lightgray", 211, 211, 211},
    {"lightgreen", 144, 238, 144},
    {"lightgrey", 211, 211, 211},
    {"lightpink", 255, 182, 193},
    {"lightsalmon", 255, 160, 122},
    {"lightseagreen", 32, 178, 170},
    {"lightskyblue", 135, 206, 250},
    {"lightslategray", 119, 136, 153},
    {"lightslategrey", 119, 136, 153},
    {"lightsteelblue", 176, 196, 222},
    {"lightyellow", 255, 255, 224},
    {"lime", 0, 255, 0},
    {"limegreen", 50, 205, 50},
    {"linen", 250, 240, 230},
    {"magenta", 255, 0, 255},
    {"maroon", 128, 0, 0},
    {"mediumaquamarine", 102, 205, 170},
    {"mediumblue", 0, 0, 205},
    {"mediumorchid", 186, 85, 211},
    {"mediumpurple", 147, 112, 219},
    {"mediumseagreen", 60, 179, 113},
    {"mediumslateblue", 123, 104, 238},
    {"mediumspringgreen", 0, 250, 154},
    {"mediumturquoise", 72, 209, 204},
    {"mediumvioletred", 199, 21, 133},
    {"midnightblue", 25, 25, 112},
    {"mintcream", 245, 255, 250},
    {"mistyrose", 255, 228, 225},
    {"moccasin", 255, 228, 181},
    {"navajowhite", 255, 222, 173},
    {"navy", 0, 0, 128},
    {"oldlace", 253, 245, 230},
    {"olive", 128, 128, 0},
    {"olivedrab", 107, 142, 35},
    {"orange", 255, 165, 0},
    {"orangered", 255, 69, 0},
    {"orchid", 218, 112, 214},
    {"palegoldenrod", 238, 232, 170},
    {"palegreen", 152, 251, 152},
    {"paleturquoise", 175, 238, 238},
    {"palevioletred", 219, 112, 147},
    {"papayawhip", 255, 239, 213},
    {"peachpuff", 255, 218, 185},
    {"peru", 205, 133, 63},
    {"pink", 255, 192, 203},
    {"plum", 221, 160, 221},
    {"powderblue", 176, 224, 230},
    {"purple", 128, 0, 128},
    {"red", 255, 0, 0},
    {"rosybrown", 188, 143, 143},
    {"royalblue", 65, 105, 225},
    {"saddlebrown", 139, 69, 19},
    {"salmon", 250, 128, 114},
    {"sandybrown", 244, 164, 96},
    {"seagreen", 46, 139, 87},
    {"seashell", 255, 245, 238},
    {"sienna", 160, 82, 45},
    {"silver", 192, 192, 192},
    {"skyblue", 135, 206, 235},
    {"slateblue", 106, 90, 205},
    {"slategray", 112, 128, 144},
    {"slategrey", 112, 128, 144},
    {"snow", 255, 250, 250},
    {"springgreen", 0, 255, 127},
    {"steelblue", 70, 130, 180},
    {"tan", 210, 180, 140},
    {"teal", 0, 128, 128},
    {"thistle", 216, 191, 216},
    {"tomato", 255, 99, 71},
    {"turquoise", 64, 224, 208},
    {"violet", 238, 130, 238},
    {"wheat", 245, 222, 179},
    {"white", 255, 255, 255},
    {"whitesmoke", 245, 245, 245},
    {"yellow", 255, 255, 0},
    {"yellowgreen", 154, 205, 50},
}};

int hexval(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}


// One rgb() component: number (0..255) or percentage; returns value in [0, 1].
std::optional<float> component(std::string_view s, bool alpha) {
  s = trim_space(s);
  if (s.empty()) return std::nullopt;
  bool pct = false;
  if (s.back() == '%') {
    pct = true;
    s.remove_suffix(1);
  }
  double v = 0;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  double out = pct ? v / 100.0 : (alpha ? v : v / 255.0);
  return static_cast<float>(std::clamp(out, 0.0, 1.0));
}

}  // namespace

std::optional<Rgba> parse_background_color(std::string_view text) {
  if (text == "chroma-green") return Rgba{0, 1, 0, 1};
  if (text == "chroma-blue") return Rgba{0, 0, 1, 1};
  if (text == "chroma-magenta") return Rgba{1, 0, 1, 1};
  // "ffffff" as `render --background` takes it, as well as CSS's "#ffffff".
  const std::string_view t = trim_space(text);
  if ((t.size() == 6 || t.size() == 8) && std::all_of(t.begin(), t.end(), [](char c) { return hexval(c) >= 0; }))
    return parse_color("#" + std::string(t));
  return parse_color(text);
}

std::optional<Rgba> parse_color(std::string_view text) {
  std::string_view s = trim_space(text);
  if (s.empty()) return std::nullopt;
  if (s[0] == '#') {
    s.remove_prefix(1);
    std::array<int, 8> h{};
    for (size_t i = 0; i < s.size(); ++i) {
      if (i >= 8 || (h[i] = hexval(s[i])) < 0) return std::nullopt;
    }
    if (s.size() == 3 || s.size() == 4) {
      Rgba c{h[0] * 17 / 255.0f, h[1] * 17 / 255.0f, h[2] * 17 / 255.0f, 1.0f};
      if (s.size() == 4) c.a = h[3] * 17 / 255.0f;
      return c;
    }
    if (s.size() == 6 || s.size() == 8) {
      Rgba c{(h[0] * 16 + h[1]) / 255.0f, (h[2] * 16 + h[3]) / 255.0f, (h[4] * 16 + h[5]) / 255.0f,
             1.0f};
      if (s.size() == 8) c.a = (h[6] * 16 + h[7]) / 255.0f;
      return c;
    }
    return std::nullopt;
  }
  std::string lower(s);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.rfind("rgb(", 0) == 0 || lower.rfind("rgba(", 0) == 0) {
    const size_t open = lower.find('('), close = lower.rfind(')');
    if (close == std::string::npos || close < open) return std::nullopt;
    std::string_view body = std::string_view(lower).substr(open + 1, close - open - 1);
    std::array<std::string_view, 4> parts{};
    size_t count = 0;
    while (!body.empty()) {
      const size_t cut = body.find_first_of(",/");
      const size_t end = cut == std::string_view::npos ? body.size() : cut;
      if (count >= 4) return std::nullopt;
      parts[count++] = body.substr(0, end);
      body = cut == std::string_view::npos ? std::string_view{} : body.substr(cut + 1);
    }
    if (count == 1) {  // space-separated CSS Color 4 form: rgb(255 0 0)
      std::string_view one = trim_space(parts[0]);
      count = 0;
      while (!one.empty() && count < 4) {
        const size_t sp = one.find(' ');
        parts[count++] = one.substr(0, sp);
        one = sp == std::string_view::npos ? std::string_view{} : trim_space(one.substr(sp));
      }
    }
    if (count != 3 && count != 4) return std::nullopt;
    Rgba c;
    for (size_t i = 0; i < count; ++i) {
      auto v = component(parts[i], i == 3);
      if (!v) return std::nullopt;
      (i == 0 ? c.r : i == 1 ? c.g : i == 2 ? c.b : c.a) = *v;
    }
    return c;
  }
  auto it = std::lower_bound(kNamed.begin(), kNamed.end(), lower,
                             [](const Named& n, const std::string& key) { return key.compare(n.name) > 0; });
  if (it != kNamed.end() && lower == it->name) {
    return Rgba{it->r / 255.0f, it->g / 255.0f, it->b / 255.0f, 1.0f};
  }
  if (lower == "transparent") return Rgba{0, 0, 0, 0};
  return std::nullopt;
}

std::string color_hex(const Rgba& c) {
  auto byte = [](float v) { return static_cast<int>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", byte(c.r), byte(c.g), byte(c.b));
  return buf;
}

}  // namespace mar
