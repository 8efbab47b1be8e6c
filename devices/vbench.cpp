#include "devices/vbench_impl.h"

#include "input/usb_midi.h"

#include <filesystem>

namespace mar {
using namespace vb;

gboolean VirtualBench::Impl::on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self) {
  auto* impl = static_cast<Impl*>(self);
  const char* node = umockdev_ioctl_client_get_devnode(c);
  BenchDev* d = impl->by_node(node);
  if (!d) return FALSE;
  const unsigned long req = umockdev_ioctl_client_get_request(c);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(c);
  std::lock_guard lock(d->m);
  if (d->kind != BenchKind::Usb && d->node != node) {  // a node of an earlier plug: gone, as in the kernel
    complete(c, -1, ENODEV);
    return TRUE;
  }
  switch (d->kind) {
    case BenchKind::Usb: return impl->usb_ioctl(*d, c, req, arg);
    case BenchKind::Gpio: return impl->gpio_ioctl(*d, c, req, arg);
    case BenchKind::Evdev: return impl->evdev_ioctl(*d, c, req, arg);
    case BenchKind::Hid:
      if (req == HIDIOCGRDESCSIZE) return answer(c, arg, int(1));
      return FALSE;
  }
  return FALSE;
}

gboolean VirtualBench::Impl::on_read(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self) {
  auto* impl = static_cast<Impl*>(self);
  const char* node = umockdev_ioctl_client_get_devnode(c);
  BenchDev* d = impl->by_node(node);
  if (!d) return FALSE;
  if (d->kind == BenchKind::Hid) return hid_read(*d, c, node);
  if (d->kind == BenchKind::Evdev) return evdev_read(*d, c, node);
  return FALSE;
}

bool VirtualBench::preload_active() {
  const char* p = std::getenv("LD_PRELOAD");
  return p && std::strstr(p, "libumockdev-preload");
}

void VirtualBench::ensure_preload(char** argv) {
  if (preload_active()) return;
  std::string pre = "libumockdev-preload.so.0";
  if (const char* old = std::getenv("LD_PRELOAD"); old && *old) pre = std::string(old) + ":" + pre;
  setenv("LD_PRELOAD", pre.c_str(), 1);
  // AddressSanitizer wants to be first in the preload list; umockdev's preload is added after it.
  std::string asan = std::getenv("ASAN_OPTIONS") ? std::getenv("ASAN_OPTIONS") : "";
  setenv("ASAN_OPTIONS", (asan.empty() ? "" : asan + ":").append("verify_asan_link_order=0").c_str(), 1);
  execv("/proc/self/exe", argv);
  std::perror("marionette: cannot re-execute under umockdev's preload");
}

VirtualBench::VirtualBench() : p_(std::make_unique<Impl>()) {
  p_->tb = umockdev_testbed_new();
  p_->handler = umockdev_ioctl_base_new();
  g_signal_connect(p_->handler, "handle-ioctl", G_CALLBACK(&Impl::on_ioctl), p_.get());
  g_signal_connect(p_->handler, "handle-read", G_CALLBACK(&Impl::on_read), p_.get());
  // The GPIO bus folder exists from the start, as on a board with a GPIO driver, so a label is
  // looked up in sysfs even while no chip is plugged: libgpiod's own search scans /dev, and a
  // scan of /dev under umockdev's preload leaves a stale entry in its map of emulated fds — a
  // later device fd with the same number then sends its ioctls nowhere and waits for ever (the
  // USB-MIDI reap that hung after the GPIO tests in the same process).
  gchar* root = umockdev_testbed_get_root_dir(p_->tb);
  std::error_code ec;
  std::filesystem::create_directories(std::string(root) + "/sys/bus/gpio/devices", ec);
  g_free(root);
}

VirtualBench::~VirtualBench() {
  stop_playing();
  for (auto& d : p_->devs) {
    for (int fd : d->line_fd)
      if (fd >= 0) ::close(fd);
    for (auto* q : {&d->in_urbs, &d->done_urbs, &d->discarded}) q->clear();
  }
  g_object_unref(p_->tb);
  g_object_unref(p_->handler);
}

// Gives the device a fresh node (a replugged device gets a new number, as in the kernel)
// and its umockdev description.
void VirtualBench::Impl::describe(BenchDev& d) {
  std::lock_guard lock(devs_m);
  if (!d.node.empty()) d.old_nodes.push_back(d.node);
  switch (d.kind) {
    case BenchKind::Usb: describe_usb(d); break;
    case BenchKind::Hid: describe_hid(d); break;
    case BenchKind::Gpio: describe_gpio(d); break;
    case BenchKind::Evdev: describe_evdev(d); break;
  }
  umockdev_testbed_attach_ioctl(tb, d.node.c_str(), handler, nullptr);
}

int VirtualBench::Impl::plug_new(std::unique_ptr<BenchDev> d) {
  describe(*d);
  add(*d);
  std::lock_guard lock(devs_m);
  devs.push_back(std::move(d));
  return int(devs.size()) - 1;
}

int VirtualBench::add_usb_midi(const UsbMidi& u) {
  auto d = std::make_unique<BenchDev>();
  d->kind = BenchKind::Usb;
  d->usb = u;
  d->driver = u.kernel_driver;
  return p_->plug_new(std::move(d));
}

int VirtualBench::add_hid(const Hid& h) {
  auto d = std::make_unique<BenchDev>();
  d->kind = BenchKind::Hid;
  d->hid = h;
  return p_->plug_new(std::move(d));
}

int VirtualBench::add_gpio(const Gpio& g) {
  auto d = std::make_unique<BenchDev>();
  d->kind = BenchKind::Gpio;
  d->gpio = g;
  d->line_fd.assign(g.lines.size(), -1);
  d->line_flags.assign(g.lines.size(), 0);
  return p_->plug_new(std::move(d));
}

int VirtualBench::add_evdev(const Evdev& e) {
  auto d = std::make_unique<BenchDev>();
  d->kind = BenchKind::Evdev;
  d->ev = e;
  return p_->plug_new(std::move(d));
}

void VirtualBench::usb_in(int dev, std::span<const uint8_t> packets, int64_t show_t) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged) return;
  d.in_packets.emplace_back(packets.begin(), packets.end());
  d.packet_t.push_back(show_t);
}

void VirtualBench::hid_report(int dev, std::span<const uint8_t> report, int64_t show_t) {
  // Reads of the node are answered from this queue (handle-read), one report per read as
  // hidraw does; the node's tty only makes poll() report it readable.
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged) return;
  d.reports.emplace_back(report.begin(), report.end());
  d.report_t.push_back(show_t);
}

void VirtualBench::gpio_edge(int dev, unsigned line, int level, int64_t mono_ns) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged || line >= d.line_fd.size() || d.line_fd[line] < 0) return;
  gpioevent_data ev{};
  ev.timestamp = uint64_t(mono_ns);
  ev.id = level ? GPIOEVENT_EVENT_RISING_EDGE : GPIOEVENT_EVENT_FALLING_EDGE;
  if (::write(d.line_fd[line], &ev, sizeof ev) < 0) std::perror("vbench: gpio write");
}

void VirtualBench::evdev_event(int dev, uint16_t type, uint16_t code, int32_t value, int64_t mono_ns) {
  // Queued for the node's reads (handle-read), as hidraw's are: an event written is readable at
  // once (bytes written to the node's tty reach its reader later, when the kernel gets to it).
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged) return;
  input_event ev{};
  ev.input_event_sec = decltype(ev.input_event_sec)(mono_ns / 1000000000);
  ev.input_event_usec = decltype(ev.input_event_usec)((mono_ns % 1000000000) / 1000);
  ev.type = type;
  ev.code = code;
  ev.value = value;
  const auto* b = reinterpret_cast<const uint8_t*>(&ev);
  d.reports.emplace_back(b, b + sizeof ev);
}

void VirtualBench::write(int dev, const WireRecord& r, int64_t epoch) {
  switch (r.kind) {
    case WireKind::UsbMidi: usb_in(dev, r.bytes(), r.t_ns); break;
    case WireKind::HidReport: hid_report(dev, r.bytes(), r.t_ns); break;
    case WireKind::GpioEdge: gpio_edge(dev, r.data[0], r.data[1], epoch + r.t_ns); break;
    default: break;
  }
}

std::vector<uint8_t> VirtualBench::usb_out(int dev) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  return d.out_bytes;
}

uint32_t VirtualBench::gpio_flags(int dev, unsigned line) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  return line < d.line_flags.size() ? d.line_flags[line] : 0;
}

bool VirtualBench::kernel_driver_detached(int dev) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  return d.detached;
}

void VirtualBench::unplug(int dev) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged) return;
  d.plugged = false;
  umockdev_testbed_uevent(p_->tb, d.syspath.c_str(), "remove");
  if (d.kind == BenchKind::Usb) {
    // As the kernel does: the node goes at once (nothing opens it again) and descriptors still
    // open get ENODEV from the handler. The testbed keeps the device's record: umockdev answers
    // nothing more on the streams of a removed device, and libusb reaping URBs on the frame
    // thread would wait forever (the hang this replaced). A replug is a new device.
    gchar* root = umockdev_testbed_get_root_dir(p_->tb);
    ::unlink((std::string(root) + d.node).c_str());
    g_free(root);
  } else {
    umockdev_testbed_remove_device(p_->tb, d.syspath.c_str());
    // umockdev leaves an input device's class link (/sys/class/input/eventN) and node behind;
    // the kernel removes both, and a program scanning the class must not find the old one.
    if (d.kind == BenchKind::Evdev) {
      gchar* root = umockdev_testbed_get_root_dir(p_->tb);
      const std::string name = d.node.substr(d.node.rfind('/') + 1);
      ::unlink((std::string(root) + "/sys/class/input/" + name).c_str());
      ::unlink((std::string(root) + d.node).c_str());
      g_free(root);
    }
  }
  for (int& fd : d.line_fd) {  // the kernel hangs up a removed chip's event fds
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
  for (auto* q : {&d.in_urbs, &d.done_urbs})  // in-flight URBs die with the device
    while (!q->empty()) {
      q->front().urb().status = -ENODEV;
      d.discarded.push_back(std::move(q->front()));
      q->pop_front();
    }
  d.in_packets.clear();
  d.packet_t.clear();
  d.unacked.clear();
  d.reports.clear();
  d.report_t.clear();
  d.detached = false;
}

void VirtualBench::replug(int dev) {
  BenchDev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (d.plugged) return;
  p_->describe(d);
  p_->add(d);
}

bool VirtualBench::plugged(int dev) const { return p_->devs[size_t(dev)]->plugged; }

void VirtualBench::deny(int dev, bool denied) {
  const BenchDev& d = *p_->devs[size_t(dev)];
  gchar* root = umockdev_testbed_get_root_dir(p_->tb);  // a copy to free
  const std::string path = std::string(root) + d.node;
  g_free(root);
  chmod(path.c_str(), denied ? 0 : 0666);
}

void VirtualBench::act_as_user(bool on) {
  __user_cap_header_struct h{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct c[2]{};
  if (syscall(SYS_capget, &h, c) != 0) return;
  const uint32_t bits = (1u << CAP_DAC_OVERRIDE) | (1u << CAP_DAC_READ_SEARCH);
  if (on) c[0].effective &= ~bits;
  else c[0].effective |= (c[0].permitted & bits);
  syscall(SYS_capset, &h, c);
}

void VirtualBench::play(int dev, SimDevice& sim, int64_t epoch, bool lockstep) {
  // One player thread per call: the bench is small (a device or two per test).
  ++p_->playing;
  std::atomic<int64_t>& written = p_->written.emplace_back(-1);
  // A MIDI controller answers what it is sent (a Korg scene request), so its player hears the
  // device's USB OUT and goes on after its timeline, until it is stopped.
  const bool hears = sim.wire() == WireKind::UsbMidi && p_->devs[size_t(dev)]->kind == BenchKind::Usb;
  p_->players.emplace_back([this, dev, &sim, epoch, lockstep, &written, hears] {
    UsbMidiDecoder sent;
    size_t seen = 0;
    auto hear = [&] {
      if (!hears) return;
      std::vector<uint8_t> out;
      {
        BenchDev& d = *p_->devs[size_t(dev)];
        std::lock_guard lock(d.m);
        if (d.out_bytes.size() > seen) out.assign(d.out_bytes.begin() + long(seen), d.out_bytes.end());
        seen += out.size();
      }
      sent.feed(out, [&](uint8_t, const MidiMessage& m) {
        if (m.is_sysex()) sim.receive(m.sysex);
        else sim.receive(std::span<const uint8_t>(m.bytes, m.size));
      });
    };
    int64_t now = -1;
    bool ended = false;
    while (!p_->stop.load()) {
      if (lockstep) {
        p_->allowed.wait(now, std::memory_order_acquire);  // until the show moves on (or stops)
        if (p_->stop.load()) break;
        now = p_->allowed.load(std::memory_order_acquire);
      } else {
        timespec ts{};
        clock_gettime(CLOCK_MONOTONIC, &ts);
        now = int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec - epoch;
      }
      hear();
      sim.drain(now, [&](const WireRecord& r) { write(dev, r, epoch); });
      if (!ended) written.store(now, std::memory_order_release);
      if (!ended && now > sim.end_ns()) {
        ended = true;
        written.store(INT64_MAX, std::memory_order_release);
        --p_->playing;
        if (!hears) return;
      }
      if (!lockstep || ended) std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    hear();  // (what was sent before it stopped)
    if (!ended) {
      written.store(INT64_MAX, std::memory_order_release);
      --p_->playing;
    }
  });
}

void VirtualBench::allow_through(int64_t t) {
  if (t <= p_->allowed.load(std::memory_order_relaxed)) return;
  p_->allowed.store(t, std::memory_order_release);
  p_->allowed.notify_all();
}

const std::atomic<int64_t>& VirtualBench::allowed() const { return p_->allowed; }

void VirtualBench::stop_playing() {
  p_->stop = true;
  p_->allowed.fetch_add(1);  // wakes lockstep players
  p_->allowed.notify_all();
  for (auto& t : p_->players) t.join();
  p_->players.clear();
  p_->written.clear();
  p_->stop = false;
  p_->allowed = -1;
}

bool VirtualBench::played_all() const { return p_->playing.load() == 0; }

int64_t VirtualBench::written_through() const {
  int64_t t = INT64_MAX;
  for (const auto& w : p_->written) t = std::min(t, w.load(std::memory_order_acquire));
  // With the read clock: USB packets reach the reader through libusb's thread, so a packet
  // queued while the reader has transfers waiting, or answered and not yet handed on, holds the
  // time before its own.
  if (!p_->clocked.load()) return t;
  std::lock_guard devs_lock(p_->devs_m);
  for (const auto& d : p_->devs) {
    if (d->kind != BenchKind::Usb) continue;
    std::lock_guard lock(d->m);
    if (!d->plugged) continue;
    if (!d->unacked.empty()) t = std::min(t, d->unacked.front() - 1);
    if (!d->in_packets.empty() && !d->in_urbs.empty()) t = std::min(t, d->packet_t.front() - 1);
  }
  return t;
}

namespace {

// The read clock of the virtual bench: per node, the time of the last read answered.
class BenchClock final : public ReadClock {
 public:
  struct Node {
    std::string node;
    BenchDev* dev;
  };
  explicit BenchClock(std::vector<Node> nodes) : nodes_(std::move(nodes)) {}
  int64_t stamp(const std::string& node, int64_t fallback) override {
    const BenchDev* d = find(node);
    const int64_t t = d ? d->read_t.load(std::memory_order_acquire) : -1;
    return t >= 0 ? t : fallback;
  }
  void taken(const std::string& node) override {
    if (BenchDev* d = find(node); d && d->kind == BenchKind::Usb) {
      std::lock_guard lock(d->m);
      if (!d->unacked.empty()) d->unacked.pop_front();
    }
  }

 private:
  BenchDev* find(const std::string& node) const {
    for (const Node& n : nodes_)
      if (n.node == node) return n.dev;
    return nullptr;
  }
  std::vector<Node> nodes_;  ///< fixed when made: read without a lock
};

}  // namespace

ReadClock& VirtualBench::read_clock() {
  std::vector<BenchClock::Node> nodes;
  {
    std::lock_guard lock(p_->devs_m);
    for (const auto& d : p_->devs) nodes.push_back({d->node, d.get()});
  }
  p_->clock = std::make_unique<BenchClock>(std::move(nodes));
  p_->clocked = true;
  return *p_->clock;
}

}  // namespace mar
