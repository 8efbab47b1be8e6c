// Rig files (TOML): handles, groups, joints, keys, swap sets, triggers, solver settings.
#include "character/rig.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  (void)mar::parse_rig(mar::fuzz::text(data, size), "fuzz.toml");
  return 0;
}
