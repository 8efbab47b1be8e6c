// Input sources: each hardware backend reads one real device through its library (libusb,
// hidapi, libgpiod, libevdev, ALSA, a UDP socket, SDL) and hands the frame the wire records
// it read (USB-MIDI packets, HID reports, GPIO edges, evdev events, OSC messages, MIDI bytes,
// SDL controls) with their timestamps; an in-process simulator is a source of the same kind.
// Decoding happens in src/input (input/decoder.h): a source states, when it opens, the
// DecoderConfig its records need (a report descriptor, axis ranges).
//
// Threads: a backend is opened, closed and looked for on the DeviceSet's reconnect thread
// (enumeration, descriptors, allocation, blocking calls all live there); the frame thread
// only polls an open device, without blocking or allocating. Ownership passes between the
// two through one atomic phase per device, never a lock.
#pragma once

#include "input/event.h"
#include "input/decoder.h"

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace mar {

enum class DeviceState : uint8_t {
  Waiting,      ///< not found yet (absent at start): looked for every 100 ms
  Connected,
  Unplugged,    ///< was connected, went away: looked for again
  Denied,       ///< found but not accessible (permissions)
  Unavailable,  ///< the backend cannot work here (no ALSA sequencer, no window for the mouse)
};
const char* device_state_name(DeviceState s);

/// What the show (or `marionette devices`) asks a backend to find.
struct DeviceSpec {
  std::string name;             ///< the show's device name
  std::string type;             ///< usb_midi | hid | gpio | tablet | alsa | osc | sdl
  int vid = -1, pid = -1;       ///< -1: any
  std::vector<int> pids;        ///< alternatives (profiles list several product IDs)
  std::string serial;           ///< empty: any
  std::string product;          ///< substring of the product/device name; empty: any
  int usage_page = -1, usage = -1;  ///< HID top-level collection
  std::string profile;          ///< matched profile name (informational)
  // GPIO
  std::string chip;             ///< gpiochip name, label or path
  struct Encoder {
    std::string a, b;           ///< line names (or offsets as text)
    int steps_per_detent = 4;
  };
  std::vector<Encoder> encoders;
  std::vector<std::string> buttons;
  double debounce_ms = 0;
  // OSC
  std::string host = "127.0.0.1";
  int port = 9000;
  std::vector<std::string> osc_addresses;  ///< bound address patterns, control number = 0xFF000000 | index
  // ALSA sequencer: connect from this client:port ("nanoKONTROL2", "20:0"); empty: wait for others
  std::string alsa_source;
  // SDL
  std::string sdl = "gamepad";  ///< mouse | touch | gamepad
  bool feedback = false;        ///< echo note/CC input back to the device (LEDs)
  // audio (ALSA capture)
  std::string pcm = "default";  ///< the capture device ("hw:1,0", a plugin)
  std::array<std::array<double, 2>, 5> voice{};  ///< a voice's calibration (input/voice.h; 0: default)
  bool detach_kernel_driver = true;
};

/// The time of reads that carry no device time of their own (hidraw reports, usbfs transfers).
/// With none installed (real devices) a read is stamped with CLOCK_MONOTONIC when it is taken.
/// The virtual bench installs one on the virtual clock: a read then carries the show time its
/// simulator's script gave the record, and the bench learns when the reader has taken it, so a
/// frame at t can wait until everything written through t is in (lockstep, app/simulate.h).
class ReadClock {
 public:
  virtual ~ReadClock() = default;
  /// Show time of what the reader of `node` has just read (`fallback` when unknown). Any thread.
  virtual int64_t stamp(const std::string& node, int64_t fallback) = 0;
  /// The reader of `node` has handed that read on (to the frame or its ring).
  virtual void taken(const std::string& node) = 0;
};
/// Installs (nullptr: removes) the process's read clock; set before devices open.
void set_read_clock(ReadClock* c);

/// The udev rule file shipped in config/udev/ (named in permission hints).
inline constexpr const char* kUdevRule = "config/udev/70-marionette.rules";

class Backend {
 public:
  Backend(DeviceSpec spec, uint16_t source) : spec_(std::move(spec)), source_(source) {}
  virtual ~Backend() = default;
  Backend(const Backend&) = delete;
  Backend& operator=(const Backend&) = delete;

  // ---- reconnect thread ----
  /// Looks for the device and opens it: Connected, Waiting (not there), Denied, or
  /// Unavailable. Sets problem() to a one-line explanation when not Connected.
  virtual DeviceState open() = 0;
  virtual void close() = 0;
  /// Whether the open device is still there (its node exists). Called while Connected.
  virtual bool present() const { return true; }

  /// File descriptors that become readable when the open device has input (for a loop that
  /// waits for input; the frame never blocks on them). Empty: poll it each frame.
  std::span<const int> pollable_fds() const { return fds_; }
  /// What decodes this device's records (valid after open() returned Connected).
  const DecoderConfig& decoder_config() const { return config_; }

  // ---- frame thread ----
  /// Reads everything pending without blocking and appends wire records (times on the show
  /// clock, `source` set). Returns false when the device has gone.
  virtual bool poll(int64_t now_ns, WireSink& out) = 0;
  /// Sends MIDI bytes to the device (controller feedback); false when not supported.
  virtual bool send_midi(std::span<const uint8_t>) { return false; }

  const DeviceSpec& spec() const { return spec_; }
  uint16_t source() const { return source_; }
  /// CLOCK_MONOTONIC time of show time 0, for device timestamps.
  void set_epoch(int64_t mono_ns) { epoch_ns_ = mono_ns; }
  const std::string& identity() const { return identity_; }
  const std::string& node() const { return node_; }
  const std::string& problem() const { return problem_; }
  /// Reads the backend itself dropped (unreadable, overflowing its ring) since start.
  uint64_t malformed() const { return malformed_.load(std::memory_order_relaxed); }
  /// Wire records handed to the frame since start.
  uint64_t records() const { return records_.load(std::memory_order_relaxed); }

 protected:
  void count_malformed(uint64_t n = 1) { malformed_.fetch_add(n, std::memory_order_relaxed); }
  /// Show time of a read that carries none (see ReadClock), and that it was handed on.
  int64_t read_time() const;
  void read_taken() const;
  /// Appends one record to `out`, counting it.
  void emit(const WireRecord& r, WireSink& out) {
    out.push(r);
    records_.fetch_add(1, std::memory_order_relaxed);
  }
  /// A one-line permission hint for `path`.
  static std::string denied_hint(const std::string& path);

  DeviceSpec spec_;
  uint16_t source_ = 0;
  int64_t epoch_ns_ = 0;
  std::string identity_, node_, problem_;
  DecoderConfig config_;
  std::vector<int> fds_;  ///< set by open(), cleared by close()

 private:
  std::atomic<uint64_t> malformed_{0}, records_{0};
};

/// Monotonic clock (CLOCK_MONOTONIC, the clock kernel input timestamps use) in ns.
int64_t monotonic_ns();

/// Makes the backend for `spec.type`; nullptr with `error` set for an unknown type.
std::unique_ptr<Backend> make_backend(const DeviceSpec& spec, uint16_t source, std::string* error);

/// The show's input sources (hardware backends and in-process simulators): polled by the
/// frame, reopened by a background thread. Each connection gets a fresh decoder, made on
/// the reconnect thread from the source's DecoderConfig; the frame thread decodes with it.
class DeviceSet {
 public:
  struct Status {
    DeviceState state = DeviceState::Waiting;
    uint64_t unplugs = 0, reconnects = 0;
    uint64_t records = 0;    ///< wire records read
    uint64_t events = 0;     ///< events decoded from them (frame thread's count)
    uint64_t malformed = 0;  ///< records or reads dropped as malformed (backend + decoder)
    double last_outage_ms = 0, max_outage_ms = 0;  ///< unplug detected -> reopened
  };

  explicit DeviceSet(int64_t epoch_mono_ns);
  ~DeviceSet();
  DeviceSet(const DeviceSet&) = delete;
  DeviceSet& operator=(const DeviceSet&) = delete;

  void add(std::unique_ptr<Backend> b);
  /// Tries every device once (so devices present at start are ready for frame 0), then
  /// starts the reconnect thread. `interval_ms`: how often absent devices are looked for.
  void start(int interval_ms = 100);
  /// Frame thread: polls every connected source for wire records. Never blocks or allocates.
  void poll(int64_t now_ns, WireSink& out);
  /// Frame thread: decodes a record polled this frame with its source's decoder (records of
  /// a source not in the set are counted in `out.dropped`).
  void decode(const WireRecord& r, EventSink& out);
  /// Frame thread: what time alone produces (debounced GPIO), for every connected source.
  void settle(int64_t now_ns, EventSink& out);
  /// Frame thread, after poll(): whether source `i` connected (again) since the last call,
  /// and the serialized DecoderConfig of that connection (recordings store it).
  bool take_connected(size_t i);
  std::span<const uint8_t> description(size_t i) const;
  /// Frame thread: source `i`'s last whole SysEx this connection and how many it has sent (0:
  /// none, or not connected yet). Valid until the next decode().
  std::span<const uint8_t> last_sysex(size_t i, uint64_t& count) const;
  size_t size() const { return ports_.size(); }
  Backend& backend(size_t i) { return *ports_[i]->b; }
  const Backend& backend(size_t i) const { return *ports_[i]->b; }
  DeviceState state(size_t i) const { return DeviceState(ports_[i]->shown.load(std::memory_order_acquire)); }
  /// Counts and state. Decoder counts are read on the frame thread (call it there).
  Status status(size_t i) const;
  /// A copy of the last problem text (taken on the reconnect thread's side).
  std::string problem(size_t i) const;

 private:
  enum Phase : uint8_t { Closed, Open, Lost };
  struct Slot {
    std::unique_ptr<Decoder> dec;
    std::vector<uint8_t> info;  ///< serialized DecoderConfig
  };
  struct Port {
    std::unique_ptr<Backend> b;
    // A connection's decoder is built in the slot the frame thread is not using; `slot`
    // is published with phase = Open, so the frame thread never sees a half-built one.
    Slot slots[2];
    uint8_t slot = 0;              ///< reconnect thread: the newest connection's slot
    std::atomic<uint8_t> live{0};  ///< published slot
    uint8_t polled = 0;            ///< frame thread: slot of the records polled this frame
    std::atomic<uint64_t> generation{0};
    uint64_t seen_generation = 0;  ///< frame thread
    bool polled_once = false;      ///< frame thread: a decoder is in `polled`
    std::atomic<uint64_t> retired_malformed{0}, retired_events{0};  ///< decoders replaced
    std::atomic<uint8_t> phase{Closed};
    std::atomic<uint8_t> shown{uint8_t(DeviceState::Waiting)};
    std::atomic<bool> gone{false};
    std::atomic<uint64_t> unplugs{0}, reconnects{0};
    std::atomic<int64_t> lost_at{0};
    std::atomic<double> last_outage_ms{0}, max_outage_ms{0};
    std::atomic<bool> was_connected{false};
    mutable std::mutex problem_mutex;  ///< problem text: reconnect thread and reports, never a frame
    std::string problem;
  };
  void attempt(Port& p);
  void loop();

  int64_t epoch_ns_ = 0;
  int interval_ms_ = 100;
  std::vector<std::unique_ptr<Port>> ports_;
  std::vector<int> port_of_source_;  ///< source -> port index (-1: none)
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace mar
