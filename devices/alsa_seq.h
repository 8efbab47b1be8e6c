// ALSA sequencer event -> MIDI bytes (for tests and the ALSA backend).
#pragma once

#include <alsa/asoundlib.h>

#include <cstddef>
#include <cstdint>

namespace mar {

/// ALSA prints its errors to stderr; ours go into the device status instead.
void quiet_alsa_errors();

/// MIDI bytes of one sequencer event (0 when it has none, e.g. port subscriptions).
size_t alsa_event_bytes(snd_midi_event_t* codec, const snd_seq_event_t& ev, uint8_t* out, size_t cap);

}  // namespace mar
