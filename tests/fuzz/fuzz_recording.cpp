// Recordings (`replay`): the MARREC03 header and blocks, each connection's description (a
// DecoderConfig, which can carry a HID descriptor) and every wire record fed to the decoder the
// description makes, as replay does. Each input is read twice: as a file (the header, the block
// lengths and checksums), and as the payload of one block with a valid header and checksum, so
// mutations reach the record parser behind the CRC-32 (a leading MARREC02 magic or MARREC03
// header and block head are dropped first, so older regression inputs keep their records).
#include "app/loop/recording.h"
#include "fuzz_util.h"
#include "input/decoder.h"

#include <cstring>
#include <map>

namespace {

void play(const std::string& bytes) {
  const std::string path = mar::fuzz::scratch_file("rec.marrec", bytes);
  auto p = mar::Playback::open(path);
  if (!p.ok()) return;
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
}

// `payload` as the one block of a take with a valid header.
std::string one_block(std::string_view payload) {
  if (payload.substr(0, 8) == "MARREC02") payload.remove_prefix(8);
  else if (payload.substr(0, 8) == "MARREC03" && payload.size() >= 28) payload.remove_prefix(28);
  uint8_t head[20] = {'M', 'A', 'R', 'R', 'E', 'C', '0', '3'};
  const uint32_t crc = mar::crc32(std::span<const uint8_t>(head, 16));
  std::memcpy(head + 16, &crc, 4);
  const auto* b = reinterpret_cast<const uint8_t*>(payload.data());
  const uint32_t block[2] = {uint32_t(payload.size()), mar::crc32(std::span<const uint8_t>(b, payload.size()))};
  std::string out(reinterpret_cast<const char*>(head), sizeof head);
  out.append(reinterpret_cast<const char*>(block), sizeof block);
  return out.append(payload);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(mar::fuzz::text(data, size));
  play(text);
  if (!text.empty()) play(one_block(text));
  return 0;
}
