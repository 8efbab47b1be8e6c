#include "input/decoder.h"

#include <cstring>

namespace mar {

const char* wire_kind_name(WireKind k) {
  switch (k) {
    case WireKind::UsbMidi: return "usb-midi";
    case WireKind::MidiBytes: return "midi-bytes";
    case WireKind::HidReport: return "hid-report";
    case WireKind::GpioEdge: return "gpio-edge";
    case WireKind::EvdevEvent: return "evdev-event";
    case WireKind::OscMessage: return "osc-message";
    case WireKind::SdlControl: return "sdl-control";
    case WireKind::AudioPcm: return "audio-pcm";
  }
  return "?";
}

namespace {

constexpr uint8_t kConfigVersion = 1;

struct Writer {
  std::vector<uint8_t> out;
  void raw(const void* p, size_t n) {
    const size_t at = out.size();
    out.resize(at + n);
    if (n) std::memcpy(out.data() + at, p, n);
  }
  template <class T>
  void put(T v) {
    raw(&v, sizeof(T));
  }
  void bytes(std::span<const uint8_t> b) {
    put(uint32_t(b.size()));
    raw(b.data(), b.size());
  }
};

struct Reader {
  std::span<const uint8_t> in;
  size_t at = 0;
  bool ok = true;
  template <class T>
  T get() {
    T v{};
    if (at + sizeof(T) > in.size()) {
      ok = false;
      return v;
    }
    std::memcpy(&v, in.data() + at, sizeof(T));
    at += sizeof(T);
    return v;
  }
  std::span<const uint8_t> bytes(size_t limit) {
    const uint32_t n = get<uint32_t>();
    if (!ok || n > limit || at + n > in.size()) {
      ok = false;
      return {};
    }
    auto s = in.subspan(at, n);
    at += n;
    return s;
  }
};

}  // namespace

std::vector<uint8_t> DecoderConfig::serialize() const {
  Writer w;
  w.put(kConfigVersion);
  w.put(uint8_t(kind));
  switch (kind) {
    case WireKind::HidReport: w.bytes(hid_descriptor); break;
    case WireKind::GpioEdge:
      w.put(int64_t(gpio.debounce_ns));
      w.put(uint16_t(gpio.encoders.size()));
      for (const auto& e : gpio.encoders) {
        w.put(int16_t(e.line_a));
        w.put(int16_t(e.line_b));
        w.put(int16_t(e.steps_per_detent));
      }
      w.put(uint16_t(gpio.buttons.size()));
      for (int b : gpio.buttons) w.put(int16_t(b));
      break;
    case WireKind::EvdevEvent:
      w.put(uint16_t(axes.size()));
      for (const auto& a : axes) {
        w.put(a.code);
        w.put(a.min);
        w.put(a.max);
      }
      break;
    case WireKind::OscMessage:
      w.put(uint16_t(osc_patterns.size()));
      for (const auto& p : osc_patterns) w.bytes({reinterpret_cast<const uint8_t*>(p.data()), p.size()});
      break;
    case WireKind::AudioPcm:
      w.put(audio_rate);
      for (const auto& f : voice) {
        w.put(f[0]);
        w.put(f[1]);
      }
      break;
    default: break;
  }
  return std::move(w.out);
}

Result<DecoderConfig> DecoderConfig::parse(std::span<const uint8_t> bytes) {
  using R = Result<DecoderConfig>;
  Reader r{bytes};
  DecoderConfig c;
  if (r.get<uint8_t>() != kConfigVersion) return R::failure("device description: unknown version");
  c.kind = WireKind(r.get<uint8_t>());
  switch (c.kind) {
    case WireKind::UsbMidi:
    case WireKind::MidiBytes:
    case WireKind::SdlControl: break;
    case WireKind::HidReport: {
      auto d = r.bytes(1 << 16);
      c.hid_descriptor.assign(d.begin(), d.end());
      break;
    }
    case WireKind::GpioEdge: {
      c.gpio.debounce_ns = r.get<int64_t>();
      const uint16_t ne = r.get<uint16_t>();
      for (uint16_t i = 0; i < ne && r.ok && i < 256; ++i) {
        GpioLayout::Encoder e;
        e.line_a = r.get<int16_t>();
        e.line_b = r.get<int16_t>();
        e.steps_per_detent = r.get<int16_t>();
        c.gpio.encoders.push_back(e);
      }
      const uint16_t nb = r.get<uint16_t>();
      for (uint16_t i = 0; i < nb && r.ok && i < 256; ++i) c.gpio.buttons.push_back(r.get<int16_t>());
      if (ne > 256 || nb > 256) r.ok = false;
      break;
    }
    case WireKind::EvdevEvent: {
      const uint16_t n = r.get<uint16_t>();
      for (uint16_t i = 0; i < n && r.ok && i < 64; ++i) {
        EvdevAxis a;
        a.code = r.get<uint16_t>();
        a.min = r.get<int32_t>();
        a.max = r.get<int32_t>();
        c.axes.push_back(a);
      }
      if (n > 64) r.ok = false;
      break;
    }
    case WireKind::OscMessage: {
      const uint16_t n = r.get<uint16_t>();
      for (uint16_t i = 0; i < n && r.ok && i < 1024; ++i) {
        auto p = r.bytes(4096);
        c.osc_patterns.emplace_back(p.begin(), p.end());
      }
      if (n > 1024) r.ok = false;
      break;
    }
    case WireKind::AudioPcm: {
      c.audio_rate = r.get<int32_t>();
      for (auto& f : c.voice) {
        f[0] = r.get<double>();
        f[1] = r.get<double>();
        if (!(f[0] >= 0 && f[0] < 1e5 && f[1] >= 0 && f[1] < 1e5)) r.ok = false;
      }
      if (c.audio_rate < 4000 || c.audio_rate > 192000) r.ok = false;
      break;
    }
    default: return R::failure("device description: unknown wire kind " + std::to_string(int(c.kind)));
  }
  if (!r.ok || r.at != bytes.size()) return R::failure("device description: truncated or malformed");
  return R::success(std::move(c));
}

std::unique_ptr<Decoder> make_decoder(const DecoderConfig& c, uint16_t source, std::string* error) {
  switch (c.kind) {
    case WireKind::UsbMidi:
    case WireKind::MidiBytes: return make_midi_decoder(c.kind, source);
    case WireKind::HidReport: {
      auto d = parse_hid_descriptor(c.hid_descriptor);
      if (!d.ok()) {
        if (error) *error = "HID report descriptor: " + d.error;
        return nullptr;
      }
      return make_hid_decoder(std::move(*d.value), source);
    }
    case WireKind::GpioEdge: return make_gpio_decoder(c.gpio, source);
    case WireKind::EvdevEvent: return make_evdev_decoder(c.axes, source);
    case WireKind::OscMessage: return make_osc_decoder(c.osc_patterns, source);
    case WireKind::SdlControl: return make_sdl_decoder(source);
    case WireKind::AudioPcm: return make_audio_decoder(c, source);
  }
  if (error) *error = "no decoder for wire kind " + std::to_string(int(c.kind));
  return nullptr;
}

}  // namespace mar
