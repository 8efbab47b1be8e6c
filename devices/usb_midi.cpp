// Class-compliant USB-MIDI controllers through libusb 1.0: the MIDIStreaming interface
// (Audio class 1, subclass 3) is found from the descriptors, its bulk IN endpoint read
// with asynchronous transfers, and bulk OUT used for feedback (LEDs). The transfers are
// serviced on a thread of the backend's own: libusb's Linux backend allocates the URBs of
// every transfer it submits (and each packet in resubmits one), so the frame thread only
// takes finished packets from a lock-free ring and leaves feedback in another.
#include "devices/backends.h"
#include "devices/util.h"
#include "input/usb_midi.h"

#include "devices/spsc.h"

#include <libusb-1.0/libusb.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

namespace mar {
namespace {

constexpr int kInTransfers = 4, kInSize = 512;
constexpr size_t kMaxSysex = 512;  ///< the longest SysEx sent (3 bytes a packet, within the ring)

class UsbMidiBackend final : public Backend {
 public:
  using Backend::Backend;
  ~UsbMidiBackend() override {
    close();
    if (ctx_) libusb_exit(ctx_);
  }
  DeviceState open() override;
  void close() override;
  bool present() const override { return devutil::exists(node_); }
  bool poll(int64_t now_ns, WireSink& out) override;
  bool send_midi(std::span<const uint8_t> bytes) override;

 private:
  static void LIBUSB_CALL on_in(libusb_transfer* t);
  static void LIBUSB_CALL on_out(libusb_transfer* t);
  void service();  // the I/O thread
  void start_out();

  libusb_context* ctx_ = nullptr;
  libusb_device_handle* h_ = nullptr;
  int iface_ = -1;
  uint8_t ep_in_ = 0, ep_out_ = 0;
  // Owned by the I/O thread while it runs (and by open()/close() otherwise).
  libusb_transfer* in_[kInTransfers] = {};
  libusb_transfer* out_ = nullptr;
  uint8_t in_buf_[kInTransfers][kInSize];
  uint8_t out_buf_[kInSize];
  bool out_busy_ = false;
  // Shared with the frame thread.
  std::atomic<int> in_flight_{0};
  std::atomic<bool> failed_{false}, stop_{false};
  SpscRing<WireRecord, 256> in_ring_;                 ///< I/O thread -> frame
  SpscRing<std::array<uint8_t, 4>, 256> out_ring_;    ///< frame -> I/O thread (USB-MIDI packets)
  std::thread io_;
};

// The MIDIStreaming interface and its bulk (or interrupt) endpoints.
bool find_midi_interface(libusb_device* dev, int& iface, uint8_t& in, uint8_t& out) {
  libusb_config_descriptor* cfg = nullptr;
  if (libusb_get_active_config_descriptor(dev, &cfg) != 0 && libusb_get_config_descriptor(dev, 0, &cfg) != 0) return false;
  bool ok = false;
  for (int i = 0; i < cfg->bNumInterfaces && !ok; ++i)
    for (int a = 0; a < cfg->interface[i].num_altsetting && !ok; ++a) {
      const libusb_interface_descriptor& d = cfg->interface[i].altsetting[a];
      if (d.bInterfaceClass != LIBUSB_CLASS_AUDIO || d.bInterfaceSubClass != 3) continue;
      in = out = 0;
      for (int e = 0; e < d.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& ep = d.endpoint[e];
        const int type = ep.bmAttributes & 3;
        if (type != LIBUSB_TRANSFER_TYPE_BULK && type != LIBUSB_TRANSFER_TYPE_INTERRUPT) continue;
        (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN ? in : out) = ep.bEndpointAddress;
      }
      if (in) {
        iface = d.bInterfaceNumber;
        ok = true;
      }
    }
  libusb_free_config_descriptor(cfg);
  return ok;
}

DeviceState UsbMidiBackend::open() {
  if (!ctx_ && libusb_init(&ctx_) != 0) {
    ctx_ = nullptr;
    problem_ = "libusb could not start";
    return DeviceState::Unavailable;
  }
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx_, &list);
  libusb_device_descriptor dd{};
  int rc = LIBUSB_ERROR_NO_DEVICE;
  bool any = false;
  // Every match is tried in turn: one that cannot be opened (held elsewhere, or gone with its
  // entry still listed) must not hide the next.
  for (ssize_t i = 0; i < n && !h_; ++i) {
    if (libusb_get_device_descriptor(list[i], &dd) != 0) continue;
    if (spec_.vid >= 0 && dd.idVendor != spec_.vid) continue;
    if (spec_.pid >= 0 && dd.idProduct != spec_.pid) continue;
    if (!find_midi_interface(list[i], iface_, ep_in_, ep_out_)) continue;
    any = true;
    char path[64];
    std::snprintf(path, sizeof path, "/dev/bus/usb/%03d/%03d", libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]));
    node_ = path;
    identity_ = devutil::vid_pid(dd.idVendor, dd.idProduct) + " interface " + std::to_string(iface_);
    rc = libusb_open(list[i], &h_);
    if (rc != 0) h_ = nullptr;
  }
  if (n >= 0) libusb_free_device_list(list, 1);
  if (!any) {
    problem_ = "no USB-MIDI device" + (spec_.vid >= 0 ? " " + devutil::vid_pid(spec_.vid, spec_.pid) : std::string());
    return DeviceState::Waiting;
  }
  if (!h_) {
    problem_ = rc == LIBUSB_ERROR_ACCESS ? denied_hint(node_) : node_ + ": " + libusb_strerror(rc);
    return rc == LIBUSB_ERROR_ACCESS ? DeviceState::Denied : DeviceState::Waiting;
  }
  if (!spec_.serial.empty() && dd.iSerialNumber) {
    unsigned char s[128] = {};
    if (libusb_get_string_descriptor_ascii(h_, dd.iSerialNumber, s, sizeof s) > 0 &&
        spec_.serial != reinterpret_cast<const char*>(s)) {
      problem_ = "USB-MIDI device " + identity_ + " has another serial";
      close();
      return DeviceState::Waiting;
    }
  }
  // snd-usb-audio usually owns the interface: detach it when the show allows.
  if (libusb_kernel_driver_active(h_, iface_) == 1) {
    if (!spec_.detach_kernel_driver || libusb_detach_kernel_driver(h_, iface_) != 0) {
      problem_ = node_ + ": the kernel's audio driver holds the MIDI interface (detach_kernel_driver = false or refused)";
      close();
      return DeviceState::Unavailable;
    }
  }
  if (int c = libusb_claim_interface(h_, iface_); c != 0) {
    problem_ = node_ + ": cannot claim interface (" + libusb_strerror(c) + ")";
    close();
    return c == LIBUSB_ERROR_ACCESS ? DeviceState::Denied : DeviceState::Waiting;
  }
  failed_ = false;
  in_flight_ = 0;
  for (int i = 0; i < kInTransfers; ++i) {
    in_[i] = libusb_alloc_transfer(0);
    libusb_fill_bulk_transfer(in_[i], h_, ep_in_, in_buf_[i], kInSize, &UsbMidiBackend::on_in, this, 0);
    if (libusb_submit_transfer(in_[i]) == 0) ++in_flight_;
  }
  if (ep_out_) out_ = libusb_alloc_transfer(0);
  stop_ = false;
  io_ = std::thread([this] { service(); });
  config_ = DecoderConfig{};
  config_.kind = WireKind::UsbMidi;
  problem_.clear();
  return DeviceState::Connected;
}

void UsbMidiBackend::close() {
  if (!h_) return;
  stop_ = true;
  if (io_.joinable()) io_.join();
  for (auto* t : in_)
    if (t) libusb_cancel_transfer(t);
  if (out_ && out_busy_) libusb_cancel_transfer(out_);
  // Cancelled transfers finish through the event loop (up to 0.5 s here). libusb_close()
  // takes any still in flight off libusb's lists, so transfers are freed only after it:
  // freeing one libusb still lists made libusb_close() lock a mutex in freed memory (the
  // abort on unplug under load), and waiting longer would delay the reconnect.
  timeval tv{0, 10000};
  for (int k = 0; k < 50 && (in_flight_ > 0 || out_busy_); ++k) libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
  libusb_release_interface(h_, iface_);
  libusb_close(h_);
  h_ = nullptr;
  for (auto*& t : in_) {
    if (t) libusb_free_transfer(t);
    t = nullptr;
  }
  if (out_) libusb_free_transfer(out_);
  out_ = nullptr;
  in_flight_ = 0;
  out_busy_ = false;
}

// The I/O thread: finishes transfers (their callbacks run here) and sends feedback. The wait
// is short so that feedback queued by the frame goes out within a few milliseconds.
void UsbMidiBackend::service() {
  while (!stop_) {
    if (failed_ && in_flight_ == 0) {  // gone: nothing more to finish until close()
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    timeval tv{0, 2000};
    libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
    if (!out_busy_ && !failed_) start_out();
  }
}

void LIBUSB_CALL UsbMidiBackend::on_in(libusb_transfer* t) {
  auto* self = static_cast<UsbMidiBackend*>(t->user_data);
  if (t->status == LIBUSB_TRANSFER_COMPLETED) {
    const int64_t at = self->read_time();  // usbfs has no timestamps: stamped when finished (ReadClock)
    for (int off = 0; off < t->actual_length; off += int(WireRecord::kMax)) {
      const size_t len = size_t(std::min<int>(t->actual_length - off, int(WireRecord::kMax)));
      if (!self->in_ring_.push(WireRecord::make(at, WireKind::UsbMidi, {t->buffer + off, len}, self->source_)))
        self->count_malformed();  // the frame has not taken the last 256 packets
    }
    if (t->actual_length > 0) self->read_taken();
    if (libusb_submit_transfer(t) == 0) return;
    self->failed_ = true;
  } else if (t->status == LIBUSB_TRANSFER_TIMED_OUT) {
    if (libusb_submit_transfer(t) == 0) return;
  } else if (t->status != LIBUSB_TRANSFER_CANCELLED) {
    self->failed_ = true;  // NO_DEVICE, ERROR, STALL, OVERFLOW
  }
  --self->in_flight_;
}

void LIBUSB_CALL UsbMidiBackend::on_out(libusb_transfer* t) {
  auto* self = static_cast<UsbMidiBackend*>(t->user_data);
  self->out_busy_ = false;
  if (t->status == LIBUSB_TRANSFER_NO_DEVICE) self->failed_ = true;
}

// Sends every packet the frame has queued, in one bulk OUT transfer.
void UsbMidiBackend::start_out() {
  if (!out_) return;
  std::array<uint8_t, 4> p;
  size_t n = 0;
  while (n + 4 <= sizeof out_buf_ && out_ring_.pop(p)) {
    std::memcpy(out_buf_ + n, p.data(), 4);
    n += 4;
  }
  if (n == 0) return;
  libusb_fill_bulk_transfer(out_, h_, ep_out_, out_buf_, int(n), &UsbMidiBackend::on_out, this, 1000);
  out_busy_ = libusb_submit_transfer(out_) == 0;
}

bool UsbMidiBackend::send_midi(std::span<const uint8_t> bytes) {
  // One message: a packet, or a SysEx in packets of three bytes (the last one ends it), whole
  // or not at all (a Korg scene is 402 bytes: 134 packets).
  if (!h_ || !out_ || bytes.empty()) return false;
  std::array<uint8_t, 4> p;
  if (bytes[0] != 0xF0) {
    if (usb_midi_encode(0, bytes, p.data()) != UsbMidiEncodeError::None) return false;
    return out_ring_.push(p);
  }
  if (bytes.back() != 0xF7 || bytes.size() > kMaxSysex || out_ring_.room() < (bytes.size() + 2) / 3) return false;
  for (size_t at = 0; at < bytes.size(); at += 3) {
    const auto chunk = bytes.subspan(at, std::min<size_t>(3, bytes.size() - at));
    if (usb_midi_encode(0, chunk, p.data()) != UsbMidiEncodeError::None || !out_ring_.push(p)) return false;
  }
  return true;
}

bool UsbMidiBackend::poll(int64_t, WireSink& out) {
  WireRecord r;
  while (in_ring_.pop(r)) emit(r, out);
  return !failed_ && in_flight_ > 0;
}

}  // namespace

std::unique_ptr<Backend> make_usb_midi_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<UsbMidiBackend>(s, source);
}

BackendReport discover_usb_midi(const std::vector<ProfileId>& profiles) {
  BackendReport r{"usb_midi", "ok", {}};
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) != 0) return {"usb_midi", "libusb could not start", {}};
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor dd{};
    libusb_config_descriptor* cfg = nullptr;
    if (libusb_get_device_descriptor(list[i], &dd) != 0 || libusb_get_active_config_descriptor(list[i], &cfg) != 0) continue;
    bool midi = false;
    for (int k = 0; k < cfg->bNumInterfaces; ++k)
      for (int a = 0; a < cfg->interface[k].num_altsetting; ++a)
        midi = midi || (cfg->interface[k].altsetting[a].bInterfaceClass == LIBUSB_CLASS_AUDIO &&
                        cfg->interface[k].altsetting[a].bInterfaceSubClass == 3);
    libusb_free_config_descriptor(cfg);
    if (!midi) continue;
    FoundDevice f;
    f.backend = "usb_midi";
    f.identity = devutil::vid_pid(dd.idVendor, dd.idProduct) + " USB-MIDI";
    char node[64];
    std::snprintf(node, sizeof node, "/dev/bus/usb/%03d/%03d", libusb_get_bus_number(list[i]), libusb_get_device_address(list[i]));
    f.node = node;
    f.profile = devutil::profile_of(profiles, dd.idVendor, dd.idProduct);
    devutil::access_status(f);
    r.found.push_back(f);
  }
  if (n >= 0) libusb_free_device_list(list, 1);
  libusb_exit(ctx);
  return r;
}

}  // namespace mar
