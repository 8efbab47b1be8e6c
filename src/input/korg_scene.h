// The Korg nanoKONTROL2's scene over SysEx, as Korg's nanoKONTROL2 MIDI implementation gives it
// (the messages the Korg Kontrol Editor sends). Its LEDs follow the host only in the External
// LED mode, a byte of the scene, so a host that wants to light them reads the scene, sets that
// byte and sends the scene back (to the current scene, not the stored one: nothing is written
// to the unit's memory, and it is back to the user's setting when unplugged):
//   host -> device                                  device -> host
//   search device   F0 42 50 00 ee F7               F0 42 50 01 0g ee 13 01 mm mm vv vv vv vv F7
//   dump request    F0 42 4g 00 01 13 00 1F 10 00 F7   scene data (below)
//   scene data      F0 42 4g 00 01 13 00 7F 7F 02 03 05 40 <388 bytes> F7   ACK 5F 23 00 / NAK 5F 24 00
//   write request   F0 42 4g 00 01 13 00 1F 11 ss F7   write done 5F 21 00 / error 5F 22 00
// (g: the unit's global MIDI channel, ee: an echo the reply repeats, 13 01: the nanoKONTROL2's
// family, 0x13 + 0x01 x 128). The 339 scene bytes travel 7 at a time as 8 MIDI bytes: first
// the top bits (bit k: byte k's bit 7), then each byte's low 7 bits; the last 3 as 4.
// Scene byte 0 is the global channel, 1 the control mode (0: CC), 2 the LED mode (1: External).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace mar::korg {

constexpr size_t kSceneBytes = 339, kLedModeAt = 2;
constexpr size_t kPackedBytes = kSceneBytes / 7 * 8 + (kSceneBytes % 7 ? kSceneBytes % 7 + 1 : 0);  // 388
constexpr size_t kSceneMessage = 13 + kPackedBytes + 1;                                               // 402
constexpr int kFamily = 0x13 + (0x01 << 7);
using Scene = std::array<uint8_t, kSceneBytes>;

enum class Kind : uint8_t {
  Other,          ///< not one of these (or malformed)
  SearchRequest,  ///< echo
  SearchReply,    ///< channel, echo, family
  DumpRequest,    ///< channel
  SceneData,      ///< channel; the scene is unpacked into parse()'s `scene`
  WriteRequest,   ///< channel, slot
  Ack, Nak, WriteDone, WriteError,  ///< channel
};
struct Message {
  Kind kind = Kind::Other;
  int channel = 0, echo = 0, family = 0, slot = 0;
};

/// What `m` (a whole SysEx, F0 ... F7) is; a SceneData's scene goes to `scene` when given.
Message parse(std::span<const uint8_t> m, Scene* scene = nullptr);

// Each writes one message into `out` (large enough: kSceneMessage for scene_data) and returns its length.
size_t search_request(int echo, std::span<uint8_t> out);
size_t search_reply(int channel, int echo, std::span<uint8_t> out);
size_t dump_request(int channel, std::span<uint8_t> out);
size_t scene_data(int channel, const Scene& scene, std::span<uint8_t> out);
size_t write_request(int channel, int slot, std::span<uint8_t> out);
/// A one-word answer: Ack, Nak, WriteDone or WriteError.
size_t answer(Kind kind, int channel, std::span<uint8_t> out);

/// The nanoKONTROL2's factory scene (CC mode, channel 1, the LED mode Internal).
Scene factory_scene();

}  // namespace mar::korg
