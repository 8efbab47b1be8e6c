#include "character/raster_loader.h"

#include "base/config_toml.h"

#include "geom/marching_squares.h"
#include "geom/polygon.h"
#include "base/read_file.h"

#include <stb/stb_image.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

namespace mar {

Result<Texture> decode_png(std::string_view bytes, const std::string& name, size_t max_pixels) {
  int w = 0, h = 0, n = 0;
  const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
  if (bytes.size() > size_t(INT32_MAX)) return Result<Texture>::failure(name + ": image file too large");
  const int size = int(bytes.size());
  // Only the formats a character may hold, by their signatures: stb_image also reads PNM, PSD,
  // TGA, HDR and PIC, and Debian 12's build of it reads outside a crafted PNM's buffer.
  const auto starts = [&](std::string_view sig) { return bytes.substr(0, sig.size()) == sig; };
  if (!starts("\x89PNG\r\n\x1a\n") && !starts("\xff\xd8\xff") && !starts("GIF87a") && !starts("GIF89a") && !starts("BM")) {
    return Result<Texture>::failure(name + ": not a PNG, JPEG, GIF or BMP image");
  }
  // The header first: a few bytes can declare an image of gigabytes.
  max_pixels = std::min(max_pixels, kMaxImagePixels);
  if (stbi_info_from_memory(data_in, size, &w, &h, &n) &&
      (w > kMaxImageSide || h > kMaxImageSide || size_t(w) * size_t(h) > max_pixels)) {
    return Result<Texture>::failure(name + ": image is " + std::to_string(w) + "x" + std::to_string(h) + "; the limit is " +
                                    std::to_string(kMaxImageSide) + " pixels a side and " +
                                    (max_pixels >= 1'000'000 ? std::to_string(max_pixels / 1'000'000) + " million pixels"
                                                             : std::to_string(max_pixels) + " pixels"));
  }
  stbi_uc* data = stbi_load_from_memory(data_in, size, &w, &h, &n, 4);
  if (!data) {
    const char* why = stbi_failure_reason();
    return Result<Texture>::failure(name + ": cannot read image: " + (why ? why : "unknown error"));
  }
  Texture t;
  t.name = name;
  t.width = w;
  t.height = h;
  t.rgba.assign(data, data + static_cast<size_t>(w) * h * 4);
  stbi_image_free(data);
  return Result<Texture>::success(std::move(t));
}

Result<Texture> read_png(const std::string& path, size_t max_pixels) {
  Result<std::string> file = read_file(path, kMaxPngBytes, "an image");
  if (!file.ok()) return Result<Texture>::failure(file.error);
  return decode_png(*file.value, path, max_pixels);
}

Result<Character> raster_character(std::shared_ptr<const Texture> image,
                                   const std::vector<std::uint8_t>& mask_rgba,
                                   const std::string& name, const RasterOptions& options) {
  const int w = image->width, h = image->height;
  const size_t npx = static_cast<size_t>(w) * h;
  std::vector<float> values(npx);
  Character ch;
  ch.source = name;
  ch.width = w;
  ch.height = h;
  if (!mask_rgba.empty()) {
    if (mask_rgba.size() != npx * 4) {
      return Result<Character>::failure(name + ": mask size differs from the image size");
    }
    for (size_t i = 0; i < npx; ++i) {
      const std::uint8_t m = std::max({mask_rgba[4 * i], mask_rgba[4 * i + 1], mask_rgba[4 * i + 2]});
      values[i] = m / 255.0f;
    }
  } else {
    bool any_transparent = false;
    for (size_t i = 0; i < npx; ++i) {
      values[i] = image->rgba[4 * i + 3] / 255.0f;
      any_transparent = any_transparent || image->rgba[4 * i + 3] < 255;
    }
    if (!any_transparent) {
      ch.warnings.push_back(name + ": image is fully opaque and no mask was given; "
                                   "the whole image is the figure (pass --mask for a cut-out)");
    }
  }
  const std::vector<Region> regions =
      trace_regions(values, w, h, options.threshold, options.tolerance, options.min_area);
  ch.layers.push_back("image");
  int k = 0;
  for (const Region& r : regions) {
    SubShape s;
    s.id = "region-" + std::to_string(++k);
    s.element = "region";
    s.layer = 0;
    auto add = [&](const Points& ring) {
      s.contours.push_back({static_cast<int>(s.points.size()), static_cast<int>(ring.size()), true});
      s.points.insert(s.points.end(), ring.begin(), ring.end());
    };
    add(r.outer);
    for (const Points& hole : r.holes) add(hole);
    s.fill.enabled = true;
    s.fill.color = Rgba{1, 1, 1, 1};
    s.fill.rule = FillRule::EvenOdd;
    s.fill.texture = image;
    s.fill.uv_from_point = Affine2::scale(1.0 / w, 1.0 / h);
    ch.shapes.push_back(std::move(s));
  }
  if (regions.empty()) ch.warnings.push_back(name + ": no figure found (empty alpha or mask)");
  return Result<Character>::success(std::move(ch));
}

Result<Character> load_raster(const std::string& path, const RasterOptions& options) {
  Result<Texture> img = read_png(path, options.max_pixels);
  if (!img.ok()) return Result<Character>::failure(img.error);
  auto tex = std::make_shared<const Texture>(std::move(*img.value));
  std::vector<std::uint8_t> mask;
  if (!options.mask_path.empty()) {
    Result<Texture> m = read_png(options.mask_path, options.max_pixels);
    if (!m.ok()) return Result<Character>::failure(m.error);
    if (m.value->width != tex->width || m.value->height != tex->height) {
      return Result<Character>::failure(
          options.mask_path + ": mask is " + std::to_string(m.value->width) + "x" +
          std::to_string(m.value->height) + " but " + path + " is " + std::to_string(tex->width) +
          "x" + std::to_string(tex->height));
    }
    mask = std::move(m.value->rgba);
  }
  return raster_character(tex, mask, path, options);
}

}  // namespace mar

namespace mar {
namespace {

// "10-arm-left" -> "arm-left": a part's name is its file's stem without a leading number.
std::string part_name(const std::string& stem) {
  size_t i = 0;
  while (i < stem.size() && std::isdigit(static_cast<unsigned char>(stem[i]))) ++i;
  if (i > 0 && i < stem.size() && (stem[i] == '-' || stem[i] == '_' || stem[i] == ' ' || stem[i] == '.')) ++i;
  return i < stem.size() ? stem.substr(i) : stem;
}

// File names in paint order: a leading number by its value, then the rest.
bool layer_before(const std::string& a, const std::string& b) {
  auto key = [](const std::string& s) {
    size_t i = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    const long long n = i > 0 && i < 18 ? std::stoll(s.substr(0, i)) : -1;
    return std::make_pair(n, s);
  };
  return key(a) < key(b);
}

}  // namespace

Result<Character> load_layers(const std::string& folder, const RasterOptions& options) {
  namespace fs = std::filesystem;
  using R = Result<Character>;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return R::failure(folder + ": not a folder");
  Character ch;
  ch.source = folder;
  std::vector<std::string> files;
  const fs::path order_file = fs::path(folder) / "layers.toml";
  if (fs::exists(order_file, ec)) {
    toml::table root;
    Result<std::string> file_text = read_file(order_file.string(), kMaxTomlBytes, "a layer order");
    if (!file_text.ok()) return R::failure(file_text.error);
    Result<toml::table> parsed = cfg::parse_toml(*file_text.value, order_file.string());
    if (!parsed.ok()) return R::failure(parsed.error);
    root = std::move(*parsed.value);
    const toml::array* order = root["order"].as_array();
    if (!order) return R::failure(order_file.string() + ": needs order = [\"back.png\", ..., \"front.png\"]");
    for (const toml::node& n : *order) {
      const auto name = n.value<std::string>();
      if (!name || name->empty() || name->find('/') != std::string::npos || name->find("..") != std::string::npos)
        return R::failure(order_file.string() + ": order names file names in the folder (\"arm-left.png\")");
      files.push_back(*name);
    }
  } else {
    for (const fs::directory_entry& e : fs::directory_iterator(folder, ec)) {
      std::string ext = e.path().extension().string();
      for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
      if (e.is_regular_file(ec) && ext == ".png") files.push_back(e.path().filename().string());
    }
    std::sort(files.begin(), files.end(), layer_before);
  }
  if (files.empty()) return R::failure(folder + ": no PNG layers in the folder");
  if (int(files.size()) > kMaxLayers)
    return R::failure(folder + ": " + std::to_string(files.size()) + " layers; the limit is " + std::to_string(kMaxLayers));
  std::set<std::string> used;
  for (const std::string& file : files) {
    const std::string path = (fs::path(folder) / file).string();
    if (!fs::exists(path, ec)) {
      ch.warnings.push_back(path + ": no such layer (named in layers.toml); left out");
      continue;
    }
    Result<Texture> img = read_png(path);
    if (!img.ok()) {
      ch.warnings.push_back(img.error + "; layer left out");
      continue;
    }
    if (ch.shapes.empty() && ch.width == 0) {
      ch.width = img.value->width;
      ch.height = img.value->height;
    } else if (img.value->width != int(ch.width) || img.value->height != int(ch.height)) {
      ch.warnings.push_back(path + ": layer is " + std::to_string(img.value->width) + "x" + std::to_string(img.value->height) +
                            " but the character is " + std::to_string(int(ch.width)) + "x" + std::to_string(int(ch.height)) +
                            " (its first layer's size); left out");
      continue;
    }
    auto tex = std::make_shared<const Texture>(std::move(*img.value));
    bool opaque = false;
    for (size_t i = 3; i < tex->rgba.size() && !opaque; i += 4) opaque = tex->rgba[i] > 0;
    if (!opaque) {
      ch.warnings.push_back(path + ": layer is empty (nothing opaque); left out");
      continue;
    }
    Result<Character> one = raster_character(tex, {}, path, options);
    if (!one.ok()) {
      ch.warnings.push_back(one.error + "; layer left out");
      continue;
    }
    for (const std::string& w : one.value->warnings) ch.warnings.push_back(w);
    const std::string base = part_name(fs::path(file).stem().string());
    const int layer = int(ch.layers.size());
    ch.layers.push_back(base);
    int k = 0;
    for (SubShape& s : one.value->shapes) {
      std::string id = k++ == 0 ? base : base + "-" + std::to_string(k);
      for (int n = 2; used.count(id); ++n) id = base + "-" + std::to_string(n);
      used.insert(id);
      s.id = id;
      s.element = "layer";
      s.layer = layer;
      ch.shapes.push_back(std::move(s));
    }
  }
  if (ch.shapes.empty()) {
    std::string why;
    for (const std::string& w : ch.warnings) why += "\n  " + w;
    return R::failure(folder + ": no usable layer" + why);
  }
  return R::success(std::move(ch));
}

}  // namespace mar
