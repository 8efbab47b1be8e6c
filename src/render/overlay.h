// Frame overlay (seed 000 Fig. 2(d)): feature lines, sewing lines (automatic and the
// user's), feature points and handles drawn over the character.
#pragma once

#include "frame/feature_frame.h"
#include "render/tessellate.h"

namespace mar {

/// Appends the overlay for frame vertices `v` (#q) and handle positions, mapped by `view`.
void append_frame_overlay(const FeatureFrame& frame, std::span<const Vec2> v, std::span<const Vec2> handles,
                          const Affine2& view, DrawList& out);

}  // namespace mar
