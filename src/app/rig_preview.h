// `marionette rig --preview rig.png`: a picture of what the automatic rig found. The drawing,
// veiled, with the body, the head and each limb tinted in a colour of its own, what was left
// out hatched grey, hinges as purple discs and handles as green ones with their names, and
// a legend below that lists them.
#pragma once

#include "character/character.h"
#include "rig/auto_rig.h"

#include <string>
#include <vector>

namespace mar {

/// The legend's lines: the body, the head, each limb (with its hinge and handle), what rides
/// on the parts, and what was left out and why.
std::vector<std::string> rig_summary(const AutoRig& ar, const Character& ch);

/// Draws the preview of `ar` over `ch` into a PNG at `path`, its drawing `long_side` pixels
/// on its longer side; returns an error (the file named) or empty.
std::string write_rig_preview(const std::string& path, const Character& ch, const AutoRig& ar, int long_side = 900);

}  // namespace mar
