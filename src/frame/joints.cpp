#include "frame/joints.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace mar {
namespace {

struct RingBounds {
  Vec2 lo, hi;
};

RingBounds ring_bounds(std::span<const Vec2> r) {
  RingBounds b{Vec2::Constant(std::numeric_limits<double>::infinity()), Vec2::Constant(-std::numeric_limits<double>::infinity())};
  for (const Vec2& p : r) {
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

// The joint sits near one end of an elongated part.
bool at_end_of_limb(std::span<const Vec2> ring, const Vec2& j) {
  const Axis ax = principal_axis(ring);
  if (ax.half_major < 1.4 * ax.half_minor) return false;
  return std::abs((j - ax.centre).dot(ax.major)) > 0.45 * ax.half_major;
}

struct ContourSpan {
  int shape = -1;
  std::span<const Vec2> pts;
  bool closed = false;
};

ContourSpan contour_of(const Character& ch, const FrameVertexOrigin& o) {
  ContourSpan c;
  if (o.shape < 0 || static_cast<size_t>(o.shape) >= ch.shapes.size()) return c;
  const SubShape& sh = ch.shapes[static_cast<size_t>(o.shape)];
  if (o.contour < 0 || static_cast<size_t>(o.contour) >= sh.contours.size()) return c;
  const Contour& ct = sh.contours[static_cast<size_t>(o.contour)];
  c.shape = o.shape;
  c.pts = std::span<const Vec2>(sh.points.data() + ct.begin, static_cast<size_t>(ct.count));
  c.closed = ct.closed && ct.count >= 3;
  return c;
}

// Frame vertices of a sub-frame nearest to p, up to k.
std::vector<int> nearest_vertices(const FeatureFrame& f, const std::vector<int>& sub, const Vec2& p, size_t k) {
  std::vector<int> v = sub;
  std::sort(v.begin(), v.end(), [&](int x, int y) {
    return (f.rest[static_cast<size_t>(x)] - p).squaredNorm() < (f.rest[static_cast<size_t>(y)] - p).squaredNorm();
  });
  v.resize(std::min(k, v.size()));
  return v;
}

}  // namespace

Axis principal_axis(std::span<const Vec2> r) {
  Axis ax;
  ax.centre = Vec2::Zero();
  for (const Vec2& p : r) ax.centre += p;
  ax.centre /= static_cast<double>(std::max<size_t>(1, r.size()));
  double sxx = 0, sxy = 0, syy = 0;
  for (const Vec2& p : r) {
    const Vec2 d = p - ax.centre;
    sxx += d.x() * d.x();
    sxy += d.x() * d.y();
    syy += d.y() * d.y();
  }
  const double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
  ax.major = Vec2(std::cos(angle), std::sin(angle));
  const Vec2 minor(-ax.major.y(), ax.major.x());
  double lo = 0, hi = 0, mlo = 0, mhi = 0;
  for (const Vec2& p : r) {
    const Vec2 d = p - ax.centre;
    lo = std::min(lo, d.dot(ax.major));
    hi = std::max(hi, d.dot(ax.major));
    mlo = std::min(mlo, d.dot(minor));
    mhi = std::max(mhi, d.dot(minor));
  }
  ax.half_major = 0.5 * (hi - lo);
  ax.half_minor = 0.5 * (mhi - mlo);
  // The centre of the extent (not of the points: dense curves would bias it).
  ax.centre += 0.5 * (hi + lo) * ax.major + 0.5 * (mhi + mlo) * minor;
  return ax;
}

bool overlap_centre(std::span<const Vec2> a, std::span<const Vec2> b, Vec2& centre, double* area) {
  const RingBounds ba = ring_bounds(a), bb = ring_bounds(b);
  const Vec2 lo = ba.lo.cwiseMax(bb.lo), hi = ba.hi.cwiseMin(bb.hi);
  if (!(lo.x() < hi.x() && lo.y() < hi.y())) return false;
  constexpr int kSamples = 48;
  Vec2 sum = Vec2::Zero();
  int n = 0;
  for (int iy = 0; iy < kSamples; ++iy) {
    for (int ix = 0; ix < kSamples; ++ix) {
      const Vec2 p(lo.x() + (hi.x() - lo.x()) * (ix + 0.5) / kSamples, lo.y() + (hi.y() - lo.y()) * (iy + 0.5) / kSamples);
      if (winding_number(a, p) != 0 && winding_number(b, p) != 0) {
        sum += p;
        ++n;
      }
    }
  }
  if (n == 0) return false;
  centre = sum / n;
  if (area) *area = n * (hi.x() - lo.x()) * (hi.y() - lo.y()) / (kSamples * kSamples);
  return true;
}

std::vector<double> part_stiffness(const Character& ch, const FrameOptions& o, std::vector<std::string>* warnings) {
  std::vector<double> k(ch.shapes.size(), 1.0);
  if (o.auto_stiffness) {
    std::vector<double> area(ch.shapes.size(), 0.0), closed_areas;
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      const SubShape& sh = ch.shapes[s];
      for (const Contour& c : sh.contours) {
        if (!c.closed || c.count < 3) continue;
        area[s] += std::abs(signed_area(std::span<const Vec2>(sh.points.data() + c.begin, static_cast<size_t>(c.count))));
      }
      if (area[s] > 0) closed_areas.push_back(area[s]);
    }
    if (!closed_areas.empty()) {
      std::nth_element(closed_areas.begin(), closed_areas.begin() + static_cast<long>(closed_areas.size() / 2), closed_areas.end());
      const double median = closed_areas[closed_areas.size() / 2];
      for (size_t s = 0; s < ch.shapes.size(); ++s) {
        if (area[s] > 0 && median > 0) k[s] = std::clamp(std::sqrt(area[s] / median), 1.0, 4.0);
      }
    }
  }
  for (const PartStiffness& p : o.stiffness) {
    bool found = false;
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      if (ch.shapes[s].id == p.id) {
        k[s] = p.stiffness;
        found = true;
      }
    }
    if (!found && warnings) warnings->push_back(p.where + ": no sub-shape '" + p.id + "'; stiffness not applied");
  }
  return k;
}

void add_joints_and_stiffness(const Character& ch, const FrameOptions& o, FeatureFrame& f) {
  f.shape_stiffness = part_stiffness(ch, o, &f.warnings);
  // Crossing vertices of two outlines are within a quarter edge of each other (see
  // refine_for_frame): such a sewing line joins overlapping parts.
  const double tiny = std::max(0.5 * f.mean_edge_length, 1e-9 * f.diagonal);
  // Sub-frame of each frame vertex.
  std::vector<int> sub_of(f.rest.size(), -1);
  for (size_t k = 0; k < f.subframes.size(); ++k) {
    for (int v : f.subframes[k]) sub_of[static_cast<size_t>(v)] = static_cast<int>(k);
  }
  struct Pending {
    int sub_a, sub_b;
    Vec2 at;
    double stiffness;
    bool automatic;
  };
  std::vector<Pending> pending;
  std::vector<char> drop(f.lines.size(), 0);
  std::vector<FrameLine> welds;
  const size_t sewing_end = f.lines.size();
  for (size_t li = static_cast<size_t>(f.feature_lines); li < sewing_end; ++li) {
    const FrameLine& l = f.lines[li];
    if (l.kind != FrameLine::Sewing) continue;
    if ((f.rest[static_cast<size_t>(l.a)] - f.rest[static_cast<size_t>(l.b)]).norm() > tiny) continue;
    const ContourSpan A = contour_of(ch, f.origin[static_cast<size_t>(l.a)]), B = contour_of(ch, f.origin[static_cast<size_t>(l.b)]);
    const int sa = sub_of[static_cast<size_t>(l.a)], sb = sub_of[static_cast<size_t>(l.b)];
    Vec2 j;
    bool hinge = false;
    double overlap = 0;
    if (o.auto_joints && A.closed && B.closed && A.shape != B.shape && overlap_centre(A.pts, B.pts, j, &overlap)) {
      // Share of the smaller part that the other covers: small for a limb over a body or a
      // wing on a body, large for hair on a head or a sleeve on an arm (welds).
      const double covered = overlap / std::max(1e-300, std::min(std::abs(signed_area(A.pts)), std::abs(signed_area(B.pts))));
      hinge = covered < 0.4 || (covered < 0.6 && (at_end_of_limb(A.pts, j) || at_end_of_limb(B.pts, j)));
    }
    if (hinge) {
      drop[li] = 1;
      pending.push_back({sa, sb, j, o.hinge_stiffness, true});
      continue;
    }
    // Not a hinge: a crossing is a weld. A zero-length line alone would be a pin (hair
    // spinning on a head), so a second line from A's vertex farthest from the crossing to
    // B's nearest vertex keeps the parts' relative orientation.
    if (sa < 0 || sb < 0) continue;
    const Vec2 x = f.rest[static_cast<size_t>(l.a)];
    int far = -1;
    for (int v : f.subframes[static_cast<size_t>(sa)]) {
      if (far < 0 || (f.rest[static_cast<size_t>(v)] - x).squaredNorm() > (f.rest[static_cast<size_t>(far)] - x).squaredNorm()) far = v;
    }
    if (far < 0 || (f.rest[static_cast<size_t>(far)] - x).norm() <= tiny) continue;
    for (int n : nearest_vertices(f, f.subframes[static_cast<size_t>(sb)], f.rest[static_cast<size_t>(far)], 1)) {
      welds.push_back({FrameLine::Sewing, far, n, 1});
    }
  }
  // The rig's joints: between the named parts, or the two topmost closed parts at the point.
  for (const JointSpec& js : o.joints) {
    auto sub_for = [&](const std::string& id, const Vec2& at, int skip_shape) {
      int best = -1;
      for (size_t k = 0; k < f.subframes.size(); ++k) {
        if (f.subframes[k].empty()) continue;
        const ContourSpan c = contour_of(ch, f.origin[static_cast<size_t>(f.subframes[k][0])]);
        if (c.shape == skip_shape) continue;
        // Named parts may be open strokes (a wick hinged to a candle); unnamed ones are the
        // closed parts containing the point.
        if (!id.empty() ? ch.shapes[static_cast<size_t>(c.shape)].id == id : c.closed && winding_number(c.pts, at) != 0) {
          best = static_cast<int>(k);  // the last (topmost) wins
        }
      }
      return best;
    };
    const int sa = sub_for(js.part_a, js.at, -1);
    const int shape_a = sa >= 0 ? f.origin[static_cast<size_t>(f.subframes[static_cast<size_t>(sa)][0])].shape : -1;
    const int sb = sub_for(js.part_b, js.at, shape_a);
    if (sa < 0 || sb < 0) {
      f.warnings.push_back(js.where + ": joint needs two closed parts" +
                           (js.part_a.empty() ? std::string(" containing the point") : std::string(" named '") + js.part_a + "' and '" + js.part_b + "'") +
                           "; not added");
      continue;
    }
    // It replaces any automatic hinge between the same two parts.
    pending.erase(std::remove_if(pending.begin(), pending.end(),
                                 [&](const Pending& p) { return (p.sub_a == sa && p.sub_b == sb) || (p.sub_a == sb && p.sub_b == sa); }),
                  pending.end());
    auto joins = [&](const FrameLine& l) {
      const int x = sub_of[static_cast<size_t>(l.a)], y = sub_of[static_cast<size_t>(l.b)];
      return (x == sa && y == sb) || (x == sb && y == sa);
    };
    auto between = [&](size_t li) { return joins(f.lines[li]); };
    // Automatic welds between the two parts give way to the rig's joint.
    welds.erase(std::remove_if(welds.begin(), welds.end(), joins), welds.end());
    if (js.weld) {
      // Keep (or make) the sewing between them, plus a line that holds their orientation.
      int kept_line = -1;
      for (size_t li = static_cast<size_t>(f.feature_lines); li < sewing_end; ++li) {
        if (!between(li)) continue;
        drop[li] = 0;
        kept_line = static_cast<int>(li);
      }
      const std::vector<int>& A = f.subframes[static_cast<size_t>(sa)];
      const std::vector<int>& B = f.subframes[static_cast<size_t>(sb)];
      int x = kept_line >= 0 ? f.lines[static_cast<size_t>(kept_line)].a : A[0];
      if (kept_line < 0) {
        // No line between them yet: sew the closest pair.
        double best = std::numeric_limits<double>::infinity();
        for (int va : A) {
          const int vb = nearest_vertices(f, B, f.rest[static_cast<size_t>(va)], 1)[0];
          if (const double d = (f.rest[static_cast<size_t>(va)] - f.rest[static_cast<size_t>(vb)]).squaredNorm(); d < best) {
            best = d;
            x = va;
          }
        }
      }
      if (kept_line < 0) {
        const int y = nearest_vertices(f, B, f.rest[static_cast<size_t>(x)], 1)[0];
        welds.push_back({FrameLine::Sewing, x, y, 1});
      }
      if (sub_of[static_cast<size_t>(x)] != sa) x = f.lines[static_cast<size_t>(kept_line)].b;
      int far = A[0];
      for (int v : A) {
        if ((f.rest[static_cast<size_t>(v)] - f.rest[static_cast<size_t>(x)]).squaredNorm() >
            (f.rest[static_cast<size_t>(far)] - f.rest[static_cast<size_t>(x)]).squaredNorm()) far = v;
      }
      welds.push_back({FrameLine::Sewing, far, nearest_vertices(f, B, f.rest[static_cast<size_t>(far)], 1)[0], 1});
      continue;
    }
    Vec2 at = js.at;
    if (!js.has_at) {
      const ContourSpan A = contour_of(ch, f.origin[static_cast<size_t>(f.subframes[static_cast<size_t>(sa)][0])]);
      const ContourSpan B = contour_of(ch, f.origin[static_cast<size_t>(f.subframes[static_cast<size_t>(sb)][0])]);
      if (!A.closed || !B.closed || !overlap_centre(A.pts, B.pts, at)) {
        f.warnings.push_back(js.where + ": parts '" + js.part_a + "' and '" + js.part_b + "' do not overlap; give the joint at = [x, y]");
        continue;
      }
    }
    for (size_t li = static_cast<size_t>(f.feature_lines); li < sewing_end; ++li) {
      if (between(li)) drop[li] = 1;
    }
    pending.push_back({sa, sb, at, js.stiffness >= 0 ? js.stiffness : o.hinge_stiffness, false});
  }
  std::vector<FrameLine> kept;
  for (size_t li = 0; li < f.lines.size(); ++li) {
    if (!drop[li]) kept.push_back(f.lines[li]);
  }
  f.lines = std::move(kept);
  f.lines.insert(f.lines.end(), welds.begin(), welds.end());
  for (const Pending& p : pending) {
    FrameJoint jt;
    jt.at = p.at;
    jt.stiffness = p.stiffness;
    jt.automatic = p.automatic;
    int ends[2];
    for (int side = 0; side < 2; ++side) {
      const int sub = side == 0 ? p.sub_a : p.sub_b;
      const std::vector<int>& vs = f.subframes[static_cast<size_t>(sub)];
      FrameVertexOrigin origin = f.origin[static_cast<size_t>(vs[0])];
      const int v = static_cast<int>(f.rest.size());
      f.rest.push_back(p.at);
      f.origin.push_back(origin);
      for (int n : nearest_vertices(f, vs, p.at, 3)) f.lines.push_back({FrameLine::Spoke, v, n, 1});
      ends[side] = v;
      (side == 0 ? jt.shape_a : jt.shape_b) = origin.shape;
    }
    jt.va = ends[0];
    jt.vb = ends[1];
    f.lines.push_back({FrameLine::Joint, ends[0], ends[1], o.joint_weight});
    if (p.stiffness > 0) {
      for (int n : nearest_vertices(f, f.subframes[static_cast<size_t>(p.sub_b)], p.at, 1)) {
        f.lines.push_back({FrameLine::Spring, ends[0], n, p.stiffness});
      }
    }
    f.joints.push_back(jt);
  }
  // Weights: a part's lines by its stiffness, a line between parts by the softer one.
  auto k_of = [&](int v) { return f.shape_stiffness[static_cast<size_t>(f.origin[static_cast<size_t>(v)].shape)]; };
  f.sewing_lines = 0;
  f.user_sewing_lines = 0;
  for (FrameLine& l : f.lines) {
    if (l.kind == FrameLine::Joint || l.kind == FrameLine::Spring) continue;
    l.weight *= std::min(k_of(l.a), k_of(l.b));
    if (l.kind == FrameLine::Sewing || l.kind == FrameLine::UserSewing) ++f.sewing_lines;
    if (l.kind == FrameLine::UserSewing) ++f.user_sewing_lines;
  }
}

}  // namespace mar
