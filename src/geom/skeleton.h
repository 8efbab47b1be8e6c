// The straight skeleton of a polygon's interior (CGAL's), as a graph: its nodes (each with
// its distance to the outline, the radius of the largest circle there) and the edges between
// them, without the spokes that run out to the outline's corners. Along an edge the radius
// changes linearly, so the graph is a medial axis of straight pieces: a limb is a branch of it.
#pragma once

#include "geom/polygon.h"

#include <span>
#include <string>
#include <utility>
#include <vector>

namespace mar {

struct SkeletonGraph {
  std::vector<Vec2> nodes;
  std::vector<double> radius;                 ///< per node: its distance to the outline
  std::vector<std::pair<int, int>> edges;     ///< node index pairs
  std::string error;                          ///< why there is none (an outline that crosses itself)
};

/// The interior straight skeleton of the simple polygon `outer` (either orientation) with
/// `holes` inside it. At most `max_vertices` outline points in all (more is refused: the work
/// grows faster than their count).
SkeletonGraph straight_skeleton(std::span<const Vec2> outer, std::span<const Points> holes = {}, size_t max_vertices = 2000);

}  // namespace mar
