// HID devices on hidraw: found through hidapi's enumeration (which matches on VID/PID,
// serial, product and usage); hidapi 0.13 has no report-descriptor call, so the descriptor
// is read from sysfs (/sys/class/hidraw/<node>/device/report_descriptor) and decoded by our
// parser. Reports are read each frame from the node, opened non-blocking: a hidraw read is
// one report as the kernel gives it, which is all hid_read() does — and hid_read() allocates
// an error string on the frame thread whenever a read fails.
#include "devices/backends.h"
#include "devices/util.h"
#include "input/hid.h"

#include <hidapi/hidapi.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace mar {
namespace {

class HidBackend final : public Backend {
 public:
  using Backend::Backend;
  ~HidBackend() override { close(); }
  DeviceState open() override;
  void close() override {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    fds_.clear();
  }
  bool present() const override { return devutil::exists(sys_); }
  bool poll(int64_t now_ns, WireSink& out) override;

 private:
  int fd_ = -1;
  std::string sys_;
};

bool matches(const DeviceSpec& s, const hid_device_info& d) {
  if (s.vid >= 0 && d.vendor_id != s.vid) return false;
  if (s.pid >= 0 || !s.pids.empty()) {
    bool any = s.pid >= 0 && d.product_id == s.pid;
    for (int p : s.pids) any = any || d.product_id == p;
    if (!any) return false;
  }
  if (!s.serial.empty() && devutil::narrow(d.serial_number) != s.serial) return false;
  if (!s.product.empty() && devutil::narrow(d.product_string).find(s.product) == std::string::npos) return false;
  if (s.usage_page >= 0 && d.usage_page != s.usage_page) return false;
  if (s.usage >= 0 && d.usage != s.usage) return false;
  return true;
}

DeviceState HidBackend::open() {
  static const int init = hid_init();
  if (init != 0) {
    problem_ = "hidapi could not start";
    return DeviceState::Unavailable;
  }
  hid_device_info* list = hid_enumerate(0, 0);
  const hid_device_info* found = nullptr;
  for (const hid_device_info* d = list; d; d = d->next)
    if (matches(spec_, *d)) {
      found = d;
      break;
    }
  if (!found) {
    hid_free_enumeration(list);
    problem_ = "no HID device matches " + (spec_.vid >= 0 ? devutil::vid_pid(spec_.vid, spec_.pid) : std::string("the show"));
    return DeviceState::Waiting;
  }
  node_ = found->path;
  identity_ = devutil::vid_pid(found->vendor_id, found->product_id) + " '" + devutil::narrow(found->product_string) +
              "'" + (found->serial_number && *found->serial_number ? " serial " + devutil::narrow(found->serial_number) : "");
  hid_free_enumeration(list);
  const std::string base = node_.substr(node_.rfind('/') + 1);
  sys_ = "/sys/class/hidraw/" + base;
  fd_ = ::open(node_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    if (errno == EACCES || errno == EPERM) {
      problem_ = denied_hint(node_);
      return DeviceState::Denied;
    }
    problem_ = node_ + ": cannot open (" + std::string(std::strerror(errno)) + ")";
    return DeviceState::Waiting;
  }
  auto bytes = devutil::read_file(sys_ + "/device/report_descriptor");
  if (bytes.empty()) {  // no "device" link: the HID device is two levels up (<hid>/hidraw/<node>)
    char real[4096];
    if (realpath(sys_.c_str(), real)) bytes = devutil::read_file(std::string(real) + "/../../report_descriptor");
  }
  auto desc = parse_hid_descriptor(bytes);
  if (bytes.empty() || !desc.ok()) {
    problem_ = node_ + ": unusable report descriptor (" + (bytes.empty() ? std::string("not readable in sysfs") : desc.error) + ")";
    close();
    return DeviceState::Unavailable;
  }
  config_ = DecoderConfig{};
  config_.kind = WireKind::HidReport;
  config_.hid_descriptor = std::move(bytes);
  problem_.clear();
  return DeviceState::Connected;
}

bool HidBackend::poll(int64_t, WireSink& out) {
  uint8_t buf[WireRecord::kMax];
  for (int k = 0; k < 256; ++k) {  // bounded: a flooding device cannot stall the frame
    const ssize_t n = ::read(fd_, buf, sizeof buf);
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;  // else gone (ENODEV, EIO)
    if (n == 0) return true;
    // hidraw has no timestamps: a report is stamped when read (ReadClock).
    emit(WireRecord::make(read_time(), WireKind::HidReport, {buf, size_t(n)}, source_), out);
    read_taken();
  }
  return true;
}

}  // namespace

std::unique_ptr<Backend> make_hid_backend(const DeviceSpec& s, uint16_t source) {
  return std::make_unique<HidBackend>(s, source);
}

BackendReport discover_hid(const std::vector<ProfileId>& profiles) {
  BackendReport r{"hid", "ok", {}};
  if (hid_init() != 0) return {"hid", "hidapi could not start", {}};
  hid_device_info* list = hid_enumerate(0, 0);
  for (const hid_device_info* d = list; d; d = d->next) {
    FoundDevice f;
    f.backend = "hid";
    char usage[32] = "";
    if (d->usage_page) std::snprintf(usage, sizeof usage, " usage %04x:%04x", d->usage_page, d->usage);
    f.identity = devutil::vid_pid(d->vendor_id, d->product_id) + " '" + devutil::narrow(d->product_string) + "'" +
                 (d->serial_number && *d->serial_number ? " serial " + devutil::narrow(d->serial_number) : "") + usage;
    f.node = d->path;
    f.profile = devutil::profile_of(profiles, d->vendor_id, d->product_id);
    devutil::access_status(f);
    r.found.push_back(f);
  }
  hid_free_enumeration(list);
  return r;
}

}  // namespace mar
