// The bench tests run the real device libraries against umockdev's emulated kernel
// devices: the program re-executes itself with umockdev's preload first.
#include "app/simulate.h"

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  mar::enable_virtual_bench(argv);  // umockdev preload; --simulate in-process
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
