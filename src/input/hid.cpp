#include "input/hid.h"

#include <algorithm>
#include <map>

namespace mar {
namespace {

struct Globals {
  uint16_t usage_page = 0;
  int32_t logical_min = 0, logical_max = 0, physical_min = 0, physical_max = 0;
  uint32_t unit = 0;
  int8_t unit_exponent = 0;
  uint32_t report_size = 0, report_count = 0;
  uint8_t report_id = 0;
};

struct Locals {
  // Usages bound to the usage page current when they are parsed (as hid-tools does; a
  // 4-byte usage carries its own page).
  std::vector<uint32_t> usages;
  bool have_min = false, have_max = false;
  uint32_t min = 0, max = 0;
  void clear() { *this = Locals{}; }
};

constexpr uint32_t kMaxReportBits = 1u << 16;  // 8 KiB: far above any real device
constexpr size_t kMaxUsages = 1u << 16;        // per local list, and in all the fields together

int32_t sdata(const uint8_t* p, int n) {
  switch (n) {
    case 1: return int8_t(p[0]);
    case 2: return int16_t(uint16_t(p[0] | p[1] << 8));
    case 4: return int32_t(uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24);
    default: return 0;
  }
}
uint32_t udata(const uint8_t* p, int n) {
  switch (n) {
    case 1: return p[0];
    case 2: return uint32_t(p[0] | p[1] << 8);
    case 4: return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
    default: return 0;
  }
}

uint32_t full_usage(uint32_t value, int size, uint16_t page) {
  return size == 4 ? value : (uint32_t(page) << 16 | (value & 0xFFFF));
}

}  // namespace

uint32_t hid_extract_bits(std::span<const uint8_t> data, uint32_t off, uint32_t n) {
  uint32_t v = 0;
  for (uint32_t i = 0; i < std::min(n, 32u); ++i) {  // (a wider field keeps its low 32 bits)
    const uint32_t bit = off + i;
    if (bit / 8 >= data.size()) break;
    v |= uint32_t((data[bit / 8] >> (bit % 8)) & 1u) << i;
  }
  return v;
}

void hid_insert_bits(std::span<uint8_t> data, uint32_t off, uint32_t n, uint32_t value) {
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t bit = off + i;
    if (bit / 8 >= data.size()) break;
    const uint8_t mask = uint8_t(1u << (bit % 8));
    if (i < 32 && ((value >> i) & 1u))  // (bits past 32 of a wider field are 0)
      data[bit / 8] |= mask;
    else
      data[bit / 8] &= uint8_t(~mask);
  }
}

bool HidField::value(std::span<const uint8_t> report, int i, int32_t& out) const {
  const uint32_t off = bit_offset + uint32_t(i) * bit_size;
  if (i < 0 || i >= count || bit_size > 32 || (off + bit_size + 7) / 8 > report.size()) return false;
  uint32_t raw = hid_extract_bits(report, off, bit_size);
  if (is_signed() && bit_size < 32 && (raw >> (bit_size - 1)) & 1u) raw |= ~0u << bit_size;
  out = int32_t(raw);
  return true;
}

const HidReport* HidDescriptor::find(HidReportType type, uint8_t id) const {
  for (const auto& r : reports)
    if (r.type == type && r.id == id) return &r;
  return nullptr;
}

const HidReport* HidDescriptor::input_for(std::span<const uint8_t> data) const {
  if (data.empty()) return nullptr;
  return find(HidReportType::Input, numbered ? data[0] : 0);
}

const HidField* HidDescriptor::find_usage(uint32_t usage, int* element) const {
  for (const auto& r : reports) {
    if (r.type != HidReportType::Input) continue;
    for (const auto& f : r.fields) {
      if (f.is_constant() || f.is_array()) continue;
      for (size_t i = 0; i < f.usages.size(); ++i)
        if (f.usages[i] == usage) {
          if (element) *element = int(i);
          return &f;
        }
    }
  }
  return nullptr;
}

Result<HidDescriptor> parse_hid_descriptor(std::span<const uint8_t> bytes) {
  using R = Result<HidDescriptor>;
  HidDescriptor d;
  Globals g;
  std::vector<Globals> stack;
  Locals l;
  std::vector<uint32_t> collections;  // usage of each open collection
  std::vector<uint8_t> collection_type;
  uint32_t application = 0;
  std::map<std::pair<int, int>, size_t> report_index;  // (type, id) -> index in d.reports

  auto fail = [](size_t at, const std::string& what) {
    return R::failure("report descriptor byte " + std::to_string(at) + ": " + what);
  };
  if (bytes.size() > kMaxHidDescriptorBytes)
    return R::failure("report descriptor is " + std::to_string(bytes.size()) + " bytes; the limit is " +
                      std::to_string(kMaxHidDescriptorBytes) + " (the kernel's HID_MAX_DESCRIPTOR_SIZE)");
  size_t total_usages = 0;  // every field's usage list together (array fields copy their list)

  size_t i = 0;
  while (i < bytes.size()) {
    const size_t at = i;
    const uint8_t prefix = bytes[i++];
    if (prefix == 0xFE) {  // long item: size, tag, data — none are defined; skip
      if (i + 2 > bytes.size()) return fail(at, "truncated long item");
      i += 2 + bytes[i];
      if (i > bytes.size()) return fail(at, "truncated long item");
      continue;
    }
    int n = prefix & 3;
    if (n == 3) n = 4;
    if (i + size_t(n) > bytes.size()) return fail(at, "truncated item");
    const uint8_t* p = bytes.data() + i;
    i += size_t(n);
    const int type = (prefix >> 2) & 3, tag = prefix >> 4;
    if (type == 1) {  // global
      switch (tag) {
        case 0: g.usage_page = uint16_t(udata(p, n)); break;
        case 1: g.logical_min = sdata(p, n); break;
        case 2: g.logical_max = g.logical_min < 0 ? sdata(p, n) : int32_t(udata(p, n)); break;
        case 3: g.physical_min = sdata(p, n); break;
        case 4: g.physical_max = g.physical_min < 0 ? sdata(p, n) : int32_t(udata(p, n)); break;
        case 5: {
          const int v = int(udata(p, n) & 0xF);
          g.unit_exponent = int8_t(v > 7 ? v - 16 : v);
          break;
        }
        case 6: g.unit = udata(p, n); break;
        case 7:
          g.report_size = udata(p, n);
          if (g.report_size > 1024) return fail(at, "absurd report size " + std::to_string(g.report_size));
          break;
        case 8:
          g.report_id = uint8_t(udata(p, n));
          if (g.report_id == 0) return fail(at, "report ID 0 is reserved");
          d.numbered = true;
          break;
        case 9:
          g.report_count = udata(p, n);
          if (g.report_count > 65535) return fail(at, "absurd report count " + std::to_string(g.report_count));
          break;
        case 10:
          if (stack.size() > 64) return fail(at, "push stack too deep");
          stack.push_back(g);
          break;
        case 11:
          if (stack.empty()) return fail(at, "pop without push");
          g = stack.back();
          stack.pop_back();
          break;
        default: break;  // reserved: ignored
      }
    } else if (type == 2) {  // local
      const uint32_t u = full_usage(udata(p, n), n, g.usage_page);
      switch (tag) {
        case 0:
          if (l.usages.size() < kMaxUsages) l.usages.push_back(u);
          break;
        case 1: l.min = u; l.have_min = true; break;
        case 2: l.max = u; l.have_max = true; break;
        default: break;  // designators, strings, delimiters
      }
      if (l.have_min && l.have_max && (tag == 1 || tag == 2)) {
        for (uint32_t x = l.min; x <= l.max && l.usages.size() < kMaxUsages; ++x) {
          l.usages.push_back(x);
          if (x == 0xFFFFFFFFu) break;
        }
        l.have_min = l.have_max = false;
      }
    } else if (type == 0) {  // main
      switch (tag) {
        case 8:
        case 9:
        case 11: {
          const HidReportType rt = tag == 8 ? HidReportType::Input
                                   : tag == 9 ? HidReportType::Output : HidReportType::Feature;
          const auto key = std::make_pair(int(rt), int(g.report_id));
          auto it = report_index.find(key);
          if (it == report_index.end()) {
            HidReport r;
            r.type = rt;
            r.id = g.report_id;
            r.size_bits = g.report_id ? 8 : 0;
            d.reports.push_back(std::move(r));
            it = report_index.emplace(key, d.reports.size() - 1).first;
          }
          HidReport& r = d.reports[it->second];
          HidField f;
          f.type = rt;
          f.report_id = g.report_id;
          f.bit_offset = r.size_bits;
          f.bit_size = uint16_t(g.report_size);
          f.count = uint16_t(g.report_count);
          f.flags = udata(p, n);
          f.logical_min = g.logical_min;
          f.logical_max = g.logical_max;
          f.physical_min = g.physical_min;
          f.physical_max = g.physical_max;
          if (f.physical_min == 0 && f.physical_max == 0) {
            f.physical_min = f.logical_min;
            f.physical_max = f.logical_max;
          }
          f.unit = g.unit;
          f.unit_exponent = g.unit_exponent;
          f.application = application;
          f.usage_page = g.usage_page;
          const uint64_t bits = uint64_t(f.bit_size) * f.count;
          if (r.size_bits + bits > kMaxReportBits) return fail(at, "report longer than 8 KiB");
          const std::vector<uint32_t>& us = l.usages;
          total_usages += f.is_array() ? us.size() : f.count;
          if (total_usages > kMaxUsages) return fail(at, "more than 65536 usages in all the fields");
          if (f.is_array()) {
            f.usages = us;
          } else if (f.count > 0) {
            f.usages.resize(f.count, us.empty() ? uint32_t(g.usage_page) << 16 : us.back());
            for (size_t k = 0; k < us.size() && k < f.count; ++k) f.usages[k] = us[k];
          }
          r.size_bits += uint32_t(bits);
          if (f.count > 0 && f.bit_size > 0) r.fields.push_back(std::move(f));
          break;
        }
        case 10: {  // collection
          const uint32_t usage = l.usages.empty() ? 0 : l.usages.front();
          const uint8_t ctype = n ? p[0] : 0;
          collections.push_back(usage);
          collection_type.push_back(ctype);
          if (ctype == 1) application = usage;
          if (collections.size() > 256) return fail(at, "collections nested too deep");
          break;
        }
        case 12:
          if (collections.empty()) return fail(at, "End Collection without Collection");
          collections.pop_back();
          collection_type.pop_back();
          application = 0;
          for (size_t k = collections.size(); k-- > 0;)
            if (collection_type[k] == 1) {
              application = collections[k];
              break;
            }
          break;
        default: return fail(at, "unknown main item tag " + std::to_string(tag));
      }
      l.clear();
    }
    // type 3 (reserved short items) are skipped
  }
  // An unterminated top-level collection is common in the wild (and harmless): accepted.
  return R::success(std::move(d));
}

}  // namespace mar
