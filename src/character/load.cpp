#include "character/load.h"

#include "character/raster_loader.h"
#include "character/svg_loader.h"
#include "base/read_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace mar {

Result<Character> load_character(const std::string& path, const LoadOptions& options) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {  // a folder of PNG layers
    if (!options.mask_path.empty()) return Result<Character>::failure(path + ": --mask applies to a single PNG, not a folder of layers");
    RasterOptions ro;
    ro.tolerance = options.raster_tolerance;
    return load_layers(path, ro);
  }
  // A character is a regular file (or a folder): a FIFO, a device or /dev/zero is refused before
  // a byte is read, and so is a file past the largest a character may be.
  if (std::string why = file_problem(path, std::max(kMaxPngBytes, kMaxSvgBytes), "a PNG character (64 MB for an SVG)");
      !why.empty())
    return Result<Character>::failure(why);
  std::ifstream in(path, std::ios::binary);
  if (!in) return Result<Character>::failure(path + ": cannot open file");
  char sig[8] = {};
  in.read(sig, sizeof sig);
  const bool png = in.gcount() == 8 && std::string_view(sig, 8) == "\x89PNG\r\n\x1a\n";
  const bool gzip = in.gcount() >= 2 && static_cast<unsigned char>(sig[0]) == 0x1f &&
                    static_cast<unsigned char>(sig[1]) == 0x8b;
  if (png) {
    RasterOptions ro;
    ro.mask_path = options.mask_path;
    ro.tolerance = options.raster_tolerance;
    return load_raster(path, ro);
  }
  if (gzip) {
    return Result<Character>::failure(path + ": compressed SVG (.svgz) is not supported; "
                                             "unpack it with gunzip first");
  }
  if (!options.mask_path.empty()) {
    return Result<Character>::failure(path + ": --mask applies to PNG characters only");
  }
  SvgOptions so;
  so.tolerance = options.svg_tolerance;
  so.images_anywhere = options.images_anywhere;
  Result<Character> first = load_svg_file(path, so);
  if (!first.ok() || !options.pixels_per_unit) return first;
  const double k = options.pixels_per_unit(first.value->width, first.value->height);
  if (!(k > 1.0001) || !std::isfinite(k)) return first;
  so.tolerance = options.svg_tolerance / std::min(k, 64.0);
  Result<Character> fine = load_svg_file(path, so);
  if (fine.ok()) return fine;
  // (finer curves can pass a bound the file kept at its own units: keep those, and say so)
  first.value->warnings.push_back(path + ": curves kept within " + std::to_string(options.svg_tolerance) +
                                  " units, coarser than 0.1 px at the canvas's scale: " + fine.error);
  return first;
}

}  // namespace mar
