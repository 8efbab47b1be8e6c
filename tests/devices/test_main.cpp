// The bench tests run the real device libraries against umockdev's emulated kernel
// devices: the program re-executes itself with umockdev's preload first.
#include "firmware_sim/vbench.h"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  mar::VirtualBench::ensure_preload(argv);
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
