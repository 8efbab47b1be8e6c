// OSC 1.0 messages and address patterns, without allocating and in time linear in the
// pattern times the address (liblo's matcher backtracks: a 47-byte address took 8.6 s).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

namespace mar {

/// OSC address-pattern match: '?' one character, '*' any run, '[a-z]' / '[!abc]' one of or
/// none of, '{foo,bar}' one of the strings. '?', '*' and classes never match '/' (they stay
/// within one part of the address). Addresses or patterns longer than 255 bytes never match.
bool osc_match(std::string_view pattern, std::string_view address);

/// One parsed OSC message (views into the message bytes).
struct OscMessage {
  std::string_view address;
  char type = 0;         ///< first argument's type tag ('f', 'd', 'i', 'h', 'T', 'F'); 0: none
  double number = 0;     ///< its value ('T' = 1, 'F' = 0)
};
/// Parses a message (not a bundle); false when the bytes are not a well-formed OSC message.
bool parse_osc_message(std::span<const uint8_t> bytes, OscMessage& out);

}  // namespace mar
