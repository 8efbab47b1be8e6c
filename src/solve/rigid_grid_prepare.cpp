// The rigid grid's preparation (solve/rigid_grid.h): the interior grid, the boundary curves,
// the triangular mesh and junction, shape points and handles through the nodes. The regions
// and the factorisation are in rigid_grid_regions.cpp, the per-frame solve in rigid_grid.cpp.
#include "solve/rigid_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>

#include "geom/polygon.h"
#include "geom/triangulate.h"

namespace mar {
namespace {



// Inside the filled region (the union of the filled, closed sub-shapes, each even-odd over its
// contours as SubShape::contains), with the edges of each shape sorted into horizontal bands so
// a query visits only the edges its height meets: a grid of thousands of corners over an outline
// of thousands of points costs a few milliseconds, not a second.
class FillIndex {
 public:
  FillIndex(const Character& ch, double band) {
    for (size_t si = 0; si < ch.shapes.size(); ++si) {
      const SubShape& s = ch.shapes[si];
      if (!s.fill.enabled || !s.closed()) continue;
      Shape sh;
      sh.index = si;
      const Bounds b = s.bounds();
      sh.lo = b.lo;
      sh.hi = b.hi;
      sh.band = band;
      sh.bands.assign(size_t(std::clamp(std::ceil((b.hi.y() - b.lo.y()) / band), 1.0, 1e6)), {});
      for (const Contour& c : s.contours) {
        if (!c.closed || c.count < 3) continue;
        for (int k = 0; k < c.count; ++k) {
          const Vec2 a = s.points[size_t(c.begin + (k + c.count - 1) % c.count)], e = s.points[size_t(c.begin + k)];
          const size_t lo = sh.band_of(std::min(a.y(), e.y())), hi = sh.band_of(std::max(a.y(), e.y()));
          for (size_t q = lo; q <= hi; ++q) sh.bands[q].push_back({a, e});
        }
      }
      shapes_.push_back(std::move(sh));
    }
  }
  bool any() const { return !shapes_.empty(); }
  bool inside(const Vec2& p) const { return shape_at(p) >= 0; }
  /// The first filled sub-shape (in the character's order) holding p, or -1.
  int shape_at(const Vec2& p) const {
    for (const Shape& sh : shapes_) {
      if (!(p.x() >= sh.lo.x() && p.x() <= sh.hi.x() && p.y() >= sh.lo.y() && p.y() <= sh.hi.y())) continue;
      bool in = false;  // winding_number's rule, edge by edge: each ±1 flips the parity
      for (const auto& [a, b] : sh.bands[sh.band_of(p.y())]) {
        const double cr = (b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y());
        if (a.y() <= p.y() ? (b.y() > p.y() && cr > 0) : (b.y() <= p.y() && cr < 0)) in = !in;
      }
      if (in) return int(sh.index);
    }
    return -1;
  }

 private:
  struct Shape {
    size_t index = 0;  ///< in Character::shapes
    Vec2 lo, hi;
    double band = 1;
    std::vector<std::vector<std::pair<Vec2, Vec2>>> bands;
    size_t band_of(double y) const {
      const double k = std::floor((y - lo.y()) / band);
      return size_t(std::clamp(k, 0.0, double(bands.size() - 1)));
    }
  };
  std::vector<Shape> shapes_;
};

// Does segment ab meet the box [lo, hi]? (Liang-Barsky clipping.)
bool segment_meets_box(const Vec2& a, const Vec2& b, const Vec2& lo, const Vec2& hi) {
  double t0 = 0, t1 = 1;
  const Vec2 d = b - a;
  for (int k = 0; k < 2; ++k) {
    if (std::abs(d[k]) < 1e-300) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / d[k], tb = (hi[k] - a[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// A polyline refined so no edge is longer than `h` (seed 003: boundary edges of about the cell
// size), every input point kept; `at[k]` is input point k's index in the result.
Points refine(std::span<const Vec2> pts, bool closed, double h, std::vector<int>& at, double& spacing) {
  const size_t n = pts.size();
  Points out;
  at.assign(n, 0);
  double len = 0;
  for (size_t k = 0; k < n; ++k) {
    at[k] = int(out.size());
    out.push_back(pts[k]);
    if (!closed && k + 1 == n) break;
    const Vec2 a = pts[k], b = pts[(k + 1) % n];
    len += (b - a).norm();
    const int pieces = int(std::ceil((b - a).norm() / h));
    for (int i = 1; i < pieces; ++i) out.push_back(a + (double(i) / pieces) * (b - a));
  }
  spacing = len / double(std::max<size_t>(1, closed ? out.size() : out.size() - 1));
  return out;
}

// Positions quantised for merging coincident points (strokes that share an end point).
struct Key {
  int64_t x, y;
  bool operator<(const Key& o) const { return x != o.x ? x < o.x : y < o.y; }
};
Key key(const Vec2& p, double q) { return {int64_t(std::llround(p.x() / q)), int64_t(std::llround(p.y() / q))}; }

// A contour's points for the grid's boundary curves, and which of them are nodes.
struct ContourPoints {
  bool closed = false;
  Points pts;                                   ///< the drawn points, and stroke ends met between them
  std::vector<int> orig;                        ///< per drawn point: its index in pts
  std::vector<char> must;                       ///< per point: a node whatever the spacing (an open end, a stroke end)
  std::vector<const std::vector<int>*> sharing;  ///< per point: the contours through it (null: this one only)
  std::vector<char> crossings;                  ///< per point: a node by keep_crossings
  std::vector<char> keep;                       ///< per point: a node
};

// The nodes kept however straight the contour runs: where the contour steps from one lattice
// cell (`step` wide, from `origin`) into the next, the end of the step nearer the line it
// crosses (both ends of a step half a cell long: a corner), and the points where the contours
// through it change (two shapes drawn edge to edge part). Each choice depends on the points
// alone, not on the way the contour runs, so an outline and its fill drawn through the same
// points keep the same ones.
void keep_crossings(ContourPoints& cp, const Vec2& origin, double step, double q, bool every_point) {
  const Points& pts = cp.pts;
  const size_t n = pts.size();
  std::vector<char>& keep = cp.crossings;
  keep.assign(cp.must.begin(), cp.must.end());
  if (every_point || n < 2) {
    keep.assign(n, 1);
    return;
  }
  auto cell = [&](const Vec2& p) {
    return std::array<int64_t, 2>{int64_t(std::floor((p.x() - origin.x()) / step)), int64_t(std::floor((p.y() - origin.y()) / step))};
  };
  auto off_line = [&](const Vec2& p, const std::array<int64_t, 2>& a, const std::array<int64_t, 2>& b) {
    double d = INFINITY;
    for (int i = 0; i < 2; ++i)
      if (a[size_t(i)] != b[size_t(i)])
        d = std::min(d, std::abs(p[i] - (origin[i] + step * double(std::max(a[size_t(i)], b[size_t(i)])))));
    return d;
  };
  auto same_contours = [&](size_t k, size_t l) {
    return cp.sharing[k] == cp.sharing[l] || (cp.sharing[k] && cp.sharing[l] && *cp.sharing[k] == *cp.sharing[l]);
  };
  for (size_t k = 0; k + (cp.closed ? 0 : 1) < n; ++k) {
    const size_t l = (k + 1) % n;
    if (!same_contours(k, l)) keep[k] = keep[l] = 1;
    const auto ck = cell(pts[k]), cl = cell(pts[l]);
    if (ck == cl) continue;
    if ((pts[l] - pts[k]).norm() >= 0.5 * step) {
      keep[k] = keep[l] = 1;
      continue;
    }
    const double dk = off_line(pts[k], ck, cl), dl = off_line(pts[l], ck, cl);
    keep[(dk != dl ? dk < dl : key(pts[k], q) < key(pts[l], q)) ? k : l] = 1;
  }
  if (size_t(std::count(keep.begin(), keep.end(), 1)) < (cp.closed ? 3u : 2u))  // within one cell: spread points of it
    for (size_t k = 0; k < n; ++k) keep[k] = keep[k] || n <= 8 || k % (n / 4) == 0;
}

// The crossings, and where a chord between two kept points strays from the points it leaves
// out by more than `stray`, the farthest of them, until none does (Douglas-Peucker from the
// kept points: a thin stroke's two sides keep their mesh between them; the farthest point of a
// chord is the same whichever way the contour runs).
void keep_straying(ContourPoints& cp, double stray, double q) {
  const Points& pts = cp.pts;
  const size_t n = pts.size();
  std::vector<char>& keep = cp.keep;
  keep = cp.crossings;
  std::vector<std::pair<size_t, size_t>> chords;
  for (size_t k = 0; k < n; ++k) {
    if (!keep[k]) continue;
    size_t l = (k + 1) % n;
    while (!keep[l]) l = (l + 1) % n;
    if (cp.closed || l > k) chords.push_back({k, l});
  }
  while (!chords.empty()) {
    const auto [a, b] = chords.back();
    chords.pop_back();
    const Vec2 pa = pts[a], d = pts[b] - pa;
    const double len2 = d.squaredNorm();
    double far = stray;
    size_t at_far = n;
    for (size_t k = (a + 1) % n; k != b; k = (k + 1) % n) {
      const double t = len2 > 0 ? std::clamp((pts[k] - pa).dot(d) / len2, 0.0, 1.0) : 0.0;
      const double off = (pts[k] - (pa + t * d)).norm();
      if (off > far || (off == far && at_far < n && key(pts[k], q) < key(pts[at_far], q))) far = off, at_far = k;
    }
    if (at_far == n) continue;
    keep[at_far] = 1;
    chords.push_back({a, at_far});
    chords.push_back({at_far, b});
  }
}


}  // namespace

bool RigidGrid::prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
                        std::string* error) {
  riders_.clear();
  rider_of_.assign(ch.shapes.size(), -1);
  rider_rest_.assign(ch.shapes.size(), {});
  handle_rider_.assign(handle_rest.size(), -1);
  grab_rider_ = -1;
  skin_.clear();
  prepare_bones(rig);
  if (!prepare_riders(ch, rig, error)) return false;
  for (size_t h = 0; h < rig.handles.size() && h < handle_rest.size(); ++h)
    for (size_t r = 0; r < riders_.size(); ++r)
      if (riders_[r].handle == int(h)) handle_rider_[h] = int(r);
  // The riding shapes are out of the mesh while it is built (their points stay theirs).
  std::vector<std::vector<Contour>> contours(ch.shapes.size());
  for (size_t si = 0; si < ch.shapes.size(); ++si)
    if (rider_of_[si] >= 0) {
      std::swap(rider_rest_[si], ch.shapes[si].points);
      std::swap(contours[si], ch.shapes[si].contours);
    }
  const bool ok = prepare_grid(ch, rig, handle_rest, w, error);
  for (size_t si = 0; si < ch.shapes.size(); ++si)
    if (rider_of_[si] >= 0) {
      ch.shapes[si].points = rider_rest_[si];
      std::swap(contours[si], ch.shapes[si].contours);
    }
  if (!ok) return false;
  skin_bones(ch);
  link_riders();
  place_riders({});
  return true;
}

bool RigidGrid::prepare_grid(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
                             std::string* error) {
  const Bounds bb = ch.bounds();
  if (bb.empty()) {
    if (error) *error = "rigid_grid: the character has no points";
    return false;
  }
  const double diag = portable_hypot(bb.width(), bb.height());
  h_ = rig.grid_cell > 0 ? rig.grid_cell : diag / 40;
  if (!(h_ > 0) || !std::isfinite(h_)) h_ = 1;
  half_width_ = rig.grid_half_width;
  region_stride_ = rig.grid_stride;
  w_r_ = rig.grid_rigidity;
  w_s_ = rig.grid_junction;
  w_p_ = w.position;
  handle_w_ = w.handle_weights;
  stiff_.clear();
  for (const RigStiffness& s : rig.stiffness) stiff_.push_back({s.name, s.center, s.radius, s.weight});
  mid_ = 0.5 * (bb.lo + bb.hi);

  // --- The interior grid: cells wholly inside the filled region, crossed by no outline that bounds
  // it (a line with the outside on one side), so a gap narrower than a cell splits the grid.
  origin_ = bb.lo - Vec2(h_, h_);
  nx_ = int(std::ceil((bb.hi.x() - origin_.x()) / h_)) + 1;
  ny_ = int(std::ceil((bb.hi.y() - origin_.y()) / h_)) + 1;
  if (double(nx_) * double(ny_) > 4e6) {
    if (error)
      *error =
          "rigid_grid: the grid would have more than 4 million cells; "
          "make [grid] cell larger";
    return false;
  }
  auto corner = [&](int i, int j) -> Vec2 { return origin_ + Vec2(i * h_, j * h_); };
  const FillIndex fill(ch, h_);
  std::vector<char> corner_in(size_t(nx_ + 1) * size_t(ny_ + 1));
  for (int j = 0; j <= ny_; ++j)
    for (int i = 0; i <= nx_; ++i) corner_in[size_t(j) * size_t(nx_ + 1) + size_t(i)] = fill.inside(corner(i, j));
  std::vector<char> crossed(size_t(nx_) * size_t(ny_), 0);
  std::vector<std::pair<Vec2, Vec2>> lines;  // every line of the character (for the fill's interior points)
  for (const SubShape& s : ch.shapes)
    for (const Contour& c : s.contours)
      for (int k = 0; c.count > 1 && k + (c.closed ? 0 : 1) < c.count; ++k) {
        const Vec2 a = s.points[size_t(c.begin + k)], b = s.points[size_t(c.begin + (k + 1) % c.count)];
        lines.push_back({a, b});
        if (!s.fill.enabled || !c.closed || (b - a).norm() < 1e-12 * h_) continue;
        const Vec2 m = 0.5 * (a + b), n = Vec2(a.y() - b.y(), b.x() - a.x()).normalized() * (1e-3 * h_);
        if (fill.inside(m + n) == fill.inside(m - n)) continue;  // inside the region
        const int i0 = std::max(0, int(std::floor((std::min(a.x(), b.x()) - origin_.x()) / h_)));
        const int i1 = std::min(nx_ - 1, int(std::floor((std::max(a.x(), b.x()) - origin_.x()) / h_)));
        const int j0 = std::max(0, int(std::floor((std::min(a.y(), b.y()) - origin_.y()) / h_)));
        const int j1 = std::min(ny_ - 1, int(std::floor((std::max(a.y(), b.y()) - origin_.y()) / h_)));
        for (int cj = j0; cj <= j1; ++cj)
          for (int ci = i0; ci <= i1; ++ci)
            if (segment_meets_box(a, b, corner(ci, cj), corner(ci + 1, cj + 1)))
              crossed[size_t(cj) * size_t(nx_) + size_t(ci)] = 1;
      }
  cell_in_.assign(size_t(nx_) * size_t(ny_), 0);
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i) {
      bool in = !crossed[size_t(j) * size_t(nx_) + size_t(i)] && fill.inside(corner(i, j) + Vec2(h_ / 2, h_ / 2));
      for (int dj = 0; dj <= 1 && in; ++dj)
        for (int di = 0; di <= 1 && in; ++di) in = corner_in[size_t(j + dj) * size_t(nx_ + 1) + size_t(i + di)];
      cell_in_[size_t(j) * size_t(nx_) + size_t(i)] = in;
    }
  rest_.clear();
  gxy_.clear();
  node_of_corner_.assign(size_t(nx_ + 1) * size_t(ny_ + 1), -1);
  for (int j = 0; j < ny_; ++j)
    for (int i = 0; i < nx_; ++i) {
      if (!cell_inside(i, j)) continue;
      for (int dj = 0; dj <= 1; ++dj)
        for (int di = 0; di <= 1; ++di) {
          int& id = node_of_corner_[size_t(j + dj) * size_t(nx_ + 1) + size_t(i + di)];
          if (id < 0) {
            id = int(rest_.size());
            rest_.push_back(corner(i + di, j + dj));
            gxy_.push_back({i + di, j + dj});
          }
        }
    }
  grid_count_ = rest_.size();

  // --- Boundary curves: every contour thinned and refined to about a cell between nodes;
  // coincident points of different contours share their node (stick figures). A stroke that
  // ends on another contour between its points (an arm drawn from the middle of a spine, a neck
  // ending on a head's ring) puts its end into that contour as a point, so the two share it too.
  const double q = 1e-7 * std::max(diag, 1e-300);
  Points stroke_ends;
  for (const SubShape& s : ch.shapes)
    for (const Contour& c : s.contours)
      if (c.count >= 2 && !(c.closed && c.count >= 3)) {
        stroke_ends.push_back(s.points[size_t(c.begin)]);
        stroke_ends.push_back(s.points[size_t(c.begin + c.count - 1)]);
      }
  const double touch = 0.25 * h_;  // an end this near a contour is on it
  // Which contours pass through each point: two shapes drawn edge to edge (or an outline and its
  // fill) keep the points where they part, so they keep sharing nodes along the run.
  std::map<Key, std::vector<int>> contours_at;
  {
    int id = 0;
    for (const SubShape& s : ch.shapes)
      for (const Contour& c : s.contours) {
        if (c.count >= 2)
          for (int k = 0; k < c.count; ++k) {
            std::vector<int>& v = contours_at[key(s.points[size_t(c.begin + k)], q)];
            if (v.empty() || v.back() != id) v.push_back(id);
          }
        ++id;
      }
  }
  // Each contour's points, with the stroke ends that touch it between its points (T-junctions).
  std::vector<ContourPoints> cps;
  double outline = 0;
  for (const SubShape& s : ch.shapes)
    for (const Contour& c : s.contours) {
      ContourPoints& cp = cps.emplace_back();
      if (c.count < 2) continue;
      const bool cl = cp.closed = c.closed && c.count >= 3;
      for (int k = 0; k < c.count; ++k) {
        const Vec2& a = s.points[size_t(c.begin + k)];
        cp.orig.push_back(int(cp.pts.size()));
        cp.pts.push_back(a);
        cp.must.push_back(!cl && (k == 0 || k + 1 == c.count));
        if (k + 1 == c.count && !cl) break;
        const Vec2& b = s.points[size_t(c.begin + (k + 1) % c.count)];
        const Vec2 ab = b - a;
        const double len2 = ab.squaredNorm();
        outline += std::sqrt(len2);
        if (len2 <= 0) continue;
        std::vector<std::pair<double, Vec2>> on;
        for (const Vec2& e : stroke_ends) {
          const double t = (e - a).dot(ab) / len2;
          if (t <= 1e-6 || t >= 1 - 1e-6 || (a + t * ab - e).norm() > touch) continue;
          if ((e - a).norm() <= touch || (e - b).norm() <= touch) continue;  // (at a point: shared already, or near enough)
          on.emplace_back(t, e);
        }
        std::sort(on.begin(), on.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (const auto& [t, e] : on)
          if ((e - cp.pts.back()).squaredNorm() > q * q) {
            cp.pts.push_back(e);
            cp.must.push_back(1);
          }
      }
      for (const Vec2& p : cp.pts) {
        const auto it = contours_at.find(key(p, q));
        cp.sharing.push_back(it == contours_at.end() ? nullptr : &it->second);
      }
    }
  // Drawn points closer than a cell are not all nodes: an editor's curve flattened in dozens of
  // points a cell made a frame's solve grow with them (a sheep's curly wool, 14,910 points, 150
  // ms a frame). Along a contour nodes are about `step` apart, a cell, or wider where the
  // outlines are long for the drawing's size, so that the lattice's crossings are at most about
  // kCurveNodes. The chords' leeway stays a twentieth of a cell however many nodes that keeps
  // (a wiggly fleece keeps more: a sheep's 14,858 points give 4,493 nodes): widened to reach
  // the budget (up to 12.8 cells), it dropped the tips of an eagle's feathers, a lindworm's and
  // a pig's outline, and the grid, bent and brought back, settled 2.5-4.5 % of their height off
  // their rest.
  constexpr double kCurveNodes = 1500, kChordStray = 0.05;  // (stray: of a cell)
  const double step = std::max(h_, outline / kCurveNodes);
  // Which points of each contour are nodes (keep_crossings, keep_straying).
  for (ContourPoints& cp : cps) {
    keep_crossings(cp, origin_, step, q, every_contour_point_);
    keep_straying(cp, kChordStray * h_, q);
  }
  struct Dropped {
    int shape, point, a, b, curve, at;  ///< a contour point no node holds, beside nodes a and b (at, at + 1) of the curve
  };
  std::vector<Dropped> dropped;
  std::map<Key, int> curve_node_at;
  curves_.clear();
  cnode_.clear();
  std::vector<char> on_open;
  binds_.assign(ch.shapes.size(), {});
  size_t contour_index = 0;
  for (size_t si = 0; si < ch.shapes.size(); ++si) {
    const SubShape& s = ch.shapes[si];
    binds_[si].assign(s.points.size(), Embed{});
    for (auto& b : binds_[si]) b.v[0] = -1;
    for (const Contour& c : s.contours) {
      const ContourPoints& cp = cps[contour_index++];
      if (c.count < 2) continue;
      const bool cl = c.closed && c.count >= 3;
      const size_t n = cp.pts.size();
      Points kept;
      std::vector<int> kept_at(n, -1);  ///< per point of cp.pts: its index in kept
      for (size_t k = 0; k < n; ++k)
        if (cp.keep[k]) {
          kept_at[k] = int(kept.size());
          kept.push_back(cp.pts[k]);
        }
      std::vector<int> at;
      double spacing = h_;
      const Points r = refine(kept, cl, step, at, spacing);
      const int first = int(cnode_.size());
      for (const Vec2& p : r) {
        auto [it, added] = curve_node_at.try_emplace(key(p, q), int(rest_.size()));
        if (added) {
          rest_.push_back(p);
          on_open.push_back(0);
        }
        if (!cl) on_open[size_t(it->second) - grid_count_] = 1;
        cnode_.push_back(it->second);
      }
      const int m = int(kept.size()), rn = int(r.size());
      for (int k = 0; k < c.count; ++k) {
        const size_t o = size_t(cp.orig[size_t(k)]);
        if (kept_at[o] >= 0) {
          binds_[si][size_t(c.begin + k)].v[0] = cnode_[size_t(first + at[size_t(kept_at[o])])];
          continue;
        }
        // Left out: between the kept points before and after it (a closed contour wraps; an open
        // one keeps its ends), beside the two refined nodes its projection on their chord falls
        // between.
        size_t a = o, b = o;
        while (kept_at[a] < 0) a = (a + n - 1) % n;
        while (kept_at[b] < 0) b = (b + 1) % n;
        const int ia = at[size_t(kept_at[a])], ib = kept_at[b] == 0 && kept_at[a] == m - 1 ? rn : at[size_t(kept_at[b])];
        const Vec2 pa = cp.pts[a], d = cp.pts[b] - pa;
        const double t = d.squaredNorm() > 0 ? std::clamp((cp.pts[o] - pa).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
        const int lo = ia + std::clamp(int(std::floor(t * (ib - ia))), 0, ib - ia - 1);
        dropped.push_back({int(si), c.begin + k, cnode_[size_t(first + lo % rn)], cnode_[size_t(first + (lo + 1) % rn)],
                           int(curves_.size()), lo});
      }
      curves_.push_back({first, int(r.size()), cl, spacing});
    }
  }
  curve_count_ = rest_.size() - grid_count_;
  if (rest_.size() < 3) {
    if (error) *error = "rigid_grid: the character has nothing to mesh";
    return false;
  }

  // --- The triangular mesh: a constrained Delaunay triangulation of every node, curves as
  // constraints. Its vertices map back to nodes; a crossing of two contours is a free vertex (V³).
  Points pts(rest_.begin(), rest_.begin() + std::ptrdiff_t(grid_count_));
  std::vector<Ring> rings;
  std::vector<char> closed;
  for (size_t k = 0; k < grid_count_; ++k) {
    rings.push_back({int(k), 1});
    closed.push_back(0);
  }
  for (const Curve& c : curves_) {
    rings.push_back({int(pts.size()), c.count});
    closed.push_back(c.closed ? 1 : 0);
    for (int k = 0; k < c.count; ++k) pts.push_back(rest_[size_t(cnode_[size_t(c.first + k)])]);
  }
  const HullMesh hm = triangulate_hull(pts, rings, closed);
  std::map<Key, int> node_at;
  for (size_t k = 0; k < rest_.size(); ++k) node_at.try_emplace(key(rest_[k], q), int(k));
  std::vector<int> node_of(hm.vertices.size());
  for (size_t v = 0; v < hm.vertices.size(); ++v) {
    auto [it, added] = node_at.try_emplace(key(hm.vertices[v], q), int(rest_.size()));
    if (added) rest_.push_back(hm.vertices[v]);
    node_of[v] = it->second;
  }
  on_open.resize(rest_.size() - grid_count_, 0);
  auto is_open = [&](int n) { return size_t(n) >= grid_count_ && on_open[size_t(n) - grid_count_]; };
  const bool any_filled = fill.any();
  tris_.clear();
  junction_.clear();
  std::vector<char> used(rest_.size(), 0);
  for (size_t t = 0; t + 2 < hm.triangles.size(); t += 3) {
    std::array<int, 3> tri{node_of[size_t(hm.triangles[t])], node_of[size_t(hm.triangles[t + 1])],
                           node_of[size_t(hm.triangles[t + 2])]};
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
    const Vec2 &a = rest_[size_t(tri[0])], &b = rest_[size_t(tri[1])], &c = rest_[size_t(tri[2])];
    const Vec2 centroid = (a + b + c) / 3.0;
    const double longest = std::max({(a - b).norm(), (b - c).norm(), (c - a).norm()});
    const bool stroke = (is_open(tri[0]) || is_open(tri[1]) || is_open(tri[2])) && longest <= 2 * h_;
    if (!(any_filled && fill.inside(centroid)) && !stroke) continue;
    // Inside an interior cell that has all eight neighbours: the regions hold it.
    bool junction = true;
    if (size_t(tri[0]) < grid_count_ && size_t(tri[1]) < grid_count_ && size_t(tri[2]) < grid_count_) {
      const int ci = int(std::floor((centroid.x() - origin_.x()) / h_)), cj = int(std::floor((centroid.y() - origin_.y()) / h_));
      bool full = cell_inside(ci, cj);
      for (int dj = -1; dj <= 1 && full; ++dj)
        for (int di = -1; di <= 1 && full; ++di) full = cell_inside(ci + di, cj + dj);
      junction = !full;
    }
    tris_.push_back(tri);
    junction_.push_back(junction ? 1 : 0);
    for (int v : tri) used[size_t(v)] = 1;
  }
  mesh_vertex_count_ = size_t(std::count(used.begin(), used.end(), 1));
  // Junction edges (each once) and the vertices whose one-ring is all junction triangles.
  edges_.clear();
  edge_len_.clear();
  std::vector<std::vector<int>> ring_tris(rest_.size());
  for (size_t t = 0; t < tris_.size(); ++t) {
    for (int v : tris_[t]) ring_tris[size_t(v)].push_back(int(t));
    if (!junction_[t]) continue;
    for (int k = 0; k < 3; ++k) {
      int a = tris_[t][size_t(k)], b = tris_[t][size_t((k + 1) % 3)];
      if (a > b) std::swap(a, b);
      edges_.push_back({a, b});
    }
  }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  for (const auto& e : edges_) edge_len_.push_back((rest_[size_t(e[0])] - rest_[size_t(e[1])]).norm());
  mvc_start_.assign(1, 0);
  mvc_node_.clear();
  mvc_w_.clear();
  tri_mode_ = rig.grid_junction_term != "mvc";
  for (size_t v = 0; v < rest_.size() && !tri_mode_; ++v) {
    const auto& rt = ring_tris[v];
    if (rt.size() < 3) continue;
    bool all = true;
    std::map<int, int> seen;  // ring vertex -> how many incident triangles hold it
    for (int t : rt) {
      all = all && junction_[size_t(t)];
      for (int u : tris_[size_t(t)])
        if (size_t(u) != v) ++seen[u];
    }
    bool closed_ring = all && seen.size() == rt.size();
    for (const auto& [u, n] : seen) closed_ring = closed_ring && n == 2;
    if (!closed_ring) continue;
    // Mean-value coordinates at rest (Floater 2003): λ_j ∝ (tan(α_{j-1}/2) + tan(α_j/2)) / |p_j - p|.
    const Vec2 p = rest_[v];
    std::vector<int> ring;
    for (const auto& [u, n] : seen) ring.push_back(u);
    std::sort(ring.begin(), ring.end(), [&](int a, int b) {
      const Vec2 da = rest_[size_t(a)] - p, db = rest_[size_t(b)] - p;
      return std::atan2(da.y(), da.x()) < std::atan2(db.y(), db.x());
    });
    const size_t m = ring.size();
    std::vector<double> tanh(m), lam(m);
    bool ok = true;
    for (size_t k = 0; k < m; ++k) {
      const Vec2 a = rest_[size_t(ring[k])] - p, b = rest_[size_t(ring[(k + 1) % m])] - p;
      const double s = cross(a, b), den = a.norm() * b.norm() + a.dot(b);
      ok = ok && s > 0 && den > 1e-9 * a.norm() * b.norm() && a.norm() > 1e-12 * h_;  // (no straight angle)
      tanh[k] = ok ? s / den : 0;
    }
    if (!ok) continue;
    double sum = 0;
    for (size_t k = 0; k < m; ++k) sum += lam[k] = (tanh[(k + m - 1) % m] + tanh[k]) / (rest_[size_t(ring[k])] - p).norm();
    mvc_node_.push_back(int(v));
    mvc_w_.push_back(1.0);
    for (size_t k = 0; k < m; ++k) {
      mvc_node_.push_back(ring[k]);
      mvc_w_.push_back(-lam[k] / sum);
    }
    mvc_start_.push_back(int(mvc_node_.size()));
  }

  // --- The fill follows the grid: grid nodes clear of every line (by a quarter cell) join the part
  // they lie in as interior points (one-point contours), bound to their node.
  std::vector<char> near_line(size_t(nx_ + 1) * size_t(ny_ + 1), 0);  // per lattice corner
  for (const auto& [a, b] : lines) {  // the corners within a quarter cell of each line
    const double m = 0.25 * h_;
    const int i0 = std::max(0, int(std::ceil((std::min(a.x(), b.x()) - m - origin_.x()) / h_)) - 1);
    const int i1 = std::min(nx_, int(std::floor((std::max(a.x(), b.x()) + m - origin_.x()) / h_)) + 1);
    const int j0 = std::max(0, int(std::ceil((std::min(a.y(), b.y()) - m - origin_.y()) / h_)) - 1);
    const int j1 = std::min(ny_, int(std::floor((std::max(a.y(), b.y()) + m - origin_.y()) / h_)) + 1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        if (point_segment_distance(corner(i, j), a, b) < m) near_line[size_t(j) * size_t(nx_ + 1) + size_t(i)] = 1;
  }
  for (size_t k = 0; k < grid_count_; ++k) {
    const Vec2 p = rest_[k];
    if (near_line[size_t(gxy_[k][1]) * size_t(nx_ + 1) + size_t(gxy_[k][0])]) continue;
    const int si = fill.shape_at(p);
    if (si < 0) continue;
    SubShape& s = ch.shapes[size_t(si)];
    s.contours.push_back({int(s.points.size()), 1, false});
    s.points.push_back(p);
    Embed e;
    e.v[0] = int(k);
    binds_[size_t(si)].push_back(e);
  }
  // A contour point no node holds: barycentric in the triangle at the two nodes beside it that
  // holds it, or that it is least far outside of by its weights (a thin triangle would throw it
  // far when it bends), so the mesh carries it exactly at rest; two contours through the point
  // choose the same triangle. A stroke with no mesh about it is carried by the nodes about it on
  // its curve (not a far one: as the curve bends, a far node threw the point across the picture).
  auto barycentric = [&](const Vec2& p, int ia, int ib, int ic) {  // p's coordinates in the triangle of nodes ia, ib, ic
    const Vec2 &a = rest_[size_t(ia)], &b = rest_[size_t(ib)], &c = rest_[size_t(ic)];
    const double det = cross(b - a, c - a), wb = cross(p - a, c - a) / det, wc = cross(b - a, p - a) / det;
    Embed e;
    e.n = 3;
    e.v[0] = ia, e.v[1] = ib, e.v[2] = ic;
    e.w[0] = 1 - wb - wc, e.w[1] = wb, e.w[2] = wc;
    return e;
  };
  for (const Dropped& d : dropped) {
    const Vec2 p = ch.shapes[size_t(d.shape)].points[size_t(d.point)];
    std::vector<int> cand(ring_tris[size_t(d.a)]);
    cand.insert(cand.end(), ring_tris[size_t(d.b)].begin(), ring_tris[size_t(d.b)].end());
    std::sort(cand.begin(), cand.end());
    double best = INFINITY;
    Embed e;
    for (int t : cand) {
      const auto& tri = tris_[size_t(t)];
      const Vec2 &a = rest_[size_t(tri[0])], &b = rest_[size_t(tri[1])], &c = rest_[size_t(tri[2])];
      if (std::abs(cross(b - a, c - a)) < 1e-6 * h_ * h_) continue;
      const Embed in = barycentric(p, tri[0], tri[1], tri[2]);
      const double out = std::max({std::abs(in.w[0]), std::abs(in.w[1]), std::abs(in.w[2])});  // 1 inside, more the farther out
      if (out < best) best = out, e = in;
    }
    if (!(best <= 2)) {  // no triangle near (a stroke alone, no mesh about it): the curve's nodes about it
      const Curve& cv = curves_[size_t(d.curve)];
      const Vec2 &a = rest_[size_t(d.a)], &b = rest_[size_t(d.b)];
      int third = -1;
      double area = 1e-3 * (b - a).squaredNorm();  // (nearly on the line: on it)
      for (const int k : {d.at - 1, d.at + 2}) {
        if (!cv.closed && (k < 0 || k >= cv.count)) continue;
        const int nk = cnode_[size_t(cv.first + (k % cv.count + cv.count) % cv.count)];
        const double ak = std::abs(cross(b - a, rest_[size_t(nk)] - a));
        if (nk != d.a && nk != d.b && ak > area) area = ak, third = nk;
      }
      if (third >= 0) {
        e = barycentric(p, d.a, d.b, third);
      } else {  // a straight run: the point is on (or within the chords' leeway of) its line
        const double len2 = (b - a).squaredNorm(), t = len2 > 0 ? (p - a).dot(b - a) / len2 : 0.0;
        e.n = 2;
        e.v[0] = d.a, e.v[1] = d.b;
        e.w[0] = 1 - t, e.w[1] = t;
      }
    }
    binds_[size_t(d.shape)][size_t(d.point)] = e;
  }
  for (size_t si = 0; si < ch.shapes.size(); ++si)  // points of no curve (earlier interior points)
    for (size_t k = 0; k < binds_[si].size(); ++k)
      if (binds_[si][k].v[0] < 0) binds_[si][k] = embed(ch.shapes[si].points[k]);

  handles_.clear();
  handle_node_.clear();
  handle_rest_.assign(handle_rest.begin(), handle_rest.end());
  for (const Vec2& p : handle_rest) {
    if (handle_rider_[handles_.size()] >= 0) {  // it turns a rider: no term of the grid's
      Embed none;
      none.w[0] = 0;
      handles_.push_back(none);
      handle_node_.push_back(-1);
      continue;
    }
    handles_.push_back(embed(p));
    const Embed& e = handles_.back();
    handle_node_.push_back(e.v[std::max_element(e.w, e.w + e.n) - e.w]);
    // Nodes are at most a cell apart on the mesh, so a handle farther than that from every
    // node is off the figure: it still works (extrapolated from the nearest triangle), but the
    // rig is probably wrong.
    double near = INFINITY;
    for (const Vec2& node : rest_) near = std::min(near, (node - p).norm());
    const bool in_cell = cell_inside(int(std::floor((p.x() - origin_.x()) / h_)), int(std::floor((p.y() - origin_.y()) / h_)));
    const bool in_ring = e.n == 4 && !in_cell;  // inside a stroked ring (a head): the ring carries it
    if (near > 1.5 * h_ && !in_ring) {
      char msg[200];
      std::snprintf(msg, sizeof msg,
                    "rigid_grid: handle %zu at (%.1f, %.1f) is %.1f units off the figure; it moves the nearest part as "
                    "if fastened to it",
                    handles_.size(), p.x(), p.y(), near);
      ch.warnings.push_back(msg);
    }
  }
  if (grid_count_ == 0 && fill.any()) {
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "rigid_grid: no grid cell (%.2f units) fits inside the figure; only its outline keeps its shape (make "
                  "[grid] cell smaller)",
                  h_);
    ch.warnings.push_back(msg);
  }
  x_ = rest_;
  p_.resize(rest_.size());
  for (size_t k = 0; k < rest_.size(); ++k) p_[k] = rest_[k] - mid_;
  const size_t n = rest_.size();
  bx_.assign(n, 0.0);
  by_.assign(n, 0.0);
  grab_update_.reserve(n);
  grab_active_ = false;
  build_runs();
  build_regions();
  return factorise(error);
}

std::vector<std::array<int, 2>> RigidGrid::grid_edges() const {
  std::vector<std::array<int, 2>> out;
  for (int j = 0; j <= ny_; ++j)
    for (int i = 0; i <= nx_; ++i) {
      const int n = corner_node(i, j);
      if (n < 0) continue;
      if (i < nx_ && corner_node(i + 1, j) >= 0 && (cell_inside(i, j - 1) || cell_inside(i, j)))
        out.push_back({n, corner_node(i + 1, j)});
      if (j < ny_ && corner_node(i, j + 1) >= 0 && (cell_inside(i - 1, j) || cell_inside(i, j)))
        out.push_back({n, corner_node(i, j + 1)});
    }
  return out;
}

std::vector<std::array<int, 3>> RigidGrid::junction_triangles() const {
  std::vector<std::array<int, 3>> out;
  for (size_t t = 0; t < tris_.size(); ++t)
    if (junction_[t]) out.push_back(tris_[t]);
  return out;
}

}  // namespace mar
