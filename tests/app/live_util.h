// Helpers of the end-to-end live tests (tests/app/test_live*.cpp): a show file around the
// figure's rig, a headless show, a handle's solved position.
#pragma once

#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

namespace mar::test {

inline std::string show_file(const std::string& name, const std::string& body) {
  const std::string rig = (test::source_dir() / "config/rigs/figure.toml").string();
  return test::write_temp(name, "[show]\nrig = \"" + rig + "\"\nrate = 60\niterations = 12\nmin_iterations = 12\n" +
                                    "[display]\nwidth = 160\nheight = 200\n" + body);
}

inline std::unique_ptr<LiveShow> load(const std::string& path, RunOptions o = {}) {
  o.headless = true;
  o.quiet = true;
  auto s = LiveShow::load(path, o);
  EXPECT_TRUE(s.ok()) << s.error;
  return s.ok() ? std::move(*s.value) : nullptr;
}

inline Vec2 handle_position(const LiveShow& s, int h) {
  return s.puppet().solver->handle_point(size_t(h));
}


}  // namespace mar::test
