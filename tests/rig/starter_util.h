// For the tests of starter shows: an automatic rig and its starter show written to a folder of
// the test's, played headless a frame at a time.
#pragma once

#include "app/live.h"
#include "rig/auto_rig.h"
#include "rig/starter_show.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <fstream>
#include <memory>

namespace mar::test {

/// The rig (rig.toml) and its starter show for a nanoKONTROL2 (show.toml) in a folder of the
/// test's: the show's path, or "" (with a failure) when either cannot be made.
inline std::string write_starter(const AutoRig& ar, const Character& ch, const std::string& folder) {
  const auto dir = temp_dir(folder);
  const bool rig = bool(std::ofstream(dir / "rig.toml") << write_auto_rig(ar, ch));
  EXPECT_TRUE(rig) << folder;
  auto text = starter_show(ar, ch, "rig.toml", "nanokontrol2");
  EXPECT_TRUE(text.ok()) << text.error;
  const bool show = text.ok() && bool(std::ofstream(dir / "show.toml") << *text.value);
  EXPECT_TRUE(show) << folder;
  return rig && show ? (dir / "show.toml").string() : "";
}

/// The show loaded headless with its first frame played (the caller plays the rest with
/// frame()); null (with a failure) when it does not load.
inline std::unique_ptr<LiveShow> first_frame(const std::string& show) {
  RunOptions o;
  o.headless = true;
  o.quiet = true;
  o.frames = 1;
  auto live = LiveShow::load(show, o);
  EXPECT_TRUE(live.ok()) << live.error;
  if (!live.ok()) return nullptr;
  std::unique_ptr<LiveShow> s = std::move(*live.value);
  (void)s->run();
  return s;
}

/// The index of a handle by name (0, with a failure, when there is none).
inline size_t handle_index(const std::vector<RigHandle>& handles, const std::string& name) {
  for (size_t h = 0; h < handles.size(); ++h)
    if (handles[h].name == name) return h;
  ADD_FAILURE() << "no handle " << name;
  return 0;
}

}  // namespace mar::test
