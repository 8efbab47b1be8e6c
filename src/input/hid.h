// HID report descriptors (Device Class Definition for HID 1.11, §6.2.2) and field
// extraction from reports. Pure code: the bytes come from hidraw/sysfs, hidapi or a
// firmware_sim device.
#pragma once

#include "base/result.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mar {

enum class HidReportType : uint8_t { Input, Output, Feature };

/// Main-item flag bits (HID 1.11 §6.2.2.5).
enum HidFlag : uint32_t {
  HidConstant = 1u << 0,
  HidVariable = 1u << 1,   ///< clear: array
  HidRelative = 1u << 2,
  HidWrap = 1u << 3,
  HidNonLinear = 1u << 4,
  HidNoPreferred = 1u << 5,
  HidNullState = 1u << 6,
};

/// One main item: `count` elements of `bit_size` bits starting at `bit_offset`.
/// Offsets count the report-ID byte when the descriptor numbers its reports.
struct HidField {
  HidReportType type = HidReportType::Input;
  uint8_t report_id = 0;
  uint32_t bit_offset = 0;
  uint16_t bit_size = 0;
  uint16_t count = 0;
  uint32_t flags = 0;
  int32_t logical_min = 0, logical_max = 0;
  int32_t physical_min = 0, physical_max = 0;
  uint32_t unit = 0;
  int8_t unit_exponent = 0;
  uint16_t usage_page = 0;   ///< global usage page at the main item
  uint32_t application = 0;  ///< usage (page << 16 | id) of the enclosing application collection
  /// Variable fields: usage of each element (size == count). Array fields: the usages the
  /// element values index, from logical_min on.
  std::vector<uint32_t> usages;

  bool is_constant() const { return flags & HidConstant; }
  bool is_array() const { return !(flags & HidVariable); }
  bool is_relative() const { return flags & HidRelative; }
  bool is_signed() const { return logical_min < 0; }
  /// Element `i` of this field in `report` (sign-extended when logical_min < 0).
  /// Returns false when the report is too short or the element is wider than 32 bits.
  bool value(std::span<const uint8_t> report, int i, int32_t& out) const;
};

struct HidReport {
  HidReportType type = HidReportType::Input;
  uint8_t id = 0;
  uint32_t size_bits = 0;  ///< including the report-ID byte when numbered
  std::vector<HidField> fields;
  uint32_t size_bytes() const { return (size_bits + 7) / 8; }
};

struct HidDescriptor {
  bool numbered = false;  ///< reports start with a report-ID byte
  std::vector<HidReport> reports;
  /// The report of this type and id, or nullptr.
  const HidReport* find(HidReportType type, uint8_t id) const;
  /// The input report that `data` is (by its first byte when numbered), or nullptr.
  const HidReport* input_for(std::span<const uint8_t> data) const;
  /// First non-constant variable input field carrying `usage`; element index in `element`.
  const HidField* find_usage(uint32_t usage, int* element = nullptr) const;
};

/// Parses a report descriptor. Errors (truncated items, unbalanced collections, absurd
/// sizes) name the byte offset.
/// Limits: at most kMaxHidDescriptorBytes bytes, report counts up to 65,535, report sizes up
/// to 1,024 bits, each report up to 8 KiB, 65,536 usages in all the fields together, push
/// depth 64, collection depth 256 — each refused with the byte offset and the limit.
constexpr size_t kMaxHidDescriptorBytes = 4096;
Result<HidDescriptor> parse_hid_descriptor(std::span<const uint8_t> bytes);

/// Reads `bit_size` bits at `bit_offset`, little-endian, LSB first (the low 32 of a wider field).
uint32_t hid_extract_bits(std::span<const uint8_t> data, uint32_t bit_offset, uint32_t bit_size);
/// Writes `bit_size` bits at `bit_offset` (the inverse of hid_extract_bits; bits past 32 are 0).
void hid_insert_bits(std::span<uint8_t> data, uint32_t bit_offset, uint32_t bit_size, uint32_t value);

constexpr uint32_t hid_usage(uint16_t page, uint16_t id) { return uint32_t(page) << 16 | id; }

}  // namespace mar
