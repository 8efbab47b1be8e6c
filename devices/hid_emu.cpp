// Emulates a hidraw node for the virtual bench: sysfs report descriptor, one queued report
// per read (hidraw keeps report boundaries).
#include "devices/vbench_impl.h"

namespace mar {
using namespace vb;

void VirtualBench::Impl::describe_hid(BenchDev& d) {
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
}

bool VirtualBench::Impl::hid_read(BenchDev& d, UMockdevIoctlClient* c, const char* node) {
  std::lock_guard lock(d.m);
  if (!d.plugged || d.node != node) {  // the program still holds a removed device's node
    complete(c, -1, ENODEV);
    return TRUE;
  }
  if (d.reports.empty()) {
    complete(c, -1, EAGAIN);
    return TRUE;
  }
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(c);
  std::vector<uint8_t>& r = d.reports.front();
  const size_t n = std::min(r.size(), size_t(arg->data_len));
  umockdev_ioctl_data_update(arg, 0, r.data(), int(n));
  d.reports.pop_front();
  d.read_t.store(d.report_t.front(), std::memory_order_release);  // before the reader returns (ReadClock)
  d.report_t.pop_front();
  complete(c, long(n), 0);
  return TRUE;
}

bool VirtualBench::Impl::evdev_read(BenchDev& d, UMockdevIoctlClient* c, const char* node) {
  // As evdev's read: as many whole input_events as fit, EAGAIN when none, EINVAL for a buffer
  // smaller than one.
  std::lock_guard lock(d.m);
  if (!d.plugged || d.node != node) {
    complete(c, -1, ENODEV);
    return TRUE;
  }
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(c);
  const size_t room = size_t(arg->data_len) / sizeof(input_event);
  if (room == 0) {
    complete(c, -1, EINVAL);
    return TRUE;
  }
  if (d.reports.empty()) {
    complete(c, -1, EAGAIN);
    return TRUE;
  }
  size_t n = 0;
  while (n < room && !d.reports.empty()) {
    umockdev_ioctl_data_update(arg, n * sizeof(input_event), d.reports.front().data(), int(sizeof(input_event)));
    d.reports.pop_front();
    ++n;
  }
  complete(c, long(n * sizeof(input_event)), 0);
  return TRUE;
}

}  // namespace mar
