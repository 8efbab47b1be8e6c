// Every device type a show may name is known to the build; a backend left out by its CMake
// option (MARIONETTE_WITH_<NAME>=OFF) still loads as a device that reports "not built" and
// the option that builds it. The layout test (tools/backend_options_test.sh) builds this
// file with backends switched off and names them in MARIONETTE_EXPECT_NOT_BUILT.
#include "devices/backends.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <set>
#include <sstream>

namespace mar {
namespace {

std::set<std::string> expected_off() {
  std::set<std::string> off;
  const char* env = std::getenv("MARIONETTE_EXPECT_NOT_BUILT");
  std::stringstream in(env ? env : "");
  for (std::string t; std::getline(in, t, ',');)
    if (!t.empty()) off.insert(t);
  if (off.count("alsa")) off.insert("audio");  // one option (MARIONETTE_WITH_ALSA) builds both
  return off;
}

TEST(BackendTable, EveryTypeIsKnownAndSaysWhetherItIsBuilt) {
  const auto off = expected_off();
  std::set<std::string> types;
  for (const BackendInfo& b : backend_table()) {
    types.insert(b.type);
    EXPECT_EQ(b.built, !off.count(b.type)) << b.type;
    EXPECT_EQ(b.make != nullptr, b.built) << b.type;
  }
  EXPECT_EQ(types, (std::set<std::string>{"usb_midi", "hid", "gpio", "tablet", "alsa", "audio", "osc", "sdl"}));
  for (const std::string& t : off) EXPECT_TRUE(types.count(t)) << "unknown type in MARIONETTE_EXPECT_NOT_BUILT: " << t;
}

TEST(BackendTable, ALeftOutBackendIsADeviceThatSaysNotBuilt) {
  const auto off = expected_off();
  for (const BackendInfo& b : backend_table()) {
    if (b.built) continue;
    DeviceSpec spec;
    spec.type = b.type;
    std::string err;
    auto dev = make_backend(spec, 0, &err);
    ASSERT_NE(dev, nullptr) << err;
    EXPECT_EQ(dev->open(), DeviceState::Unavailable);
    EXPECT_NE(dev->problem().find(std::string(b.option) + "=OFF"), std::string::npos) << dev->problem();
  }
  const auto reports = discover_devices({});
  ASSERT_EQ(reports.size(), backend_table().size());
  for (const BackendReport& r : reports) {
    if (off.count(r.backend)) {
      EXPECT_EQ(r.status.rfind("not built (MARIONETTE_WITH_", 0), 0u) << r.status;
    }
  }
}

TEST(BackendTable, AnUnknownTypeIsAnError) {
  DeviceSpec spec;
  spec.type = "serial";
  std::string err;
  EXPECT_EQ(make_backend(spec, 0, &err), nullptr);
  EXPECT_NE(err.find("unknown device type 'serial'"), std::string::npos) << err;
}

}  // namespace
}  // namespace mar
