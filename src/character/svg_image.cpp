#include "character/svg_parse.h"

#include <stb/stb_image.h>

#include <filesystem>
#include <fstream>

namespace mar::svg {

std::shared_ptr<const Texture> decode_image_href(std::string_view href, const std::string& base_dir,
                                                 std::string& problem) {
  std::vector<unsigned char> bytes;
  std::string label;
  if (href.rfind("data:", 0) == 0) {
    const size_t comma = href.find(',');
    const std::string_view head = href.substr(0, comma);
    if (comma == std::string_view::npos || head.find(";base64") == std::string_view::npos) {
      problem = "image data URI is not base64";
      return nullptr;
    }
    if (head.find("svg") != std::string_view::npos) {
      problem = "nested SVG images are not supported";
      return nullptr;
    }
    bytes = base64_decode(href.substr(comma + 1));
    label = "embedded image";
  } else {
    if (href.find("://") != std::string_view::npos) {
      problem = "remote image '" + std::string(href) + "' not loaded";
      return nullptr;
    }
    const std::filesystem::path p = std::filesystem::path(base_dir) / std::string(href);
    if (p.extension() == ".svg" || p.extension() == ".svgz") {
      problem = "nested SVG images are not supported";
      return nullptr;
    }
    std::ifstream in(p, std::ios::binary);
    if (!in) {
      problem = "image file '" + p.string() + "' not found";
      return nullptr;
    }
    bytes.assign(std::istreambuf_iterator<char>(in), {});
    label = p.string();
  }
  int w = 0, h = 0, comp = 0;
  stbi_uc* px = bytes.empty() || bytes.size() > (1u << 30)
                    ? nullptr
                    : stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &comp, 4);
  if (!px) {
    problem = "cannot decode image (" + label + ")";
    return nullptr;
  }
  auto t = std::make_shared<Texture>();
  t->name = label;
  t->width = w;
  t->height = h;
  t->rgba.assign(px, px + static_cast<size_t>(w) * h * 4);
  stbi_image_free(px);
  return t;
}

}  // namespace mar::svg
