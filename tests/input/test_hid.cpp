// HID report descriptor parser against an independent parser (hid-tools): the layout of
// every input report of all 247 corpus descriptors, field by field; and the PenPartner
// recording decoded value by value.
#include "input/event.h"
#include "input/hid.h"
#include "test_util.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <sstream>

namespace mar {
namespace {

using test::hex_bytes;

using nlohmann::json;
namespace fs = std::filesystem;

// Usage names as hid-tools prints them, from the HUT tables shipped in the corpus.
struct Names {
  std::map<uint16_t, std::string> pages;
  std::map<uint32_t, std::string> usages;
  explicit Names(const fs::path& dir) {
    for (const auto& e : fs::directory_iterator(dir)) {
      std::ifstream in(e.path());
      std::string line;
      uint16_t page = 0;
      while (std::getline(in, line)) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto tab = line.find('\t');
        if (tab == std::string::npos) continue;
        const std::string id = line.substr(0, tab), name = line.substr(tab + 1);
        if (id.front() == '(') {
          page = uint16_t(std::stoul(id.substr(1, id.size() - 2), nullptr, 16));
          pages[page] = name;
        } else if (id.find('-') == std::string::npos) {
          usages[uint32_t(page) << 16 | uint32_t(std::stoul(id, nullptr, 16))] = name;
        }
      }
    }
  }
  std::string page(uint32_t usage) const {
    auto it = pages.find(uint16_t(usage >> 16));
    return it == pages.end() ? "" : it->second;
  }
  // Whether the oracle's name `e` denotes usage `u`. hid-tools names usages from these
  // tables, "B<n>" on the Button page, and otherwise prints the number in hex; it calls
  // usage 0 "Undefined" on some pages and an unnamed application collection "Vendor".
  bool matches(uint32_t u, const std::string& e, bool application = false) const {
    if (e.rfind("0x", 0) == 0) return std::stoul(e, nullptr, 16) == u;
    if ((u >> 16) == 0x09 && e == "B" + std::to_string(u & 0xFFFF)) return true;
    auto it = usages.find(u);
    if (it != usages.end() && it->second == e) return true;
    if ((u & 0xFFFF) == 0 && e == "Undefined") return true;
    return application && e == "Vendor" && (it == usages.end() || (u & 0xFFFF) == 0);
  }
};

std::vector<uint8_t> read_descriptor(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::vector<uint8_t> out;
  if (p.extension() == ".hex") {
    std::string tok;
    while (in >> tok) out.push_back(uint8_t(std::stoul(tok, nullptr, 16)));
  } else {
    out.assign(std::istreambuf_iterator<char>(in), {});
  }
  return out;
}

// Our layout in the oracle's form: variable fields one entry per element, consecutive
// identical entries merged with `repeat`, constant fields left out.
json layout(const HidReport& r, const Names& n) {
  json fields = json::array();
  auto push = [&](json e) {
    if (!fields.empty()) {
      json& last = fields.back();
      const int rep = last.value("repeat", 1);
      json a = last, b = e;
      a.erase("repeat");
      a.erase("start_bit");
      b.erase("start_bit");
      if (a == b && e["start_bit"].get<int>() ==
                         last["start_bit"].get<int>() + rep * last["bits"].get<int>() * last["count"].get<int>()) {
        last["repeat"] = rep + 1;
        return;
      }
    }
    fields.push_back(std::move(e));
  };
  for (const auto& f : r.fields) {
    if (f.is_constant()) continue;
    if (f.is_array()) {
      push({{"page", n.page(uint32_t(f.usage_page) << 16)}, {"start_bit", f.bit_offset},
            {"bits", f.bit_size}, {"count", f.count}, {"lmin", f.logical_min}, {"lmax", f.logical_max},
            {"array", true}});
      continue;
    }
    for (int k = 0; k < f.count; ++k)
      push({{"page", n.page(uint32_t(f.usage_page) << 16)}, {"start_bit", f.bit_offset + uint32_t(k) * f.bit_size},
            {"bits", f.bit_size}, {"count", 1}, {"lmin", f.logical_min}, {"lmax", f.logical_max},
            {"usages", json::array({f.usages[size_t(k)]})}});
  }
  return fields;
}

TEST(Hid, EveryCorpusDescriptorMatchesTheOracleFieldByField) {
  const fs::path root = test::corpus_dir() / "hid";
  const fs::path oracle = root / "expected-decodes/report-layouts.hidtools.json";
  if (!fs::exists(oracle)) GTEST_SKIP() << "corpus not found";
  const Names names(root / "hid-tools-data/hut");
  std::ifstream f(oracle);
  const json doc = json::parse(f);
  const json& descs = doc["descriptors"];
  ASSERT_EQ(descs.size(), 247u);
  int matched = 0, fields_compared = 0;
  for (const auto& [rel, exp] : descs.items()) {
    SCOPED_TRACE(rel);
    const auto bytes = read_descriptor(root / rel);
    ASSERT_EQ(bytes.size(), exp["bytes"].get<size_t>());
    auto parsed = parse_hid_descriptor(bytes);
    ASSERT_TRUE(parsed.ok()) << parsed.error;
    const HidDescriptor& d = *parsed.value;
    json got = json::object();
    for (const auto& r : d.reports) {
      if (r.type != HidReportType::Input) continue;
      const std::string id = d.numbered ? std::to_string(r.id) : "-1";
      got[id] = {{"size_bytes", r.size_bytes()},
                 {"application", r.fields.empty() ? 0 : r.fields.front().application},
                 {"fields", layout(r, names)}};
    }
    bool ok = true;
    for (const auto& [id, er] : exp["input"].items()) {
      SCOPED_TRACE("report " + id);
      if (!got.contains(id)) {
        ADD_FAILURE() << "missing input report";
        ok = false;
        continue;
      }
      const json& gr = got[id];
      EXPECT_EQ(gr["size_bytes"], er["size_bytes"]);
      const bool app_ok = names.matches(gr["application"].get<uint32_t>(), er["application"], true);
      EXPECT_TRUE(app_ok) << "application " << gr["application"] << " vs " << er["application"];
      const json& ef = er["fields"];
      const json& gf = gr["fields"];
      EXPECT_EQ(gf.size(), ef.size());
      for (size_t i = 0; i < std::min(gf.size(), ef.size()); ++i) {
        json g = gf[i], e = ef[i];
        bool usages_ok = g.contains("usages") == e.contains("usages");
        if (usages_ok && g.contains("usages"))
          usages_ok = names.matches(g["usages"][0].get<uint32_t>(), e["usages"][0].get<std::string>());
        g.erase("usages");
        e.erase("usages");
        EXPECT_EQ(g, e) << "field " << i;
        EXPECT_TRUE(usages_ok) << "field " << i << " usage " << gf[i]["usages"] << " vs " << ef[i]["usages"];
        ok = ok && g == e && usages_ok;
        ++fields_compared;
      }
      ok = ok && gf.size() == ef.size() && gr["size_bytes"] == er["size_bytes"] && app_ok;
    }
    EXPECT_EQ(got.size(), exp["input"].size());
    matched += ok && got.size() == exp["input"].size();
  }
  EXPECT_EQ(matched, 247);
  EXPECT_GT(fields_compared, 4000);
}

TEST(Hid, PenPartnerRecordingDecodesToTheOracleValues) {
  const fs::path root = test::corpus_dir() / "hid";
  const fs::path oracle = root / "expected-decodes/Wacom_PenPartner.hidtools-decode.json";
  if (!fs::exists(oracle)) GTEST_SKIP() << "corpus not found";
  std::ifstream rec(root / "wacom-hid-descriptors/Wacom_PenPartner/hidrecord.txt");
  std::string line;
  std::vector<uint8_t> rdesc;
  while (std::getline(rec, line))
    if (line.rfind("R: ", 0) == 0) {
      std::istringstream ls(line.substr(3));
      int n;
      ls >> n;
      std::string tok;
      while (ls >> tok) rdesc.push_back(uint8_t(std::stoul(tok, nullptr, 16)));
      ASSERT_EQ(rdesc.size(), size_t(n));
      break;
    }
  auto parsed = parse_hid_descriptor(rdesc);
  ASSERT_TRUE(parsed.ok()) << parsed.error;
  const HidDescriptor& d = *parsed.value;
  std::ifstream f(oracle);
  const json doc = json::parse(f);
  ASSERT_EQ(doc["events"].size(), 874u);
  int compared = 0;
  for (const auto& ev : doc["events"]) {
    const auto bytes = hex_bytes(ev["hex"]);
    const HidReport* r = d.input_for(bytes);
    ASSERT_NE(r, nullptr);
    ASSERT_EQ(r->id, ev["id"].get<int>());
    json values = json::array();
    for (const auto& fld : r->fields) {
      if (fld.is_constant()) continue;
      json v = json::array();
      for (int k = 0; k < fld.count; ++k) {
        int32_t x = 0;
        ASSERT_TRUE(fld.value(bytes, k, x));
        v.push_back(x);
      }
      // The oracle lists variable fields one element at a time.
      if (fld.is_array()) values.push_back(v);
      else
        for (const auto& x : v) values.push_back(json::array({x}));
    }
    ASSERT_EQ(values, ev["values"]) << ev["hex"];
    ++compared;
  }
  EXPECT_EQ(compared, 874);
}

TEST(Hid, MalformedDescriptorsAreRejectedWithAnOffset) {
  const std::vector<uint8_t> truncated = {0x05, 0x01, 0x09, 0x02, 0xA1, 0x01, 0x26, 0xFF};
  auto r = parse_hid_descriptor(truncated);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error.find("byte 6"), std::string::npos) << r.error;
  const std::vector<uint8_t> unbalanced = {0xC0};
  EXPECT_FALSE(parse_hid_descriptor(unbalanced).ok());
  const std::vector<uint8_t> huge = {0x75, 0xFF, 0x96, 0xFF, 0x0F, 0x81, 0x02};
  EXPECT_FALSE(parse_hid_descriptor(huge).ok());
}

// Hostile descriptors stay small: before these limits, 9,000 array items each naming 65,536
// usages (63 KB of descriptor) took 5.6 GB and 23 s to parse (found by fuzz_hid's seeds).
TEST(Hid, HostileDescriptorsAreRefusedWithTheirLimit) {
  const std::vector<uint8_t> head = {0x05, 0x09, 0x09, 0x05, 0xA1, 0x01, 0x75, 0x01, 0x95, 0x01, 0x15, 0x00, 0x27, 0xFF, 0xFF, 0x00, 0x00};
  const std::vector<uint8_t> array_item = {0x19, 0x00, 0x2A, 0xFF, 0xFF, 0x81, 0x00};  // usages 0..65535, one array element
  auto build = [&](int items) {
    std::vector<uint8_t> d = head;
    for (int k = 0; k < items; ++k) d.insert(d.end(), array_item.begin(), array_item.end());
    d.push_back(0xC0);
    return d;
  };
  // Over the kernel's 4,096 bytes: refused before anything is read.
  const auto big = parse_hid_descriptor(build(9000));
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error.find("63018 bytes; the limit is 4096"), std::string::npos) << big.error;
  // Within it, the second array item's copy of 65,536 usages passes the limit in all fields.
  const auto many = parse_hid_descriptor(build(500));
  ASSERT_FALSE(many.ok());
  EXPECT_NE(many.error.find("more than 65536 usages"), std::string::npos) << many.error;
  EXPECT_NE(many.error.find("byte 29:"), std::string::npos) << many.error;  // the second Input item
  // One field of 65,535 32-bit elements: 2 Mbit, refused as a report over 8 KiB.
  const std::vector<uint8_t> wide = {0x05, 0x01, 0x09, 0x05, 0xA1, 0x01, 0x75, 0x20, 0x96, 0xFF, 0xFF, 0x09, 0x30, 0x81, 0x02, 0xC0};
  const auto w = parse_hid_descriptor(wide);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.error.find("byte 13: report longer than 8 KiB"), std::string::npos) << w.error;
  // 65,536 elements (one more than a report count can say) is refused, not wrapped to 0.
  const std::vector<uint8_t> count = {0x05, 0x01, 0x09, 0x05, 0xA1, 0x01, 0x75, 0x01, 0x97, 0x00, 0x00, 0x01, 0x00, 0x81, 0x02, 0xC0};
  const auto c = parse_hid_descriptor(count);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error.find("byte 8: absurd report count 65536"), std::string::npos) << c.error;
}

TEST(Hid, SignedFieldsExtendAndInsertRoundTrips) {
  std::vector<uint8_t> buf(6, 0);
  hid_insert_bits(buf, 3, 12, 0xABC);
  EXPECT_EQ(hid_extract_bits(buf, 3, 12), 0xABCu);
  HidField f;
  f.bit_offset = 3;
  f.bit_size = 12;
  f.count = 1;
  f.logical_min = -2048;
  f.logical_max = 2047;
  int32_t v = 0;
  ASSERT_TRUE(f.value(buf, 0, v));
  EXPECT_EQ(v, int32_t(0xABC) - 4096);
  EXPECT_FALSE(f.value(std::span<const uint8_t>(buf).first(1), 0, v));
}

// A descriptor may declare fields up to 1,024 bits wide: the bit reader keeps the low 32 and the
// writer clears the rest (no shift past 31 bits: the sanitizer build checks).
TEST(Hid, FieldsWiderThan32BitsKeepTheirLow32) {
  std::vector<uint8_t> buf(8, 0xFF);
  hid_insert_bits(buf, 4, 40, 0x89ABCDEFu);
  EXPECT_EQ(hid_extract_bits(buf, 4, 40), 0x89ABCDEFu);
  EXPECT_EQ(hid_extract_bits(buf, 36, 8), 0u);    // bits 32..39 of the field: cleared
  EXPECT_EQ(hid_extract_bits(buf, 44, 4), 0xFu);  // past the field: untouched
  EXPECT_EQ(hid_extract_bits(buf, 0, 1024), hid_extract_bits(buf, 0, 32));
}

// A logical range of INT32_MIN..INT32_MAX normalises without overflow.
TEST(Hid, TheWidestLogicalRangeNormalises) {
  Event e;
  e.lo = INT32_MIN;
  e.hi = INT32_MAX;
  e.value = INT32_MAX;
  EXPECT_DOUBLE_EQ(normalized(e), 1.0);
  e.value = INT32_MIN;
  EXPECT_DOUBLE_EQ(normalized(e), 0.0);
  e.value = 0;
  EXPECT_NEAR(normalized(e), 0.5, 1e-9);
  e.lo = e.hi = 5;
  EXPECT_EQ(normalized(e), 0.0);
}

}  // namespace
}  // namespace mar
