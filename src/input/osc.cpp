#include "input/osc.h"
#include "input/decoder.h"

#include <bit>
#include <bitset>
#include <cmath>
#include <cstring>
#include <string>

namespace mar {

bool osc_match(std::string_view p, std::string_view s) {
  constexpr size_t kMaxLen = 255;
  if (p.size() > kMaxLen || s.size() > kMaxLen) return false;
  // cur: the address positions the pattern read so far can end at.
  std::bitset<kMaxLen + 1> cur, next;
  cur.set(0);
  size_t i = 0;
  while (i < p.size() && cur.any()) {
    next.reset();
    const char c = p[i];
    if (c == '*') {
      // Every position from a reached one up to the next '/': one sweep (a pattern of stars
      // against a long address was quadratic in the address per star).
      bool reach = false;
      for (size_t k = 0; k <= s.size(); ++k) {
        reach = reach || cur.test(k);
        if (reach) next.set(k);
        if (k < s.size() && s[k] == '/') reach = false;
      }
      ++i;
    } else if (c == '[') {
      const size_t close = p.find(']', i + 1);
      if (close == std::string_view::npos) return false;  // malformed pattern
      std::string_view set = p.substr(i + 1, close - i - 1);
      const bool negate = !set.empty() && set[0] == '!';
      if (negate) set.remove_prefix(1);
      auto in_set = [&](char ch) {
        for (size_t k = 0; k < set.size(); ++k) {
          if (k + 2 < set.size() && set[k + 1] == '-') {
            if (ch >= set[k] && ch <= set[k + 2]) return true;
            k += 2;
          } else if (set[k] == ch) {
            return true;
          }
        }
        return false;
      };
      for (size_t k = 0; k < s.size(); ++k)
        if (cur.test(k) && s[k] != '/' && in_set(s[k]) != negate) next.set(k + 1);
      i = close + 1;
    } else if (c == '{') {
      const size_t close = p.find('}', i + 1);
      if (close == std::string_view::npos) return false;
      const std::string_view alts = p.substr(i + 1, close - i - 1);
      for (size_t a = 0; a <= alts.size();) {
        size_t e = alts.find(',', a);
        if (e == std::string_view::npos) e = alts.size();
        const std::string_view alt = alts.substr(a, e - a);
        for (size_t k = 0; k + alt.size() <= s.size(); ++k)
          if (cur.test(k) && s.substr(k, alt.size()) == alt) next.set(k + alt.size());
        a = e + 1;
      }
      i = close + 1;
    } else {
      for (size_t k = 0; k < s.size(); ++k)
        if (cur.test(k) && (c == '?' ? s[k] != '/' : s[k] == c)) next.set(k + 1);
      ++i;
    }
    cur = next;
  }
  return i == p.size() && cur.test(s.size());
}

namespace {

uint32_t be32(const uint8_t* b) { return uint32_t(b[0]) << 24 | uint32_t(b[1]) << 16 | uint32_t(b[2]) << 8 | b[3]; }
uint64_t be64(const uint8_t* b) { return uint64_t(be32(b)) << 32 | be32(b + 4); }

// An OSC string: NUL-terminated, padded to a multiple of 4. Returns the bytes it takes, or 0.
size_t osc_string(std::span<const uint8_t> b, size_t at, std::string_view& out) {
  if (at >= b.size()) return 0;
  const void* nul = std::memchr(b.data() + at, 0, b.size() - at);
  if (!nul) return 0;
  const size_t len = size_t(static_cast<const uint8_t*>(nul) - (b.data() + at));
  const size_t padded = (len + 4) & ~size_t(3);
  if (at + padded > b.size()) return 0;
  out = std::string_view(reinterpret_cast<const char*>(b.data() + at), len);
  return padded;
}

}  // namespace

bool parse_osc_message(std::span<const uint8_t> b, OscMessage& m) {
  m = OscMessage{};
  const size_t a = osc_string(b, 0, m.address);
  if (!a || m.address.empty() || m.address[0] != '/') return false;
  if (a == b.size()) return true;  // no type tags: an old-style message without arguments
  std::string_view tags;
  const size_t t = osc_string(b, a, tags);
  if (!t || tags.empty() || tags[0] != ',') return false;
  if (tags.size() < 2) return true;
  const uint8_t* arg = b.data() + a + t;
  const size_t left = b.size() - a - t;
  m.type = tags[1];
  switch (m.type) {
    case 'i':
      if (left < 4) return false;
      m.number = double(int32_t(be32(arg)));
      return true;
    case 'f': {
      if (left < 4) return false;
      m.number = double(std::bit_cast<float>(be32(arg)));
      return std::isfinite(m.number);
    }
    case 'd':
      if (left < 8) return false;
      m.number = std::bit_cast<double>(be64(arg));
      return std::isfinite(m.number);
    case 'h':
      if (left < 8) return false;
      m.number = double(int64_t(be64(arg)));
      return true;
    case 'T': m.number = 1; return true;
    case 'F': m.number = 0; return true;
    default: m.type = 0; return true;  // other argument types: a trigger
  }
}

namespace {

// OSC messages -> HidValue events on the vendor page (number 0xFF000000 | pattern index):
// floats and doubles over 0..65535 (0..1), integers as given over 0..127, booleans 0/1.
class OscDecoder final : public Decoder {
 public:
  OscDecoder(std::vector<std::string> patterns, uint16_t source)
      : Decoder(WireKind::OscMessage, source), patterns_(std::move(patterns)) {}

 private:
  void decode(const WireRecord& r, EventSink& out) override {
    OscMessage m;
    if (!parse_osc_message(r.bytes(), m)) return malformed();  // not OSC: dropped
    int hit = -1;
    for (size_t i = 0; i < patterns_.size() && hit < 0; ++i)
      if (osc_match(patterns_[i], m.address) || osc_match(m.address, patterns_[i])) hit = int(i);
    if (hit < 0) return;
    Event e = event(r.t_ns, ControlKind::HidValue);
    e.number = 0xFF000000u | uint32_t(hit);
    e.hi = 1;
    e.value = 1;
    auto clamp = [](double v) { return int32_t(std::lround(std::fmin(2147483647.0, std::fmax(-2147483648.0, v)))); };
    switch (m.type) {
      case 'f':
      case 'd': e.value = clamp(m.number * 65535); e.hi = 65535; break;
      case 'i':
      case 'h': e.value = clamp(m.number); e.hi = 127; break;
      case 'T':
      case 'F': e.value = int32_t(m.number); break;
      default: break;  // no argument: a trigger
    }
    out.push(e);
  }
  std::vector<std::string> patterns_;
};

}  // namespace

std::unique_ptr<Decoder> make_osc_decoder(std::vector<std::string> patterns, uint16_t source) {
  return std::make_unique<OscDecoder>(std::move(patterns), source);
}

}  // namespace mar
