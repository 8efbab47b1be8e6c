#include "geom/marching_squares.h"

#include "geom/polygon.h"

namespace mar {

std::vector<TracedRing> trace_iso_rings(std::span<const float> values, int width, int height,
                                        float threshold) {
  std::vector<TracedRing> rings;
  if (width <= 0 || height <= 0 || values.size() < static_cast<size_t>(width) * height) {
    return rings;
  }
  // Sample grid with a one-sample border of "outside": sample (i, j), i in [-1, width],
  // lives at pixel centre (i + 0.5, j + 0.5).
  auto v = [&](int i, int j) -> float {
    if (i < 0 || j < 0 || i >= width || j >= height) return -1.0f;  // strictly outside
    return values[static_cast<size_t>(j) * width + i];
  };
  auto in = [&](int i, int j) { return v(i, j) > threshold; };
  const int gw = width + 2;  // sample columns -1..width
  const int gh = height + 2;
  // Edge ids: horizontal edge (i,j)-(i+1,j) -> 2*idx, vertical (i,j)-(i,j+1) -> 2*idx+1,
  // idx = (j+1)*gw + (i+1).
  auto hid = [&](int i, int j) { return 2 * ((j + 1) * gw + (i + 1)); };
  auto vid = [&](int i, int j) { return 2 * ((j + 1) * gw + (i + 1)) + 1; };
  auto crossing = [&](int i0, int j0, int i1, int j1) {
    const float a = v(i0, j0), b = v(i1, j1);
    double t = 0.5;
    if (a != b) t = std::clamp(static_cast<double>((threshold - a) / (b - a)), 0.0, 1.0);
    return Vec2{i0 + 0.5 + t * (i1 - i0), j0 + 0.5 + t * (j1 - j0)};
  };

  const size_t n_edges = static_cast<size_t>(2) * gw * gh;
  std::vector<int> next(n_edges, -1);  // segment start edge -> end edge
  std::vector<Vec2> pos(n_edges, Vec2::Zero());
  std::vector<int> starts;

  auto add_seg = [&](int e0, int e1) {
    next[e0] = e1;
    starts.push_back(e0);
  };

  for (int j = -1; j < height; ++j) {
    for (int i = -1; i < width; ++i) {
      const bool tl = in(i, j), tr = in(i + 1, j), br = in(i + 1, j + 1), bl = in(i, j + 1);
      const int code = (tl << 3) | (tr << 2) | (br << 1) | static_cast<int>(bl);
      if (code == 0 || code == 15) continue;
      const int T = hid(i, j), B = hid(i, j + 1), L = vid(i, j), R = vid(i + 1, j);
      // Record crossing positions (idempotent across the two cells sharing an edge).
      if (tl != tr) pos[T] = crossing(i, j, i + 1, j);
      if (bl != br) pos[B] = crossing(i, j + 1, i + 1, j + 1);
      if (tl != bl) pos[L] = crossing(i, j, i, j + 1);
      if (tr != br) pos[R] = crossing(i + 1, j, i + 1, j + 1);
      // Segments are oriented so the inside is on the side (-dy, dx) of the direction,
      // which makes outer rings positive under the shoelace formula.
      switch (code) {
        case 1: add_seg(L, B); break;   // bl
        case 2: add_seg(B, R); break;   // br
        case 3: add_seg(L, R); break;   // bl br
        case 4: add_seg(R, T); break;   // tr
        case 5: add_seg(L, T); add_seg(R, B); break;  // tr bl (saddle, connected)
        case 6: add_seg(B, T); break;   // tr br
        case 7: add_seg(L, T); break;   // all but tl
        case 8: add_seg(T, L); break;   // tl
        case 9: add_seg(T, B); break;   // tl bl
        case 10: add_seg(T, R); add_seg(B, L); break;  // tl br (saddle, connected)
        case 11: add_seg(T, R); break;  // all but tr
        case 12: add_seg(R, L); break;  // tl tr
        case 13: add_seg(R, B); break;  // all but br
        case 14: add_seg(B, L); break;  // all but bl
        default: break;
      }
    }
  }
  std::vector<int> visited_mark(n_edges, 0);
  for (int s : starts) {
    if (visited_mark[s] || next[s] < 0) continue;
    TracedRing ring;
    int e = s;
    size_t guard = 0;
    while (e >= 0 && !visited_mark[e] && guard++ < n_edges) {
      visited_mark[e] = 1;
      ring.points.push_back(pos[e]);
      e = next[e];
    }
    remove_duplicate_points(ring.points, true);
    if (ring.points.size() >= 3) {
      ring.area = signed_area(ring.points);
      rings.push_back(std::move(ring));
    }
  }
  return rings;
}

std::vector<Region> trace_regions(std::span<const float> values, int width, int height,
                                  float threshold, double tolerance, double min_area) {
  std::vector<TracedRing> rings = trace_iso_rings(values, width, height, threshold);
  std::vector<Region> regions;
  std::vector<double> outer_area;
  std::vector<Points> holes;
  for (TracedRing& r : rings) {
    if (std::abs(r.area) < min_area) continue;
    Points simple = simplify_polyline(r.points, tolerance, true);
    if (simple.size() < 3 || std::abs(signed_area(simple)) < min_area) continue;
    if (r.area > 0) {
      regions.push_back({std::move(simple), {}});
      outer_area.push_back(r.area);
    } else {
      holes.push_back(std::move(simple));
    }
  }
  for (Points& h : holes) {
    int best = -1;
    for (size_t k = 0; k < regions.size(); ++k) {
      if (winding_number(regions[k].outer, h[0]) != 0 &&
          (best < 0 || outer_area[k] < outer_area[static_cast<size_t>(best)])) {
        best = static_cast<int>(k);
      }
    }
    if (best >= 0) regions[static_cast<size_t>(best)].holes.push_back(std::move(h));
  }
  return regions;
}

}  // namespace mar
