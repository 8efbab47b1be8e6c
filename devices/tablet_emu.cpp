// Emulates an evdev pen-tablet node for the virtual bench: EVIOCG* answers and
// input_events written to the node.
#include "devices/vbench_impl.h"

namespace mar {
using namespace vb;

namespace {
void set_bit(std::vector<uint8_t>& bits, unsigned b) {
  if (b / 8 < bits.size()) bits[b / 8] |= uint8_t(1u << (b % 8));
}
}  // namespace

void VirtualBench::Impl::describe_evdev(BenchDev& d) {
  const std::string num = std::to_string(ev_n++);
  const std::string dev = "/devices/evusb" + num + "/input/input" + num;
  d.node = "/dev/input/event" + num;
  d.syspath = "/sys" + dev;
  d.record = "P: " + dev + "\nE: SUBSYSTEM=input\nE: NAME=\"" + d.ev.name + "\"\nA: name=" + d.ev.name + "\\n\n\n" +
             "P: " + dev + "/event" + num + "\nN: input/event" + num + "\nE: SUBSYSTEM=input\nE: DEVNAME=/dev/input/event" +
             num + "\nA: dev=13:" + std::to_string(64 + std::stoi(num)) + "\\n\n";
}

bool VirtualBench::Impl::evdev_ioctl(BenchDev& d, UMockdevIoctlClient* c, unsigned long req, UMockdevIoctlData* arg) {
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

}  // namespace mar
