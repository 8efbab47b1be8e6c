// The base every library uses (src/base): the TOML nesting check before toml++ parses, and
// reading a file named from outside within its limit, refusing what is not a regular file
// without blocking.
#include "base/config_toml.h"
#include "base/read_file.h"
#include "test_util.h"

#include "base/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>

namespace mar {
namespace {

// The nesting check counts what toml++ would recurse into: dotted key segments (in keys and
// table headers, not in floats or strings), inline tables and arrays.
TEST(TomlNesting, CountsKeysTablesAndArraysNotStringsOrNumbers) {
  auto deep = [](const std::string& text) { return !cfg::toml_nesting_problem(text, "t.toml", 8).empty(); };
  EXPECT_FALSE(deep("a.b.c.d = 1.5\n[x.y.z]\nq = [1.5, 2.5, [3.5]]\n"));
  EXPECT_TRUE(deep("a.b.c.d.e.f.g.h.i = 1\n"));
  EXPECT_TRUE(deep("[a.b.c.d.e.f.g.h.i]\n"));
  EXPECT_TRUE(deep("[[a.b.c.d.e.f.g.h.i]]\n"));
  EXPECT_TRUE(deep("x = [[[[[[[[[1]]]]]]]]]\n"));
  EXPECT_TRUE(deep("x = {a = {b = {c = {d.e.f.g.h = 1}}}}\n"));
  EXPECT_FALSE(deep("x = {a = {b = {c = {d.e.f.g = 1}}}}\n"));  // eight: at the limit
  EXPECT_FALSE(deep("x = \"a.b.c.d.e.f.g.h.i.j\"\ny = 1.2\n# a.b.c.d.e.f.g.h.i [[[[[[[[[[\n"));
  EXPECT_FALSE(deep("x = \"\"\"\n[[[[[[[[[[\n\"\"\"\ny = '''\n{{{{{{{{{{\n'''\n"));
  EXPECT_FALSE(deep("\"a.b.c.d.e.f.g.h.i.j\" = 1\n"));
  const std::string why = cfg::toml_nesting_problem("ok = 1\n\na.b.c.d.e.f.g.h.i = 1\n", "t.toml", 8);
  EXPECT_EQ(why, "t.toml:3: keys, tables or arrays nest deeper than 8 levels (the limit); file refused");
  // Through parse_toml, as every reader parses: refused before toml++ sees it.
  std::string key = "a";
  for (int k = 0; k < 50000; ++k) key += ".a";
  const auto r = cfg::parse_toml(key + " = 1\n", "deep.toml");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("deep.toml:1: keys, tables or arrays nest deeper than 64"), std::string::npos);
  const auto bad = cfg::parse_toml("x = = 1\n", "bad.toml");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error.rfind("bad.toml:1: ", 0), 0u) << bad.error;
}

TEST(ReadFile, AFileWithinItsLimitIsReadAndOtherThingsAreRefusedByName) {
  const auto dir = test::temp_dir("base-read");
  const std::string small = (dir / "small.toml").string();
  ASSERT_TRUE(bool(std::ofstream(small) << "a = 1\n"));
  auto ok = read_file(small, 100, "a test file");
  ASSERT_TRUE(ok.ok()) << ok.error;
  EXPECT_EQ(*ok.value, "a = 1\n");
  auto big = read_file(small, 3, "a test file");
  ASSERT_FALSE(big.ok());
  EXPECT_EQ(big.error.rfind(small, 0), 0u) << "the message starts with the path: " << big.error;
  EXPECT_NE(big.error.find("a test file"), std::string::npos) << big.error;
  auto folder = read_file(dir.string(), 100, "a test file");
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.error.find("directory"), std::string::npos) << folder.error;
  // a FIFO with no writer: refused at once, not waited on
  const std::string fifo = (dir / "pipe").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  auto pipe = read_file(fifo, 100, "a test file");
  ASSERT_FALSE(pipe.ok());
  EXPECT_NE(pipe.error.find("FIFO"), std::string::npos) << pipe.error;
  EXPECT_EQ(file_problem(small, 100, "a test file"), "");
}

// The worker pool runs every item exactly once per run, whatever thread takes it, run after
// run (each run's items see that run's job: no helper is still in the last one), and a pool of
// one thread is a plain loop.
TEST(WorkerPool, EveryItemRunsOncePerRunOnAnyNumberOfThreads) {
  for (int threads : {1, 2, 4}) {
    WorkerPool pool(threads);
    EXPECT_EQ(pool.threads(), threads);
    std::vector<std::atomic<int>> hits(37);
    for (int run = 0; run < 2000; ++run) {
      const int add = run % 3 + 1;
      auto job = [&](size_t i) { hits[i].fetch_add(add, std::memory_order_relaxed); };
      pool.run(hits.size(), job);
    }
    int want = 0;
    for (int run = 0; run < 2000; ++run) want += run % 3 + 1;
    for (size_t i = 0; i < hits.size(); ++i) {
      EXPECT_EQ(hits[i].load(), want) << "item " << i << " with " << threads << " threads";
    }
    if (threads == 1) {
      EXPECT_EQ(pool.helped(), 0u);
    }
  }
}

}  // namespace
}  // namespace mar
