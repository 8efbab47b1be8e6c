#include "firmware_sim/microphone.h"

#include "base/read_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace mar {

namespace {

// Linear resampling to the microphone's rate (speech and test tones: enough).
std::vector<int16_t> resample(const std::vector<int16_t>& in, int from, int to) {
  if (from == to || in.empty()) return in;
  const size_t n = size_t(double(in.size()) * to / from);
  std::vector<int16_t> out(n);
  for (size_t i = 0; i < n; ++i) {
    const double x = double(i) * from / to;
    const size_t k = std::min(in.size() - 1, size_t(x));
    const double f = x - double(k);
    const double a = in[k], b = in[std::min(in.size() - 1, k + 1)];
    out[i] = int16_t(std::lround(a + f * (b - a)));
  }
  return out;
}

}  // namespace

Result<std::vector<int16_t>> read_wav(const std::string& path, int& rate) {
  using R = Result<std::vector<int16_t>>;
  Result<std::string> file = read_file(path, kMaxWavBytes, "a WAV file");
  if (!file.ok()) return R::failure(file.error);
  const std::string& b = *file.value;
  if (b.size() < 12 || std::memcmp(b.data(), "RIFF", 4) != 0 || std::memcmp(b.data() + 8, "WAVE", 4) != 0)
    return R::failure(path + ": not a WAV file (no RIFF/WAVE header)");
  uint16_t format = 0, channels = 0, bits = 0;
  uint32_t srate = 0;
  bool have_fmt = false;
  for (size_t i = 12; i + 8 <= b.size();) {
    uint32_t n = 0;
    std::memcpy(&n, &b[i + 4], 4);
    const size_t body = i + 8;
    if (n > b.size() - body) n = uint32_t(b.size() - body);
    if (std::memcmp(&b[i], "fmt ", 4) == 0 && n >= 16) {
      std::memcpy(&format, &b[body], 2);
      std::memcpy(&channels, &b[body + 2], 2);
      std::memcpy(&srate, &b[body + 4], 4);
      std::memcpy(&bits, &b[body + 14], 2);
      if (format == 0xFFFE && n >= 26) std::memcpy(&format, &b[body + 24], 2);  // WAVE_FORMAT_EXTENSIBLE's subformat
      have_fmt = true;
    } else if (std::memcmp(&b[i], "data", 4) == 0) {
      if (!have_fmt) return R::failure(path + ": the data comes before its format (no fmt chunk)");
      if (format != 1) return R::failure(path + ": not PCM (format " + std::to_string(format) + "); a microphone plays 16-bit PCM");
      if (bits != 16) return R::failure(path + ": " + std::to_string(bits) + "-bit samples; a microphone plays 16-bit PCM");
      if (channels < 1 || channels > 2) return R::failure(path + ": " + std::to_string(channels) + " channels; mono or stereo");
      if (srate < 8000 || srate > 48000)
        return R::failure(path + ": a sample rate of " + std::to_string(srate) + " Hz; the microphone takes 8,000 to 48,000");
      const size_t frames = n / (2u * channels);
      std::vector<int16_t> pcm(frames);
      for (size_t f = 0; f < frames; ++f) {
        int32_t sum = 0;
        for (uint16_t c = 0; c < channels; ++c) {
          int16_t s = 0;
          std::memcpy(&s, &b[body + (f * channels + c) * 2], 2);
          sum += s;
        }
        pcm[f] = int16_t(sum / channels);
      }
      rate = int(srate);
      return R::success(std::move(pcm));
    }
    i = body + n + (n & 1);
  }
  return R::failure(path + ": no audio data in the WAV file");
}

Result<std::unique_ptr<MicrophoneSim>> MicrophoneSim::make(const std::string& file, const std::string& dir) {
  using R = Result<std::unique_ptr<MicrophoneSim>>;
  std::unique_ptr<MicrophoneSim> m(new MicrophoneSim());
  m->dir_ = dir;
  if (!file.empty()) {
    int rate = 0;
    auto pcm = read_wav(file, rate);
    if (!pcm.ok()) return R::failure(pcm.error);
    const std::vector<int16_t> at = resample(*pcm.value, rate, kRate);
    m->place(0, at);
    m->rebuild();
    m->finish();
  }
  return R::success(std::move(m));
}

void MicrophoneSim::place(double t, std::span<const int16_t> pcm) {
  const size_t at = size_t(std::max(0.0, t) * kRate);
  if (track_.size() < at + pcm.size()) track_.resize(at + pcm.size(), 0);
  for (size_t i = 0; i < pcm.size(); ++i)
    track_[at + i] = int16_t(std::clamp(int32_t(track_[at + i]) + pcm[i], -32768, 32767));  // sounds that overlap mix
}

void MicrophoneSim::rebuild() {
  // The whole track as blocks, and half a second of silence after it (the mouth closes).
  timeline_.clear();
  const size_t total = track_.size() + kRate / 2;
  constexpr size_t kBlock = WireRecord::kMax / 2;
  int16_t buf[kBlock];
  for (size_t i = 0; i < total; i += kBlock) {
    const size_t n = std::min(kBlock, total - i);
    for (size_t k = 0; k < n; ++k) buf[k] = i + k < track_.size() ? track_[i + k] : 0;
    // stamped when its last sample is in, as a capture device delivers it
    emit(to_ns(double(i + n) / kRate), std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(buf), n * 2));
  }
}

Result<bool> MicrophoneSim::action(double t, const std::vector<std::string>& w) {
  using R = Result<bool>;
  if (w[0] == "play") {
    if (w.size() != 2) return R::failure("expected 'play FILE.wav'");
    std::filesystem::path f(w[1]);
    if (f.is_relative() && !dir_.empty()) f = std::filesystem::path(dir_) / f;
    int rate = 0;
    auto pcm = read_wav(f.string(), rate);
    if (!pcm.ok()) return R::failure(pcm.error);
    place(t, resample(*pcm.value, rate, kRate));
    rebuild();
    return R::success(true);
  }
  if (w[0] != "say") return R::failure("unknown action '" + w[0] + "' (a microphone can: say \"TEXT\" [voice V], play FILE.wav)");
  std::vector<std::string> words(w.begin() + 1, w.end());
  std::string voice = "en";
  if (words.size() >= 2 && words[words.size() - 2] == "voice") {
    voice = words.back();
    words.resize(words.size() - 2);
  }
  std::string text;
  for (const std::string& s : words) text += (text.empty() ? "" : " ") + s;
  if (text.size() >= 2 && text.front() == '"' && text.back() == '"') text = text.substr(1, text.size() - 2);
  if (text.find_first_not_of(" \t") == std::string::npos) return R::failure("say has nothing to say (say \"TEXT\")");
  // espeak-ng, run directly (no shell), into a temporary WAV.
  char tmp[] = "/tmp/marionette-say-XXXXXX";
  const int fd = ::mkstemp(tmp);
  if (fd < 0) return R::failure("cannot make a temporary file for speech");
  ::close(fd);
  const std::string out = tmp;
  std::vector<std::string> args{"espeak-ng", "-v", voice, "-w", out, "--", text};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  const int rc = posix_spawnp(&pid, "espeak-ng", &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  int status = 0;
  if (rc == 0) ::waitpid(pid, &status, 0);
  if (rc != 0) {
    std::remove(out.c_str());
    return R::failure("espeak-ng is not installed (Debian package espeak-ng): a microphone's say lines need it");
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::remove(out.c_str());
    return R::failure("espeak-ng could not say it (voice '" + voice + "'?)");
  }
  int rate = 0;
  auto pcm = read_wav(out, rate);
  std::remove(out.c_str());
  if (!pcm.ok()) return R::failure(pcm.error);
  place(t, resample(*pcm.value, rate, kRate));
  rebuild();
  return R::success(true);
}

}  // namespace mar
