// The automatic rig's parts (rig/auto_rig_graph.h): the closed, filled sub-shapes, where they
// overlap, what is scenery, what rides on what (details, twins), which touch, and the strokes
// that join two of them.
#include "rig/auto_rig_graph.h"

#include "geom/polygon.h"
#include "rig/limb_geometry.h"
#include "rig/silhouette.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace mar {

void find_parts(PartGraph& G, const AutoRigOptions& options) {
  const Character& ch = G.ch;
  const double height = G.height;
  const std::set<int>& members = G.members;
  std::vector<PartGeo>& geo = G.geo;
  int traced_pieces = 0;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    const SubShape& sh = ch.shapes[s];
    if (members.count(int(s)) || sh.role != ShapeRole::Paint) continue;  // (a clip or mask shape rides along)
    PartGeo g;
    g.shape = int(s);
    g.ring = sh.largest_ring();
    g.area = std::abs(signed_area(g.ring));
    // A shape drawn in pieces (an outline as many small filled quads, a limb in strips): its
    // outline is the outline of all its pieces together.
    // (at most 64 such shapes, each a twentieth of the drawing's height or more: each is drawn
    // and traced, and a file of thousands of tiny ones took 18 s)
    // (the `rig` command's only: a show's plain rig loads without drawing and tracing)
    if (options.silhouette && sh.contours.size() > 3 && sh.fill.enabled && traced_pieces < 64) {
      const Bounds b = sh.bounds();
      const double box = b.empty() ? 0.0 : (b.hi.x() - b.lo.x()) * (b.hi.y() - b.lo.y());
      if (g.area < 0.3 * box && std::max(b.hi.x() - b.lo.x(), b.hi.y() - b.lo.y()) >= 0.05 * height && ++traced_pieces)
        if (Points u = union_outline(sh); u.size() >= 3 && std::abs(signed_area(u)) > g.area) {
          g.ring = std::move(u);
          g.area = std::abs(signed_area(g.ring));
        }
    }
    if (!sh.fill.enabled || g.area <= 1e-6 * height * height) continue;
    g.lo = g.hi = g.ring[0];
    for (const Vec2& p : g.ring) {
      g.lo = g.lo.cwiseMin(p);
      g.hi = g.hi.cwiseMax(p);
    }
    g.centroid = ring_centroid(g.ring);
    g.named = !sh.label.empty() || !made_up(sh.id);
    if (g.named) g.words = name_words(sh.label.empty() ? sh.id : sh.label);
    g.hint = hint_of(g.words);
    geo.push_back(std::move(g));
  }
  // At most the 1,000 biggest are parts (in drawing order): the phases below weigh every pair,
  // and a file of 140,000 small shapes ran the rig out of memory. The others ride along.
  if (constexpr size_t kMaxParts = 1000; geo.size() > kMaxParts) {
    std::vector<size_t> order(geo.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return geo[a].area > geo[b].area; });
    order.resize(kMaxParts);
    std::sort(order.begin(), order.end());
    std::vector<PartGeo> kept;
    for (size_t k : order) kept.push_back(std::move(geo[k]));
    G.left_small = geo.size() - kept.size();
    geo = std::move(kept);
  }
  G.n = geo.size();
  G.group_part.assign(G.n, -1);
  if (options.silhouette) join_groups(G);  // (drawn and traced: the `rig` command's only, as pieces above)
}

namespace {

// The innermost group's name ("head/Mouth" -> "Mouth").
std::string innermost_group(const SubShape& sh) { return sh.group.substr(sh.group.rfind('/') == std::string::npos ? 0 : sh.group.rfind('/') + 1); }

}  // namespace

void join_groups(PartGraph& G) {
  // A group (`<g>`) whose pieces together make one region — a foot and its straps, a head
  // drawn in patches of colour, a limb in light and shade — is one part: artists group a
  // part's pieces. Its largest piece stands for it, with the outline of all its pieces as its
  // own; the other pieces ride on it as details do (relate_parts). Not a layer, nor a group
  // that holds most of the drawing (the whole character), nor one whose pieces are named parts of
  // their own (an upper arm and a forearm), nor one in separate regions (two eyes, both wings).
  const Character& ch = G.ch;
  std::vector<PartGeo>& geo = G.geo;
  Bounds all;
  for (const PartGeo& g : geo) {
    all.add(g.lo);
    all.add(g.hi);
  }
  const double all_box = all.width() * all.height();
  std::map<int, std::vector<size_t>> by_group;
  for (size_t i = 0; i < G.n; ++i)
    if (const SubShape& sh = ch.shapes[size_t(geo[i].shape)]; sh.group_key >= 0 && !sh.group_is_layer) by_group[sh.group_key].push_back(i);
  int traced = 0;
  for (const auto& [key, pieces] : by_group) {
    // (each is drawn and traced: at most 64 groups, of at most 256 pieces; hair in a thousand
    // strands is no one part)
    if (pieces.size() < 2 || pieces.size() > 256 || ++traced > 64) continue;
    Bounds box;
    bool named_parts = false;
    for (size_t i : pieces) {
      box.add(geo[i].lo);
      box.add(geo[i].hi);
      named_parts = named_parts || geo[i].hint != Hint::None;
    }
    if (named_parts || box.width() * box.height() > 0.4 * all_box) continue;
    std::vector<const SubShape*> shapes;
    for (size_t i : pieces) shapes.push_back(&ch.shapes[size_t(geo[i].shape)]);
    Points u = union_outline(shapes);
    if (u.size() < 3) continue;
    // One region: every piece inside the traced outline (within two of its pixels), judged on
    // at most 32 points of its outline.
    const double px = 2.0 * std::max(box.width(), box.height()) / 160.0;
    bool one = true;
    for (size_t i : pieces) {
      const Points& ring = geo[i].ring;
      const size_t step = std::max<size_t>(1, ring.size() / 32);
      size_t in = 0, seen = 0;
      for (size_t k = 0; k < ring.size(); k += step, ++seen) in += winding_number(u, ring[k]) != 0 || ring_distance(Points{ring[k]}, u) <= px;
      one = one && in >= 0.9 * double(seen);
    }
    if (!one) continue;
    size_t rep = pieces[0];
    for (size_t i : pieces)
      if (geo[i].area > geo[rep].area) rep = i;
    PartGeo& g = geo[rep];
    g.ring = std::move(u);
    g.area = std::abs(signed_area(g.ring));
    g.lo = box.lo;
    g.hi = box.hi;
    g.centroid = ring_centroid(g.ring);
    // (the group's own name, when the piece has none: a `<g id="wing-left">`)
    const std::string name = innermost_group(ch.shapes[size_t(g.shape)]);
    if (!g.named && !name.empty() && !made_up(name)) {
      g.named = true;
      g.words = name_words(name);
      g.hint = hint_of(g.words);
    }
    for (size_t i : pieces) G.group_part[i] = int(rep);
  }
}

int PartGraph::part_at(const Vec2& q, bool with_details) const {
  int best = -1;
  double bd = 0.02 * height;
  for (size_t i = 0; i < n; ++i) {
    if ((!with_details && container[i] >= 0) || scenery[i]) continue;
    const double d = winding_number(geo[i].ring, q) != 0 ? 0.0 : ring_distance(Points{q}, geo[i].ring);
    if (d <= bd && (best < 0 || d < bd || geo[i].area < geo[size_t(best)].area)) {
      bd = d;
      best = int(i);
    }
  }
  return best;
}

namespace {

// Whether a ring is drawn as a disc (a circle or an ellipse, at any angle): every outline point
// at the same normalised distance from its centre under the filled shape's second moments (2 for
// an ellipse), within 6 %. A face with a nose, a head of hair with locks are not.
bool disc_like(const Points& ring) {
  const size_t n = ring.size();
  if (n < 8) return false;
  Vec2 o = Vec2::Zero();
  for (const Vec2& p : ring) o += p;
  o /= double(n);
  double a = 0, cx = 0, cy = 0, ixx = 0, iyy = 0, ixy = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p = ring[i] - o, q = ring[(i + 1) % n] - o;
    const double c = p.x() * q.y() - q.x() * p.y();
    a += c;
    cx += (p.x() + q.x()) * c;
    cy += (p.y() + q.y()) * c;
    ixx += c * (p.x() * p.x() + p.x() * q.x() + q.x() * q.x());
    iyy += c * (p.y() * p.y() + p.y() * q.y() + q.y() * q.y());
    ixy += c * (p.x() * q.y() + 2 * p.x() * p.y() + 2 * q.x() * q.y() + q.x() * p.y());
  }
  if (!(std::abs(a) > 1e-12)) return false;
  a *= 0.5;
  const Vec2 c(cx / (6 * a), cy / (6 * a));
  const double sxx = ixx / (12 * a) - c.x() * c.x(), syy = iyy / (12 * a) - c.y() * c.y(), sxy = ixy / (24 * a) - c.x() * c.y();
  const double det = sxx * syy - sxy * sxy;
  if (!(det > 0)) return false;
  for (const Vec2& p0 : ring) {
    const Vec2 p = p0 - o - c;
    const double r2 = (syy * p.x() * p.x() - 2 * sxy * p.x() * p.y() + sxx * p.y() * p.y()) / det;
    if (std::abs(std::sqrt(r2) - 2.0) > 0.12) return false;
  }
  return true;
}

}  // namespace

void relate_parts(PartGraph& G, AutoRig& out) {
  const Character& ch = G.ch;
  const double height = G.height;
  const std::set<int>& members = G.members;
  const std::vector<PartGeo>& geo = G.geo;
  const size_t n = G.n;
  const Bounds cb = ch.bounds();
  auto& overlap = G.overlap;
  auto& overlap_at = G.overlap_at;
  overlap.assign(n, std::vector<double>(n, 0.0));
  overlap_at.assign(n, std::vector<Vec2>(n, Vec2::Zero()));
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (geo[i].hi.x() < geo[j].lo.x() || geo[j].hi.x() < geo[i].lo.x() || geo[i].hi.y() < geo[j].lo.y() || geo[j].hi.y() < geo[i].lo.y())
        continue;
      Vec2 c;
      double a = 0;
      if (overlap_centre(geo[i].ring, geo[j].ring, c, &a) && a > 0) {
        overlap[i][j] = overlap[j][i] = a;
        overlap_at[i][j] = overlap_at[j][i] = c;
      }
    }
  // Scenery: a disc or a rectangle behind most of the character (a sun, a frame), or a shadow
  // under its feet. Left out of the tree, never the body; a handle keeps it where it is drawn.
  auto& scenery = G.scenery;
  scenery.assign(n, 0);
  {
    // (again after each find: a second disc inside a glow behind a horse)
    for (bool found = true; found;) {
    found = false;
    double total = 0;
    for (size_t i = 0; i < n; ++i) total += scenery[i] ? 0.0 : geo[i].area;
    for (size_t i = 0; i < n && n >= 3; ++i) {
      if (geo[i].hint != Hint::None || scenery[i]) continue;  // (a part named as one is one)
      const double others = total - geo[i].area;
      double inside = 0, behind = 0;
      bool straddled = false;  // a big part of the character half in front of it, half beside it
      for (size_t j = 0; j < n; ++j) {
        if (j == i || scenery[j]) continue;
        const double in = std::min(overlap[i][j], geo[j].area);
        inside += in;
        if (geo[j].shape > geo[i].shape) behind += geo[j].area;
        straddled = straddled || (geo[j].shape > geo[i].shape && geo[j].area >= 0.25 * geo[i].area && in >= 0.2 * geo[j].area &&
                                  in <= 0.8 * geo[j].area);
      }
      const Vec2 ext = geo[i].hi - geo[i].lo;
      const double box = std::max(1e-12, ext.x() * ext.y());
      const bool filled = geo[i].area >= 0.7 * box;  // most of its box (a shadow's ellipse, a blob)
      // a disc (0.785 of its box) or a rectangle, drawn as one (a blob of back hair is not)
      const bool plain = geo[i].area >= 0.95 * box || (filled && disc_like(geo[i].ring));
      const bool first = behind >= 0.7 * others;    // drawn behind the rest
      // (a body drawn first has its limbs attached along its outline; a backdrop has the
      // character itself crossing it)
      // (and a rectangle under the whole drawing is its background, whatever is on it)
      const Vec2 all = cb.hi - cb.lo;
      const bool canvas = geo[i].area >= 0.95 * box && first && box >= 0.9 * all.x() * all.y();
      // (a face behind its hair is no backdrop: two of its eyes, nose, mouth lie on it and
      // touch nothing else, where what lies on a sun behind a horse lies on or touches the horse)
      int own_details = 0;
      for (size_t j = 0; j < n && own_details < 2 && !canvas; ++j) {
        if (j == i || scenery[j] || geo[j].shape < geo[i].shape || geo[j].area >= 0.2 * geo[i].area ||
            overlap[i][j] < 0.9 * geo[j].area)
          continue;
        bool elsewhere = false;
        for (size_t k = 0; k < n && !elsewhere; ++k)
          elsewhere = k != i && k != j && !scenery[k] && geo[k].area > geo[j].area && overlap[k][j] >= 0.05 * geo[j].area;
        own_details += !elsewhere;
      }
      const bool backdrop = (plain && first && geo[i].area >= 0.3 * others && straddled && own_details < 2) || canvas;
      const bool ground = filled && first && ext.x() >= 3 * ext.y() && geo[i].centroid.y() >= cb.lo.y() + 0.8 * height &&
                          geo[i].area <= 0.3 * others && inside > 0;
      if (!backdrop && !ground) continue;
      scenery[i] = 1;
      found = true;
      out.left_out.push_back({geo[i].shape, canvas     ? "a rectangle under the whole drawing, its background: kept still, never the body"
                                            : backdrop ? "a disc or rectangle behind most of the character: kept still, never the body"
                                                       : "a shadow under the feet: kept still"});
    }
    }
  }
  // Details: mostly inside a bigger part (eyes, a pocket, spots). They follow their container.
  // An outline and its fill drawn as two shapes, one right after the other (a black shape a
  // little larger behind the colour, or the colour over it) are twins: the one drawn later
  // rides on the first, so the pair is one part.
  auto& container = G.container;
  container.assign(n, -1);
  for (size_t i = 0; i < n; ++i) {
    if (scenery[i]) continue;
    for (size_t j = 0; j < n && container[i] < 0; ++j) {
      if (j == i || scenery[j] || geo[j].shape >= geo[i].shape || geo[i].shape - geo[j].shape > 2) continue;
      const double lo = std::min(geo[i].area, geo[j].area), hi = std::max(geo[i].area, geo[j].area);
      if (lo >= 0.5 * hi && overlap[i][j] >= 0.7 * lo) container[i] = int(j);
    }
  }
  if (G.left_small > 0)
    out.notes.push_back(std::to_string(G.left_small) + " small filled shapes are not parts (only the 1000 biggest are): they ride along");
  // A group's pieces ride on the part that stands for it (join_groups), and it on none of them.
  {
    std::string said;
    int groups = 0;
    for (size_t i = 0; i < n; ++i) {
      if (G.group_part[i] != int(i)) continue;
      const long pieces = std::count(G.group_part.begin(), G.group_part.end(), int(i));
      if (++groups <= 4) said += (said.empty() ? "" : "; ") + innermost_group(ch.shapes[size_t(geo[i].shape)]) + " (" + std::to_string(pieces) + " pieces, " + G.id(i) + ")";
    }
    if (groups > 4) said += "; and " + std::to_string(groups - 4) + " more";
    if (groups > 0) out.notes.push_back(std::to_string(groups) + (groups == 1 ? " group makes" : " groups make") + " one region, one part: " + said);
  }
  for (size_t i = 0; i < n; ++i) {
    const int rep = G.group_part[i];
    if (rep < 0 || scenery[i] || scenery[size_t(rep)]) continue;
    if (size_t(rep) == i) {
      if (container[i] >= 0 && G.group_part[size_t(container[i])] == rep) container[i] = -1;
    } else {
      container[i] = rep;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    double best = 0;
    if (scenery[i] || container[i] >= 0) continue;
    for (size_t j = 0; j < n; ++j)
      if (j != i && !scenery[j] && geo[j].area > geo[i].area && overlap[i][j] >= 0.85 * geo[i].area && overlap[i][j] > best) {
        best = overlap[i][j];
        container[i] = int(j);
      }
  }
  // Neighbours among the others: overlapping, or within 2% of the height of each other.
  auto& nb = G.nb;
  nb.assign(n, {});
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 1; j < n; ++j) {
      if (container[i] >= 0 || container[j] >= 0 || scenery[i] || scenery[j]) continue;
      bool near = overlap[i][j] > 0;
      if (!near) {
        const double gap = 0.02 * height;
        const bool boxes = !(geo[i].hi.x() + gap < geo[j].lo.x() || geo[j].hi.x() + gap < geo[i].lo.x() || geo[i].hi.y() + gap < geo[j].lo.y() ||
                             geo[j].hi.y() + gap < geo[i].lo.y());
        if (boxes && ring_distance(geo[i].ring, geo[j].ring) <= gap) {
          near = true;
          // Where they come closest stands for the overlap: the middle of the run of i's
          // outline within 0.4 % of the height of the closest step. Two shapes drawn edge to
          // edge meet along it (a ladybug's head on the straight cut of its back): the nearest
          // single point was one end of that edge, and the head turned about its corner,
          // opening a wedge.
          const Points& a = geo[i].ring;
          const Points& b = geo[j].ring;
          Points along;  // i's outline, a point every 0.2 % of the height at least
          for (size_t k = 0; k < a.size(); ++k) {
            const Vec2 p = a[k], q = a[(k + 1) % a.size()];
            const int steps = std::clamp(int(std::ceil((q - p).norm() / (0.002 * height))), 1, 256);
            for (int t = 0; t < steps; ++t) along.push_back(p + (q - p) * (double(t) / steps));
          }
          std::vector<double> off(along.size(), std::numeric_limits<double>::infinity());
          double best = std::numeric_limits<double>::infinity();
          for (size_t m = 0; m < along.size(); ++m) {
            for (size_t k = 0; k < b.size(); ++k) off[m] = std::min(off[m], point_segment_distance(along[m], b[k], b[(k + 1) % b.size()]));
            best = std::min(best, off[m]);
          }
          Vec2 sum = Vec2::Zero();
          int count = 0;
          for (size_t m = 0; m < along.size(); ++m)
            if (off[m] <= best + 0.004 * height) sum += along[m], ++count;
          if (count > 0) overlap_at[i][j] = overlap_at[j][i] = sum / count;
        }
      }
      if (near) {
        nb[i].push_back(int(j));
        nb[j].push_back(int(i));
      }
    }
  // Connectors: an open stroke from one part to another (a wick from a candle to its flame)
  // joins them; a hinge then goes where it leaves the parent.
  auto& via = G.via;                // the stroke's shape
  auto& stroke_end = G.stroke_end;  // its end at the first part
  via.assign(n, std::vector<int>(n, -1));
  stroke_end.assign(n, std::vector<Vec2>(n, Vec2::Zero()));
  G.is_part.assign(ch.shapes.size(), 0);
  for (const PartGeo& p : geo) G.is_part[size_t(p.shape)] = 1;
  const auto& is_part = G.is_part;
  {
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      const SubShape& sh = ch.shapes[s];
      if (is_part[s] || members.count(int(s)) || !sh.stroke.enabled) continue;
      for (const Contour& c : sh.contours) {
        if (c.closed || c.count < 2) continue;
        const Vec2 a = sh.points[size_t(c.begin)], b = sh.points[size_t(c.begin + c.count - 1)];
        const int pa = G.part_at(a, false), pb = G.part_at(b, false);
        if (pa < 0 || pb < 0 || pa == pb || overlap[size_t(pa)][size_t(pb)] > 0) continue;
        if (std::find(nb[size_t(pa)].begin(), nb[size_t(pa)].end(), pb) != nb[size_t(pa)].end()) continue;
        nb[size_t(pa)].push_back(pb);
        nb[size_t(pb)].push_back(pa);
        via[size_t(pa)][size_t(pb)] = via[size_t(pb)][size_t(pa)] = int(s);
        stroke_end[size_t(pa)][size_t(pb)] = a;
        stroke_end[size_t(pb)][size_t(pa)] = b;
        overlap_at[size_t(pa)][size_t(pb)] = a;  // (where each is attached: its end of the stroke)
        overlap_at[size_t(pb)][size_t(pa)] = b;
      }
    }
  }
}

}  // namespace mar
