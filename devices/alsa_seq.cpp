// MIDI input from the ALSA sequencer: a "marionette" client with one writable port, so
// software MIDI sources and virtual ports can feed a show (and hardware the kernel's
// driver already owns). Sequencer events are turned back into MIDI bytes with
// snd_midi_event: the wire records are MIDI bytes, decoded like any MIDI stream.
#include "devices/alsa_seq.h"
#include "devices/backends.h"
#include "devices/util.h"

#include <alsa/asoundlib.h>

#include <poll.h>

#include <cerrno>

namespace mar {

namespace {
void ignore_alsa_error(const char*, int, const char*, int, const char*, ...) {}
}  // namespace

void quiet_alsa_errors() { snd_lib_error_set_handler(&ignore_alsa_error); }

size_t alsa_event_bytes(snd_midi_event_t* codec, const snd_seq_event_t& ev, uint8_t* out, size_t cap) {
  const long n = snd_midi_event_decode(codec, out, long(cap), const_cast<snd_seq_event_t*>(&ev));
  return n > 0 ? size_t(n) : 0;
}

namespace {

class AlsaSeqBackend final : public Backend {
 public:
  using Backend::Backend;
  ~AlsaSeqBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    if (codec_) snd_midi_event_free(codec_);
    if (seq_) snd_seq_close(seq_);
    codec_ = nullptr;
    seq_ = nullptr;
    fds_.clear();
  }
  bool present() const override { return devutil::exists("/dev/snd/seq"); }
  bool poll(int64_t now_ns, WireSink& out) override;

 private:
  snd_seq_t* seq_ = nullptr;
  snd_midi_event_t* codec_ = nullptr;
};

DeviceState AlsaSeqBackend::open() {
  quiet_alsa_errors();
  const int rc = snd_seq_open(&seq_, "default", SND_SEQ_OPEN_INPUT, SND_SEQ_NONBLOCK);
  if (rc < 0) {
    seq_ = nullptr;
    if (rc == -EACCES || rc == -EPERM) {
      problem_ = "permission denied on /dev/snd/seq: add yourself to the 'audio' group";
      return DeviceState::Denied;
    }
    problem_ = "no ALSA sequencer (/dev/snd/seq: " + std::string(snd_strerror(rc)) + "; is snd-seq loaded?)";
    return DeviceState::Unavailable;
  }
  snd_seq_set_client_name(seq_, "marionette");
  const int port = snd_seq_create_simple_port(seq_, spec_.name.c_str(), SND_SEQ_PORT_CAP_WRITE | SND_SEQ_PORT_CAP_SUBS_WRITE,
                                              SND_SEQ_PORT_TYPE_MIDI_GENERIC | SND_SEQ_PORT_TYPE_APPLICATION);
  if (port < 0) {
    problem_ = std::string("ALSA sequencer: cannot create a port (") + snd_strerror(port) + ")";
    close();
    return DeviceState::Unavailable;
  }
  identity_ = "ALSA client " + std::to_string(snd_seq_client_id(seq_)) + ":" + std::to_string(port);
  node_ = "/dev/snd/seq";
  if (!spec_.alsa_source.empty()) {
    snd_seq_addr_t src{};
    if (snd_seq_parse_address(seq_, &src, spec_.alsa_source.c_str()) < 0 ||
        snd_seq_connect_from(seq_, port, src.client, src.port) < 0) {
      problem_ = "ALSA source '" + spec_.alsa_source + "' not found";
      close();
      return DeviceState::Waiting;
    }
    identity_ += " <- " + spec_.alsa_source;
  }
  fds_.clear();
  pollfd pfd[4];
  const int n = snd_seq_poll_descriptors(seq_, pfd, 4, POLLIN);
  for (int k = 0; k < n; ++k) fds_.push_back(pfd[k].fd);
  snd_midi_event_new(256, &codec_);
  snd_midi_event_no_status(codec_, 1);  // full status bytes: the stream decoder owns running status
  config_ = DecoderConfig{};
  config_.kind = WireKind::MidiBytes;
  problem_.clear();
  return DeviceState::Connected;
}

bool AlsaSeqBackend::poll(int64_t now_ns, WireSink& out) {
  for (int k = 0; k < 1024; ++k) {
    snd_seq_event_t* ev = nullptr;
    const int rc = snd_seq_event_input(seq_, &ev);
    if (rc == -EAGAIN) return true;
    if (rc == -ENOSPC) {  // input overrun: events were lost
      count_malformed();
      continue;
    }
    if (rc < 0 || !ev) return rc == -EINTR;
    if (ev->type == SND_SEQ_EVENT_CLIENT_EXIT || ev->type == SND_SEQ_EVENT_PORT_EXIT) continue;
    uint8_t buf[WireRecord::kMax];
    if (const size_t n = alsa_event_bytes(codec_, *ev, buf, sizeof buf))
      emit(WireRecord::make(now_ns, WireKind::MidiBytes, {buf, n}, source_), out);
  }
  return true;
}

}  // namespace

std::unique_ptr<Backend> make_alsa_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<AlsaSeqBackend>(s, source);
}

BackendReport discover_alsa(const std::vector<ProfileId>&) {
  snd_seq_t* seq = nullptr;
  quiet_alsa_errors();
  const int rc = snd_seq_open(&seq, "default", SND_SEQ_OPEN_INPUT, SND_SEQ_NONBLOCK);
  if (rc < 0) return {"alsa", std::string("no ALSA sequencer (/dev/snd/seq: ") + snd_strerror(rc) + ")", {}};
  BackendReport r{"alsa", "ok", {}};
  snd_seq_client_info_t* ci = nullptr;
  snd_seq_port_info_t* pi = nullptr;
  snd_seq_client_info_malloc(&ci);
  snd_seq_port_info_malloc(&pi);
  snd_seq_client_info_set_client(ci, -1);
  while (snd_seq_query_next_client(seq, ci) >= 0) {
    const int client = snd_seq_client_info_get_client(ci);
    if (client == SND_SEQ_CLIENT_SYSTEM) continue;
    snd_seq_port_info_set_client(pi, client);
    snd_seq_port_info_set_port(pi, -1);
    while (snd_seq_query_next_port(seq, pi) >= 0) {
      const unsigned caps = snd_seq_port_info_get_capability(pi);
      if ((caps & (SND_SEQ_PORT_CAP_READ | SND_SEQ_PORT_CAP_SUBS_READ)) != (SND_SEQ_PORT_CAP_READ | SND_SEQ_PORT_CAP_SUBS_READ))
        continue;
      FoundDevice f;
      f.backend = "alsa";
      f.identity = std::to_string(client) + ":" + std::to_string(snd_seq_port_info_get_port(pi)) + " '" +
                   snd_seq_client_info_get_name(ci) + "' / '" + snd_seq_port_info_get_name(pi) + "'";
      f.node = "/dev/snd/seq";
      f.status = "available";
      r.found.push_back(f);
    }
  }
  snd_seq_port_info_free(pi);
  snd_seq_client_info_free(ci);
  snd_seq_close(seq);
  return r;
}

}  // namespace mar
