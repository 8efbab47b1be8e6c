#include "input/korg_scene.h"

#include <algorithm>

namespace mar::korg {
namespace {

constexpr uint8_t kHead[] = {0x42, 0x40, 0x00, 0x01, 0x13, 0x00};  // Korg, 4g, the nanoKONTROL2's id
constexpr uint8_t kSceneHead[] = {0x7F, 0x7F, 0x02, 0x03, 0x05, 0x40};

size_t put(std::span<uint8_t> out, std::initializer_list<uint8_t> bytes) {
  if (out.size() < bytes.size()) return 0;
  std::copy(bytes.begin(), bytes.end(), out.begin());
  return bytes.size();
}

/// F0 42 4g 00 01 13 00 (the command list's head): the channel, or -1.
int command_channel(std::span<const uint8_t> m) {
  if (m.size() < 11 || m[0] != 0xF0 || m.back() != 0xF7 || m[1] != kHead[0] || (m[2] & 0xF0) != 0x40) return -1;
  if (!std::equal(kHead + 2, std::end(kHead), m.begin() + 3)) return -1;
  return m[2] & 0x0F;
}

}  // namespace

Message parse(std::span<const uint8_t> m, Scene* scene) {
  Message r;
  if (m.size() < 6 || m[0] != 0xF0 || m.back() != 0xF7 || m[1] != 0x42) return r;
  for (size_t i = 1; i + 1 < m.size(); ++i)
    if (m[i] & 0x80) return r;  // (a SysEx carries 7-bit data only)
  if (m[2] == 0x50) {  // search device
    if (m.size() == 6 && m[3] == 0x00) {
      r.kind = Kind::SearchRequest;
      r.echo = m[4];
    } else if (m.size() == 15 && m[3] == 0x01 && m[4] < 16) {
      r.kind = Kind::SearchReply;
      r.channel = m[4];
      r.echo = m[5];
      r.family = m[6] | m[7] << 7;
    }
    return r;
  }
  const int ch = command_channel(m);
  if (ch < 0) return r;
  r.channel = ch;
  const std::span<const uint8_t> body = m.subspan(7, m.size() - 8);
  if (body.size() == 3 && body[0] == 0x1F && body[1] == 0x10 && body[2] == 0x00) r.kind = Kind::DumpRequest;
  else if (body.size() == 3 && body[0] == 0x1F && body[1] == 0x11 && body[2] < 4) {
    r.kind = Kind::WriteRequest;
    r.slot = body[2];
  } else if (body.size() == 3 && body[0] == 0x5F && body[2] == 0x00) {
    switch (body[1]) {
      case 0x23: r.kind = Kind::Ack; break;
      case 0x24: r.kind = Kind::Nak; break;
      case 0x21: r.kind = Kind::WriteDone; break;
      case 0x22: r.kind = Kind::WriteError; break;
      default: break;
    }
  } else if (body.size() == sizeof kSceneHead + kPackedBytes && std::equal(std::begin(kSceneHead), std::end(kSceneHead), body.begin())) {
    r.kind = Kind::SceneData;
    if (scene) {
      const std::span<const uint8_t> packed = body.subspan(sizeof kSceneHead);
      size_t k = 0;
      for (size_t g = 0; g < packed.size(); g += 8) {
        const uint8_t top = packed[g];
        for (size_t j = 1; j < 8 && g + j < packed.size() && k < kSceneBytes; ++j)
          (*scene)[k++] = uint8_t(packed[g + j] | ((top >> (j - 1)) & 1) << 7);
      }
    }
  }
  return r;
}

size_t search_request(int echo, std::span<uint8_t> out) {
  return put(out, {0xF0, 0x42, 0x50, 0x00, uint8_t(echo & 0x7F), 0xF7});
}

size_t search_reply(int channel, int echo, std::span<uint8_t> out) {
  // The firmware's version (1.00 here) is the last four bytes before F7.
  return put(out, {0xF0, 0x42, 0x50, 0x01, uint8_t(channel & 0x0F), uint8_t(echo & 0x7F), 0x13, 0x01, 0x00, 0x00, 0x00,
                   0x00, 0x01, 0x00, 0xF7});
}

namespace {
size_t command(int channel, std::span<uint8_t> out, std::initializer_list<uint8_t> body) {
  if (out.size() < 8 + body.size()) return 0;
  size_t n = 0;
  out[n++] = 0xF0;
  out[n++] = 0x42;
  out[n++] = uint8_t(0x40 | (channel & 0x0F));
  for (size_t i = 2; i < sizeof kHead; ++i) out[n++] = kHead[i];
  for (uint8_t b : body) out[n++] = b;
  out[n++] = 0xF7;
  return n;
}
}  // namespace

size_t dump_request(int channel, std::span<uint8_t> out) { return command(channel, out, {0x1F, 0x10, 0x00}); }

size_t write_request(int channel, int slot, std::span<uint8_t> out) {
  return command(channel, out, {0x1F, 0x11, uint8_t(slot & 0x03)});
}

size_t answer(Kind kind, int channel, std::span<uint8_t> out) {
  const uint8_t code = kind == Kind::Ack ? 0x23 : kind == Kind::Nak ? 0x24 : kind == Kind::WriteDone ? 0x21 : 0x22;
  return command(channel, out, {0x5F, code, 0x00});
}

size_t scene_data(int channel, const Scene& scene, std::span<uint8_t> out) {
  if (out.size() < kSceneMessage) return 0;
  size_t n = command(channel, out, {}) - 1;  // (without its F7)
  for (uint8_t b : kSceneHead) out[n++] = b;
  for (size_t k = 0; k < kSceneBytes; k += 7) {
    const size_t top = n++;
    out[top] = 0;
    for (size_t j = 0; j < 7 && k + j < kSceneBytes; ++j) {
      out[top] = uint8_t(out[top] | (scene[k + j] >> 7) << j);
      out[n++] = scene[k + j] & 0x7F;
    }
  }
  out[n++] = 0xF7;
  return n;
}

Scene factory_scene() {
  Scene s{};
  s[0] = 0;  // global channel 1, CC mode, LED mode Internal
  s[1] = 0;
  s[kLedModeAt] = 0;
  auto control = [&](size_t at, int cc) {  // assign CC, momentary, its number, off 0, on 127
    s[at] = 1;
    s[at + 1] = 0;
    s[at + 2] = uint8_t(cc);
    s[at + 3] = 0;
    s[at + 4] = 127;
  };
  for (int g = 0; g < 8; ++g) {
    const size_t at = 3 + size_t(g) * 31;
    s[at] = 16;  // the group's channel: the global one
    const int base[] = {0, 16, 32, 48, 64};  // fader, knob, solo, mute, rec
    for (size_t c = 0; c < 5; ++c) control(at + 1 + 6 * c, base[c] + g);
  }
  const int transport[] = {58, 59, 46, 60, 61, 62, 43, 44, 42, 41, 45};  // track -/+, cycle, markers, rew, ff, stop, play, rec
  for (size_t c = 0; c < std::size(transport); ++c) control(251 + 1 + 6 * c, transport[c]);
  return s;
}

}  // namespace mar::korg
