// Frame overlay (seed 000 Fig. 2(d)): feature lines (blue), sewing lines (orange; the user's
// red), feature points (black), hinges (purple rings, their spokes grey) and handles (green)
// drawn over the character.
#pragma once

#include "frame/feature_frame.h"
#include "render/tessellate.h"

#include <array>

namespace mar {

/// Appends the overlay for frame vertices `v` (#q) and handle positions, mapped by `view`.
void append_frame_overlay(const FeatureFrame& frame, std::span<const Vec2> v, std::span<const Vec2> handles,
                          const Affine2& view, DrawList& out);

/// Appends the rig's markers alone (no frame): hinges as purple discs, handles as green ones
/// (`selected`, when >= 0, larger and darker), mapped by `view`.
void append_markers(std::span<const Vec2> handles, std::span<const Vec2> hinges, int selected, const Affine2& view, DrawList& out);

/// Appends the rig studio's pen marks, mapped by `view`: a ring of `radius` about `at` (the
/// brush's reach; radius 0: none) and the polyline `stroke` (a curve being drawn).
void append_pen_marks(const Vec2& at, double radius, std::span<const Vec2> stroke, const Affine2& view, DrawList& out);

/// Appends a triangle mesh (a solver's: edges grey, vertices black) and handle positions
/// (green rings), mapped by `view`.
void append_mesh_overlay(std::span<const Vec2> v, std::span<const std::array<int, 3>> triangles,
                         std::span<const Vec2> handles, const Affine2& view, DrawList& out);

/// Appends the rigid grid's hybrid representation like seed 003 Figs. 1(e-f) and 2: the
/// interior grid (blue cell edges), the junction triangles (orange edges), the boundary
/// curve nodes (dark red dots; nodes [grid_count, ...) of `v`) and handles (green rings).
void append_grid_overlay(std::span<const Vec2> v, size_t grid_count, std::span<const std::array<int, 2>> grid_edges,
                         std::span<const std::array<int, 3>> junction_triangles, std::span<const Vec2> handles,
                         const Affine2& view, DrawList& out);

}  // namespace mar
