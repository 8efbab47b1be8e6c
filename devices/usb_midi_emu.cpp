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
  // Addresses run 2..127 on a bus, as the kernel's do; after 126 plugs the next bus is used, so
  // each plug keeps a node of its own (the old node's record is kept, see unplug) and libusb's
  // 8-bit bus and device numbers never overflow (they did at the 255th replug).
  const int k = usb_n++;
  const int bus = 1 + k / 126, dev = 2 + k % 126, n = k + 2;
  if (bus > 255) throw std::runtime_error("vbench: more than 32,130 USB plugs in one bench");
  char node[32], vp[64];
  std::snprintf(node, sizeof node, "bus/usb/%03d/%03d", bus, dev);
  std::snprintf(vp, sizeof vp, "A: idVendor=%04x\\n\nA: idProduct=%04x\\n\n", d.usb.vid, d.usb.pid);
  const std::string b = std::to_string(bus), v = std::to_string(dev);
  d.node = std::string("/dev/") + node;
  d.syspath = "/sys/devices/usbmidi" + std::to_string(n);
  d.record = "P: /devices/usbmidi" + std::to_string(n) + "\nN: " + node + "\nE: SUBSYSTEM=usb\nE: DEVTYPE=usb_device\n" +
             "E: DRIVER=usb\nE: BUSNUM=" + std::string(node + 8, 3) + "\nE: DEVNUM=" + v + "\nE: DEVNAME=/dev/" + node + "\n" +
             "A: busnum=" + b + "\\n\nA: devnum=" + v + "\\n\nA: speed=12\\n\nA: bConfigurationValue=1\\n\n" + vp +
             "A: dev=189:" + std::to_string((bus - 1) * 128 + dev - 1) + "\\n\nH: descriptors=" +
             hex(midi_descriptors(d.usb.vid, d.usb.pid)) + "\n";
}

bool VirtualBench::Impl::usb_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
  // A closed descriptor's URBs are gone (the kernel discards them on close).
  for (auto* q : {&d.in_urbs, &d.done_urbs, &d.discarded})
    q->erase(std::remove_if(q->begin(), q->end(), [](const BenchUrb& u) { return !umockdev_ioctl_client_get_connected(u.fd); }),
             q->end());
  auto mine = [c](std::deque<BenchUrb>& q) { return std::find_if(q.begin(), q.end(), [c](const BenchUrb& u) { return u.fd == c; }); };
  // Unplugged: URBs that died with the device are still reaped, anything else is ENODEV.
  const bool reap = req == USBDEVFS_REAPURB || req == USBDEVFS_REAPURBNDELAY;
  if (!d.plugged && !(reap && mine(d.discarded) != d.discarded.end()) && req != USBDEVFS_DISCARDURB) {
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
      if (urb->endpoint & 0x80) {
        d.in_urbs.emplace_back(urb_data, c);
      } else {
        if (buf) d.out_bytes.insert(d.out_bytes.end(), buf->data, buf->data + urb->buffer_length);
        urb->actual_length = urb->buffer_length;
        urb->status = 0;
        d.done_urbs.emplace_back(urb_data, c);
      }
      complete(c, 0, 0);
      return true;
    }
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: {
      std::deque<BenchUrb>* from = nullptr;
      std::deque<BenchUrb>::iterator it;
      if (it = mine(d.discarded); it != d.discarded.end()) {
        from = &d.discarded;
        it->urb().status = -ENOENT;
        it->urb().actual_length = 0;
      } else if (it = mine(d.done_urbs); it != d.done_urbs.end()) {
        from = &d.done_urbs;
      } else if (it = mine(d.in_urbs); it != d.in_urbs.end() && !d.in_packets.empty()) {
        from = &d.in_urbs;
        usbdevfs_urb& urb = it->urb();
        std::vector<uint8_t>& p = d.in_packets.front();
        const size_t n = std::min(p.size(), size_t(urb.buffer_length));
        std::memcpy(urb.buffer, p.data(), n);
        urb.actual_length = int(n);
        urb.status = 0;
        d.in_packets.pop_front();
        // The read clock's time for this transfer (its reader reaps and finishes one at a time).
        d.read_t.store(d.packet_t.front(), std::memory_order_release);
        if (clocked) d.unacked.push_back(d.packet_t.front());
        d.packet_t.pop_front();
      }
      if (!from) {
        complete(c, -1, EAGAIN);
        return true;
      }
      UMockdevIoctlData* ptr = umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), nullptr);
      umockdev_ioctl_data_set_ptr(ptr, 0, it->data);
      from->erase(it);
      complete(c, 0, 0);
      return true;
    }
    case USBDEVFS_DISCARDURB: {
      const gulong addr = *reinterpret_cast<gulong*>(arg->data);
      for (auto it = d.in_urbs.begin(); it != d.in_urbs.end(); ++it)
        if (it->fd == c && it->data->client_addr == addr) {
          d.discarded.push_back(std::move(*it));
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
