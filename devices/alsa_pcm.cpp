// A voice from a microphone: ALSA capture (type = "audio"; `pcm` names the device, "default"
// unless the show says "hw:1,0" or a plugin). A capture thread of its own reads mono 16-bit PCM
// at 22,050 Hz (ALSA resamples when the card cannot) in blocks of 48 samples, stamps each with
// its read time and hands it to the frame through a ring: the blocks are the wire records,
// which recordings keep and the audio decoder (input/voice.h) turns into level, visemes and
// onsets. A full ring (a frame thread that stalled for longer than the ring holds) drops blocks,
// counted as malformed.
#include "devices/alsa_seq.h"
#include "devices/backends.h"
#include "devices/spsc.h"

#include <alsa/asoundlib.h>

#include <atomic>
#include <fstream>
#include <sstream>
#include <cerrno>
#include <thread>

namespace mar {
namespace {

constexpr unsigned kRate = 22050;
constexpr snd_pcm_uframes_t kBlock = WireRecord::kMax / 2;

class AudioBackend final : public Backend {
 public:
  using Backend::Backend;
  ~AudioBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (pcm_) snd_pcm_close(pcm_);
    pcm_ = nullptr;
  }
  bool poll(int64_t, WireSink& out) override {
    WireRecord r;
    while (ring_.pop(r)) emit(r, out);
    return !gone_;
  }

 private:
  void capture();
  snd_pcm_t* pcm_ = nullptr;
  std::atomic<bool> stop_{false}, gone_{false};
  std::thread thread_;
  SpscRing<WireRecord, 4096> ring_;  ///< about 9 s of audio
};

DeviceState AudioBackend::open() {
  quiet_alsa_errors();
  const std::string name = spec_.pcm.empty() ? "default" : spec_.pcm;
  int rc = snd_pcm_open(&pcm_, name.c_str(), SND_PCM_STREAM_CAPTURE, 0);
  if (rc < 0) {
    pcm_ = nullptr;
    if (rc == -EACCES || rc == -EPERM) {
      problem_ = "permission denied on the ALSA capture device '" + name + "': add yourself to the 'audio' group";
      return DeviceState::Denied;
    }
    problem_ = "no ALSA capture device '" + name + "' (" + snd_strerror(rc) + "; arecord -l lists them)";
    return rc == -EBUSY || rc == -ENOENT || rc == -ENODEV ? DeviceState::Waiting : DeviceState::Unavailable;
  }
  rc = snd_pcm_set_params(pcm_, SND_PCM_FORMAT_S16_LE, SND_PCM_ACCESS_RW_INTERLEAVED, 1, kRate, 1, 20000);
  if (rc < 0) {
    problem_ = "ALSA capture '" + name + "': mono 16-bit at 22050 Hz not available (" + snd_strerror(rc) + ")";
    snd_pcm_close(pcm_);
    pcm_ = nullptr;
    return DeviceState::Unavailable;
  }
  config_ = DecoderConfig{};
  config_.kind = WireKind::AudioPcm;
  config_.audio_rate = int32_t(kRate);
  config_.voice = spec_.voice;
  identity_ = "ALSA capture " + name;
  node_ = "alsa-pcm:" + name;
  problem_.clear();
  stop_ = false;
  gone_ = false;
  thread_ = std::thread([this] { capture(); });
  return DeviceState::Connected;
}

void AudioBackend::capture() {
  int16_t buf[kBlock];
  while (!stop_) {
    const snd_pcm_sframes_t n = snd_pcm_readi(pcm_, buf, kBlock);
    if (n == -EPIPE || n == -ESTRPIPE) {  // an overrun (or a suspend): start again, counted
      count_malformed();
      snd_pcm_prepare(pcm_);
      continue;
    }
    if (n == -EAGAIN || n == -EINTR) continue;
    if (n < 0) {  // the device went (unplugged)
      gone_ = true;
      return;
    }
    if (n == 0) continue;
    const WireRecord r = audio_record(read_time(), std::span<const int16_t>(buf, size_t(n)), source_);
    if (!ring_.push(r)) count_malformed();
  }
}

}  // namespace

std::unique_ptr<Backend> make_audio_backend(const DeviceSpec& s, uint16_t source) { return std::make_unique<AudioBackend>(s, source); }

BackendReport discover_audio(const std::vector<ProfileId>&) {
  // The sound cards the kernel has (a capture device is one of their PCMs), read from
  // /proc/asound/cards (" 0 [PCH ]: HDA-Intel - HDA Intel PCH"); none is said, not "ok".
  BackendReport r{"audio", "ok", {}};
  std::ifstream in("/proc/asound/cards");
  for (std::string line; std::getline(in, line);) {
    std::istringstream w(line);
    int card = -1;
    if (!(w >> card) || line.find(']') == std::string::npos) continue;  // (the second line of each card)
    FoundDevice f;
    f.backend = "audio";
    std::string name = line.substr(line.find(']') + 1);
    if (const size_t dash = name.find(" - "); dash != std::string::npos) name = name.substr(dash + 3);
    f.identity = "hw:" + std::to_string(card) + " '" + name + "'";
    f.node = "/dev/snd/pcmC" + std::to_string(card) + "D0c";
    f.status = "available";
    r.found.push_back(f);
  }
  if (r.found.empty()) r.status = "no sound card (the kernel lists none; a show's microphone can be simulated: sim = \"microphone\")";
  return r;
}

}  // namespace mar
