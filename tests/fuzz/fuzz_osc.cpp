// OSC packets (the UDP backend parses them itself) and address patterns against addresses
// ('*', '?', [classes], {alternatives}) in both directions. Input: pattern, NUL, packet.
#include "fuzz_util.h"
#include "input/decoder.h"
#include "input/osc.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto [pattern, packet] = mar::fuzz::split(mar::fuzz::text(data, size));
  const std::span<const uint8_t> bytes(reinterpret_cast<const uint8_t*>(packet.data()), packet.size());
  mar::OscMessage m;
  if (mar::parse_osc_message(bytes, m)) {
    (void)mar::osc_match(pattern, m.address);
    (void)mar::osc_match(m.address, pattern);
  }
  (void)mar::osc_match(pattern, pattern);
  auto dec = mar::make_osc_decoder({std::string(pattern), "/fader/*", "/{a,b}/[0-9]"}, 1);
  if (bytes.size() <= mar::WireRecord::kMax)
    dec->feed(mar::WireRecord::make(0, mar::WireKind::OscMessage, bytes, 1), [](const mar::Event&) {});
  return 0;
}
