// Emulates a class-compliant USB-MIDI device at usbdevfs for the virtual bench: the
// descriptors libusb reads and the URB ioctls (bulk IN/OUT, claim, kernel driver).
#include "devices/vbench_impl.h"

namespace mar {
using namespace vb;

namespace {
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
}  // namespace

void VirtualBench::Impl::describe_usb(BenchDev& d) {
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
}

bool VirtualBench::Impl::usb_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
  // Unplugged: URBs that died with the device are still reaped, anything else is ENODEV.
  const bool reap = req == USBDEVFS_REAPURB || req == USBDEVFS_REAPURBNDELAY;
  if (!d.plugged && !(reap && !d.discarded.empty()) && req != USBDEVFS_DISCARDURB) {
    complete(c, -1, ENODEV);
    return true;
  }
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

}  // namespace mar
