// Video takes (output/video_out.h): a recorded take rendered offline to FFV1 decodes, frame for
// frame, to exactly what the live show drew (its --dump-frames), each frame at its show time;
// ProRes 4444 keeps a transparent background's alpha; H.264 is close; a live run records as it
// plays; an unknown codec, a file name with no container and a full disk are refused or said.
// Decoding and probing go through ffmpeg and ffprobe (Debian package ffmpeg), independent readers.
#include "output/video_out.h"
#include "render/image.h"
#include "test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace mar {
namespace {

bool have_ffmpeg() { return std::system("command -v ffmpeg >/dev/null 2>&1 && command -v ffprobe >/dev/null 2>&1") == 0; }

// The candle at 96x96 with a nanoKONTROL2 blowing on its flame: every frame differs.
std::string candle_show(const std::string& name, const std::string& background) {
  return test::write_temp(name + ".toml", "[show]\nrig = \"" + (test::source_dir() / "config/rigs/candle.toml").string() +
                                              "\"\nrate = 60\niterations = 6\n[display]\nwidth = 96\nheight = 96\nbackground = \"" + background +
                                              "\"\n[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\nscript = \"\"\"\n0.0 move knob1 0.5\n"
                                              "0.2 move knob1 0.1 over 0.6\n1.0 move knob1 0.9 over 0.8\n\"\"\"\n"
                                              "[[binding]]\ndevice = \"korg\"\ncontrol = \"cc 16\"\ntarget = \"physics.wind\"\nrange = [-1500.0, 1500.0]\n");
}

// Every frame of `video` as RGBA (ffmpeg decodes), `w` x `h`.
std::vector<std::vector<uint8_t>> decode(const std::filesystem::path& video, int w, int h) {
  const auto raw = video.parent_path() / (video.stem().string() + ".rgba");
  const std::string cmd = "ffmpeg -v error -y -i '" + video.string() + "' -fps_mode passthrough -f rawvideo -pix_fmt rgba '" + raw.string() + "'";
  if (std::system(cmd.c_str()) != 0) return {};
  std::ifstream in(raw, std::ios::binary);
  const std::vector<uint8_t> all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::vector<uint8_t>> frames;
  const size_t n = size_t(w) * size_t(h) * 4;
  for (size_t at = 0; at + n <= all.size(); at += n) frames.emplace_back(all.begin() + long(at), all.begin() + long(at + n));
  return frames;
}

nlohmann::json probe(const std::filesystem::path& video) {
  const auto out = video.parent_path() / (video.stem().string() + ".probe.json");
  const std::string cmd = "ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,pix_fmt,width,height -show_entries frame=pts_time -of json '" +
                          video.string() + "' > '" + out.string() + "'";
  if (std::system(cmd.c_str()) != 0) return {};
  std::ifstream in(out);
  return nlohmann::json::parse(in);
}

std::vector<uint8_t> png(const std::filesystem::path& dir, int frame) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06d.png", frame);
  auto img = read_png_image((dir / name).string());
  return img.ok() ? img.value->rgba : std::vector<uint8_t>{};
}

TEST(VideoTake, AReplayInFfv1IsFrameForFrameWhatTheLiveShowDrew) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg and ffprobe are not installed (Debian package ffmpeg): nothing to decode with";
  const std::string show = candle_show("video_live", "#f4f1ea");
  const auto dir = test::temp_dir("video_ffv1");
  auto live = test::run_cli("run " + show + " --headless --frames 120 --record " + (dir / "take.rec").string() + " --dump-frames " +
                            (dir / "live").string() + " --every 1");
  ASSERT_EQ(live.exit_code, 0) << live.err;
  auto rep = test::run_cli("replay " + (dir / "take.rec").string() + " --show " + show + " --video " + (dir / "take.mkv").string() +
                           " --stats " + (dir / "stats.json").string());
  ASSERT_EQ(rep.exit_code, 0) << rep.err;
  EXPECT_NE(rep.out.find("120 frames encoded (ffv1) to"), std::string::npos) << rep.out;

  const auto p = probe(dir / "take.mkv");
  ASSERT_FALSE(p.is_null());
  EXPECT_EQ(p["streams"][0]["codec_name"], "ffv1");
  EXPECT_EQ(p["streams"][0]["pix_fmt"], "bgra") << "alpha kept";
  EXPECT_EQ(p["streams"][0]["width"], 96);
  ASSERT_EQ(p["frames"].size(), 120u);
  for (size_t k = 0; k < 120; ++k)  // each frame at its show time (the file's clock is in ms)
    EXPECT_NEAR(std::stod(p["frames"][k]["pts_time"].get<std::string>()), double(k) / 60, 0.0006) << k;

  const auto frames = decode(dir / "take.mkv", 96, 96);
  ASSERT_EQ(frames.size(), 120u);
  int distinct = 0;
  for (int k = 0; k < 120; ++k) {
    const auto drawn = png(dir / "live", k);
    ASSERT_FALSE(drawn.empty()) << k;
    ASSERT_EQ(frames[size_t(k)], drawn) << "frame " << k << " decodes to what the live show drew";
    distinct += k > 0 && frames[size_t(k)] != frames[size_t(k) - 1];
  }
  EXPECT_GE(distinct, 60) << "the flame moves";
  std::ifstream sj(dir / "stats.json");
  const auto stats = nlohmann::json::parse(sj);
  EXPECT_EQ(stats["video"]["written"], 120);
  EXPECT_EQ(stats["video"]["dropped"], 0);
  EXPECT_EQ(stats["heap_allocations_after_warmup"], 0);
}

TEST(VideoTake, ProRes4444KeepsAlphaAndH264IsClose) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg and ffprobe are not installed (Debian package ffmpeg): nothing to decode with";
  const auto dir = test::temp_dir("video_codecs");
  const std::string show = candle_show("video_alpha", "transparent");
  auto live = test::run_cli("run " + show + " --headless --frames 30 --record " + (dir / "take.rec").string());
  ASSERT_EQ(live.exit_code, 0) << live.err;
  struct Case {
    const char* codec;
    const char* file;
    const char* pix_fmt;
    double max_mean_error;  ///< per channel, on 0..255, over pixels with alpha
  };
  for (const Case c : {Case{"prores4444", "take.mov", "yuva444p", 2.0}, Case{"h264", "take.mp4", "yuv420p", 6.0}}) {
    const auto video = dir / c.file;
    const auto dumps = dir / (std::string("dumps-") + c.codec);
    auto rep = test::run_cli("replay " + (dir / "take.rec").string() + " --show " + show + " --size 128x96 --video " + video.string() + " --codec " +
                             c.codec + " --dump-frames " + dumps.string() + " --every 1");
    ASSERT_EQ(rep.exit_code, 0) << c.codec << ": " << rep.err;
    const auto p = probe(video);
    ASSERT_FALSE(p.is_null()) << c.codec;
    EXPECT_EQ(p["streams"][0]["pix_fmt"].get<std::string>().rfind(c.pix_fmt, 0), 0u) << c.codec << ": " << p["streams"][0]["pix_fmt"];
    EXPECT_EQ(p["streams"][0]["width"], 128) << "--size";
    const auto frames = decode(video, 128, 96);
    ASSERT_EQ(frames.size(), 30u) << c.codec;
    double err = 0, alpha_err = 0;
    size_t n = 0, transparent = 0;
    for (int k = 0; k < 30; ++k) {
      const auto drawn = png(dumps, k);
      ASSERT_EQ(drawn.size(), frames[size_t(k)].size());
      for (size_t i = 0; i < drawn.size(); i += 4) {
        alpha_err += std::abs(int(frames[size_t(k)][i + 3]) - int(drawn[i + 3]));
        transparent += drawn[i + 3] == 0;
        if (drawn[i + 3] < 255) continue;
        for (int ch = 0; ch < 3; ++ch) err += std::abs(int(frames[size_t(k)][i + size_t(ch)]) - int(drawn[i + size_t(ch)]));
        n += 3;
      }
    }
    const double mean = n ? err / double(n) : 0, mean_alpha = alpha_err / (30.0 * 128 * 96);
    std::printf("%s: mean error %.2f per colour channel on opaque pixels, %.2f on alpha\n", c.codec, mean, mean_alpha);
    EXPECT_GT(transparent, size_t(30 * 128 * 96 / 4)) << "the background is transparent";
    EXPECT_LT(mean, c.max_mean_error) << c.codec;
    if (std::string(c.codec) == "prores4444") {
      EXPECT_LT(mean_alpha, 0.5) << "alpha kept";
    } else {
      EXPECT_GT(mean_alpha, 50.0) << "h264 has no alpha: the transparent background comes out opaque";
    }
  }
}

TEST(VideoTake, ALiveRunRecordsAsItPlays) {
  if (!have_ffmpeg()) GTEST_SKIP() << "ffmpeg and ffprobe are not installed (Debian package ffmpeg): nothing to decode with";
  const auto dir = test::temp_dir("video_live");
  const std::string show = candle_show("video_rt", "#102030");
  auto r = test::run_cli("run " + show + " --headless --realtime --frames 90 --video " + (dir / "live.mkv").string() + " --stats " +
                         (dir / "stats.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream sj(dir / "stats.json");
  const auto stats = nlohmann::json::parse(sj);
  EXPECT_EQ(stats["video"]["pushed"], 90);
  EXPECT_EQ(stats["video"]["written"].get<int>() + stats["video"]["dropped"].get<int>(), 90) << "each frame encoded or counted";
  EXPECT_EQ(stats["heap_allocations_after_warmup"], 0) << "the frame thread only copies";
  const auto p = probe(dir / "live.mkv");
  ASSERT_FALSE(p.is_null());
  EXPECT_EQ(p["frames"].size(), stats["video"]["written"].get<size_t>());
}

TEST(VideoTake, BadTakesAreRefusedOrSaid) {
  const std::string show = candle_show("video_bad", "#102030");
  const auto dir = test::temp_dir("video_bad");
  auto codec = test::run_cli("run " + show + " --headless --frames 5 --video " + (dir / "a.mkv").string() + " --codec theora");
  EXPECT_EQ(codec.exit_code, 2);
  EXPECT_NE(codec.err.find("unknown codec 'theora'; --codec is one of ffv1, prores4444, h264"), std::string::npos) << codec.err;
  auto ext = test::run_cli("run " + show + " --headless --frames 5 --video " + (dir / "a.take").string());
  EXPECT_NE(ext.exit_code, 0);
  EXPECT_NE(ext.err.find("a.take: no container for this file name"), std::string::npos) << ext.err;
  auto odd = VideoOut::open({(dir / "odd.mp4").string(), "h264", 95, 96});
  ASSERT_FALSE(odd.ok());
  EXPECT_NE(odd.error.find("h264 needs an even width and height"), std::string::npos) << odd.error;
  // The disk fills mid-take (a file-size limit: writes past 60 kB fail with EFBIG): said with
  // the file's name and counted; the show plays to its end; the run exits 1.
  auto full = test::run_cli("run " + show + " --headless --frames 300 --video " + (dir / "full.mkv").string() + " --stats " + (dir / "s.json").string(),
                            "trap '' XFSZ; prlimit --fsize=60000 --");
  EXPECT_EQ(full.exit_code, 1) << full.err;
  EXPECT_NE(full.err.find("full.mkv: writing the video"), std::string::npos) << full.err;
  std::ifstream sj(dir / "s.json");
  const auto stats = nlohmann::json::parse(sj);
  EXPECT_EQ(stats["frames"], 300) << "the show played to its end";
  EXPECT_GT(stats["video"]["dropped"].get<int>(), 0);
  EXPECT_EQ(stats["video"]["written"].get<int>() + stats["video"]["dropped"].get<int>(), 300);
}

}  // namespace
}  // namespace mar
