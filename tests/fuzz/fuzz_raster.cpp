// Raster characters: a PNG decoded, its alpha traced by marching squares, simplified and
// made into textured sub-shapes (load_raster). Large images are refused by the loader's
// size limit; the harness keeps the trace small by refusing inputs over 64 KB.
#include "character/raster_loader.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 65536) return 0;
  const std::string path = mar::fuzz::scratch_file("image.png", mar::fuzz::text(data, size));
  (void)mar::load_raster(path);
  return 0;
}
