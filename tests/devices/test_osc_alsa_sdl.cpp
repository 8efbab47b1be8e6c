// OSC over UDP (liblo), the ALSA sequencer (none on this machine: the message says so, and
// the event conversion is checked with ALSA's own codec) and SDL game controllers (a
// virtual joystick).
#include "bench_util.h"
#include "devices/alsa_seq.h"
#include "devices/backends.h"
#include "test_util.h"

#include <SDL.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <lo/lo.h>

#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

namespace mar {
namespace {

TEST(OscBackend, BoundAddressPatternsBecomeEventsAndGarbageIsCounted) {
  DeviceSpec s;
  s.name = "osc";
  s.type = "osc";
  s.port = 39517;
  s.osc_addresses = {"/fader/1", "/pad/*/x"};
  const int64_t epoch = monotonic_ns();
  DeviceSet set(epoch);
  set.add(make_osc_backend(s, 3));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
  EXPECT_EQ(set.backend(0).identity(), "osc.udp://127.0.0.1:39517");
  lo_address to = lo_address_new("127.0.0.1", "39517");
  lo_send(to, "/fader/1", "f", 0.5f);
  lo_send(to, "/pad/2/x", "i", 100);
  lo_send(to, "/unbound", "f", 1.0f);
  // Not OSC: a stray datagram.
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(39517);
  inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
  const char junk[] = "\x01garbage";
  sendto(fd, junk, sizeof junk, 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
  close(fd);
  std::vector<Event> got;
  ASSERT_TRUE(test::poll_until(set, epoch, got, [&] { return got.size() >= 2 && set.status(0).malformed >= 1; }, 3000));
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].source, 3);
  EXPECT_EQ(got[0].number, 0xFF000000u);
  EXPECT_EQ(got[0].value, 32768);  // 0.5 of 0..65535
  EXPECT_EQ(got[1].number, 0xFF000001u);
  EXPECT_EQ(got[1].value, 100);
  EXPECT_EQ(got[1].hi, 127);
  EXPECT_EQ(set.status(0).malformed, 1u);
  lo_address_free(to);
}

TEST(OscBackend, APortInUseIsReportedNotFatal) {
  DeviceSpec s;
  s.type = "osc";
  s.port = 39518;
  DeviceSet a(monotonic_ns()), b(monotonic_ns());
  a.add(make_osc_backend(s, 0));
  b.add(make_osc_backend(s, 0));
  a.start();
  b.start();
  EXPECT_EQ(a.state(0), DeviceState::Connected);
  EXPECT_EQ(b.state(0), DeviceState::Unavailable);
  EXPECT_NE(b.problem(0).find("cannot listen on 127.0.0.1:39518"), std::string::npos) << b.problem(0);
}

TEST(AlsaSeqBackend, WithoutASequencerTheProblemIsStated) {
  if (access("/dev/snd/seq", F_OK) == 0) GTEST_SKIP() << "this machine has an ALSA sequencer";
  DeviceSpec s;
  s.type = "alsa";
  DeviceSet set(monotonic_ns());
  set.add(make_alsa_backend(s, 0));
  set.start();
  EXPECT_EQ(set.state(0), DeviceState::Unavailable);
  EXPECT_NE(set.problem(0).find("no ALSA sequencer (/dev/snd/seq"), std::string::npos) << set.problem(0);
}

TEST(AlsaSeqBackend, SequencerEventsBecomeMidiBytes) {
  snd_midi_event_t* codec = nullptr;
  ASSERT_EQ(snd_midi_event_new(64, &codec), 0);
  snd_midi_event_no_status(codec, 1);
  snd_seq_event_t ev{};
  snd_seq_ev_set_noteon(&ev, 2, 60, 100);
  uint8_t b[8];
  ASSERT_EQ(alsa_event_bytes(codec, ev, b, sizeof b), 3u);
  EXPECT_EQ(b[0], 0x92);
  EXPECT_EQ(b[1], 60);
  EXPECT_EQ(b[2], 100);
  snd_seq_ev_set_controller(&ev, 0, 7, 64);
  ASSERT_EQ(alsa_event_bytes(codec, ev, b, sizeof b), 3u);
  EXPECT_EQ(b[0], 0xB0);  // full status each time: running status is the decoder's business
  EXPECT_EQ(b[1], 7);
  snd_seq_ev_set_pitchbend(&ev, 1, 1000);
  ASSERT_EQ(alsa_event_bytes(codec, ev, b, sizeof b), 3u);
  EXPECT_EQ(b[0], 0xE1);
  EXPECT_EQ((b[2] << 7 | b[1]) - 8192, 1000);
  snd_midi_event_free(codec);
}

TEST(SdlBackend, VirtualGameControllerSticksAndButtons) {
  SDL_SetHint(SDL_HINT_JOYSTICK_ALLOW_BACKGROUND_EVENTS, "1");
  ASSERT_EQ(SDL_InitSubSystem(SDL_INIT_GAMECONTROLLER), 0) << SDL_GetError();
  SDL_VirtualJoystickDesc d{};
  d.version = SDL_VIRTUAL_JOYSTICK_DESC_VERSION;
  d.type = SDL_JOYSTICK_TYPE_GAMECONTROLLER;
  d.naxes = SDL_CONTROLLER_AXIS_MAX;
  d.nbuttons = SDL_CONTROLLER_BUTTON_MAX;
  d.vendor_id = 0x054c;
  d.product_id = 0x09cc;
  d.name = "Virtual Pad";
  const int index = SDL_JoystickAttachVirtualEx(&d);
  ASSERT_GE(index, 0) << SDL_GetError();
  DeviceSpec s;
  s.type = "sdl";
  s.sdl = "gamepad";
  s.vid = 0x054c;
  const int64_t epoch = monotonic_ns();
  auto set_ptr = std::make_unique<DeviceSet>(epoch);  // stopped before SDL quits (its thread calls SDL)
  DeviceSet& set = *set_ptr;
  set.add(make_sdl_backend(s, 0));
  set.start();
  ASSERT_EQ(set.state(0), DeviceState::Connected) << set.problem(0);
  SDL_Joystick* j = SDL_JoystickOpen(index);
  SDL_JoystickSetVirtualAxis(j, SDL_CONTROLLER_AXIS_LEFTX, 16000);
  SDL_JoystickSetVirtualButton(j, SDL_CONTROLLER_BUTTON_A, 1);
  std::vector<Event> got;
  auto has = [&](uint32_t usage, int32_t v) {
    for (const Event& e : got)
      if (e.number == usage && e.value == v) return true;
    return false;
  };
  EXPECT_TRUE(test::poll_until(set, epoch, got, [&] { return has(0x010030, 16000) && has(0x090001, 1); }, 2000));
  SDL_JoystickClose(j);
  SDL_JoystickDetachVirtual(index);
  EXPECT_TRUE(test::poll_until(set, epoch, got, [&] { return set.state(0) == DeviceState::Unplugged; }, 2000));
  set_ptr.reset();
  SDL_QuitSubSystem(SDL_INIT_GAMECONTROLLER);
}

}  // namespace
}  // namespace mar

namespace mar {
namespace {

// A voice through ALSA capture, the real library all the way: ALSA's file plugin reads a
// recorded voice (espeak-ng's) as the capture device (a PCM defined in an .asoundrc in the
// run's HOME), and the show's visemes pick the singer's mouth. A PCM that is not there is a
// device that waits and names it.
TEST(AudioBackend, AVoiceCapturedThroughAlsaPicksTheMouth) {
  if (std::system("command -v espeak-ng >/dev/null 2>&1") != 0) GTEST_SKIP() << "espeak-ng is not installed (Debian package espeak-ng)";
  const auto dir = test::temp_dir("alsa_capture");
  const std::string raw = (dir / "voice.raw").string(), wav = (dir / "voice.wav").string();
  ASSERT_EQ(std::system(("espeak-ng -v en -w '" + wav + "' 'Hello, oh so gladly.' 2>/dev/null").c_str()), 0);
  // the WAV's samples after its 44-byte header, as the raw input (espeak writes 22,050 Hz mono)
  {
    std::ifstream in(wav, std::ios::binary);
    std::vector<char> b((std::istreambuf_iterator<char>(in)), {});
    ASSERT_GT(b.size(), 44u);
    std::ofstream(raw, std::ios::binary).write(b.data() + 44, long(b.size() - 44));
  }
  std::ofstream(dir / ".asoundrc") << "pcm.marionette_test {\n  type file\n  slave.pcm \"null\"\n  file \"/dev/null\"\n  infile \"" << raw
                                   << "\"\n  format \"raw\"\n}\n";
  const std::string show = test::write_temp("alsa_voice.toml", "[show]\nrig = \"" + (test::source_dir() / "config/rigs/singer.toml").string() +
                                                                  "\"\n[[device]]\nname = \"mic\"\ntype = \"audio\"\npcm = \"marionette_test\"\n"
                                                                  "[[binding]]\ndevice = \"mic\"\ncontrol = \"viseme o\"\ntarget = \"swap.mouth.mouth-o\"\n"
                                                                  "[[binding]]\ndevice = \"mic\"\ncontrol = \"viseme a\"\ntarget = \"swap.mouth.mouth-a\"\n"
                                                                  "[[binding]]\ndevice = \"mic\"\ncontrol = \"viseme closed\"\ntarget = \"swap.mouth.mouth-smile\"\n");
  auto r = test::run_cli("run '" + show + "' --headless --frames 90 --stats '" + (dir / "s.json").string() + "'", "HOME='" + dir.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  std::ifstream f(dir / "s.json");
  const auto j = nlohmann::json::parse(f);
  const auto& dev = j["devices"][0];
  EXPECT_EQ(dev["status"], "connected") << dev.dump();
  // (the file plugin over ALSA's null device reads as fast as it is asked, unpaced: the ring
  // overflows and counts the blocks it drops; a real card delivers 22,050 samples a second)
  EXPECT_GT(dev["records"].get<int>(), 100) << "PCM blocks read";
  EXPECT_GT(dev["events"].get<int>(), 10) << "a level, visemes, onsets";
  EXPECT_GT(j["events"]["mapped"].get<int>(), 2) << "the mouth picked";
  // an ALSA device that is not there is a device that waits, and says so
  auto none = test::run_cli("run '" + test::write_temp("alsa_none.toml", "[show]\nrig = \"" + (test::source_dir() / "config/rigs/singer.toml").string() +
                                                                            "\"\n[[device]]\nname = \"mic\"\ntype = \"audio\"\npcm = \"nonexistent_pcm\"\n") +
                            "' --headless --frames 5 --stats '" + (dir / "n.json").string() + "'");
  ASSERT_EQ(none.exit_code, 0) << none.err;
  std::ifstream nf(dir / "n.json");
  const auto nj = nlohmann::json::parse(nf);
  EXPECT_NE(nj["devices"][0]["status"], "present");
  EXPECT_NE(nj["devices"][0].dump().find("nonexistent_pcm"), std::string::npos) << nj["devices"][0].dump();
}

}  // namespace
}  // namespace mar
