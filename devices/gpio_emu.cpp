// Emulates a gpiochip for the virtual bench: the v1 line ioctls, edges with our own
// timestamps through a pipe per requested line.
#include "devices/vbench_impl.h"

#include <poll.h>

namespace mar {
using namespace vb;

void VirtualBench::Impl::describe_gpio(BenchDev& d) {
  const std::string num = std::to_string(gpio_n++);
  d.node = "/dev/gpiochip" + num;
  d.syspath = "/sys/devices/platform/gpio" + num + "/gpiochip" + num;
  d.record = "P: /devices/platform/gpio" + num + "/gpiochip" + num + "\nN: gpiochip" + num +
             "\nE: SUBSYSTEM=gpio\nE: DEVNAME=/dev/gpiochip" + num + "\nA: dev=254:" + num + "\\n\n";
}

namespace {
// As in the kernel, closing a line's event fd releases the line: the read end of its pipe is
// gone when the write end polls as an error.
bool released(int write_fd) {
  pollfd p{write_fd, 0, 0};
  return ::poll(&p, 1, 0) == 1 && (p.revents & POLLERR);
}
}  // namespace

bool VirtualBench::Impl::gpio_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
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
      if (d.line_fd[r->lineoffset] >= 0 && released(d.line_fd[r->lineoffset])) {
        ::close(d.line_fd[r->lineoffset]);  // the program closed its event fd: the line is free again
        d.line_fd[r->lineoffset] = -1;
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

}  // namespace mar
