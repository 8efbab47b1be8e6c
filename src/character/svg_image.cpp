#include "character/svg_parse.h"

#include "character/raster_loader.h"
#include "base/read_file.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <filesystem>

namespace mar::svg {

bool image_href_bytes(std::string_view href, const std::string& base_dir, bool anywhere, std::vector<unsigned char>& bytes,
                      std::string& label, std::string& problem) {
  bytes.clear();
  if (href.rfind("data:", 0) == 0) {
    const size_t comma = href.find(',');
    const std::string_view head = href.substr(0, comma);
    if (comma == std::string_view::npos || head.find(";base64") == std::string_view::npos) {
      problem = "image data URI is not base64";
      return false;
    }
    bytes = base64_decode(href.substr(comma + 1));
    label = "embedded image";
    return true;
  }
  if (href.find("://") != std::string_view::npos) {
    problem = "remote image '" + std::string(href) + "' not loaded";
    return false;
  }
  const std::filesystem::path p = std::filesystem::path(base_dir) / std::string(href);
  // Beside the drawing only, unless the show says otherwise: an href that climbs out of the
  // character's folder (or a link that leads out of it) could name any file on the machine.
  std::error_code ec;
  const std::filesystem::path dir = std::filesystem::weakly_canonical(base_dir.empty() ? "." : base_dir, ec);
  const std::filesystem::path real = std::filesystem::weakly_canonical(p, ec);
  const std::filesystem::path rel = real.lexically_relative(dir);
  if (!anywhere && (ec || rel.empty() || *rel.begin() == "..")) {
    problem = "image file '" + p.string() + "' is outside the character's folder ([show] images = \"anywhere\" allows it)";
    return false;
  }
  Result<std::string> read = read_file(p.string(), kMaxPngBytes, "an image");
  if (!read.ok()) {
    problem = "image file " + read.error;
    return false;
  }
  bytes.assign(read.value->begin(), read.value->end());
  label = p.string();
  return true;
}

bool is_svg_image(std::string_view href, const std::vector<unsigned char>& bytes) {
  if (href.rfind("data:", 0) == 0) {
    const std::string_view head = href.substr(0, href.find(','));
    if (head.find("svg") != std::string_view::npos) return true;
  } else {
    const std::string ext = std::filesystem::path(std::string(href)).extension().string();
    if (ext == ".svg" || ext == ".svgz") return true;
  }
  // (no type given: the bytes say; gzip is an .svgz's)
  const std::string_view b(reinterpret_cast<const char*>(bytes.data()), std::min<size_t>(bytes.size(), 4096));
  const size_t lt = b.find("<svg");
  return lt != std::string_view::npos && b.substr(0, lt).find_first_not_of(" \t\r\n") == b.substr(0, lt).find("<");
}

std::shared_ptr<const Texture> decode_image_bytes(const std::vector<unsigned char>& bytes, const std::string& label,
                                                  std::string& problem) {
  // The header first: a few bytes can declare an image of gigabytes.
  {
    int w = 0, h = 0, comp = 0;
    if (!bytes.empty() && bytes.size() <= (1u << 30) &&
        stbi_info_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &comp) &&
        (w > kMaxImageSide || h > kMaxImageSide || size_t(w) * size_t(h) > kMaxImagePixels)) {
      problem = label + " is " + std::to_string(w) + "x" + std::to_string(h) + "; at most " + std::to_string(kMaxImageSide) +
                " pixels a side and " + std::to_string(kMaxImagePixels / 1'000'000) + " million pixels";
      return nullptr;
    }
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
