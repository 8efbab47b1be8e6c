// Quadrature decoding of real and synthetic encoder captures (exact counts from the corpus
// README), also with synthetic contact bounce injected.
#include "input/quadrature.h"
#include "input/filters.h"
#include "input/event.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include <fstream>
#include <random>
#include <sstream>

namespace mar {
namespace {

struct Capture {
  std::vector<double> t;
  std::vector<std::vector<int>> cols;  // per sample: levels of every column
};

Capture read_edges(const std::filesystem::path& p) {
  Capture c;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ls(line);
    double t;
    ls >> t;
    std::vector<int> v;
    int x;
    while (ls >> x) v.push_back(x);
    c.t.push_back(t);
    c.cols.push_back(v);
  }
  return c;
}

// Splits one axis (columns ca, cb) into two per-line edge streams, plus the initial levels.
void split(const Capture& c, int ca, int cb, std::vector<LineEdge>& a, std::vector<LineEdge>& b, bool& a0, bool& b0) {
  a0 = c.cols[0][size_t(ca)];
  b0 = c.cols[0][size_t(cb)];
  for (size_t i = 1; i < c.t.size(); ++i) {
    const int64_t t = int64_t(std::llround(c.t[i] * 1e9));
    if (c.cols[i][size_t(ca)] != c.cols[i - 1][size_t(ca)]) a.push_back({t, 0, uint8_t(c.cols[i][size_t(ca)])});
    if (c.cols[i][size_t(cb)] != c.cols[i - 1][size_t(cb)]) b.push_back({t, 1, uint8_t(c.cols[i][size_t(cb)])});
  }
}

// Contact bounce: after some genuine edges on `line`, a burst of 1-5 ms toggling the line
// and ending at the genuine level — only where the burst ends before the next edge of either
// line (a bouncing contact settles before the other contact moves; otherwise it is a
// different signal, not bounce).
std::vector<LineEdge> add_bounce(const std::vector<LineEdge>& own, const std::vector<LineEdge>& other, std::mt19937& rng,
                                 int* bursts) {
  std::vector<LineEdge> out;
  size_t j = 0;
  for (size_t i = 0; i < own.size(); ++i) {
    out.push_back(own[i]);
    const int64_t burst = 1'000'000 + int64_t(rng() % 4'000'001);  // 1-5 ms
    const int64_t t0 = own[i].t_ns;
    while (j < other.size() && other[j].t_ns <= t0) ++j;
    const int64_t next_other = j < other.size() ? other[j].t_ns : INT64_MAX;
    const int64_t next_own = i + 1 < own.size() ? own[i + 1].t_ns : INT64_MAX;
    const int64_t room = std::min(next_other, next_own) - t0;
    // Captures faster than any bounce (rotary-ramp: ~47 us between edges) get bursts
    // squeezed into half the gap instead, so every file is exercised.
    const int64_t len = burst < room ? burst : room / 2;
    if (rng() % 2 || len < 2000) continue;
    const int toggles = 2 * (1 + int(rng() % 4));  // even: ends at the genuine level
    for (int k = 1; k <= toggles; ++k)
      out.push_back({t0 + len * k / toggles, own[i].line, uint8_t(k % 2 ? !own[i].level : own[i].level)});
    ++*bursts;
  }
  return out;
}

struct Expect {
  const char* file;
  int ca, cb;
  uint64_t quarter;
  int64_t net;
};

TEST(Quadrature, CorpusCountsExactAlsoWithBounce) {
  const auto root = test::corpus_dir() / "encoder";
  if (!std::filesystem::exists(root)) GTEST_SKIP() << "corpus not found";
  const std::string h = "sigrok-hdns2000-quadrature/agilent_hdns_2000_move_mouse_";
  const std::string a = "sigrok-adns2051-quadrature/avago_adns_2051_move_mouse_";
  const Expect cases[] = {
      {"fast", 0, 1, 3003, 67}, {"fast", 2, 3, 485, 47}, {"left_right", 0, 1, 919, 11},
      {"left_right", 2, 3, 45, -23}, {"up_down", 0, 1, 103, 59}, {"up_down", 2, 3, 939, 71},
  };
  const Expect acases[] = {
      {"fast", 0, 1, 560, 128}, {"fast", 2, 3, 4154, 88}, {"left_right", 0, 1, 1041, -29},
      {"left_right", 2, 3, 48, -22}, {"up_down", 0, 1, 43, -21}, {"up_down", 2, 3, 629, 37},
  };
  std::vector<std::pair<std::string, Expect>> all;
  for (const auto& e : cases) all.push_back({h + e.file + ".edges.txt", e});
  for (const auto& e : acases) all.push_back({a + e.file + ".edges.txt", e});
  all.push_back({"sigrok-graycode/rotary-ramp.edges.txt", {"", 0, 1, 12732, -12732}});
  all.push_back({"sigrok-graycode/rotary-sin.edges.txt", {"", 0, 1, 1016, 0}});
  std::mt19937 rng(11);
  int total_bursts = 0;
  for (const auto& [file, e] : all) {
    SCOPED_TRACE(file + " columns " + std::to_string(e.ca) + "," + std::to_string(e.cb));
    const Capture c = read_edges(root / file);
    ASSERT_FALSE(c.t.empty());
    std::vector<LineEdge> la, lb;
    bool a0, b0;
    split(c, e.ca, e.cb, la, lb, a0, b0);
    QuadratureDecoder q;
    q.set_levels(a0, b0);
    merge_line_edges(std::span<const LineEdge>(la), std::span<const LineEdge>(lb), [&](const LineEdge& x) { q.edge(x); });
    EXPECT_EQ(q.quarter_steps(), e.quarter);
    EXPECT_EQ(q.position(), e.net);
    EXPECT_EQ(q.invalid(), 0u);
    // Bounce on A, then on B: the net count must not change.
    for (int which = 0; which < 2; ++which) {
      int bursts = 0;
      std::vector<LineEdge> ba = which == 0 ? add_bounce(la, lb, rng, &bursts) : la;
      std::vector<LineEdge> bb = which == 1 ? add_bounce(lb, la, rng, &bursts) : lb;
      QuadratureDecoder qb;
      qb.set_levels(a0, b0);
      merge_line_edges(std::span<const LineEdge>(ba), std::span<const LineEdge>(bb), [&](const LineEdge& x) { qb.edge(x); });
      EXPECT_EQ(qb.position(), e.net) << bursts << " bursts on line " << which;
      if (e.quarter > 100) {
        EXPECT_GT(bursts, 0);
      }
      total_bursts += bursts;
    }
  }
  EXPECT_GT(total_bursts, 1000);
}

TEST(Quadrature, IdleCaptureCountsNothing) {
  const auto p = test::corpus_dir() / "encoder/sigrok-hdns2000-quadrature/agilent_hdns_2000_idle.edges.txt";
  if (!std::filesystem::exists(p)) GTEST_SKIP() << "corpus not found";
  const Capture c = read_edges(p);
  std::vector<LineEdge> la, lb;
  bool a0, b0;
  split(c, 0, 1, la, lb, a0, b0);
  QuadratureDecoder q;
  q.set_levels(a0, b0);
  merge_line_edges(std::span<const LineEdge>(la), std::span<const LineEdge>(lb), [&](const LineEdge& x) { q.edge(x); });
  EXPECT_EQ(q.position(), 0);
}

// Quarter-step edges of `detents` detents starting at state 11 (a common detent rest).
std::vector<LineEdge> turn(int detents, int64_t t0, int64_t dt) {
  // Positive order 00 -> 01 -> 11 -> 10 -> 00 (AB); from 11 a positive step drops B.
  static const int seq[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  std::vector<LineEdge> out;
  int idx = 2;
  for (int s = 0; s < 4 * std::abs(detents); ++s) {
    const int next = (idx + (detents > 0 ? 1 : 3)) % 4;
    const int line = seq[idx][0] != seq[next][0] ? 0 : 1;
    out.push_back({t0 + s * dt, uint8_t(line), uint8_t(seq[next][line])});
    idx = next;
  }
  return out;
}

TEST(Quadrature, DetentsAndDebounceFilter) {
  QuadratureDecoder q(4);
  q.set_levels(true, true);
  for (const auto& e : turn(5, 0, 1000)) q.edge(e);
  EXPECT_EQ(q.take_detents(), 5);
  for (const auto& e : turn(-3, 10000, 1000)) q.edge(e);
  EXPECT_EQ(q.take_detents(), -3);
  // With a 1 ms stable-time filter a 0.2 ms glitch pair is ignored entirely.
  QuadratureDecoder f(4, 1'000'000);
  f.set_levels(true, true);
  f.edge({0, 0, 0});
  f.edge({200'000, 0, 1});
  f.settle(5'000'000);
  EXPECT_EQ(f.quarter_steps(), 0u);
  // A genuine slow turn passes the filter with its steps in order.
  for (const auto& e : turn(2, 10'000'000, 3'000'000)) f.edge(e);
  f.settle(100'000'000);
  EXPECT_EQ(f.take_detents(), 2);
  EXPECT_EQ(f.position(), 8);
}

// Device timestamps are whatever a device or a recording says: at the int64 limits the debounce
// compares without overflow (the sanitizer build checks), and a One Euro filter stays finite.
TEST(Quadrature, TimestampsAtTheInt64LimitsDoNotOverflow) {
  EXPECT_TRUE(elapsed_at_least(INT64_MAX, INT64_MIN, 2'000'000));
  EXPECT_FALSE(elapsed_at_least(INT64_MIN, INT64_MAX, 0));
  EXPECT_TRUE(elapsed_at_least(INT64_MAX, INT64_MAX - 5, 5));
  EXPECT_FALSE(elapsed_at_least(INT64_MAX, INT64_MAX - 4, 5));
  QuadratureDecoder q(4, 2'000'000);
  q.edge({INT64_MIN, 0, 0});
  q.edge({INT64_MIN + 1, 1, 0});
  q.settle(INT64_MAX);
  q.edge({INT64_MAX, 0, 1});
  q.settle(INT64_MAX);
  OneEuro f;
  f.enabled = true;
  EXPECT_EQ(f.filter(0.25, INT64_MIN), 0.25);
  EXPECT_TRUE(std::isfinite(f.filter(0.75, INT64_MAX)));
}

}  // namespace
}  // namespace mar
