#include "rig/silhouette.h"

#include "character/raster_loader.h"
#include "geom/skeleton.h"
#include "render/canvas.h"
#include "render/tessellate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>

namespace mar {

namespace {

// A branch of the skeleton sampled densely: points and their radii, from its first node on.
struct Sampled {
  std::vector<Vec2> p;
  std::vector<double> r, arc;
};

Sampled sample(const SkeletonGraph& g, const std::vector<int>& path, double step) {
  Sampled s;
  for (size_t k = 0; k < path.size(); ++k) {
    const Vec2 a = g.nodes[size_t(path[k])];
    const double ra = g.radius[size_t(path[k])];
    if (k == 0) {
      s.p.push_back(a);
      s.r.push_back(ra);
      s.arc.push_back(0);
      continue;
    }
    const Vec2 from = g.nodes[size_t(path[k - 1])];
    const double rf = g.radius[size_t(path[k - 1])];
    const double len = (a - from).norm();
    const int n = std::max(1, int(std::ceil(len / step)));
    const double base = s.arc.back();
    for (int i = 1; i <= n; ++i) {
      const double t = double(i) / n;
      s.p.push_back(from + t * (a - from));
      s.r.push_back(rf + t * (ra - rf));  // (linear along a straight skeleton's edge)
      s.arc.push_back(base + t * len);
    }
  }
  return s;
}

// The point `d` along the samples (clamped).
size_t at_arc(const Sampled& s, double d) {
  const auto it = std::lower_bound(s.arc.begin(), s.arc.end(), d);
  return std::min(size_t(it - s.arc.begin()), s.arc.size() - 1);
}

double turn(const Vec2& u, const Vec2& v) {
  const double nu = u.norm(), nv = v.norm();
  if (nu < 1e-12 || nv < 1e-12) return 0;
  return std::acos(std::clamp(u.dot(v) / (nu * nv), -1.0, 1.0));
}

}  // namespace

Silhouette silhouette_limbs(const Points& outline, std::span<const Points> holes) {
  Silhouette out;
  out.outline = outline;
  out.holes.assign(holes.begin(), holes.end());
  if (outline.size() < 3) {
    out.error = "no outline";
    return out;
  }
  Vec2 lo = outline[0], hi = outline[0];
  for (const Vec2& p : outline) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double size = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-9});
  // The outline simplified until its skeleton is cheap: the twigs of a bumpy outline are
  // pruned below anyway.
  double tol = 0.004 * size;
  Points ring = simplify_polyline(outline, tol, true);
  while (ring.size() > 600) ring = simplify_polyline(outline, tol *= 1.5, true);
  std::vector<Points> hs;
  for (const Points& h : holes) {
    if (h.size() < 3 || std::abs(signed_area(h)) < 4e-4 * size * size) continue;
    Points s = simplify_polyline(h, tol, true);
    if (s.size() >= 3) hs.push_back(std::move(s));
  }
  SkeletonGraph g = straight_skeleton(ring, hs);
  if (!g.error.empty() && !hs.empty()) g = straight_skeleton(ring);  // (without the holes, then)
  if (!g.error.empty()) {
    out.error = g.error;
    return out;
  }
  const size_t n = g.nodes.size();
  std::vector<std::vector<int>> adj(n);
  for (const auto& [a, b] : g.edges) {
    if (a == b) continue;
    adj[size_t(a)].push_back(b);
    adj[size_t(b)].push_back(a);
  }
  auto deg = [&](size_t v) { return adj[v].size(); };
  auto unlink = [&](int a, int b) {
    auto& x = adj[size_t(a)];
    x.erase(std::remove(x.begin(), x.end(), b), x.end());
    auto& y = adj[size_t(b)];
    y.erase(std::remove(y.begin(), y.end(), a), y.end());
  };
  // From a leaf to the first node of another degree: the branch's nodes.
  auto branch = [&](int leaf) {
    std::vector<int> path{leaf};
    int prev = -1, cur = leaf;
    while (true) {
      int next = -1;
      for (int w : adj[size_t(cur)])
        if (w != prev) {
          next = w;
          break;
        }
      if (next < 0) break;
      path.push_back(next);
      prev = cur;
      cur = next;
      if (deg(size_t(cur)) != 2 || path.size() > n) break;
    }
    return path;
  };
  auto length_of = [&](const std::vector<int>& path) {
    double L = 0;
    for (size_t k = 1; k < path.size(); ++k) L += (g.nodes[size_t(path[k])] - g.nodes[size_t(path[k - 1])]).norm();
    return L;
  };
  // Pruning: the twig that stands out least beyond its junction's circle goes first, while
  // one stands out less than its own width (a bump of the outline, not a leg: a short leg on a
  // big body stands out by more than its width) and 3% of the size.
  for (size_t guard = 0; guard < n; ++guard) {
    double least = std::numeric_limits<double>::infinity();
    std::vector<int> worst;
    for (size_t v = 0; v < n; ++v) {
      if (deg(v) != 1) continue;
      const std::vector<int> path = branch(int(v));
      const int j = path.back();
      if (deg(size_t(j)) < 3) continue;  // (a path end to end: the last two ends stay)
      const double out_by = length_of(path) + g.radius[v] - g.radius[size_t(j)];
      std::vector<double> rs;
      for (size_t k = 0; k + 1 < path.size(); ++k) rs.push_back(g.radius[size_t(path[k])]);
      std::nth_element(rs.begin(), rs.begin() + long(rs.size() / 2), rs.end());
      const double own = rs.empty() ? g.radius[v] : rs[rs.size() / 2];
      const double bar = std::max(std::min(2 * own, 0.8 * g.radius[size_t(j)]), 0.03 * size);
      if (out_by < bar && out_by < least) {
        least = out_by;
        worst = path;
      }
    }
    if (worst.empty()) break;
    for (size_t k = 1; k < worst.size(); ++k) unlink(worst[k - 1], worst[k]);
  }
  // The core: the widest point still on the tree.
  int root = -1;
  for (size_t v = 0; v < n; ++v)
    if (deg(v) > 0 && (root < 0 || g.radius[v] > g.radius[size_t(root)])) root = int(v);
  if (root < 0) {  // a round blob: its widest node, no limbs
    for (size_t v = 0; v < n; ++v)
      if (root < 0 || g.radius[v] > g.radius[size_t(root)]) root = int(v);
    if (root >= 0) {
      out.core = g.nodes[size_t(root)];
      out.core_radius = g.radius[size_t(root)];
    }
    return out;
  }
  out.core = g.nodes[size_t(root)];
  out.core_radius = g.radius[size_t(root)];
  // The tree about the core.
  std::vector<int> parent(n, -2);
  {
    std::deque<int> q{root};
    parent[size_t(root)] = -1;
    while (!q.empty()) {
      const int u = q.front();
      q.pop_front();
      for (int w : adj[size_t(u)])
        if (parent[size_t(w)] == -2) {
          parent[size_t(w)] = u;
          q.push_back(w);
        }
    }
  }
  const double step = 0.005 * size;
  for (size_t v = 0; v < n; ++v) {
    if (deg(v) != 1 || int(v) == root || parent[v] == -2) continue;
    // Toward the core, to the first junction (or the core).
    std::vector<int> path{int(v)};
    for (int u = parent[v]; u >= 0; u = parent[size_t(u)]) {
      path.push_back(u);
      if (deg(size_t(u)) >= 3 || u == root) break;
    }
    const Sampled s = sample(g, path, step);
    if (s.p.size() < 2) continue;
    const double total = s.arc.back();
    // Its own width: the median radius of its outer 70%.
    std::vector<double> rs;
    for (size_t k = 0; k < s.p.size() && s.arc[k] <= 0.7 * total; ++k) rs.push_back(s.r[k]);
    if (rs.empty()) continue;
    std::nth_element(rs.begin(), rs.begin() + long(rs.size() / 2), rs.end());
    const double rl = rs[rs.size() / 2];
    // The joint: walking out from the junction, where it has narrowed to 1.3 times that.
    size_t jk = s.p.size() - 1;
    while (jk > 0 && s.r[jk] > 1.3 * rl) --jk;
    SilhouetteLimb limb;
    limb.width = 2 * rl;
    limb.length = s.arc[jk] + s.r[0];
    size_t ek = 0;
    for (size_t k = 0; k <= jk && s.arc[k] <= 0.4 * s.arc[jk]; ++k)
      if (s.r[k] > s.r[ek]) ek = k;
    limb.end_radius = s.r[ek];
    limb.end_centre = s.p[ek];
    // (as wide as the core, it is a limb only when long: a stick figure is all one width)
    if (limb.length < 1.2 * limb.width || (rl > 0.75 * out.core_radius && limb.length < 4 * limb.width)) continue;
    limb.joint = s.p[jk];
    limb.narrowest = s.r[ek];
    for (size_t k = ek; k <= jk; ++k) limb.narrowest = std::min(limb.narrowest, s.r[k]);
    limb.axis.assign(s.p.begin(), s.p.begin() + long(jk) + 1);
    limb.radius.assign(s.r.begin(), s.r.begin() + long(jk) + 1);
    // the handle: inside the free end, halfway from the end circle's centre to the outline
    const Vec2 inward = s.p[at_arc(s, std::min(s.r[0], s.arc[jk]))] - s.p[0];
    limb.tip = s.p[0] - (inward.norm() > 1e-12 ? Vec2(inward.normalized() * 0.5 * s.r[0]) : Vec2(Vec2::Zero()));
    // A bend: the sharpest turn of its axis over two widths each way, away from its ends.
    const double win = 2 * rl;
    double sharpest = 0;
    size_t bk = 0;
    for (size_t k = 0; k < jk; ++k) {
      if (s.arc[k] < win || s.arc[k] > s.arc[jk] - win) continue;
      const double t = turn(s.p[k] - s.p[at_arc(s, s.arc[k] - win)], s.p[at_arc(s, s.arc[k] + win)] - s.p[k]);
      if (t > sharpest) {
        sharpest = t;
        bk = k;
      }
    }
    if (sharpest > 30 * M_PI / 180) limb.bends.push_back(s.p[bk]);
    out.limbs.push_back(std::move(limb));
  }
  return out;
}

namespace {

// Every shape of `sub` drawn opaque white: its paint, for tracing.
void opaque(SubShape& s) {
  s.layer = 0;
  s.owner = -1;
  s.fill.color = Rgba{1, 1, 1, 1};
  s.fill.opacity = 1;
  s.fill.texture.reset();
  s.stroke.color = Rgba{1, 1, 1, 1};
  s.stroke.opacity = 1;
  s.stroke.texture.reset();
  s.stroke.dashes.clear();
}

// `sub` drawn `long_side` pixels long and traced: its largest region's outline and holes, in
// its own units. An error when it draws nothing.
std::string largest_region(const Character& sub, int long_side, Points& outline, std::vector<Points>& holes) {
  if (sub.shapes.empty() || !(sub.width > 0) || !(sub.height > 0)) return "nothing drawn";
  const double scale = double(std::clamp(long_side, 32, 2048)) / std::max(sub.width, sub.height);
  RenderOptions o;
  o.width = std::max(8, int(std::ceil(sub.width * scale)));
  o.height = std::max(8, int(std::ceil(sub.height * scale)));
  auto img = render_character(sub, prepare_mesh(sub), o);
  if (!img.ok()) return img.error;
  auto tex = std::make_shared<Texture>();
  tex->name = "silhouette";
  tex->width = img.value->width;
  tex->height = img.value->height;
  tex->rgba = std::move(img.value->rgba);
  auto traced = raster_character(tex, {}, "silhouette");
  if (!traced.ok() || traced.value->shapes.empty()) return traced.ok() ? "nothing drawn" : traced.error;
  const Affine2 back = fit_view(sub.width, sub.height, o.width, o.height).inverse();
  const SubShape* best = nullptr;
  double best_area = 0;
  for (const SubShape& s : traced.value->shapes) {
    const double a = std::abs(signed_area(s.largest_ring()));
    if (a > best_area) {
      best_area = a;
      best = &s;
    }
  }
  if (!best) return "nothing drawn";
  const Points outer = best->largest_ring();
  for (const Contour& c : best->contours) {
    if (!c.closed || c.count < 3) continue;
    Points r;
    for (int k = 0; k < c.count; ++k) r.push_back(back.apply(best->points[size_t(c.begin + k)]));
    if (outline.empty() && c.count == int(outer.size()) && best->points[size_t(c.begin)] == outer[0]) outline = std::move(r);
    else holes.push_back(std::move(r));
  }
  return outline.empty() ? "nothing drawn" : "";
}

}  // namespace

Points union_outline(const SubShape& shape, int long_side) { return union_outline(std::span<const SubShape* const>(std::array{&shape}), long_side); }

Points union_outline(std::span<const SubShape* const> shapes, int long_side) {
  Bounds b;
  double stroke = 0;
  for (const SubShape* sh : shapes) {
    b.add(sh->bounds());
    if (sh->stroke.enabled) stroke = std::max(stroke, sh->stroke.width);
  }
  if (b.empty()) return {};
  const double pad = 0.02 * std::max(b.hi.x() - b.lo.x(), b.hi.y() - b.lo.y()) + stroke;
  Character sub;
  sub.width = b.hi.x() - b.lo.x() + 2 * pad;
  sub.height = b.hi.y() - b.lo.y() + 2 * pad;
  sub.layers.push_back("shape");
  for (const SubShape* sh : shapes) {
    SubShape s = *sh;
    s.hidden = false;
    s.role = ShapeRole::Paint;
    opaque(s);
    for (Vec2& p : s.points) p -= b.lo - Vec2(pad, pad);
    sub.shapes.push_back(std::move(s));
  }
  Points outline;
  std::vector<Points> holes;
  if (!largest_region(sub, long_side, outline, holes).empty()) return {};
  for (Vec2& p : outline) p += b.lo - Vec2(pad, pad);
  return outline;
}

Silhouette silhouette_of(const Character& ch, std::span<const int> shapes, int long_side) {
  Character sub;
  sub.width = ch.width;
  sub.height = ch.height;
  sub.layers.push_back("silhouette");
  for (int k : shapes) {
    if (k < 0 || size_t(k) >= ch.shapes.size()) continue;
    SubShape s = ch.shapes[size_t(k)];
    if (s.hidden || s.role != ShapeRole::Paint) continue;
    opaque(s);
    sub.shapes.push_back(std::move(s));
  }
  Points outline;
  std::vector<Points> holes;
  if (std::string e = largest_region(sub, long_side, outline, holes); !e.empty()) {
    Silhouette none;
    none.error = e;
    return none;
  }
  return silhouette_limbs(outline, holes);
}

}  // namespace mar
