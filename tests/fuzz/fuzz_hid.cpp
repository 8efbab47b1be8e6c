// HID report descriptors and the reports they describe: the descriptor parser, every field's
// elements read from each report, the decoder a HID connection makes, and writing a value
// back into a report as the simulated devices do. Input: u16 descriptor length (little
// endian), the descriptor, then reports, each a length byte and its bytes.
#include "fuzz_util.h"
#include "input/decoder.h"
#include "input/hid.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const size_t len = std::min<size_t>(size - 2, size_t(data[0]) | size_t(data[1]) << 8);
  const std::span<const uint8_t> descriptor(data + 2, len);
  auto parsed = mar::parse_hid_descriptor(descriptor);
  if (!parsed.ok()) return 0;
  const mar::HidDescriptor& d = *parsed.value;
  auto dec = mar::make_hid_decoder(d, 1);
  std::vector<uint8_t> scratch;
  for (size_t i = 2 + len; i < size;) {
    const size_t n = std::min<size_t>(data[i], size - i - 1);
    const std::span<const uint8_t> report(data + i + 1, n);
    i += 1 + n;
    if (const mar::HidReport* r = d.input_for(report)) {
      for (const mar::HidField& f : r->fields) {
        for (int k = 0; k < f.count && k < 4096; ++k) {
          int32_t v = 0;
          (void)f.value(report, k, v);
        }
      }
      scratch.assign(r->size_bytes(), 0);
      for (const mar::HidField& f : r->fields)
        if (f.bit_size <= 32) mar::hid_insert_bits(scratch, f.bit_offset, f.bit_size, 0xA5A5A5A5u);
    }
    (void)mar::hid_extract_bits(report, uint32_t(n), 32);
    dec->feed(mar::WireRecord::make(int64_t(i), mar::WireKind::HidReport, report, 1), [](const mar::Event&) {});
  }
  return 0;
}
