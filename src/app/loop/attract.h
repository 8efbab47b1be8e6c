// The attract loop of an unattended show ([attract]): after `after` seconds without a visitor
// touching a bound control, a recorded take or a timeline script plays the character, faded
// in; the first visitor input fades it out again and the visitor has the character.
//
// The attract plays into its own copy of the show's mapping (same bindings, its own control
// state), so the visitor's controls keep their positions underneath and the crossfade goes
// from what the attract shows to what the visitor's controls say: handle targets and
// key-pose weights are blended (key weights blended linearly are the interpolation path).
// Everything is made at load; a frame allocates nothing.
#pragma once

#include "app/show.h"
#include "firmware_sim/sim_device.h"
#include "base/result.h"
#include "input/decoder.h"
#include "input/mapping.h"

#include <memory>
#include <string>
#include <vector>

namespace mar {

/// The idle timer and the crossfade weight (0: the visitor's controls, 1: the attract).
class AttractClock {
 public:
  enum class State { Live, FadeIn, Playing, FadeOut };
  AttractClock(double after_s, double fade_s) : after_(after_s), fade_(fade_s) {}
  /// One frame of `dt` seconds; `input`: a visitor moved a bound control in it. True when the
  /// attract starts in this frame (from the beginning of its take or script).
  bool step(double dt, bool input);
  State state() const { return state_; }
  /// The crossfade weight, eased in and out (smoothstep of the linear ramp).
  double weight() const;
  /// Whether the attract is seen at all (its records play while this is true).
  bool shown() const { return state_ != State::Live; }
  double idle_seconds() const { return idle_; }

 private:
  double after_, fade_;
  State state_ = State::Live;
  double idle_ = 0, ramp_ = 0;  ///< ramp_: linear weight 0..1
};

class Attract {
 public:
  /// Prepares the script (on a fresh simulator of `sim_kind`, decoded as `decoder` with
  /// `source`) or reads the whole take into memory (at most kMaxTakeRecords records).
  /// `fresh` is the show's mapping before any input: the attract's starting state.
  static Result<std::unique_ptr<Attract>> make(const AttractConfig& c, const Mapping& fresh, const std::string& sim_kind,
                                               const std::string& descriptor, uint16_t source, int64_t debounce_ns);
  static constexpr size_t kMaxTakeRecords = 1'000'000;

  /// One frame: `input` as AttractClock::step; plays the attract's records up to its own
  /// clock into its mapping while it is shown.
  void step(double dt, bool input);
  double weight() const { return clock_.weight(); }
  bool shown() const { return clock_.shown(); }
  AttractClock::State state() const { return clock_.state(); }
  const Mapping& mapping() const { return mapping_; }
  Mapping& mapping() { return mapping_; }
  uint64_t starts() const { return starts_; }
  uint64_t handovers() const { return handovers_; }
  double seconds_shown() const { return shown_s_; }

 private:
  Attract(const AttractConfig& c, const Mapping& fresh) : clock_(c.after, c.fade), fresh_(fresh), mapping_(fresh) {}
  void play(int64_t until_ns);

  AttractClock clock_;
  Mapping fresh_, mapping_;
  // a script: its simulator and the decoder of its records
  std::unique_ptr<SimDevice> sim_;
  std::unique_ptr<Decoder> decoder_;
  // a take: every record in time order, each source's decoder, the take's length
  std::vector<WireRecord> take_;
  std::vector<std::unique_ptr<Decoder>> take_decoders_;
  int64_t take_ns_ = 0;
  size_t next_ = 0;
  int64_t offset_ns_ = 0;
  int64_t t_ns_ = 0;  ///< the attract's own clock (advances while shown)
  std::vector<Event> events_;
  uint64_t starts_ = 0, handovers_ = 0;
  double shown_s_ = 0;
};

}  // namespace mar
