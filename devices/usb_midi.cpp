// Class-compliant USB-MIDI controllers through libusb 1.0: the MIDIStreaming interface
// (Audio class 1, subclass 3) is found from the descriptors, its bulk IN endpoint read
// with asynchronous transfers serviced from the frame loop (libusb's poll fds polled with
// a zero timeout), and bulk OUT used for feedback (LEDs).
#include "devices/backends.h"
#include "devices/util.h"
#include "input/usb_midi.h"

#include <libusb-1.0/libusb.h>
#include <poll.h>

#include <cstring>

namespace mar {
namespace {

constexpr int kInTransfers = 4, kInSize = 512, kRing = 256;

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
  void start_out();

  libusb_context* ctx_ = nullptr;
  libusb_device_handle* h_ = nullptr;
  int iface_ = -1;
  uint8_t ep_in_ = 0, ep_out_ = 0;
  libusb_transfer* in_[kInTransfers] = {};
  libusb_transfer* out_ = nullptr;
  uint8_t in_buf_[kInTransfers][kInSize];
  uint8_t out_buf_[kInSize];
  uint8_t pending_out_[kInSize];
  size_t pending_n_ = 0;
  bool out_busy_ = false;
  int in_flight_ = 0;
  bool in_active_[kInTransfers] = {};  ///< libusb owns in_[i] (submitted, not yet finished)
  bool failed_ = false;
  pollfd pfds_[16];
  nfds_t nfds_ = 0;
  WireRecord ring_[kRing];
  size_t ring_n_ = 0;
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
  ring_n_ = 0;
  for (int i = 0; i < kInTransfers; ++i) {
    in_[i] = libusb_alloc_transfer(0);
    libusb_fill_bulk_transfer(in_[i], h_, ep_in_, in_buf_[i], kInSize, &UsbMidiBackend::on_in, this, 0);
    in_active_[i] = libusb_submit_transfer(in_[i]) == 0;
    if (in_active_[i]) ++in_flight_;
  }
  if (ep_out_) out_ = libusb_alloc_transfer(0);
  nfds_ = 0;
  if (const libusb_pollfd** pf = libusb_get_pollfds(ctx_)) {
    for (size_t i = 0; pf[i] && nfds_ < std::size(pfds_); ++i) pfds_[nfds_++] = {pf[i]->fd, pf[i]->events, 0};
    fds_.clear();
    for (nfds_t i = 0; i < nfds_; ++i) fds_.push_back(pfds_[i].fd);
    libusb_free_pollfds(pf);
  }
  config_ = DecoderConfig{};
  config_.kind = WireKind::UsbMidi;
  problem_.clear();
  return DeviceState::Connected;
}

void UsbMidiBackend::close() {
  if (!h_) return;
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
  fds_.clear();
  for (int i = 0; i < kInTransfers; ++i) {
    if (in_[i]) libusb_free_transfer(in_[i]);
    in_[i] = nullptr;
    in_active_[i] = false;
  }
  if (out_) libusb_free_transfer(out_);
  out_ = nullptr;
  in_flight_ = 0;
  out_busy_ = false;
}

void LIBUSB_CALL UsbMidiBackend::on_in(libusb_transfer* t) {
  auto* self = static_cast<UsbMidiBackend*>(t->user_data);
  if (t->status == LIBUSB_TRANSFER_COMPLETED) {
    for (int off = 0; off < t->actual_length; off += int(WireRecord::kMax)) {
      const size_t len = size_t(std::min<int>(t->actual_length - off, int(WireRecord::kMax)));
      if (self->ring_n_ < kRing)
        self->ring_[self->ring_n_++] = WireRecord::make(monotonic_ns() - self->epoch_ns_, WireKind::UsbMidi, {t->buffer + off, len}, self->source_);
      else
        self->count_malformed();
    }
    if (libusb_submit_transfer(t) == 0) return;
    self->failed_ = true;
  } else if (t->status == LIBUSB_TRANSFER_TIMED_OUT) {
    if (libusb_submit_transfer(t) == 0) return;
  } else if (t->status != LIBUSB_TRANSFER_CANCELLED) {
    self->failed_ = true;  // NO_DEVICE, ERROR, STALL, OVERFLOW
  }
  for (int i = 0; i < kInTransfers; ++i) {
    if (self->in_[i] == t) self->in_active_[i] = false;
  }
  --self->in_flight_;
}

void LIBUSB_CALL UsbMidiBackend::on_out(libusb_transfer* t) {
  auto* self = static_cast<UsbMidiBackend*>(t->user_data);
  self->out_busy_ = false;
  if (t->status == LIBUSB_TRANSFER_NO_DEVICE) self->failed_ = true;
  if (self->pending_n_ && !self->failed_) self->start_out();
}

void UsbMidiBackend::start_out() {
  std::memcpy(out_buf_, pending_out_, pending_n_);
  libusb_fill_bulk_transfer(out_, h_, ep_out_, out_buf_, int(pending_n_), &UsbMidiBackend::on_out, this, 1000);
  pending_n_ = 0;
  out_busy_ = libusb_submit_transfer(out_) == 0;
}

bool UsbMidiBackend::send_midi(std::span<const uint8_t> bytes) {
  if (!h_ || !out_) return false;
  uint8_t p[4];
  if (usb_midi_encode(0, bytes, p) != UsbMidiEncodeError::None || pending_n_ + 4 > sizeof pending_out_) return false;
  std::memcpy(pending_out_ + pending_n_, p, 4);
  pending_n_ += 4;
  if (!out_busy_) start_out();
  return true;
}

bool UsbMidiBackend::poll(int64_t, WireSink& out) {
  for (nfds_t i = 0; i < nfds_; ++i) pfds_[i].revents = 0;
  if (nfds_ == 0 || ::poll(pfds_, nfds_, 0) > 0) {
    timeval zero{0, 0};
    libusb_handle_events_timeout_completed(ctx_, &zero, nullptr);
  }
  for (size_t i = 0; i < ring_n_; ++i) emit(ring_[i], out);
  ring_n_ = 0;
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
