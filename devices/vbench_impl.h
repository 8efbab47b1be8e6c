// The virtual bench's insides, shared by its core (vbench.cpp) and the per-bus emulators
// beside each backend (usb_midi_emu.cpp, hid_emu.cpp, gpio_emu.cpp, tablet_emu.cpp).
#pragma once

#include "devices/vbench.h"

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
#include <utility>

namespace mar {

enum class BenchKind { Usb, Hid, Gpio, Evdev };

/// A submitted URB and the open descriptor (umockdev client) it belongs to, as in usbfs: only
/// that descriptor reaps it, and closing the descriptor discards it. Holds a reference on both.
struct BenchUrb {
  UMockdevIoctlData* data = nullptr;
  UMockdevIoctlClient* fd = nullptr;
  BenchUrb(UMockdevIoctlData* d, UMockdevIoctlClient* c) : data(d), fd(c) {
    umockdev_ioctl_data_ref(data);
    g_object_ref(fd);
  }
  BenchUrb(BenchUrb&& o) noexcept : data(std::exchange(o.data, nullptr)), fd(std::exchange(o.fd, nullptr)) {}
  BenchUrb& operator=(BenchUrb&& o) noexcept {
    std::swap(data, o.data);
    std::swap(fd, o.fd);
    return *this;
  }
  ~BenchUrb() {
    if (data) umockdev_ioctl_data_unref(data);
    if (fd) g_object_unref(fd);
  }
  usbdevfs_urb& urb() const { return *reinterpret_cast<usbdevfs_urb*>(data->data); }
};

struct BenchDev {
  BenchKind kind;
  std::string record;     // umockdev description (re-added on replug)
  std::string syspath;    // /sys/devices/... of the device that owns the node
  std::string node;       // /dev/...
  bool plugged = false;
  int master = -1;        // pty master (hidraw, evdev)
  std::deque<std::vector<uint8_t>> reports;  // hidraw: one per read; evdev: input_events
  std::deque<int64_t> report_t;              // hidraw: each report's show time (-1: none given)
  std::atomic<int64_t> read_t{-1};           // show time of the last hidraw read or IN URB answered
  std::mutex m;
  // USB
  std::deque<BenchUrb> in_urbs, done_urbs, discarded;
  std::deque<std::vector<uint8_t>> in_packets;
  std::deque<int64_t> packet_t;  // each in_packets entry's show time (-1: none given)
  std::deque<int64_t> unacked;   // IN URBs answered with packets the reader has not handed on yet (times)
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
  std::vector<std::unique_ptr<BenchDev>> devs;
  int usb_n = 0, hid_n = 0, gpio_n = 0, ev_n = 0;
  std::vector<std::thread> players;
  std::atomic<bool> stop{false};
  std::atomic<int> playing{0};
  std::deque<std::atomic<int64_t>> written;  // per player: show time written through
  std::atomic<int64_t> allowed{-1};          // lockstep players: show time they may write through
  std::unique_ptr<ReadClock> clock;           // read_clock()
  std::atomic<bool> clocked{false};           // made: IN URBs are tracked until handed on
  std::mutex devs_m;  // devs and their node names (the ioctl thread looks them up)
  BenchDev* by_node(const char* node) {
    std::lock_guard lock(devs_m);
    for (auto& d : devs)
      if (d->node == node || std::find(d->old_nodes.begin(), d->old_nodes.end(), node) != d->old_nodes.end())
        return d.get();
    return nullptr;
  }
  void add(BenchDev& d) {
    GError* err = nullptr;
    if (!umockdev_testbed_add_from_string(tb, d.record.c_str(), &err)) {
      const std::string msg = err ? err->message : "?";
      if (err) g_error_free(err);
      throw std::runtime_error("umockdev: " + msg);
    }
    d.plugged = true;
    if (d.kind == BenchKind::Hid || d.kind == BenchKind::Evdev) {
      d.master = umockdev_testbed_get_dev_fd(tb, d.node.c_str());
      termios t{};
      tcgetattr(d.master, &t);
      cfmakeraw(&t);  // binary reports: no ^C, ^S/^Q or CR handling on the line
      tcsetattr(d.master, TCSANOW, &t);
      // hidraw and evdev reads are served by the handler; one byte on the tty keeps poll() ready.
      if (::write(d.master, "r", 1) != 1) std::perror("vbench: hidraw/evdev node");
    }
    umockdev_testbed_uevent(tb, d.syspath.c_str(), "add");
  }
  void describe(BenchDev& d);
  int plug_new(std::unique_ptr<BenchDev> d);
  static gboolean on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self);
  static gboolean on_read(UMockdevIoctlBase*, UMockdevIoctlClient* c, gpointer self);
  void describe_usb(BenchDev& d);
  void describe_hid(BenchDev& d);
  void describe_gpio(BenchDev& d);
  void describe_evdev(BenchDev& d);
  static bool hid_read(BenchDev& d, UMockdevIoctlClient* c, const char* node);
  static bool evdev_read(BenchDev& d, UMockdevIoctlClient* c, const char* node);
  bool usb_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg);
  bool gpio_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg);
  bool evdev_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg);
};

namespace vb {
inline std::string hex(std::span<const uint8_t> b) {
  std::string s;
  char t[3];
  for (uint8_t v : b) {
    std::snprintf(t, sizeof t, "%02x", v);
    s += t;
  }
  return s;
}
inline void complete(UMockdevIoctlClient* c, long res, int err) { umockdev_ioctl_client_complete(c, res, err); }
template <class T>
inline bool answer(UMockdevIoctlClient* c, UMockdevIoctlData* arg, const T& v) {
  UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(T), nullptr);
  if (!d) return false;
  std::memcpy(d->data, &v, sizeof(T));
  complete(c, 0, 0);
  return true;
}
inline bool answer_bytes(UMockdevIoctlClient* c, UMockdevIoctlData* arg, size_t len, const void* src, size_t n, long result) {
  UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, len, nullptr);
  if (!d) return false;
  std::memset(d->data, 0, len);
  std::memcpy(d->data, src, std::min(len, n));
  complete(c, result, 0);
  return true;
}
}  // namespace vb

}  // namespace mar
