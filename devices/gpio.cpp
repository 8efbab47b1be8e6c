// GPIO encoders and buttons through libgpiod 1.6 (v1 API): both-edge event requests with
// pull-up bias; the kernel timestamps each edge. A line's events come on its own fd, so
// the edges of all lines are merged by timestamp before the quadrature decoder sees them.
#include "devices/backends.h"
#include "devices/util.h"

#include <gpiod.h>
#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace mar {
namespace {

class GpioBackend final : public Backend {
 public:
  GpioBackend(const DeviceSpec& s, uint16_t source) : Backend(s, source) {
    GpioLayout g;
    int line = 0;
    for (const auto& e : spec_.encoders) {
      g.encoders.push_back({line, line + 1, e.steps_per_detent});
      names_.push_back(e.a);
      names_.push_back(e.b);
      line += 2;
    }
    for (const auto& b : spec_.buttons) {
      g.buttons.push_back(line++);
      names_.push_back(b);
    }
    g.debounce_ns = int64_t(spec_.debounce_ms * 1e6);
    layout_ = g;
  }
  ~GpioBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    if (chip_) gpiod_chip_close(chip_);  // releases the requested lines too
    chip_ = nullptr;
    lines_.clear();
    pfds_.clear();
    fds_.clear();
  }
  bool present() const override { return devutil::exists(dev_path_); }
  bool poll(int64_t now_ns, WireSink& out) override;

 private:
  struct Edge {
    int64_t t;
    uint8_t line, level;
  };
  GpioLayout layout_;
  std::vector<std::string> names_;
  gpiod_chip* chip_ = nullptr;
  std::vector<gpiod_line*> lines_;
  std::vector<pollfd> pfds_;
  std::string dev_path_;
  Edge edges_[1024];
};

gpiod_line* find_line(gpiod_chip* chip, const std::string& name) {
  if (gpiod_line* l = gpiod_chip_find_line(chip, name.c_str())) return l;
  char* end = nullptr;
  const long off = std::strtol(name.c_str(), &end, 10);
  if (end && *end == 0 && !name.empty() && off >= 0) return gpiod_chip_get_line(chip, unsigned(off));
  return nullptr;
}

// By name, path or number (libgpiod), else by label: the chips listed in sysfs are opened and
// asked. libgpiod's own label search scans /dev (which not every setup lists, and which under
// umockdev's preload leaks a socket per scan), so it is used only where sysfs has no GPIO
// folders at all.
gpiod_chip* open_chip(const std::string& want) {
  const bool number = !want.empty() && want.find_first_not_of("0123456789") == std::string::npos;
  const bool label = !number && want.find('/') == std::string::npos && want.rfind("gpiochip", 0) != 0;
  if (!label) return gpiod_chip_open_lookup(want.c_str());
  bool listed = false;
  int denied = 0;  // a chip this user may not open may be the one asked for
  for (const char* dir : {"/sys/bus/gpio/devices", "/sys/class/gpio"}) {
    listed = listed || devutil::exists(dir);
    for (const std::string& n : devutil::list_dir(dir)) {
      if (n.rfind("gpiochip", 0) != 0) continue;
      if (gpiod_chip* c = gpiod_chip_open(("/dev/" + n).c_str())) {
        if (want == gpiod_chip_label(c)) return c;
        gpiod_chip_close(c);
      } else if (errno == EACCES || errno == EPERM) {
        denied = errno;
      }
    }
  }
  if (!listed) return gpiod_chip_open_lookup(want.c_str());
  errno = denied ? denied : ENOENT;
  return nullptr;
}

DeviceState GpioBackend::open() {
  errno = 0;
  chip_ = open_chip(spec_.chip);
  if (!chip_) {
    const int e = errno;
    const std::string what = spec_.chip.find('/') == std::string::npos ? "/dev/" + spec_.chip : spec_.chip;
    if (e == EACCES || e == EPERM) {
      problem_ = denied_hint(what);
      return DeviceState::Denied;
    }
    problem_ = "GPIO chip '" + spec_.chip + "' not found";
    return DeviceState::Waiting;
  }
  fds_.clear();
  dev_path_ = std::string("/dev/") + gpiod_chip_name(chip_);
  node_ = dev_path_;
  identity_ = std::string(gpiod_chip_name(chip_)) + " '" + gpiod_chip_label(chip_) + "'";
  for (const std::string& n : names_) {
    gpiod_line* l = find_line(chip_, n);
    if (!l) {
      problem_ = "GPIO line '" + n + "' not found on " + identity_;
      close();
      return DeviceState::Waiting;
    }
    gpiod_line_request_config cfg{"marionette", GPIOD_LINE_REQUEST_EVENT_BOTH_EDGES, GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP};
    if (gpiod_line_request(l, &cfg, 0) != 0) {
      const int e = errno;
      problem_ = "GPIO line '" + n + "' on " + identity_ + ": " +
                 (e == EBUSY ? std::string("in use by another program") : std::string(std::strerror(e)));
      close();
      return e == EACCES || e == EPERM ? DeviceState::Denied : DeviceState::Waiting;
    }
    lines_.push_back(l);
    pfds_.push_back({gpiod_line_event_get_fd(l), POLLIN, 0});
    fds_.push_back(pfds_.back().fd);
  }
  config_ = DecoderConfig{};
  config_.kind = WireKind::GpioEdge;
  config_.gpio = layout_;
  problem_.clear();
  return DeviceState::Connected;
}

bool GpioBackend::poll(int64_t, WireSink& out) {
  if (pfds_.empty()) return true;
  if (::poll(pfds_.data(), nfds_t(pfds_.size()), 0) < 0) return errno == EINTR;
  size_t n = 0;
  for (size_t i = 0; i < pfds_.size(); ++i) {
    if (pfds_[i].revents & (POLLERR | POLLHUP | POLLNVAL)) return false;
    if (!(pfds_[i].revents & POLLIN)) continue;
    gpiod_line_event ev[64];
    const int got = gpiod_line_event_read_fd_multiple(pfds_[i].fd, ev, 64);
    if (got < 0) {
      if (errno == EAGAIN) continue;
      return false;
    }
    for (int k = 0; k < got; ++k) {
      if (n == std::size(edges_)) {  // more edges in one frame than it can hold: counted, dropped
        count_malformed(uint64_t(got - k));
        break;
      }
      const int64_t ts = int64_t(ev[k].ts.tv_sec) * 1000000000 + ev[k].ts.tv_nsec;
      edges_[n++] = {ts - epoch_ns_, uint8_t(i), uint8_t(ev[k].event_type == GPIOD_LINE_EVENT_RISING_EDGE)};
    }
  }
  // Each line's fd is in time order; the lines together are not. Insertion sort: stable,
  // in place (std::stable_sort may allocate), and the input is nearly sorted.
  for (size_t k = 1; k < n; ++k)
    for (size_t j = k; j > 0 && edges_[j].t < edges_[j - 1].t; --j) std::swap(edges_[j], edges_[j - 1]);
  for (size_t k = 0; k < n; ++k) {
    const uint8_t d[2] = {edges_[k].line, edges_[k].level};
    emit(WireRecord::make(edges_[k].t, WireKind::GpioEdge, d, source_), out);
  }
  return true;
}

}  // namespace

std::unique_ptr<Backend> make_gpio_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<GpioBackend>(s, source);
}

BackendReport discover_gpio(const std::vector<ProfileId>&) {
  BackendReport r{"gpio", "ok", {}};
  std::vector<std::string> seen;
  for (const char* dir : {"/sys/bus/gpio/devices", "/sys/class/gpio"})
    for (const std::string& n : devutil::list_dir(dir)) {
      if (n.rfind("gpiochip", 0) != 0 || std::find(seen.begin(), seen.end(), n) != seen.end()) continue;
      seen.push_back(n);
      FoundDevice f;
      f.backend = "gpio";
      f.node = "/dev/" + n;
      if (gpiod_chip* c = gpiod_chip_open(f.node.c_str())) {
        f.identity = n + " '" + gpiod_chip_label(c) + "' " + std::to_string(gpiod_chip_num_lines(c)) + " lines";
        gpiod_chip_close(c);
        f.status = "available";
      } else {
        f.identity = n;
        devutil::access_status(f);
        if (f.status == "available") {
          f.status = "unreadable";
          f.problem = "libgpiod cannot open it";
        }
      }
      r.found.push_back(f);
    }
  return r;
}

}  // namespace mar
