// Timeline scripts of the simulated devices (one action per line), then the timeline played
// on a loop for a while, as a show's [[device]] script is. The first byte picks the device.
// The record limit is lowered to 20,000 (250,000 in the program): a stick moved over a long
// time writes a report per scan (250 a second), and `0 stick left 1,1 over 999` (249,750
// records) took 1.7-2.6 s instrumented, at the 2 s timeout; 20,000 records take 0.16 s. The
// limit's own checks are what is tested.
#include "firmware_sim/sim_device.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kinds[] = {"nanokontrol2", "knob_box", "pen_tablet", "gamepad"};
  auto dev = mar::make_sim_device(kinds[data[0] % 4], "", 1.5, 7);
  if (!dev.ok()) return 0;
  mar::SimDevice& d = **dev.value;
  d.set_max_records(20'000);
  if (!d.load_script(std::string(mar::fuzz::text(data + 1, size - 1))).ok()) return 0;
  d.set_loop(data[0] & 0x80 ? 0.5 : 0.0);
  d.finish();
  size_t n = 0;
  for (int64_t t = 0; t <= 3'000'000'000; t += 250'000'000) d.drain(t, [&](const mar::WireRecord&) { ++n; });
  return n == size_t(-1);
}
