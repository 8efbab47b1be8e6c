// Outline tracing of a scalar image (mask or alpha) by marching squares.
#pragma once

#include "geom/types.h"

#include <cstdint>
#include <span>

namespace mar {

/// A closed ring (last point not repeated) in pixel coordinates: pixel (x, y) covers
/// [x, x+1] x [y, y+1], samples sit at pixel centres.
struct TracedRing {
  Points points;
  double area = 0;  ///< signed: > 0 outer boundary, < 0 hole
};

/// Traces the iso-line `value == threshold` of a width x height row-major image;
/// "inside" is value > threshold, the outside of the image counts as outside.
/// Crossings are interpolated linearly, so soft alpha gives sub-pixel outlines.
/// Saddle cells keep diagonal inside pixels connected (8-connected figure).
/// Outer rings come out with positive signed_area(), holes with negative.
std::vector<TracedRing> trace_iso_rings(std::span<const float> values, int width, int height,
                                        float threshold);

/// One connected region: an outer ring and the holes inside it.
struct Region {
  Points outer;
  std::vector<Points> holes;
};

/// Traces, simplifies each ring to `tolerance` pixels (Douglas–Peucker), drops rings
/// whose area is below `min_area` square pixels, and assigns every hole to the smallest
/// outer ring that contains it.
std::vector<Region> trace_regions(std::span<const float> values, int width, int height,
                                  float threshold, double tolerance, double min_area);

}  // namespace mar
