// Recordings (`replay`): the MARREC02 records, each connection's description (a
// DecoderConfig, which can carry a HID descriptor) and every wire record fed to the decoder
// the description makes, as replay does.
#include "app/loop/recording.h"
#include "fuzz_util.h"
#include "input/decoder.h"

#include <map>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mar::fuzz::scratch_file("rec.marrec", mar::fuzz::text(data, size));
  auto p = mar::Playback::open(path);
  if (!p.ok()) return 0;
  std::map<uint16_t, std::unique_ptr<mar::Decoder>> decoders;
  std::vector<mar::WireRecord> wires;
  int64_t t = 0;
  int iterations = 0;
  const auto on_device = [&](uint16_t source, std::span<const uint8_t> description) {
    auto c = mar::DecoderConfig::parse(description);
    if (!c.ok()) return;
    std::string error;
    decoders[source] = mar::make_decoder(*c.value, source, &error);
  };
  while ((*p.value)->next_frame(wires, t, iterations, on_device)) {
    for (const mar::WireRecord& r : wires) {
      const auto d = decoders.find(r.source);
      if (d == decoders.end() || !d->second) continue;
      d->second->feed(r, [](const mar::Event&) {});
    }
    for (auto& [source, d] : decoders) {
      if (!d) continue;
      d->settle(t, [](const mar::Event&) {});
    }
  }
  return 0;
}
