#include "frame/feature_frame.h"

#include "frame/feature_points.h"
#include "frame/joints.h"
#include "geom/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>

namespace mar {

FrameOptions default_frame_options() { return FrameOptions{}; }

FrameOptions frame_options_from_rig(const Rig& rig) {
  FrameOptions o = default_frame_options();
  o.mode = rig.uniform_sampling ? SamplingMode::Uniform : SamplingMode::Features;
  o.interval = rig.interval;
  o.max_spacing = rig.max_spacing;
  for (const RigSewing& e : rig.sewing) {
    SewingEdit s;
    s.kind = e.action == RigSewing::Add ? SewingEdit::Add : e.action == RigSewing::Delete ? SewingEdit::Delete : SewingEdit::Move;
    s.from = e.from;
    s.to = e.to;
    s.new_from = e.new_from;
    s.new_to = e.new_to;
    s.where = rig.path + ":" + std::to_string(e.line);
    o.sewing.push_back(s);
  }
  o.auto_joints = rig.auto_joints;
  o.auto_stiffness = rig.auto_stiffness;
  for (const RigJoint& j : rig.joints) {
    o.joints.push_back({j.has_at, j.at, j.part_a, j.part_b, j.stiffness, j.weld, rig.path + ":" + std::to_string(j.line)});
  }
  for (const RigPart& p : rig.parts) o.stiffness.push_back({p.id, p.stiffness, rig.path + ":" + std::to_string(p.line)});
  return o;
}

namespace {

constexpr int kDenseContour = 4096;

// Indices of a subset of `pts` whose consecutive points are at least `gap` apart (the first
// point always kept); at least three points where the contour has them.
std::vector<int> spaced_subset(std::span<const Vec2> pts, double gap) {
  std::vector<int> keep{0};
  for (size_t i = 1; i < pts.size(); ++i)
    if ((pts[i] - pts[static_cast<size_t>(keep.back())]).norm() >= gap) keep.push_back(static_cast<int>(i));
  if (keep.size() < 3) {
    keep.clear();
    for (size_t k = 0; k < 3 && k < pts.size(); ++k) keep.push_back(static_cast<int>(k * (pts.size() - 1) / 2));
  }
  return keep;
}

struct ContourRef {
  int shape, contour;
  std::span<const Vec2> pts;
  bool closed;
  int begin;  // offset of the contour in the shape's points
};

bool segments_intersect(const Vec2& p, const Vec2& p2, const Vec2& q, const Vec2& q2, Vec2& at) {
  const Vec2 r = p2 - p, s = q2 - q;
  const double den = r.x() * s.y() - r.y() * s.x();
  if (std::abs(den) < 1e-15) return false;
  const Vec2 qp = q - p;
  const double t = (qp.x() * s.y() - qp.y() * s.x()) / den;
  const double u = (qp.x() * r.y() - qp.y() * r.x()) / den;
  if (t < 0 || t > 1 || u < 0 || u > 1) return false;
  at = p + t * r;
  return true;
}

int nearest_index(std::span<const Vec2> pts, const Vec2& p) {
  int best = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < pts.size(); ++i) {
    const double d = (pts[i] - p).squaredNorm();
    if (d < bd) {
      bd = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

Bounds bounds_of(std::span<const Vec2> pts) {
  Bounds b;
  for (const Vec2& p : pts) b.add(p);
  return b;
}

bool overlap(const Bounds& a, const Bounds& b) {
  return !(a.hi.x() < b.lo.x() || b.hi.x() < a.lo.x() || a.hi.y() < b.lo.y() || b.hi.y() < a.lo.y());
}

struct Insertion {
  int segment;  // index of the segment's first point within the contour
  double t;
  Vec2 p;
};

double mean_edge(const Character& ch) {
  double sum = 0;
  size_t count = 0;
  for (const SubShape& sh : ch.shapes) {
    for (const Contour& c : sh.contours) {
      for (int k = 0; k + 1 < c.count || (c.closed && k < c.count && c.count > 2); ++k) {
        const int k1 = (k + 1) % c.count;
        sum += (sh.points[static_cast<size_t>(c.begin + k1)] - sh.points[static_cast<size_t>(c.begin + k)]).norm();
        ++count;
      }
    }
  }
  return count ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace

size_t refine_for_frame(Character& ch, const FrameOptions& o) {
  const double merge = 0.25 * mean_edge(ch);
  // requests[shape][contour] -> insertions
  std::vector<std::vector<std::vector<Insertion>>> req(ch.shapes.size());
  for (size_t s = 0; s < ch.shapes.size(); ++s) req[s].resize(ch.shapes[s].contours.size());
  struct Seg {
    int shape, contour, k;
    Vec2 a, b;
  };
  std::vector<Seg> segs;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    const SubShape& sh = ch.shapes[s];
    for (size_t c = 0; c < sh.contours.size(); ++c) {
      const Contour& ct = sh.contours[c];
      const int ns = ct.closed && ct.count > 2 ? ct.count : ct.count - 1;
      for (int k = 0; k < ns; ++k) {
        segs.push_back({static_cast<int>(s), static_cast<int>(c), k, sh.points[static_cast<size_t>(ct.begin + k)],
                        sh.points[static_cast<size_t>(ct.begin + (k + 1) % ct.count)]});
      }
    }
  }
  auto request = [&](const Seg& g, const Vec2& p) {
    if ((p - g.a).norm() < merge || (p - g.b).norm() < merge) return;
    const double len2 = (g.b - g.a).squaredNorm();
    const double t = len2 > 0 ? (p - g.a).dot(g.b - g.a) / len2 : 0.0;
    req[static_cast<size_t>(g.shape)][static_cast<size_t>(g.contour)].push_back({g.k, t, p});
  };
  if (o.mode == SamplingMode::Features) {
    // Sort segments by min x for a sweep; test pairs whose x-extents overlap.
    std::vector<size_t> order(segs.size());
    std::iota(order.begin(), order.end(), 0);
    auto lo = [&](size_t i) { return std::min(segs[i].a.x(), segs[i].b.x()); };
    auto hi = [&](size_t i) { return std::max(segs[i].a.x(), segs[i].b.x()); };
    std::sort(order.begin(), order.end(), [&](size_t x, size_t y) { return lo(x) < lo(y); });
    for (size_t u = 0; u < order.size(); ++u) {
      const Seg& A = segs[order[u]];
      for (size_t w = u + 1; w < order.size() && lo(order[w]) <= hi(order[u]); ++w) {
        const Seg& B = segs[order[w]];
        if (A.shape == B.shape) continue;
        Vec2 at;
        if (segments_intersect(A.a, A.b, B.a, B.b, at)) {
          request(A, at);
          request(B, at);
        }
      }
    }
  }
  for (const SewingEdit& e : o.sewing) {
    if (e.kind == SewingEdit::Delete) continue;
    for (const Vec2& p : {e.kind == SewingEdit::Move ? e.new_from : e.from, e.kind == SewingEdit::Move ? e.new_to : e.to}) {
      const Seg* best = nullptr;
      double bd = std::numeric_limits<double>::infinity();
      for (const Seg& g : segs) {
        const double d = point_segment_distance(p, g.a, g.b);
        if (d < bd) {
          bd = d;
          best = &g;
        }
      }
      if (!best) continue;
      const double len2 = (best->b - best->a).squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - best->a).dot(best->b - best->a) / len2, 0.0, 1.0) : 0.0;
      request(*best, best->a + t * (best->b - best->a));
    }
  }
  size_t inserted = 0;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    SubShape& sh = ch.shapes[s];
    bool any = false;
    for (const auto& r : req[s]) any = any || !r.empty();
    if (!any) continue;
    Points pts;
    std::vector<Contour> contours;
    for (size_t c = 0; c < sh.contours.size(); ++c) {
      const Contour& ct = sh.contours[c];
      std::vector<Insertion> ins = req[s][c];
      std::sort(ins.begin(), ins.end(), [](const Insertion& x, const Insertion& y) {
        return x.segment != y.segment ? x.segment < y.segment : x.t < y.t;
      });
      const int begin = static_cast<int>(pts.size());
      size_t next = 0;
      for (int k = 0; k < ct.count; ++k) {
        pts.push_back(sh.points[static_cast<size_t>(ct.begin + k)]);
        for (; next < ins.size() && ins[next].segment == k; ++next) {
          if ((ins[next].p - pts.back()).norm() >= 1e-9) {
            pts.push_back(ins[next].p);
            ++inserted;
          }
        }
      }
      contours.push_back({begin, static_cast<int>(pts.size()) - begin, ct.closed});
    }
    sh.points = std::move(pts);
    sh.contours = std::move(contours);
  }
  return inserted;
}

FeatureFrame build_feature_frame(const Character& ch, const FrameOptions& o) {
  FeatureFrame f;
  std::vector<ContourRef> contours;
  double edge_sum = 0;
  size_t edge_count = 0;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    const SubShape& sh = ch.shapes[s];
    f.shape_vertices += sh.points.size();
    for (size_t c = 0; c < sh.contours.size(); ++c) {
      const Contour& ct = sh.contours[c];
      if (ct.count < 1 || ct.begin < 0 || static_cast<size_t>(ct.begin + ct.count) > sh.points.size()) continue;
      std::span<const Vec2> pts(sh.points.data() + ct.begin, static_cast<size_t>(ct.count));
      contours.push_back({static_cast<int>(s), static_cast<int>(c), pts, ct.closed && ct.count >= 3, ct.begin});
      const std::vector<double> len = cumulative_length(pts, ct.closed);
      edge_sum += len.back();
      edge_count += static_cast<size_t>(ct.closed ? ct.count : ct.count - 1);
    }
  }
  const Bounds bb = ch.bounds();
  f.diagonal = bb.empty() ? 1.0 : std::max(1e-9, (bb.hi - bb.lo).norm());
  f.mean_edge_length = edge_count ? edge_sum / static_cast<double>(edge_count) : 0.0;
  const double diag = f.diagonal;

  // 1. Feature points per contour.
  std::vector<std::vector<int>> feat(contours.size());
  for (size_t k = 0; k < contours.size(); ++k) {
    const ContourRef& c = contours[k];
    const int n = static_cast<int>(c.pts.size());
    std::vector<int>& F = feat[k];
    if (o.mode == SamplingMode::Uniform) {
      const double interval = o.interval > 0 ? o.interval : diag / 24;
      F = arc_length_samples(c.pts, c.closed, interval);
    } else {
      // A contour of thousands of points (a drawing flattened finely, a traced picture) is
      // searched on its points a quarter of d_min apart: both searches look at the points in
      // a window, so their work would grow as n^2 with the density. Shipped drawings' contours
      // stay under the threshold and are searched point by point.
      std::vector<int> keep;
      Points thinned;
      std::span<const Vec2> search = c.pts;
      if (n > kDenseContour) {
        keep = spaced_subset(c.pts, 0.25 * o.d_min * diag);
        for (int i : keep) thinned.push_back(c.pts[static_cast<size_t>(i)]);
        search = thinned;
      }
      F = ipan99_corners(search, c.closed, o.d_min * diag, o.d_max * diag, o.alpha_max_deg * M_PI / 180);
      const auto infl = inflection_points(search, c.closed, o.inflection_window * diag,
                                          o.inflection_hysteresis_deg * M_PI / 180);
      F.insert(F.end(), infl.begin(), infl.end());
      if (!keep.empty())
        for (int& i : F) i = keep[static_cast<size_t>(i)];
    }
    if (!c.closed) {
      F.push_back(0);
      F.push_back(n - 1);
    }
  }
  // Intersections between contours of different sub-shapes: both get the point.
  if (o.mode == SamplingMode::Features) {
    std::vector<Bounds> cb(contours.size());
    for (size_t k = 0; k < contours.size(); ++k) cb[k] = bounds_of(contours[k].pts);
    for (size_t a = 0; a < contours.size(); ++a) {
      for (size_t b = a + 1; b < contours.size(); ++b) {
        if (contours[a].shape == contours[b].shape || !overlap(cb[a], cb[b])) continue;
        const ContourRef &A = contours[a], &B = contours[b];
        const size_t na = A.pts.size(), nb = B.pts.size();
        const size_t sa = A.closed ? na : na - 1, sb = B.closed ? nb : nb - 1;
        for (size_t i = 0; i < sa; ++i) {
          const Vec2 &p = A.pts[i], &p2 = A.pts[(i + 1) % na];
          Bounds segb;
          segb.add(p);
          segb.add(p2);
          if (!overlap(segb, cb[b])) continue;
          for (size_t j = 0; j < sb; ++j) {
            Vec2 at;
            if (!segments_intersect(p, p2, B.pts[j], B.pts[(j + 1) % nb], at)) continue;
            feat[a].push_back((at - p).squaredNorm() <= (at - p2).squaredNorm() ? static_cast<int>(i)
                                                                                 : static_cast<int>((i + 1) % na));
            feat[b].push_back((at - B.pts[j]).squaredNorm() <= (at - B.pts[(j + 1) % nb]).squaredNorm()
                                  ? static_cast<int>(j)
                                  : static_cast<int>((j + 1) % nb));
          }
        }
      }
    }
  }
  auto normalise = [](std::vector<int>& F) {
    std::sort(F.begin(), F.end());
    F.erase(std::unique(F.begin(), F.end()), F.end());
  };
  for (auto& F : feat) normalise(F);

  // 2. User sewing end points: merge with a feature point closer than a quarter of the
  // mean shape edge length, else insert the nearest shape vertex as a new feature point.
  const double merge_radius = 0.25 * f.mean_edge_length;
  struct EndRef {
    size_t contour;
    int point;
  };
  auto resolve_end = [&](const Vec2& p) -> std::optional<EndRef> {
    if (contours.empty()) return std::nullopt;
    size_t best_c = 0;
    int best_i = 0;
    double bd = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < contours.size(); ++k) {
      const int i = nearest_index(contours[k].pts, p);
      const double d = (contours[k].pts[static_cast<size_t>(i)] - p).squaredNorm();
      if (d < bd) {
        bd = d;
        best_c = k;
        best_i = i;
      }
    }
    const Vec2 q = contours[best_c].pts[static_cast<size_t>(best_i)];
    for (int fi : feat[best_c]) {
      if ((contours[best_c].pts[static_cast<size_t>(fi)] - q).norm() < merge_radius) return EndRef{best_c, fi};
    }
    feat[best_c].push_back(best_i);
    normalise(feat[best_c]);
    return EndRef{best_c, best_i};
  };
  struct PendingAdd {
    EndRef a, b;
  };
  std::vector<PendingAdd> adds;
  for (const SewingEdit& e : o.sewing) {
    if (e.kind == SewingEdit::Delete) continue;
    const Vec2 from = e.kind == SewingEdit::Move ? e.new_from : e.from;
    const Vec2 to = e.kind == SewingEdit::Move ? e.new_to : e.to;
    auto ra = resolve_end(from), rb = resolve_end(to);
    if (ra && rb) adds.push_back({*ra, *rb});
  }

  // Closed contours need at least three feature points; optional maximum spacing.
  for (size_t k = 0; k < contours.size(); ++k) {
    const ContourRef& c = contours[k];
    std::vector<int>& F = feat[k];
    const int n = static_cast<int>(c.pts.size());
    if (c.closed) {
      const std::vector<double> s = cumulative_length(c.pts, true);
      const double total = s.back();
      const int origin = F.empty() ? 0 : F.front();
      for (int t = 0; static_cast<int>(F.size()) < 3 && t < 3; ++t) {
        // points at thirds of the perimeter from the first feature
        const double target = std::fmod(s[static_cast<size_t>(origin)] + total * (t + 1) / 3.0, total);
        int best = 0;
        for (int i = 0; i < n; ++i) {
          if (std::abs(s[static_cast<size_t>(i)] - target) < std::abs(s[static_cast<size_t>(best)] - target)) best = i;
        }
        F.push_back(best);
        normalise(F);
      }
    } else if (F.empty()) {
      F.push_back(0);
    }
    if (o.max_spacing > 0 && F.size() >= 1) {
      const double gap = o.max_spacing * diag;
      const std::vector<double> s = cumulative_length(c.pts, c.closed);
      std::vector<int> extra;
      const size_t m = F.size();
      for (size_t j = 0; j < (c.closed ? m : m - 1); ++j) {
        const int i0 = F[j];
        const int i1 = (j + 1 < m) ? F[j + 1] : F[0] + n;
        auto arc = [&](int i) { return i < n ? s[static_cast<size_t>(i)] : s.back() + s[static_cast<size_t>(i - n)]; };
        const double len = arc(i1) - arc(i0);
        const int pieces = static_cast<int>(std::ceil(len / gap));
        for (int p = 1; p < pieces; ++p) {
          const double target = arc(i0) + len * p / pieces;
          int best = i0;
          for (int i = i0; i <= i1; ++i) {
            if (std::abs(arc(i) - target) < std::abs(arc(best) - target)) best = i;
          }
          extra.push_back(best % n);
        }
      }
      F.insert(F.end(), extra.begin(), extra.end());
      normalise(F);
    }
  }

  // 3. Frame vertices and feature lines (sub-frames).
  std::vector<std::map<int, int>> vertex_of(contours.size());
  for (size_t k = 0; k < contours.size(); ++k) {
    const ContourRef& c = contours[k];
    std::vector<int> sub;
    for (int i : feat[k]) {
      const int v = static_cast<int>(f.rest.size());
      f.rest.push_back(c.pts[static_cast<size_t>(i)]);
      f.origin.push_back({c.shape, c.contour, c.begin + i});
      vertex_of[k][i] = v;
      sub.push_back(v);
    }
    const size_t m = sub.size();
    for (size_t j = 0; j + 1 < m; ++j) f.lines.push_back({FrameLine::Feature, sub[j], sub[j + 1]});
    if (c.closed && m >= 3) f.lines.push_back({FrameLine::Feature, sub[m - 1], sub[0]});
    f.subframes.push_back(std::move(sub));
  }
  f.feature_lines = static_cast<int>(f.lines.size());

  // 4. Sewing lines: Euclidean minimum spanning tree over sub-frames (Prim), edge length
  // = the smallest distance between their vertices.
  std::vector<FrameLine> sewing;
  const size_t m = f.subframes.size();
  if (m > 1) {
    std::vector<char> in_tree(m, 0);
    std::vector<double> best(m, std::numeric_limits<double>::infinity());
    std::vector<std::pair<int, int>> link(m, {-1, -1});
    auto closest = [&](size_t a, size_t b, int& va, int& vb) {
      double bd = std::numeric_limits<double>::infinity();
      for (int x : f.subframes[a]) {
        for (int y : f.subframes[b]) {
          const double d = (f.rest[static_cast<size_t>(x)] - f.rest[static_cast<size_t>(y)]).squaredNorm();
          if (d < bd) {
            bd = d;
            va = x;
            vb = y;
          }
        }
      }
      return bd;
    };
    // A sub-frame lying wholly inside a closed part of another shape (an eye in a face, a
    // patch on a body) is sewn to that container: their distance counts as zero.
    std::vector<int> container(m, -1);
    for (size_t a = 0; a < m; ++a) {
      if (f.subframes[a].empty()) continue;
      const FrameVertexOrigin& oa = f.origin[static_cast<size_t>(f.subframes[a][0])];
      for (size_t b = 0; b < m; ++b) {
        if (b == a || f.subframes[b].empty() || !contours[b].closed) continue;
        if (contours[b].shape == oa.shape) continue;
        bool all_inside = true;
        for (const Vec2& p : contours[a].pts) all_inside = all_inside && winding_number(contours[b].pts, p) != 0;
        // the smallest container wins
        if (all_inside && (container[a] < 0 || std::abs(signed_area(contours[b].pts)) <
                                                   std::abs(signed_area(contours[static_cast<size_t>(container[a])].pts)))) {
          container[a] = static_cast<int>(b);
        }
      }
    }
    auto distance = [&](size_t a, size_t b, int& va, int& vb) {
      const double d = closest(a, b, va, vb);
      return (container[a] == static_cast<int>(b) || container[b] == static_cast<int>(a)) ? 0.0 : d;
    };
    size_t cur = 0;
    in_tree[0] = 1;
    for (size_t step = 1; step < m; ++step) {
      for (size_t j = 0; j < m; ++j) {
        if (in_tree[j] || f.subframes[j].empty() || f.subframes[cur].empty()) continue;
        int va = -1, vb = -1;
        const double d = distance(cur, j, va, vb);
        if (d < best[j]) {
          best[j] = d;
          link[j] = {va, vb};
        }
      }
      size_t next = m;
      for (size_t j = 0; j < m; ++j) {
        if (!in_tree[j] && (next == m || best[j] < best[next])) next = j;
      }
      if (next == m) break;
      in_tree[next] = 1;
      if (link[next].first >= 0) sewing.push_back({FrameLine::Sewing, link[next].first, link[next].second});
      cur = next;
    }
  }
  // User deletes and moves remove the automatic or earlier line nearest to (from, to).
  for (const SewingEdit& e : o.sewing) {
    if (e.kind == SewingEdit::Add) continue;
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < sewing.size(); ++i) {
      const Vec2 a = f.rest[static_cast<size_t>(sewing[i].a)], b = f.rest[static_cast<size_t>(sewing[i].b)];
      const double d = std::min((a - e.from).norm() + (b - e.to).norm(), (a - e.to).norm() + (b - e.from).norm());
      if (d < bd) {
        bd = d;
        best = static_cast<int>(i);
      }
    }
    if (best >= 0 && bd <= 0.1 * diag) {
      sewing.erase(sewing.begin() + best);
    } else {
      f.warnings.push_back(e.where + ": no sewing line near the given end points; nothing deleted");
    }
  }
  for (const PendingAdd& p : adds) {
    const int va = vertex_of[p.a.contour].at(p.a.point), vb = vertex_of[p.b.contour].at(p.b.point);
    if (va != vb) sewing.push_back({FrameLine::UserSewing, va, vb});
  }
  for (const FrameLine& l : sewing) {
    f.lines.push_back(l);
    ++f.sewing_lines;
    if (l.kind == FrameLine::UserSewing) ++f.user_sewing_lines;
  }

  // 5. Parametric coordinates of every shape vertex on its salient feature.
  f.params.resize(ch.shapes.size());
  for (size_t s = 0; s < ch.shapes.size(); ++s) f.params[s].resize(ch.shapes[s].points.size());
  for (size_t k = 0; k < contours.size(); ++k) {
    const ContourRef& c = contours[k];
    const std::vector<int>& F = feat[k];
    const int n = static_cast<int>(c.pts.size());
    const size_t mf = F.size();
    std::vector<ShapeParam>& P = f.params[static_cast<size_t>(c.shape)];
    auto set = [&](int i, int fa, int fb) {
      const int va = vertex_of[k].at(fa), vb = vertex_of[k].at(fb);
      const Vec2 a = f.rest[static_cast<size_t>(va)], b = f.rest[static_cast<size_t>(vb)];
      const Vec2 p = c.pts[static_cast<size_t>(i)];
      ShapeParam sp;
      sp.a = va;
      sp.b = vb;
      const Vec2 d = b - a;
      const double len2 = d.squaredNorm();
      if (va == vb || len2 < 1e-18 * diag * diag) {
        sp.offset_only = true;
        sp.ox = p.x() - a.x();
        sp.oy = p.y() - a.y();
      } else {
        // z = (p - a) / (b - a) as complex numbers
        const Vec2 r = p - a;
        sp.zr = (r.x() * d.x() + r.y() * d.y()) / len2;
        sp.zi = (r.y() * d.x() - r.x() * d.y()) / len2;
      }
      P[static_cast<size_t>(c.begin + i)] = sp;
    };
    if (mf == 1) {
      for (int i = 0; i < n; ++i) set(i, F[0], F[0]);
      continue;
    }
    for (size_t j = 0; j < mf; ++j) {
      const bool last = j + 1 == mf;
      if (last && !c.closed) {
        set(F[j], F[j - 1], F[j]);  // the final end point lies on the last line
        break;
      }
      const int fa = F[j], fb = last ? F[0] : F[j + 1];
      const int stop = last ? fb + n : fb;
      for (int i = fa; i < stop; ++i) set(i % n, fa, fb);
    }
    if (c.closed) {
      // vertices before the first feature point belong to the wrap-around line (already set)
    } else {
      for (int i = 0; i < F.front(); ++i) set(i, F[0], F[1]);
    }
  }
  add_joints_and_stiffness(ch, o, f);
  return f;
}

void reconstruct_shapes(const FeatureFrame& frame, std::span<const Vec2> v, std::vector<Points>& out) {
  for (size_t s = 0; s < frame.params.size() && s < out.size(); ++s) {
    const std::vector<ShapeParam>& P = frame.params[s];
    Points& O = out[s];
    for (size_t i = 0; i < P.size() && i < O.size(); ++i) O[i] = eval_param(P[i], v);
  }
}

ShapeParam bind_point(const FeatureFrame& frame, const Character& ch, const Vec2& p) {
  // A point inside a closed part belongs to the topmost such part; else to the nearest
  // contour. The nearest point of that part's contours gives the feature line.
  int inside = -1;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    for (const Contour& c : ch.shapes[s].contours) {
      if (c.closed && c.count >= 3 &&
          winding_number(std::span<const Vec2>(ch.shapes[s].points.data() + c.begin, static_cast<size_t>(c.count)), p) != 0) {
        inside = static_cast<int>(s);
      }
    }
  }
  double bd = std::numeric_limits<double>::infinity();
  size_t bs = 0, bi = 0;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    if (inside >= 0 && static_cast<int>(s) != inside) continue;
    const SubShape& sh = ch.shapes[s];
    for (const Contour& c : sh.contours) {
      for (int k = 0; k < c.count; ++k) {
        const bool wrap = k + 1 == c.count;
        if (wrap && !c.closed && c.count > 1) continue;
        const size_t i0 = static_cast<size_t>(c.begin + k);
        const size_t i1 = static_cast<size_t>(c.begin + (wrap ? 0 : k + 1));
        const double d = point_segment_distance(p, sh.points[i0], sh.points[i1]);
        if (d < bd) {
          bd = d;
          bs = s;
          bi = (p - sh.points[i0]).squaredNorm() <= (p - sh.points[i1]).squaredNorm() ? i0 : i1;
        }
      }
    }
  }
  ShapeParam sp;
  if (!std::isfinite(bd) || bs >= frame.params.size() || bi >= frame.params[bs].size()) {
    sp.offset_only = true;
    if (!frame.rest.empty()) {
      sp.ox = p.x() - frame.rest[0].x();
      sp.oy = p.y() - frame.rest[0].y();
    }
    return sp;
  }
  sp = frame.params[bs][bi];
  const Vec2 a = frame.rest[static_cast<size_t>(sp.a)], b = frame.rest[static_cast<size_t>(sp.b)];
  const Vec2 d = b - a;
  const double len2 = d.squaredNorm();
  if (sp.a == sp.b || len2 < 1e-18 * frame.diagonal * frame.diagonal) {
    sp.offset_only = true;
    sp.ox = p.x() - a.x();
    sp.oy = p.y() - a.y();
  } else {
    const Vec2 r = p - a;
    sp.offset_only = false;
    sp.zr = (r.x() * d.x() + r.y() * d.y()) / len2;
    sp.zi = (r.y() * d.x() - r.x() * d.y()) / len2;
  }
  return sp;
}

}  // namespace mar
