#include "character/raster_loader.h"

#include "geom/marching_squares.h"
#include "geom/polygon.h"

#include <stb/stb_image.h>

namespace mar {

Result<Texture> read_png(const std::string& path) {
  int w = 0, h = 0, n = 0;
  // The header first: a few bytes can declare an image of gigabytes.
  if (stbi_info(path.c_str(), &w, &h, &n) &&
      (w > kMaxImageSide || h > kMaxImageSide || size_t(w) * size_t(h) > kMaxImagePixels)) {
    return Result<Texture>::failure(path + ": image is " + std::to_string(w) + "x" + std::to_string(h) +
                                    "; the limit is " + std::to_string(kMaxImageSide) + " pixels a side and " +
                                    std::to_string(kMaxImagePixels / 1'000'000) + " million pixels");
  }
  stbi_uc* data = stbi_load(path.c_str(), &w, &h, &n, 4);
  if (!data) {
    const char* why = stbi_failure_reason();
    return Result<Texture>::failure(path + ": cannot read image: " + (why ? why : "unknown error"));
  }
  Texture t;
  t.name = path;
  t.width = w;
  t.height = h;
  t.rgba.assign(data, data + static_cast<size_t>(w) * h * 4);
  stbi_image_free(data);
  return Result<Texture>::success(std::move(t));
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
  Result<Texture> img = read_png(path);
  if (!img.ok()) return Result<Character>::failure(img.error);
  auto tex = std::make_shared<const Texture>(std::move(*img.value));
  std::vector<std::uint8_t> mask;
  if (!options.mask_path.empty()) {
    Result<Texture> m = read_png(options.mask_path);
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
