// Pen tablets through libevdev: /dev/input/event* nodes with pressure, tilt, proximity
// and stylus buttons, selected by name or USB ID. The node's axis and key events are the
// wire records (decoded by input/evdev_decoder.cpp into the HID digitizer usages, so pen
// bindings are the same for evdev and hidraw tablets); the kernel's event timestamps
// (CLOCK_MONOTONIC) are kept, and the axes' ranges are the decoder's configuration.
#include "devices/backends.h"
#include "devices/util.h"
#include "input/evdev.h"

#include <fcntl.h>
#include <libevdev/libevdev.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <ctime>

namespace mar {
namespace {

class TabletBackend final : public Backend {
 public:
  using Backend::Backend;
  ~TabletBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    if (dev_) libevdev_free(dev_);
    if (fd_ >= 0) ::close(fd_);
    dev_ = nullptr;
    fd_ = -1;
    fds_.clear();
  }
  bool present() const override { return devutil::exists(sys_); }
  bool poll(int64_t now_ns, WireSink& out) override;

 private:
  void put(const input_event& ev, WireSink& out);
  libevdev* dev_ = nullptr;
  int fd_ = -1;
  std::string sys_;
};

bool is_pen(libevdev* d) {
  return libevdev_has_event_code(d, EV_ABS, ABS_X) && libevdev_has_event_code(d, EV_ABS, ABS_Y) &&
         (libevdev_has_event_code(d, EV_KEY, BTN_TOOL_PEN) || libevdev_has_event_code(d, EV_ABS, ABS_PRESSURE));
}

DeviceState TabletBackend::open() {
  bool denied = false;
  std::string denied_node;
  for (const std::string& name : devutil::list_dir("/sys/class/input")) {
    if (name.rfind("event", 0) != 0) continue;
    const std::string node = "/dev/input/" + name;
    const int fd = ::open(node.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      if (errno == EACCES || errno == EPERM) {
        denied = true;
        denied_node = node;
      }
      continue;
    }
    libevdev* d = nullptr;
    if (libevdev_new_from_fd(fd, &d) != 0) {
      ::close(fd);
      continue;
    }
    const std::string dname = libevdev_get_name(d) ? libevdev_get_name(d) : "";
    const bool ok = is_pen(d) && (spec_.product.empty() || dname.find(spec_.product) != std::string::npos) &&
                    (spec_.vid < 0 || libevdev_get_id_vendor(d) == spec_.vid) &&
                    (spec_.pid < 0 || libevdev_get_id_product(d) == spec_.pid);
    if (!ok) {
      libevdev_free(d);
      ::close(fd);
      continue;
    }
    libevdev_set_clock_id(d, CLOCK_MONOTONIC);  // older kernels stamp with REALTIME by default
    config_ = DecoderConfig{};
    config_.kind = WireKind::EvdevEvent;
    for (unsigned code = 0; code <= ABS_MAX; ++code)
      if (evdev::abs_usage(uint16_t(code)) != 0 && libevdev_has_event_code(d, EV_ABS, code))
        if (const input_absinfo* a = libevdev_get_abs_info(d, code))
          config_.axes.push_back({uint16_t(code), a->minimum, a->maximum});
    dev_ = d;
    fd_ = fd;
    fds_ = {fd};
    node_ = node;
    sys_ = "/sys/class/input/" + name;
    identity_ = devutil::vid_pid(libevdev_get_id_vendor(d), libevdev_get_id_product(d)) + " '" + dname + "'";
    problem_.clear();
    return DeviceState::Connected;
  }
  if (denied) {
    problem_ = denied_hint(denied_node);
    return DeviceState::Denied;
  }
  problem_ = "no pen tablet" + (spec_.product.empty() ? std::string() : " named '" + spec_.product + "'") +
             " among /dev/input/event*";
  return DeviceState::Waiting;
}

void TabletBackend::put(const input_event& ev, WireSink& out) {
  if (ev.type != EV_ABS && ev.type != EV_KEY) return;
  const int64_t t = int64_t(ev.input_event_sec) * 1000000000 + int64_t(ev.input_event_usec) * 1000 - epoch_ns_;
  emit(evdev_record(t, ev.type, ev.code, ev.value, source_), out);
}

bool TabletBackend::poll(int64_t, WireSink& out) {
  input_event ev;
  for (int k = 0; k < 4096; ++k) {
    int rc = libevdev_next_event(dev_, LIBEVDEV_READ_FLAG_NORMAL, &ev);
    if (rc == LIBEVDEV_READ_STATUS_SYNC) {
      // The kernel dropped events: catch up with the device's current state.
      count_malformed();
      while (rc == LIBEVDEV_READ_STATUS_SYNC) {
        put(ev, out);
        rc = libevdev_next_event(dev_, LIBEVDEV_READ_FLAG_SYNC, &ev);
      }
      continue;
    }
    if (rc == -EAGAIN) return true;
    if (rc < 0) return false;  // -ENODEV: unplugged
    put(ev, out);
  }
  return true;
}

}  // namespace

std::unique_ptr<Backend> make_tablet_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<TabletBackend>(s, source);
}

BackendReport discover_tablet(const std::vector<ProfileId>&) {
  BackendReport r{"tablet", "ok", {}};
  for (const std::string& name : devutil::list_dir("/sys/class/input")) {
    if (name.rfind("event", 0) != 0) continue;
    FoundDevice f;
    f.backend = "tablet";
    f.node = "/dev/input/" + name;
    const int fd = ::open(f.node.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
      f.identity = devutil::read_line("/sys/class/input/" + name + "/device/name");
      if (f.identity.empty()) continue;
      devutil::access_status(f);
      r.found.push_back(f);
      continue;
    }
    libevdev* d = nullptr;
    if (libevdev_new_from_fd(fd, &d) == 0) {
      const bool pen = libevdev_has_event_code(d, EV_ABS, ABS_X) &&
                       (libevdev_has_event_code(d, EV_KEY, BTN_TOOL_PEN) || libevdev_has_event_code(d, EV_ABS, ABS_PRESSURE));
      if (pen) {
        f.identity = devutil::vid_pid(libevdev_get_id_vendor(d), libevdev_get_id_product(d)) + " '" +
                     (libevdev_get_name(d) ? libevdev_get_name(d) : "") + "'";
        f.status = "available";
        r.found.push_back(f);
      }
      libevdev_free(d);
    }
    ::close(fd);
  }
  return r;
}

}  // namespace mar
