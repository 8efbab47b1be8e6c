// Helpers of the end-to-end live tests (tests/app/test_live*.cpp): a show file around the
// figure's rig, a headless show, a handle's solved position, a part's distance from its rest.
#pragma once

#include "app/live.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
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

/// The drawing's height, a sub-shape's index by id (-1: none), and how far its farthest point is
/// from its rest as the puppet is posed (0 for none).
inline double height(const Puppet& p) { return p.character.bounds().hi.y() - p.character.bounds().lo.y(); }

inline int shape_of(const Puppet& p, const std::string& id) {
  for (size_t k = 0; k < p.character.shapes.size(); ++k)
    if (p.character.shapes[k].id == id) return int(k);
  return -1;
}

inline double off_rest(const Puppet& p, int k) {
  double d = 0;
  for (size_t i = 0; k >= 0 && i < p.shapes[size_t(k)].size(); ++i)
    d = std::max(d, (p.shapes[size_t(k)][i] - p.character.shapes[size_t(k)].points[i]).norm());
  return d;
}

inline double off_rest(const Puppet& p, const std::string& id) { return off_rest(p, shape_of(p, id)); }


}  // namespace mar::test
