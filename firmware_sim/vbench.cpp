#include "firmware_sim/vbench.h"

#include <umockdev.h>

#include <fcntl.h>
#include <linux/capability.h>
#include <linux/gpio.h>
#include <linux/hidraw.h>
#include <linux/input.h>
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace mar {
namespace {

std::string hex(std::span<const uint8_t> b) {
  std::string s;
  char t[3];
  for (uint8_t v : b) {
    std::snprintf(t, sizeof t, "%02x", v);
    s += t;
  }
  return s;
}

// A class-compliant USB-MIDI device: AudioControl + MIDIStreaming with bulk 0x01/0x81.
std::vector<uint8_t> midi_descriptors(int vid, int pid) {
  std::vector<uint8_t> d = {0x12, 0x01, 0x00, 0x02, 0x00, 0x00, 0x00, 0x40, uint8_t(vid), uint8_t(vid >> 8),
                            uint8_t(pid), uint8_t(pid >> 8), 0x00, 0x01, 0x01, 0x02, 0x00, 0x01};
  const std::vector<uint8_t> cfg = {
      0x09, 0x02, 71, 0x00, 0x02, 0x01, 0x00, 0x80, 0x32,           // configuration, 2 interfaces
      0x09, 0x04, 0x00, 0x00, 0x00, 0x01, 0x01, 0x00, 0x00,         // interface 0: AudioControl
      0x09, 0x24, 0x01, 0x00, 0x01, 0x09, 0x00, 0x01, 0x01,         // AC header -> interface 1
      0x09, 0x04, 0x01, 0x00, 0x02, 0x01, 0x03, 0x00, 0x00,         // interface 1: MIDIStreaming
      0x07, 0x24, 0x01, 0x00, 0x01, 0x07, 0x00,                     // MS header
      0x09, 0x05, 0x01, 0x02, 0x40, 0x00, 0x00, 0x00, 0x00,         // bulk OUT 0x01
      0x05, 0x25, 0x01, 0x01, 0x01,                                 // MS bulk data endpoint
      0x09, 0x05, 0x81, 0x02, 0x40, 0x00, 0x00, 0x00, 0x00,         // bulk IN 0x81
      0x05, 0x25, 0x01, 0x01, 0x01};
  d.insert(d.end(), cfg.begin(), cfg.end());
  return d;
}

void set_bit(std::vector<uint8_t>& bits, unsigned b) {
  if (b / 8 < bits.size()) bits[b / 8] |= uint8_t(1u << (b % 8));
}

}  // namespace

enum class Kind { Usb, Hid, Gpio, Evdev };

struct Dev {
  Kind kind;
  std::string record;     // umockdev description (re-added on replug)
  std::string syspath;    // /sys/devices/... of the device that owns the node
  std::string node;       // /dev/...
  bool plugged = false;
  int master = -1;        // pty master (hidraw, evdev)
  std::deque<std::vector<uint8_t>> reports;  // hidraw: one per read
  std::mutex m;
  // USB
  std::deque<UMockdevIoctlData*> in_urbs, done_urbs, discarded;
  std::deque<std::vector<uint8_t>> in_packets;
  std::vector<uint8_t> out_bytes;
  bool driver = false, detached = false;
  // GPIO
  VirtualBench::Gpio gpio;
  std::vector<int> line_fd;  // write ends, per line (-1: not requested)
  std::vector<uint32_t> line_flags;
  // evdev
  VirtualBench::Evdev ev;
  VirtualBench::UsbMidi usb;
  VirtualBench::Hid hid;
  std::vector<std::string> old_nodes;  // before replugs: programs may still hold them open
};

struct VirtualBench::Impl {
  UMockdevTestbed* tb = nullptr;
  UMockdevIoctlBase* handler = nullptr;
  std::vector<std::unique_ptr<Dev>> devs;
  int usb_n = 0, hid_n = 0, gpio_n = 0, ev_n = 0;
  std::vector<std::thread> players;
  std::atomic<bool> stop{false};
  std::atomic<int> playing{0};
  std::mutex devs_m;  // devs and their node names (the ioctl thread looks them up)
  Dev* by_node(const char* node) {
    std::lock_guard lock(devs_m);
    for (auto& d : devs)
      if (d->node == node || std::find(d->old_nodes.begin(), d->old_nodes.end(), node) != d->old_nodes.end())
        return d.get();
    return nullptr;
  }
  void add(Dev& d) {
    GError* err = nullptr;
    if (!umockdev_testbed_add_from_string(tb, d.record.c_str(), &err)) {
      const std::string msg = err ? err->message : "?";
      if (err) g_error_free(err);
      throw std::runtime_error("umockdev: " + msg);
    }
    d.plugged = true;
    if (d.kind == Kind::Hid || d.kind == Kind::Evdev) {
      d.master = umockdev_testbed_get_dev_fd(tb, d.node.c_str());
      termios t{};
      tcgetattr(d.master, &t);
      cfmakeraw(&t);  // binary reports: no ^C, ^S/^Q or CR handling on the line
      tcsetattr(d.master, TCSANOW, &t);
      // hidraw reads are served by the handler; one byte on the tty keeps poll() ready.
      if (d.kind == Kind::Hid && ::write(d.master, "r", 1) != 1) std::perror("vbench: hidraw node");
    }
    umockdev_testbed_uevent(tb, d.syspath.c_str(), "add");
  }
  void describe(Dev& d);
  int plug_new(std::unique_ptr<Dev> d);
  static gboolean on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self);
  static gboolean on_read(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self);
  bool usb_ioctl(Dev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg);
  bool gpio_ioctl(Dev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg);
  bool evdev_ioctl(Dev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg);
};

namespace {
void complete(UMockdevIoctlClient* c, long res, int err) { umockdev_ioctl_client_complete(c, res, err); }
template <class T>
bool answer(UMockdevIoctlClient* c, UMockdevIoctlData* arg, const T& v) {
  UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(T), nullptr);
  if (!d) return false;
  std::memcpy(d->data, &v, sizeof(T));
  complete(c, 0, 0);
  return true;
}
bool answer_bytes(UMockdevIoctlClient* c, UMockdevIoctlData* arg, size_t len, const void* src, size_t n, long result) {
  UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, len, nullptr);
  if (!d) return false;
  std::memset(d->data, 0, len);
  std::memcpy(d->data, src, std::min(len, n));
  complete(c, result, 0);
  return true;
}
}  // namespace

gboolean VirtualBench::Impl::on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self) {
  auto* impl = static_cast<Impl*>(self);
  Dev* d = impl->by_node(umockdev_ioctl_client_get_devnode(c));
  if (!d) return FALSE;
  const unsigned long req = umockdev_ioctl_client_get_request(c);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(c);
  std::lock_guard lock(d->m);
  switch (d->kind) {
    case Kind::Usb: return impl->usb_ioctl(*d, c, req, arg);
    case Kind::Gpio: return impl->gpio_ioctl(*d, c, req, arg);
    case Kind::Evdev: return impl->evdev_ioctl(*d, c, req, arg);
    case Kind::Hid:
      if (req == HIDIOCGRDESCSIZE) return answer(c, arg, int(1));
      return FALSE;
  }
  return FALSE;
}

gboolean VirtualBench::Impl::on_read(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self) {
  auto* impl = static_cast<Impl*>(self);
  const char* node = umockdev_ioctl_client_get_devnode(c);
  Dev* d = impl->by_node(node);
  if (!d || d->kind != Kind::Hid) return FALSE;
  std::lock_guard lock(d->m);
  if (!d->plugged || d->node != node) {  // the program still holds a removed device's node
    complete(c, -1, ENODEV);
    return TRUE;
  }
  if (d->reports.empty()) {
    complete(c, -1, EAGAIN);
    return TRUE;
  }
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(c);
  std::vector<uint8_t>& r = d->reports.front();
  const size_t n = std::min(r.size(), size_t(arg->data_len));
  umockdev_ioctl_data_update(arg, 0, r.data(), int(n));
  d->reports.pop_front();
  complete(c, long(n), 0);
  return TRUE;
}

bool VirtualBench::Impl::usb_ioctl(Dev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
  switch (req) {
    case USBDEVFS_GET_CAPABILITIES:
      return answer(c, arg, uint32_t(USBDEVFS_CAP_BULK_CONTINUATION | USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                                     USBDEVFS_CAP_REAP_AFTER_DISCONNECT | USBDEVFS_CAP_ZERO_PACKET));
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_CLEAR_HALT:
    case USBDEVFS_RESETEP:
    case USBDEVFS_SETINTERFACE:
      complete(c, 0, 0);
      return true;
    case USBDEVFS_GETDRIVER: {
      if (!d.driver || d.detached) {
        complete(c, -1, ENODATA);
        return true;
      }
      usbdevfs_getdriver g{};
      std::strcpy(g.driver, "snd-usb-audio");
      UMockdevIoctlData* a = umockdev_ioctl_data_resolve(arg, 0, sizeof g, nullptr);
      auto* in = reinterpret_cast<usbdevfs_getdriver*>(a->data);
      g.interface = in->interface;
      std::memcpy(a->data, &g, sizeof g);
      complete(c, 0, 0);
      return true;
    }
    case USBDEVFS_IOCTL: {  // USBDEVFS_DISCONNECT through the generic ioctl: detach the driver
      d.detached = true;
      complete(c, 0, 0);
      return true;
    }
    case USBDEVFS_SUBMITURB: {
      UMockdevIoctlData* urb_data = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
      auto* urb = reinterpret_cast<usbdevfs_urb*>(urb_data->data);
      UMockdevIoctlData* buf = umockdev_ioctl_data_resolve(urb_data, offsetof(usbdevfs_urb, buffer), size_t(urb->buffer_length), nullptr);
      umockdev_ioctl_data_ref(urb_data);
      if (urb->endpoint & 0x80) {
        d.in_urbs.push_back(urb_data);
      } else {
        if (buf) d.out_bytes.insert(d.out_bytes.end(), buf->data, buf->data + urb->buffer_length);
        urb->actual_length = urb->buffer_length;
        urb->status = 0;
        d.done_urbs.push_back(urb_data);
      }
      complete(c, 0, 0);
      return true;
    }
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: {
      UMockdevIoctlData* urb_data = nullptr;
      if (!d.discarded.empty()) {
        urb_data = d.discarded.front();
        d.discarded.pop_front();
        reinterpret_cast<usbdevfs_urb*>(urb_data->data)->status = -ENOENT;
        reinterpret_cast<usbdevfs_urb*>(urb_data->data)->actual_length = 0;
      } else if (!d.done_urbs.empty()) {
        urb_data = d.done_urbs.front();
        d.done_urbs.pop_front();
      } else if (!d.in_urbs.empty() && !d.in_packets.empty()) {
        urb_data = d.in_urbs.front();
        d.in_urbs.pop_front();
        auto* urb = reinterpret_cast<usbdevfs_urb*>(urb_data->data);
        std::vector<uint8_t>& p = d.in_packets.front();
        const size_t n = std::min(p.size(), size_t(urb->buffer_length));
        std::memcpy(urb->buffer, p.data(), n);
        urb->actual_length = int(n);
        urb->status = 0;
        d.in_packets.pop_front();
      }
      if (!urb_data) {
        complete(c, -1, EAGAIN);
        return true;
      }
      UMockdevIoctlData* ptr = umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), nullptr);
      umockdev_ioctl_data_set_ptr(ptr, 0, urb_data);
      umockdev_ioctl_data_unref(urb_data);
      complete(c, 0, 0);
      return true;
    }
    case USBDEVFS_DISCARDURB: {
      const gulong addr = *reinterpret_cast<gulong*>(arg->data);
      for (auto it = d.in_urbs.begin(); it != d.in_urbs.end(); ++it)
        if ((*it)->client_addr == addr) {
          d.discarded.push_back(*it);
          d.in_urbs.erase(it);
          complete(c, 0, 0);
          return true;
        }
      complete(c, -1, EINVAL);
      return true;
    }
    default:
      return false;
  }
}

bool VirtualBench::Impl::gpio_ioctl(Dev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
  switch (req) {
    case GPIO_GET_CHIPINFO_IOCTL: {
      gpiochip_info info{};
      std::snprintf(info.name, sizeof info.name, "%s", d.node.substr(5).c_str());
      std::snprintf(info.label, sizeof info.label, "%s", d.gpio.label.c_str());
      info.lines = uint32_t(d.gpio.lines.size());
      return answer(c, arg, info);
    }
    case GPIO_GET_LINEINFO_IOCTL: {
      UMockdevIoctlData* a = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpioline_info), nullptr);
      auto* info = reinterpret_cast<gpioline_info*>(a->data);
      const uint32_t off = info->line_offset;
      if (off >= d.gpio.lines.size()) {
        complete(c, -1, EINVAL);
        return true;
      }
      info->flags = 0;
      if (d.line_fd[off] >= 0) {
        info->flags |= GPIOLINE_FLAG_KERNEL;
        std::snprintf(info->consumer, sizeof info->consumer, "marionette");
      }
      std::snprintf(info->name, sizeof info->name, "%s", d.gpio.lines[off].c_str());
      complete(c, 0, 0);
      return true;
    }
    case GPIO_GET_LINEEVENT_IOCTL: {
      UMockdevIoctlData* a = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpioevent_request), nullptr);
      auto* r = reinterpret_cast<gpioevent_request*>(a->data);
      if (r->lineoffset >= d.gpio.lines.size()) {
        complete(c, -1, EINVAL);
        return true;
      }
      if (d.line_fd[r->lineoffset] >= 0) {
        complete(c, -1, EBUSY);
        return true;
      }
      int p[2];
      if (pipe2(p, O_CLOEXEC | O_NONBLOCK) != 0) {
        complete(c, -1, errno);
        return true;
      }
      d.line_fd[r->lineoffset] = p[1];
      d.line_flags[r->lineoffset] = r->handleflags;
      r->fd = p[0];  // same process: the program reads the pipe like a kernel event fd
      complete(c, 0, 0);
      return true;
    }
    default:
      return false;
  }
}

bool VirtualBench::Impl::evdev_ioctl(Dev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
  const unsigned nr = _IOC_NR(req), len = _IOC_SIZE(req);
  if (_IOC_TYPE(req) != 'E') return false;
  const Evdev& e = d.ev;
  if (req == EVIOCGVERSION) return answer(c, arg, int(0x010001));
  if (req == EVIOCGID) return answer(c, arg, input_id{BUS_USB, uint16_t(e.vid), uint16_t(e.pid), 1});
  if (req == EVIOCSCLOCKID || req == EVIOCGRAB) {
    complete(c, 0, 0);
    return true;
  }
  if (req == EVIOCGREP) return answer(c, arg, std::array<unsigned, 2>{0, 0});
  if (_IOC_DIR(req) == _IOC_READ && nr == 0x06) return answer_bytes(c, arg, len, e.name.c_str(), e.name.size() + 1, long(e.name.size() + 1));
  if (_IOC_DIR(req) == _IOC_READ && (nr == 0x07 || nr == 0x08)) return answer_bytes(c, arg, len, "", 1, 1);
  if (_IOC_DIR(req) == _IOC_READ && nr == 0x09) {
    std::vector<uint8_t> p(len, 0);
    set_bit(p, INPUT_PROP_POINTER);
    return answer_bytes(c, arg, len, p.data(), p.size(), long(len));
  }
  if (_IOC_DIR(req) == _IOC_READ && nr >= 0x18 && nr <= 0x1b) {  // key/led/snd/sw state: all off
    std::vector<uint8_t> z(len, 0);
    return answer_bytes(c, arg, len, z.data(), z.size(), long(len));
  }
  if (_IOC_DIR(req) == _IOC_READ && nr >= 0x20 && nr < 0x20 + EV_CNT) {
    std::vector<uint8_t> bits(len, 0);
    switch (nr - 0x20) {
      case 0:
        for (unsigned t : {EV_SYN, EV_KEY, EV_ABS}) set_bit(bits, t);
        break;
      case EV_KEY:
        for (unsigned k : {BTN_TOOL_PEN, BTN_TOOL_RUBBER, BTN_TOUCH, BTN_STYLUS, BTN_STYLUS2}) set_bit(bits, k);
        break;
      case EV_ABS:
        for (unsigned a : {ABS_X, ABS_Y, ABS_PRESSURE, ABS_TILT_X, ABS_TILT_Y}) set_bit(bits, a);
        break;
      default:
        break;
    }
    return answer_bytes(c, arg, len, bits.data(), bits.size(), long(len));
  }
  if (_IOC_DIR(req) == _IOC_READ && nr >= 0x40 && nr < 0x40 + ABS_CNT) {
    input_absinfo a{};
    switch (nr - 0x40) {
      case ABS_X: a.maximum = e.x_max; break;
      case ABS_Y: a.maximum = e.y_max; break;
      case ABS_PRESSURE: a.maximum = e.pressure_max; break;
      case ABS_TILT_X:
      case ABS_TILT_Y: a.minimum = -e.tilt; a.maximum = e.tilt - 1; break;
      default: break;
    }
    return answer(c, arg, a);
  }
  if (_IOC_DIR(req) == _IOC_READ && nr == 0x0a) {  // MT slots: none
    complete(c, -1, EINVAL);
    return true;
  }
  return false;
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
}

VirtualBench::~VirtualBench() {
  stop_playing();
  for (auto& d : p_->devs) {
    for (int fd : d->line_fd)
      if (fd >= 0) ::close(fd);
    for (auto* q : {&d->in_urbs, &d->done_urbs, &d->discarded})
      for (auto* u : *q) umockdev_ioctl_data_unref(u);
  }
  g_object_unref(p_->tb);
  g_object_unref(p_->handler);
}

// Gives the device a fresh node (a replugged device gets a new number, as in the kernel)
// and its umockdev description.
void VirtualBench::Impl::describe(Dev& d) {
  std::lock_guard lock(devs_m);
  if (!d.node.empty()) d.old_nodes.push_back(d.node);
  switch (d.kind) {
    case Kind::Usb: {
      const int n = ++usb_n + 1;
      char node[32], vp[64];
      std::snprintf(node, sizeof node, "bus/usb/001/%03d", n);
      std::snprintf(vp, sizeof vp, "A: idVendor=%04x\\n\nA: idProduct=%04x\\n\n", d.usb.vid, d.usb.pid);
      d.node = std::string("/dev/") + node;
      d.syspath = "/sys/devices/usbmidi" + std::to_string(n);
      d.record = "P: /devices/usbmidi" + std::to_string(n) + "\nN: " + node + "\nE: SUBSYSTEM=usb\nE: DEVTYPE=usb_device\n" +
                 "E: DRIVER=usb\nE: BUSNUM=001\nE: DEVNUM=" + std::to_string(n) + "\nE: DEVNAME=/dev/" + node + "\n" +
                 "A: busnum=1\\n\nA: devnum=" + std::to_string(n) + "\\n\nA: speed=12\\n\nA: bConfigurationValue=1\\n\n" +
                 vp + "A: dev=189:" + std::to_string(n) + "\\n\nH: descriptors=" + hex(midi_descriptors(d.usb.vid, d.usb.pid)) + "\n";
      break;
    }
    case Kind::Hid: {
      const int n = hid_n++;
      const Hid& h = d.hid;
      char id[64], vp[128], hid_id[64];
      std::snprintf(id, sizeof id, "0003:%04X:%04X.%04X", h.vid, h.pid, n + 1);
      std::snprintf(vp, sizeof vp, "A: idVendor=%04x\\n\nA: idProduct=%04x\\n\n", h.vid, h.pid);
      std::snprintf(hid_id, sizeof hid_id, "0003:%08X:%08X", h.vid, h.pid);
      const std::string num = std::to_string(n), ifc = num + "-1:1.0";  // unique: bus links outlive removal
      const std::string usb = "/devices/hidusb" + num, hid = usb + "/" + ifc + "/" + id;
      d.node = "/dev/hidraw" + num;
      d.syspath = "/sys" + usb;  // unplugging removes the whole USB device
      d.record = "P: " + usb + "\nE: SUBSYSTEM=usb\nE: DEVTYPE=usb_device\n" + vp + "A: manufacturer=marionette bench\\n\n" +
                 "A: product=" + h.name + "\\n\nA: serial=" + h.uniq + "\\n\n\n" + "P: " + usb +
                 "/" + ifc + "\nE: SUBSYSTEM=usb\nE: DEVTYPE=usb_interface\nA: bInterfaceNumber=00\\n\n\n" + "P: " + hid +
                 "\nE: SUBSYSTEM=hid\nE: HID_ID=" + hid_id + "\nE: HID_NAME=" + h.name + "\nE: HID_UNIQ=" + h.uniq +
                 "\nH: report_descriptor=" + hex(h.descriptor) + "\n\n" + "P: " + hid + "/hidraw/hidraw" + num +
                 "\nN: hidraw" + num + "\nE: SUBSYSTEM=hidraw\nE: DEVNAME=/dev/hidraw" + num + "\nA: dev=240:" + num + "\\n\n";
      break;
    }
    case Kind::Gpio: {
      const std::string num = std::to_string(gpio_n++);
      d.node = "/dev/gpiochip" + num;
      d.syspath = "/sys/devices/platform/gpio" + num + "/gpiochip" + num;
      d.record = "P: /devices/platform/gpio" + num + "/gpiochip" + num + "\nN: gpiochip" + num +
                 "\nE: SUBSYSTEM=gpio\nE: DEVNAME=/dev/gpiochip" + num + "\nA: dev=254:" + num + "\\n\n";
      break;
    }
    case Kind::Evdev: {
      const std::string num = std::to_string(ev_n++);
      const std::string dev = "/devices/evusb" + num + "/input/input" + num;
      d.node = "/dev/input/event" + num;
      d.syspath = "/sys" + dev;
      d.record = "P: " + dev + "\nE: SUBSYSTEM=input\nE: NAME=\"" + d.ev.name + "\"\nA: name=" + d.ev.name + "\\n\n\n" +
                 "P: " + dev + "/event" + num + "\nN: input/event" + num + "\nE: SUBSYSTEM=input\nE: DEVNAME=/dev/input/event" +
                 num + "\nA: dev=13:" + std::to_string(64 + std::stoi(num)) + "\\n\n";
      break;
    }
  }
  umockdev_testbed_attach_ioctl(tb, d.node.c_str(), handler, nullptr);
}

int VirtualBench::Impl::plug_new(std::unique_ptr<Dev> d) {
  describe(*d);
  add(*d);
  std::lock_guard lock(devs_m);
  devs.push_back(std::move(d));
  return int(devs.size()) - 1;
}

int VirtualBench::add_usb_midi(const UsbMidi& u) {
  auto d = std::make_unique<Dev>();
  d->kind = Kind::Usb;
  d->usb = u;
  d->driver = u.kernel_driver;
  return p_->plug_new(std::move(d));
}

int VirtualBench::add_hid(const Hid& h) {
  auto d = std::make_unique<Dev>();
  d->kind = Kind::Hid;
  d->hid = h;
  return p_->plug_new(std::move(d));
}

int VirtualBench::add_gpio(const Gpio& g) {
  auto d = std::make_unique<Dev>();
  d->kind = Kind::Gpio;
  d->gpio = g;
  d->line_fd.assign(g.lines.size(), -1);
  d->line_flags.assign(g.lines.size(), 0);
  return p_->plug_new(std::move(d));
}

int VirtualBench::add_evdev(const Evdev& e) {
  auto d = std::make_unique<Dev>();
  d->kind = Kind::Evdev;
  d->ev = e;
  return p_->plug_new(std::move(d));
}

void VirtualBench::usb_in(int dev, std::span<const uint8_t> packets) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (d.plugged) d.in_packets.emplace_back(packets.begin(), packets.end());
}

void VirtualBench::hid_report(int dev, std::span<const uint8_t> report) {
  // Reads of the node are answered from this queue (handle-read), one report per read as
  // hidraw does; the node's tty only makes poll() report it readable.
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (d.plugged) d.reports.emplace_back(report.begin(), report.end());
}

void VirtualBench::gpio_edge(int dev, unsigned line, int level, int64_t mono_ns) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged || line >= d.line_fd.size() || d.line_fd[line] < 0) return;
  gpioevent_data ev{};
  ev.timestamp = uint64_t(mono_ns);
  ev.id = level ? GPIOEVENT_EVENT_RISING_EDGE : GPIOEVENT_EVENT_FALLING_EDGE;
  if (::write(d.line_fd[line], &ev, sizeof ev) < 0) std::perror("vbench: gpio write");
}

void VirtualBench::evdev_event(int dev, uint16_t type, uint16_t code, int32_t value, int64_t mono_ns) {
  Dev& d = *p_->devs[size_t(dev)];
  if (!d.plugged) return;
  input_event ev{};
  ev.input_event_sec = decltype(ev.input_event_sec)(mono_ns / 1000000000);
  ev.input_event_usec = decltype(ev.input_event_usec)((mono_ns % 1000000000) / 1000);
  ev.type = type;
  ev.code = code;
  ev.value = value;
  if (::write(d.master, &ev, sizeof ev) < 0) std::perror("vbench: evdev write");
}

void VirtualBench::write(int dev, const WireRecord& r, int64_t epoch) {
  switch (r.kind) {
    case WireKind::UsbMidi: usb_in(dev, r.bytes()); break;
    case WireKind::HidReport: hid_report(dev, r.bytes()); break;
    case WireKind::GpioEdge: gpio_edge(dev, r.data[0], r.data[1], epoch + r.t_ns); break;
    default: break;
  }
}

std::vector<uint8_t> VirtualBench::usb_out(int dev) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  return d.out_bytes;
}

uint32_t VirtualBench::gpio_flags(int dev, unsigned line) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  return line < d.line_flags.size() ? d.line_flags[line] : 0;
}

bool VirtualBench::kernel_driver_detached(int dev) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  return d.detached;
}

void VirtualBench::unplug(int dev) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (!d.plugged) return;
  d.plugged = false;
  umockdev_testbed_uevent(p_->tb, d.syspath.c_str(), "remove");
  umockdev_testbed_remove_device(p_->tb, d.syspath.c_str());
  for (int& fd : d.line_fd) {  // the kernel hangs up a removed chip's event fds
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
  for (auto* q : {&d.in_urbs, &d.done_urbs})  // in-flight URBs die with the device
    while (!q->empty()) {
      reinterpret_cast<usbdevfs_urb*>(q->front()->data)->status = -ENODEV;
      d.discarded.push_back(q->front());
      q->pop_front();
    }
  d.in_packets.clear();
  d.reports.clear();
  d.detached = false;
}

void VirtualBench::replug(int dev) {
  Dev& d = *p_->devs[size_t(dev)];
  std::lock_guard lock(d.m);
  if (d.plugged) return;
  p_->describe(d);
  p_->add(d);
}

bool VirtualBench::plugged(int dev) const { return p_->devs[size_t(dev)]->plugged; }

void VirtualBench::deny(int dev, bool denied) {
  const Dev& d = *p_->devs[size_t(dev)];
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

void VirtualBench::play(int dev, SimDevice& sim, int64_t epoch) {
  // One player thread per call: the bench is small (a device or two per test).
  ++p_->playing;
  p_->players.emplace_back([this, dev, &sim, epoch] {
    while (!p_->stop.load()) {
      timespec ts{};
      clock_gettime(CLOCK_MONOTONIC, &ts);
      const int64_t now = int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec - epoch;
      sim.drain(now, [&](const WireRecord& r) { write(dev, r, epoch); });
      if (now > sim.end_ns()) break;
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    --p_->playing;
  });
}

void VirtualBench::stop_playing() {
  p_->stop = true;
  for (auto& t : p_->players) t.join();
  p_->players.clear();
  p_->stop = false;
}

bool VirtualBench::played_all() const { return p_->playing.load() == 0; }

}  // namespace mar
