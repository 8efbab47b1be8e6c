// Simulated devices: each models a device's firmware and writes the bytes or edges the
// real device would send (USB-MIDI packets, HID reports per a real report descriptor,
// GPIO edges with contact bounce). They are driven by a physical-units API or a timeline
// script (docs: firmware_sim/README.md), and their output feeds the same decoders as
// hardware.
//
// Records are generated when an action is scheduled (load time), kept sorted by time, and
// handed out by drain() without allocating. A script may end with `loop SECONDS`: the
// timeline then repeats with that period, for shows of any length.
#pragma once

#include "base/result.h"
#include "input/decoder.h"

#include <algorithm>
#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mar {

class SimDevice {
 public:
  virtual ~SimDevice() = default;
  /// Device kind for messages ("nanokontrol2", "knob_box", "pen_tablet", "gamepad").
  virtual const char* kind() const = 0;
  /// The wire kind every record of this device has.
  virtual WireKind wire() const = 0;
  /// What decodes this device's records, as a receiver connected to it would set it up
  /// (the receiver may add its own settings, e.g. a debounce time).
  virtual DecoderConfig decoder_config() const {
    DecoderConfig c;
    c.kind = wire();
    return c;
  }

  /// A voice's calibration for the decoder (a microphone: F1, F2 of a, i, u, e, o; others ignore it).
  virtual void set_voice(const std::array<std::array<double, 2>, 5>&) {}
  /// A message the host sent it (feedback: a MIDI controller's LEDs). false: it sets nothing.
  virtual bool receive(std::span<const uint8_t>) { return false; }
  /// What its LEDs show ("name=value ..."; empty: it has none, or none is set).
  virtual std::string leds() const { return {}; }

  /// Runs a timeline script (one action per line, times in seconds from start; see
  /// README). Errors are "line N: ..." and leave the device unchanged.
  Result<bool> load_script(const std::string& text);
  /// Repeats the timeline every `period_s` seconds (0: play once).
  void set_loop(double period_s);
  /// Sorts the timeline; call after scheduling actions and before drain().
  void finish();
  /// Limits of a script: times and durations up to kMaxSeconds, at most kMaxRecords records
  /// (about 28 MB), and a loop period at least the timeline's length and kMinLoopSeconds.
  static constexpr double kMaxSeconds = 1e5, kMinLoopSeconds = 0.01;
  static constexpr size_t kMaxRecords = 250000;
  /// Lowers the record limit for this device (at most kMaxRecords): the fuzz harness uses it
  /// so that a script at the limit costs milliseconds; the limit's checks are the same.
  void set_max_records(size_t n) { max_records_ = std::min(n, kMaxRecords); }

  /// Calls `on(const WireRecord&)` for records with time <= now_ns, in time order: first its
  /// answers to what it was sent since the last call (at now_ns), then its timeline.
  template <class F>
  void drain(int64_t now_ns, F&& on) {
    for (size_t i = 0; i < replies_used_; ++i) {
      WireRecord out = replies_[i];
      out.t_ns = now_ns;
      on(static_cast<const WireRecord&>(out));
    }
    replies_used_ = 0;
    while (!timeline_.empty()) {
      if (next_ == timeline_.size()) {
        if (loop_ns_ <= 0) return;
        next_ = 0;
        offset_ns_ += loop_ns_;
        // Far behind (a stalled show): periods long past are skipped, the last 64 replayed, so
        // a catch-up costs a bounded amount of work.
        if (const int64_t behind = (now_ns - offset_ns_ - timeline_.back().t_ns) / loop_ns_; behind > 64)
          offset_ns_ += (behind - 64) * loop_ns_;
      }
      const WireRecord& r = timeline_[next_];
      if (r.t_ns + offset_ns_ > now_ns) return;
      WireRecord out = r;
      out.t_ns += offset_ns_;
      ++next_;
      on(static_cast<const WireRecord&>(out));
    }
  }
  /// Restarts playback from time 0.
  void rewind() { next_ = 0; offset_ns_ = 0; }
  const std::vector<WireRecord>& timeline() const { return timeline_; }
  /// Time of the last scheduled record (ns).
  int64_t end_ns() const;

 protected:
  /// One script line's action at time `t` (seconds), `w` = words after the time.
  virtual Result<bool> action(double t, const std::vector<std::string>& w) = 0;
  void emit(int64_t t_ns, std::span<const uint8_t> bytes);
  /// Queues an answer (a whole MIDI message, as USB-MIDI packets on cable 0) for the next
  /// drain(). Allocation-free; false when the queue (kReplyRecords) is full: then it is dropped.
  bool reply_midi(std::span<const uint8_t> message);
  static constexpr size_t kReplyRecords = 8;  ///< 8 x 96 bytes: a 576-byte SysEx
  std::vector<WireRecord> timeline_;
  bool too_many_ = false;  ///< emit() refused records past max_records_

 private:
  size_t next_ = 0;
  size_t max_records_ = kMaxRecords;
  int64_t loop_ns_ = 0, offset_ns_ = 0;
  std::array<WireRecord, kReplyRecords> replies_{};
  size_t replies_used_ = 0;
};

/// Makes a simulated device by kind. `descriptor` is a HID report descriptor file (.hex
/// text or raw .bin) for the HID devices; empty selects the built-in one. `options` holds
/// the show file's extra keys as text (e.g. "bounce_ms" for the knob box).
Result<std::unique_ptr<SimDevice>> make_sim_device(const std::string& kind, const std::string& descriptor,
                                                   double bounce_ms = 0, uint32_t seed = 1);

// Helpers for script parsing, shared by the devices.
double seconds(int64_t ns);
int64_t to_ns(double s);
bool parse_number(const std::string& s, double& out);

}  // namespace mar
