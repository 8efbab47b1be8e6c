// Raster characters: a PNG decoded, its alpha traced by marching squares, simplified and
// made into textured sub-shapes (decode_png, then raster_character, as load_raster does, from
// memory: no file per input). Images over 65,536 pixels are refused from their header before
// decoding, as the loader refuses ones over its limit, so each input's work stays small (the
// trace of a 16-million-pixel image a 64 KB input could declare ran the harness at 211/s).
#include "character/raster_loader.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 65536) return 0;
  auto image = mar::decode_png(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.png", 65536);
  if (!image.ok()) return 0;
  (void)mar::raster_character(std::make_shared<const mar::Texture>(std::move(*image.value)), {}, "fuzz.png");
  return 0;
}
