// Feature points of one polyline (seed 000 §3, docs/algorithms.md §1): IPAN99 high-curvature
// points, inflection points with hysteresis, and uniform arc-length samples.
// Indices refer to the polyline's points; results are sorted and unique.
#pragma once

#include "geom/types.h"

#include <span>

namespace mar {

/// IPAN99 (Chetverikov & Szabó 1999). A point p is a candidate when some admissible
/// triangle (p-, p, p+) exists with d_min <= |p - p-|, |p - p+| <= d_max and opening angle
/// <= alpha_max (radians); its sharpness is the smallest such angle. Candidates that are
/// not the sharpest within d_max of each other are dropped.
std::vector<int> ipan99_corners(std::span<const Vec2> pts, bool closed, double d_min, double d_max,
                                double alpha_max);

/// Sign changes of the curvature, measured at each vertex as the turn between the chords
/// reaching window/2 of arc length back and forward (light smoothing). The sign only flips once
/// the windowed turning passes +-`hysteresis` radians, so noise does not create points;
/// the inflection is placed midway between the last vertex of the old sign and the first
/// of the new.
std::vector<int> inflection_points(std::span<const Vec2> pts, bool closed, double window,
                                   double hysteresis);

/// Vertices nearest to every multiple of `interval` in arc length (from point 0; the last
/// point of an open polyline is included).
std::vector<int> arc_length_samples(std::span<const Vec2> pts, bool closed, double interval);

/// Cumulative arc length: out[i] = length from point 0 to point i (size n, or n + 1 for a
/// closed polyline, whose last entry is the perimeter).
std::vector<double> cumulative_length(std::span<const Vec2> pts, bool closed);

}  // namespace mar
