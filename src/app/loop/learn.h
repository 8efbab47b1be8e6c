// `--learn TARGET`: the first control that moves is bound to TARGET. The control is written
// in the show grammar (format_control prints what parse_control reads).
#pragma once

#include "app/show.h"

#include <span>
#include <string>

namespace mar {

struct Learned {
  size_t device = 0;    ///< show device index
  std::string control;  ///< "cc 7 ch 1", "encoder 2", "usage x", ...
};

/// The first event in `events` that names a bindable control; false when none does.
bool learn_control(std::span<const Event> events, const ShowConfig& show, Learned& out);

}  // namespace mar
