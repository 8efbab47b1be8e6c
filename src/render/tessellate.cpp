#include "render/tessellate.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace mar {
namespace {

SDL_Color to_sdl(const Rgba& c, float opacity) {
  auto byte = [](float v) { return static_cast<Uint8>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  return SDL_Color{byte(c.r), byte(c.g), byte(c.b), byte(c.a * opacity)};
}

int push_vertex(DrawList& out, const Vec2& p, SDL_Color color, SDL_FPoint uv = {0, 0}) {
  out.vertices.push_back(SDL_Vertex{{static_cast<float>(p.x()), static_cast<float>(p.y())}, color, uv});
  return static_cast<int>(out.vertices.size()) - 1;
}

void tri(DrawList& out, int a, int b, int c) {
  out.indices.push_back(a);
  out.indices.push_back(b);
  out.indices.push_back(c);
}

Vec2 perp(const Vec2& d) { return {-d.y(), d.x()}; }

// Fan of triangles around `c` on the arc from angle a0 sweeping `sweep` radians.
void fan(DrawList& out, const Vec2& c, double r, double a0, double sweep, double tol, SDL_Color col) {
  const double max_step = r > tol ? 2.0 * std::acos(std::max(-1.0, 1.0 - tol / r)) : M_PI / 2;
  const int n = std::clamp(static_cast<int>(std::ceil(std::abs(sweep) / std::max(max_step, 1e-3))), 1, 64);
  const int ic = push_vertex(out, c, col);
  int prev = push_vertex(out, c + r * Vec2(std::cos(a0), std::sin(a0)), col);
  for (int k = 1; k <= n; ++k) {
    const double a = a0 + sweep * k / n;
    const int cur = push_vertex(out, c + r * Vec2(std::cos(a), std::sin(a)), col);
    tri(out, ic, prev, cur);
    prev = cur;
  }
}

void begin_batch(DrawList& out, const Texture* tex) {
  const int first = static_cast<int>(out.indices.size());
  if (!out.batches.empty() && out.batches.back().texture == tex) return;
  out.batches.push_back({tex, first, 0});
}

void end_batch(DrawList& out) {
  if (out.batches.empty()) return;
  DrawList::Batch& b = out.batches.back();
  b.index_count = static_cast<int>(out.indices.size()) - b.first_index;
}

// The edges of a fill's triangulation that only one triangle has. Vertices at the same rest
// position count as one (a ring's closing point, a point where two rings touch).
std::vector<std::array<int, 3>> fill_outline(const FillMesh& m) {
  std::map<std::pair<double, double>, int> first;
  std::vector<int> canon(m.vertices.size());
  for (size_t v = 0; v < m.vertices.size(); ++v)
    canon[v] = first.emplace(std::make_pair(m.vertices[v].x(), m.vertices[v].y()), int(v)).first->second;
  struct Half {
    int lo, hi, a, b, c;
  };
  std::vector<Half> halves;
  for (size_t t = 0; t + 2 < m.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const int a = m.triangles[t + size_t(k)], b = m.triangles[t + size_t((k + 1) % 3)], c = m.triangles[t + size_t((k + 2) % 3)];
      const int ca = canon[size_t(a)], cb = canon[size_t(b)];
      if (ca == cb) continue;
      halves.push_back({std::min(ca, cb), std::max(ca, cb), a, b, c});
    }
  std::sort(halves.begin(), halves.end(), [](const Half& x, const Half& y) { return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi); });
  std::vector<std::array<int, 3>> out;
  for (size_t i = 0; i < halves.size();) {
    size_t j = i;
    while (j < halves.size() && halves[j].lo == halves[i].lo && halves[j].hi == halves[i].hi) ++j;
    if (j - i == 1) out.push_back({halves[i].a, halves[i].b, halves[i].c});
    i = j;
  }
  return out;
}

SDL_Color with_alpha(SDL_Color c, double k) {
  c.a = static_cast<Uint8>(std::lround(std::clamp(k, 0.0, 1.0) * c.a));
  return c;
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// A fill with its fringe (DrawList::fringe). `pos`: the mesh's vertices in pixels.
void fill_with_fringe(const ShapeMesh& sm, std::span<const Vec2> pos, SDL_Color col, bool textured, DrawList& out) {
  auto& fv = out.fringe_scratch;
  const size_t nv = pos.size();
  fv.assign(nv, DrawList::FringeVertex{});
  for (size_t v = 0; v < nv; ++v) fv[v].p = pos[v];
  // Outward normals of the outline's edges, summed at their ends.
  for (const auto& [a, b, c] : sm.outline) {
    const Vec2 e = pos[size_t(b)] - pos[size_t(a)];
    const double len = e.norm();
    if (!(len > 1e-9)) continue;
    Vec2 n = perp(e) / len;
    if (n.dot(pos[size_t(c)] - pos[size_t(a)]) > 0) n = -n;
    for (int v : {a, b}) {
      fv[size_t(v)].off += n;
      fv[size_t(v)].count += 1;
      int* nx = fv[size_t(v)].next;
      (nx[0] < 0 ? nx[0] : nx[1]) = v == a ? b : a;
    }
    if (textured) {  // the texture's gradient at a and b, from this triangle
      const Vec2 p = pos[size_t(b)] - pos[size_t(a)], q = pos[size_t(c)] - pos[size_t(a)];
      const double det = cross2(p, q);
      if (std::abs(det) > 1e-12) {
        const SDL_FPoint ua = sm.uv[size_t(a)], ub = sm.uv[size_t(b)], uc = sm.uv[size_t(c)];
        const double du1 = ub.x - ua.x, du2 = uc.x - ua.x, dv1 = ub.y - ua.y, dv2 = uc.y - ua.y;
        const double j[4] = {(du1 * q.y() - du2 * p.y()) / det, (du2 * p.x() - du1 * q.x()) / det,
                             (dv1 * q.y() - dv2 * p.y()) / det, (dv2 * p.x() - dv1 * q.x()) / det};
        for (int v : {a, b}) std::copy(j, j + 4, fv[size_t(v)].j);
      }
    }
  }
  // Half a pixel along the mitred normal (at most 2 px at a sharp corner).
  for (auto& x : fv) {
    if (x.count == 0) continue;
    const Vec2 avg = x.off / x.count;
    const double l2 = avg.squaredNorm();
    x.off = l2 > 1e-12 ? Vec2(0.5 * avg / l2) : Vec2(Vec2::Zero());
    if (x.off.norm() > 2) x.off *= 2 / x.off.norm();
  }
  // Where the shape is thinner than a pixel, pulling both sides in by half a pixel would turn
  // triangles over: pull them in only until the triangle closes, and draw them that much fainter
  // (a band w < 1 px wide ends up as a 1 px fringe at alpha w, its coverage).
  const auto& tris = sm.fill.triangles;
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    const int a = tris[t], b = tris[t + 1], c = tris[t + 2];
    if (fv[size_t(a)].count == 0 && fv[size_t(b)].count == 0 && fv[size_t(c)].count == 0) continue;
    const Vec2 u = pos[size_t(b)] - pos[size_t(a)], w = pos[size_t(c)] - pos[size_t(a)];
    const Vec2 du = fv[size_t(a)].off - fv[size_t(b)].off, dw = fv[size_t(a)].off - fv[size_t(c)].off;
    auto area = [&](double s) { return cross2(u + s * du, w + s * dw); };
    const double a0 = area(0);
    if (a0 == 0 || area(1) * a0 > 0) continue;
    // Thin means outlines facing each other less than a pixel and a half apart: a vertex that
    // close to the outline at another whose offset faces its own. A sliver along one side of a
    // thick shape (offsets side by side), or one across it from side to side (facing, but the
    // sides far apart), may turn over harmlessly.
    auto near_side = [&](int x, int y) {
      for (int z : fv[size_t(y)].next)
        if (z >= 0 && point_segment_distance(pos[size_t(x)], pos[size_t(y)], pos[size_t(z)]) < 1.5) return true;
      return false;
    };
    auto opposed = [&](int x, int y) {
      return fv[size_t(x)].off.dot(fv[size_t(y)].off) < -0.1 * fv[size_t(x)].off.norm() * fv[size_t(y)].off.norm() &&
             (near_side(x, y) || near_side(y, x));
    };
    if (!opposed(a, b) && !opposed(b, c) && !opposed(a, c)) continue;
    double lo = 0, hi = 1;
    for (int it = 0; it < 12; ++it) {
      const double mid = 0.5 * (lo + hi);
      (area(mid) * a0 > 0 ? lo : hi) = mid;
    }
    for (int v : {a, b, c}) fv[size_t(v)].f = std::min(fv[size_t(v)].f, lo);
  }
  // The inside, pulled in; then the fringe, one quad per outline edge.
  auto uv_at = [&](size_t v, const Vec2& d) {
    if (!textured) return SDL_FPoint{0, 0};
    const auto& j = fv[v].j;
    return SDL_FPoint{std::clamp(float(sm.uv[v].x + j[0] * d.x() + j[1] * d.y()), 0.0f, 1.0f),
                      std::clamp(float(sm.uv[v].y + j[2] * d.x() + j[3] * d.y()), 0.0f, 1.0f)};
  };
  SDL_Color clear = col;
  clear.a = 0;
  if (textured) clear = {0, 0, 0, 0};
  const int base = static_cast<int>(out.vertices.size());
  for (size_t v = 0; v < nv; ++v) {
    const Vec2 d = -fv[v].f * fv[v].off;
    SDL_Color c = with_alpha(col, fv[v].f);
    if (textured) c = {Uint8(c.r * c.a / 255), Uint8(c.g * c.a / 255), Uint8(c.b * c.a / 255), c.a};
    push_vertex(out, fv[v].p + d, c, uv_at(v, d));
  }
  for (int idx : tris) out.indices.push_back(base + idx);
  for (const auto& [a, b, c] : sm.outline) {
    for (int v : {a, b})
      if (fv[size_t(v)].outer < 0) fv[size_t(v)].outer = push_vertex(out, fv[size_t(v)].p + fv[size_t(v)].off, clear, uv_at(size_t(v), fv[size_t(v)].off));
    tri(out, base + a, base + b, fv[size_t(b)].outer);
    tri(out, base + a, fv[size_t(b)].outer, fv[size_t(a)].outer);
  }
}

// A fan around p with its fringe: the core out to radius `core` along each of `n` directions
// dir(k) (scaled: a direction of length l reaches l * radius), then a strip out to `outer`
// whose alpha falls to 0. Round joins and caps, mitres, bevels and square dots are all fans.
template <class Dir>
void fringed_fan(DrawList& out, const Vec2& p, int n, Dir dir, double core, double outer, SDL_Color col) {
  SDL_Color clear = col;
  clear.a = 0;
  const int ic = push_vertex(out, p, col);
  int pc = -1, po = -1;
  for (int k = 0; k < n; ++k) {
    const Vec2 u = dir(k);
    const int c = push_vertex(out, p + core * u, col), o = push_vertex(out, p + outer * u, clear);
    if (k > 0) {
      tri(out, ic, pc, c);
      tri(out, pc, c, o);
      tri(out, pc, o, po);
    }
    pc = c;
    po = o;
  }
}

// A strip from a to b across the normal nr: a core out to `core` either side, fringes out to
// `outer` fading to 0. The core takes colour `at_a` at a and `at_b` at b (a cap's fringe across
// the end fades along it too).
void fringed_strip(DrawList& out, const Vec2& a, const Vec2& b, const Vec2& nr, double core, double outer, SDL_Color at_a,
                   SDL_Color at_b) {
  int prev[4] = {-1, -1, -1, -1};
  for (int row = 0; row < 2; ++row) {
    const Vec2 p = row == 0 ? a : b;
    const SDL_Color in = row == 0 ? at_a : at_b;
    SDL_Color clear = at_a;
    clear.a = 0;
    const int v[4] = {push_vertex(out, p + outer * nr, clear), push_vertex(out, p + core * nr, in),
                      push_vertex(out, p - core * nr, in), push_vertex(out, p - outer * nr, clear)};
    if (prev[0] >= 0)
      for (int k = 0; k < 3; ++k) {
        tri(out, prev[k], prev[k + 1], v[k + 1]);
        tri(out, prev[k], v[k + 1], v[k]);
      }
    std::copy(v, v + 4, prev);
  }
}

// A stroke with its fringe (DrawList::fringe): a core w - 1 px wide and half-pixel fringes
// either side; thinner than a pixel, a 1 px fringe at alpha w. Segments overlap at joins as the
// plain stroke's do; only the outside of a join (and the caps) get a fan of their own.
void stroke_with_fringe(std::span<const Vec2> pts, bool closed, const StrokeStyle& st, SDL_Color col, DrawList& out) {
  const size_t n = pts.size();
  const double hw = std::max(st.half_width, 0.5);
  col = with_alpha(col, std::min(1.0, 2 * st.half_width));
  SDL_Color clear = col;
  clear.a = 0;
  const double core = hw - 0.5, outer = hw + 0.5;
  const size_t nseg = closed ? n : n - 1;
  auto dir = [&](size_t i) -> Vec2 {
    const Vec2 d = pts[(i + 1) % n] - pts[i];
    const double len = d.norm();
    return len > 1e-12 ? Vec2(d / len) : Vec2(Vec2::Zero());
  };
  size_t first = nseg, last = nseg;  // the first and last segments that have a direction
  for (size_t i = 0; i < nseg; ++i)
    if (!dir(i).isZero()) {
      if (first == nseg) first = i;
      last = i;
    }
  auto round_dirs = [&](const Vec2& from, double sweep) {
    const double r = outer;
    const double max_step = r > st.tolerance ? 2.0 * std::acos(std::max(-1.0, 1.0 - st.tolerance / r)) : M_PI / 2;
    const int steps = std::clamp(static_cast<int>(std::ceil(std::abs(sweep) / std::max(max_step, 1e-3))), 1, 64);
    const double a0 = std::atan2(from.y(), from.x());
    return std::make_pair(steps + 1, [a0, sweep, steps](int k) {
      const double a = a0 + sweep * k / steps;
      return Vec2(std::cos(a), std::sin(a));
    });
  };
  if (first == nseg) {  // all points coincide: a dot, drawn by round or square caps only
    if (st.cap == LineCap::Round) {
      auto [cnt, f] = round_dirs(Vec2(1, 0), 2 * M_PI);
      fringed_fan(out, pts[0], cnt, f, core, outer, col);
    } else if (st.cap == LineCap::Square) {
      const Vec2 c[5] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}};
      fringed_fan(out, pts[0], 5, [&](int k) { return c[k]; }, core, outer, col);
    }
    return;
  }
  // An open end: a round cap is a half fan; butt and square end with a fringe across.
  const bool open = !closed;
  auto end_of = [&](const Vec2& p, const Vec2& d, bool at_end) {  // d: the segment's direction
    const Vec2 o = at_end ? d : Vec2(-d);
    if (st.cap == LineCap::Round) return p;
    return Vec2(p + o * ((st.cap == LineCap::Square ? st.half_width : 0.0) - 0.5));
  };
  for (size_t i = 0; i < nseg; ++i) {
    const Vec2 d = dir(i);
    if (d.isZero()) continue;
    Vec2 a = pts[i], b = pts[(i + 1) % n];
    if (open && i == first) a = end_of(a, d, false);
    if (open && i == last) b = end_of(b, d, true);
    fringed_strip(out, a, b, perp(d), core, outer, col, col);
  }
  // Joins: the outside of each turn.
  auto join_at = [&](const Vec2& p, const Vec2& d0, const Vec2& d1) {
    const double cross = d0.x() * d1.y() - d0.y() * d1.x();
    const double dot = d0.dot(d1);
    if (std::abs(cross) < 1e-9 && dot > 0) return;
    const double s = cross > 0 ? -1.0 : 1.0;
    const Vec2 n0 = s * perp(d0), n1 = s * perp(d1);
    if (st.join == LineJoin::Round || (std::abs(cross) < 1e-9 && st.join != LineJoin::Bevel)) {
      double delta = std::atan2(n1.y(), n1.x()) - std::atan2(n0.y(), n0.x());
      while (delta > M_PI) delta -= 2 * M_PI;
      while (delta < -M_PI) delta += 2 * M_PI;
      if (std::abs(cross) < 1e-9) delta = cross2(n0, d0) > 0 ? M_PI : -M_PI;
      if (st.join == LineJoin::Round) {
        auto [cnt, f] = round_dirs(n0, delta);
        fringed_fan(out, p, cnt, f, core, outer, col);
        return;
      }
    }
    if (st.join == LineJoin::Miter) {
      const double sin_half = std::sqrt(std::max(0.0, (1.0 + dot) / 2.0));
      const Vec2 m = n0 + n1;
      if (sin_half > 1e-9 && 1.0 / sin_half <= st.miter_limit && m.norm() > 1e-12) {
        const Vec2 tip = m / m.norm() / sin_half;
        const Vec2 u[3] = {n0, tip, n1};
        fringed_fan(out, p, 3, [&](int k) { return u[k]; }, core, outer, col);
        return;
      }
    }
    const Vec2 u[2] = {n0, n1};
    fringed_fan(out, p, 2, [&](int k) { return u[k]; }, core, outer, col);
  };
  Vec2 last_dir = Vec2::Zero();
  for (size_t i = 0; i < nseg; ++i) {
    const Vec2 d = dir(i);
    if (d.isZero()) continue;
    if (!last_dir.isZero()) join_at(pts[i], last_dir, d);
    last_dir = d;
  }
  if (closed) {
    join_at(pts[first], last_dir, dir(first));
    return;
  }
  // Caps: a half fan (round), or a fringe across the end (butt, square; the segment stops half a
  // pixel short of it).
  auto cap = [&](const Vec2& p, const Vec2& d) {  // d points outwards
    const Vec2 nr = perp(d);
    if (st.cap == LineCap::Round) {
      auto [cnt, f] = round_dirs(nr, cross2(nr, d) > 0 ? M_PI : -M_PI);
      fringed_fan(out, p, cnt, f, core, outer, col);
      return;
    }
    const Vec2 e = p + d * ((st.cap == LineCap::Square ? st.half_width : 0.0) - 0.5);
    fringed_strip(out, e, e + d, nr, core, outer, col, clear);
  };
  cap(pts[first], -dir(first));
  size_t last_end = (last + 1) % n;
  cap(pts[last_end], dir(last));
}

}  // namespace

CharacterMesh prepare_mesh(const Character& ch) {
  CharacterMesh m;
  m.shapes.resize(ch.shapes.size());
  for (size_t i = 0; i < ch.shapes.size(); ++i) {
    const SubShape& s = ch.shapes[i];
    if (!s.fill.enabled) continue;
    const std::vector<Ring> rings = s.rings();
    m.shapes[i].fill = triangulate_fill(s.points, rings, s.fill.rule);
    m.shapes[i].outline = fill_outline(m.shapes[i].fill);
    if (s.fill.texture) {
      for (const Vec2& v : m.shapes[i].fill.vertices) {
        // SDL_RenderGeometry rejects a whole call for one coordinate outside [0, 1],
        // and rounding (or an outline traced half a pixel past the border) gets there.
        const Vec2 uv = s.fill.uv_from_point.apply(v).cwiseMax(Vec2(0, 0)).cwiseMin(Vec2(1, 1));
        m.shapes[i].uv.push_back({static_cast<float>(uv.x()), static_cast<float>(uv.y())});
      }
    }
  }
  return m;
}

void stroke_polyline(std::span<const Vec2> pts, bool closed, const StrokeStyle& st, SDL_Color col,
                     DrawList& out) {
  const size_t n = pts.size();
  if (n < 2 || st.half_width <= 0) return;
  if (out.fringe) return stroke_with_fringe(pts, closed, st, col, out);
  const double hw = st.half_width;
  const size_t nseg = closed ? n : n - 1;
  // Segment directions (zero-length segments get a zero direction and are skipped).
  auto dir = [&](size_t i) -> Vec2 {
    const Vec2 d = pts[(i + 1) % n] - pts[i];
    const double len = d.norm();
    return len > 1e-12 ? Vec2(d / len) : Vec2(Vec2::Zero());
  };
  for (size_t i = 0; i < nseg; ++i) {
    const Vec2 d = dir(i);
    if (d.isZero()) continue;
    const Vec2 a = pts[i], b = pts[(i + 1) % n], nr = perp(d) * hw;
    const int i0 = push_vertex(out, a + nr, col), i1 = push_vertex(out, a - nr, col);
    const int i2 = push_vertex(out, b - nr, col), i3 = push_vertex(out, b + nr, col);
    tri(out, i0, i1, i2);
    tri(out, i0, i2, i3);
  }
  // Joins: between the last non-degenerate incoming and the next outgoing direction.
  auto join_at = [&](const Vec2& p, const Vec2& d0, const Vec2& d1) {
    const double cross = d0.x() * d1.y() - d0.y() * d1.x();
    const double dot = d0.dot(d1);
    if (std::abs(cross) < 1e-9 && dot > 0) return;  // straight on
    const double s = cross > 0 ? -1.0 : 1.0;       // outer side
    const Vec2 o0 = p + s * hw * perp(d0), o1 = p + s * hw * perp(d1);
    switch (st.join) {
      case LineJoin::Round: {
        // Arc from o0 to o1 the short way round the outside; a full reversal goes
        // around the far side (through p + d0 * hw).
        const double a0 = std::atan2(o0.y() - p.y(), o0.x() - p.x());
        const double a1 = std::atan2(o1.y() - p.y(), o1.x() - p.x());
        double delta = a1 - a0;
        while (delta > M_PI) delta -= 2 * M_PI;
        while (delta < -M_PI) delta += 2 * M_PI;
        if (std::abs(cross) < 1e-9) {
          const Vec2 r0 = o0 - p;
          delta = (r0.x() * d0.y() - r0.y() * d0.x()) > 0 ? M_PI : -M_PI;
        }
        fan(out, p, hw, a0, delta, st.tolerance, col);
        return;
      }
      case LineJoin::Miter: {
        // SVG: miter length / stroke width = 1 / sin(theta / 2), theta = angle between
        // the segments; cos of the turn angle = dot.
        const double sin_half = std::sqrt(std::max(0.0, (1.0 + dot) / 2.0));
        if (sin_half > 1e-9 && 1.0 / sin_half <= st.miter_limit) {
          Vec2 m = perp(d0) + perp(d1);
          const double ml = m.norm();
          if (ml > 1e-12) {
            const Vec2 tip = p + s * (m / ml) * (hw / sin_half);
            const int ic = push_vertex(out, p, col), ia = push_vertex(out, o0, col);
            const int it = push_vertex(out, tip, col), ib = push_vertex(out, o1, col);
            tri(out, ic, ia, it);
            tri(out, ic, it, ib);
            return;
          }
        }
        [[fallthrough]];
      }
      case LineJoin::Bevel: {
        const int ic = push_vertex(out, p, col), ia = push_vertex(out, o0, col), ib = push_vertex(out, o1, col);
        tri(out, ic, ia, ib);
        return;
      }
    }
  };
  // Walk vertices with valid in/out directions.
  Vec2 first_dir = Vec2::Zero(), last_dir = Vec2::Zero();
  size_t first_vertex = 0;
  for (size_t i = 0; i < nseg; ++i) {
    const Vec2 d = dir(i);
    if (d.isZero()) continue;
    if (first_dir.isZero()) {
      first_dir = d;
      first_vertex = i;
    } else {
      join_at(pts[i], last_dir, d);
    }
    last_dir = d;
  }
  if (first_dir.isZero()) {
    // All points coincide: a dot, drawn by round or square caps only.
    if (st.cap == LineCap::Round) fan(out, pts[0], hw, 0, 2 * M_PI, st.tolerance, col);
    if (st.cap == LineCap::Square) {
      const Vec2 p = pts[0];
      const int a = push_vertex(out, p + Vec2(-hw, -hw), col), b = push_vertex(out, p + Vec2(hw, -hw), col);
      const int c = push_vertex(out, p + Vec2(hw, hw), col), d = push_vertex(out, p + Vec2(-hw, hw), col);
      tri(out, a, b, c);
      tri(out, a, c, d);
    }
    return;
  }
  if (closed) {
    join_at(pts[first_vertex], last_dir, first_dir);
    return;
  }
  // Caps at both ends.
  auto cap = [&](const Vec2& p, const Vec2& d) {  // d points outwards
    if (st.cap == LineCap::Butt) return;
    const Vec2 nr = perp(d) * hw;
    if (st.cap == LineCap::Square) {
      const int a = push_vertex(out, p + nr, col), b = push_vertex(out, p - nr, col);
      const int c = push_vertex(out, p - nr + d * hw, col), e = push_vertex(out, p + nr + d * hw, col);
      tri(out, a, b, c);
      tri(out, a, c, e);
    } else {
      const double a0 = std::atan2(nr.y(), nr.x());
      // from +n through d to -n: the sweep direction that passes d
      const double cross = nr.x() * d.y() - nr.y() * d.x();
      fan(out, p, hw, a0, cross > 0 ? M_PI : -M_PI, st.tolerance, col);
    }
  };
  cap(pts[first_vertex], -first_dir);
  // last non-degenerate segment end
  size_t last_end = n - 1;
  while (last_end > 0 && (pts[last_end] - pts[last_end - 1]).norm() <= 1e-12) --last_end;
  cap(pts[last_end], last_dir);
}

namespace {

// A textured stroke (a gradient): each of its vertices (from `first_vertex` on, in pixels) takes
// the texture coordinates of the rest point it stands for — through the view's inverse, and
// for a deformed shape through the affine map that best fits its deformation back to rest.
void texture_stroke(const SubShape& s, std::span<const Vec2> pts, const Affine2& view, size_t first_vertex, DrawList& out) {
  Affine2 to_rest = view.inverse();
  if (pts.data() != s.points.data()) to_rest = affine_fit(pts, s.points) * to_rest;
  const Affine2 uv = s.stroke.uv_from_point * to_rest;
  for (size_t v = first_vertex; v < out.vertices.size(); ++v) {
    SDL_Vertex& x = out.vertices[v];
    const Vec2 t = uv.apply(Vec2(x.position.x, x.position.y));
    x.tex_coord = {std::clamp(float(t.x()), 0.0f, 1.0f), std::clamp(float(t.y()), 0.0f, 1.0f)};
    // The GPU's textures are premultiplied, and so are its modulation colours (DrawList::fringe).
    if (out.fringe) x.color = {Uint8(x.color.r * x.color.a / 255), Uint8(x.color.g * x.color.a / 255), Uint8(x.color.b * x.color.a / 255), x.color.a};
  }
}

// A dashed stroke: the contour `c` of `s` (its points in pixels: `px`) cut where the dash
// pattern says, measured along the rest outline, so that a dash stretches with its stretch of
// outline. Each dash is stroked as an open polyline.
void stroke_dashes(const SubShape& s, const Contour& c, std::span<const Vec2> px, const StrokeStyle& st, SDL_Color col, DrawList& out) {
  const std::vector<double>& dash = s.stroke.dashes;
  double period = 0;
  for (double d : dash) period += d;
  if (!(period > 0)) return;
  // Where the pattern is at the contour's start.
  double at = std::fmod(s.stroke.dash_offset, period);
  if (at < 0) at += period;
  size_t k = 0;
  for (size_t guard = 0; at >= dash[k] && guard < dash.size(); ++guard) {
    at -= dash[k];
    k = (k + 1) % dash.size();
  }
  double left = dash[k] - at;  // of the current dash (even k) or gap (odd k)
  auto& piece = out.dash_scratch;
  piece.clear();
  if (k % 2 == 0) piece.push_back(px[0]);
  const int segments = c.count - (c.stroke_closed() ? 0 : 1);
  for (int j = 0; j < segments; ++j) {
    const size_t i0 = size_t(j), i1 = size_t((j + 1) % c.count);
    const Vec2 &a = px[i0], &b = px[i1];
    const double len = (s.points[size_t(c.begin) + i1] - s.points[size_t(c.begin) + i0]).norm();
    double done = 0;  // of this segment, in rest units
    while (len - done > left) {
      done += left;
      const Vec2 p = a + (b - a) * (done / len);
      if (k % 2 == 0) {
        piece.push_back(p);
        if (piece.size() >= 2) stroke_polyline(piece, false, st, col, out);
        piece.clear();
      } else {
        piece.clear();
        piece.push_back(p);
      }
      k = (k + 1) % dash.size();
      left = dash[k];
    }
    left -= len - done;
    if (k % 2 == 0) piece.push_back(b);
  }
  if (k % 2 == 0 && piece.size() >= 2) stroke_polyline(piece, false, st, col, out);
}

// One shape's fill and stroke, in its paint order; a clip shape as its fill alone, opaque white
// (the clip is the union of its shapes' coverage).
void draw_shape(const SubShape& s, const ShapeMesh* mesh, std::span<const Vec2> pts, const Affine2& view, double tolerance_px,
                float alpha, DrawList& out) {
  const double scale = std::sqrt(std::abs(view.det()));
  const bool clip = s.role == ShapeRole::Clip;
  auto draw_fill = [&] {
    if ((s.fill.enabled || clip) && mesh && !mesh->fill.triangles.empty()) {
      const ShapeMesh& sm = *mesh;
      const Texture* tex = clip ? nullptr : s.fill.texture.get();
      const SDL_Color col = clip ? SDL_Color{255, 255, 255, 255} : to_sdl(s.fill.color, s.fill.opacity * alpha);
      begin_batch(out, tex);
      out.item_starts.push_back(static_cast<int>(out.indices.size()));
      const int base = static_cast<int>(out.vertices.size());
      const size_t nv = sm.fill.vertices.size();
      out.scratch.resize(nv);
      fill_mesh_positions(sm.fill, pts, out.scratch);
      for (Vec2& v : out.scratch) v = view.apply(v);
      const int outline_begin = static_cast<int>(out.outline.size());
      if (out.fringe) {
        fill_with_fringe(sm, out.scratch, col, tex != nullptr, out);
      } else {
        for (size_t v = 0; v < nv; ++v) push_vertex(out, out.scratch[v], col, tex ? sm.uv[v] : SDL_FPoint{0, 0});
        for (int idx : sm.fill.triangles) out.indices.push_back(base + idx);
        // The outline stands for the triangles while none is turned over (counter-clockwise
        // at rest, as the view keeps or mirrors them).
        const double sign = view.det() < 0 ? -1.0 : 1.0;
        bool folded = false;
        const auto& t = sm.fill.triangles;
        for (size_t k = 0; k + 2 < t.size() && !folded; k += 3) {
          const Vec2 &a = out.scratch[size_t(t[k])], &b = out.scratch[size_t(t[k + 1])], &c = out.scratch[size_t(t[k + 2])];
          folded = !(sign * ((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x())) >= 0);
        }
        if (!folded)
          for (const auto& e : sm.outline) {
            out.outline.push_back(base + e[0]);
            out.outline.push_back(base + e[1]);
          }
      }
      out.item_outline.push_back({outline_begin, static_cast<int>(out.outline.size())});
      end_batch(out);
    }
  };
  auto draw_stroke = [&] {
    if (s.stroke.enabled && !clip) {
      StrokeStyle st;
      st.half_width = 0.5 * s.stroke.width * scale;
      st.join = s.stroke.join;
      st.cap = s.stroke.cap;
      st.miter_limit = s.stroke.miter_limit;
      st.tolerance = tolerance_px;
      const SDL_Color col = to_sdl(s.stroke.color, s.stroke.opacity * alpha);
      const Texture* tex = s.stroke.texture.get();
      begin_batch(out, tex);
      out.item_starts.push_back(static_cast<int>(out.indices.size()));
      out.item_outline.push_back({static_cast<int>(out.outline.size()), static_cast<int>(out.outline.size())});
      const size_t first_vertex = out.vertices.size();
      // A pen wider one way than the other (Stroke::pen): stroke round in its space, then take
      // the outline back; the pen turns with the shape (the linear part of the affine map that
      // best fits its deformation) and with the view.
      Affine2 pen, from_pen;
      const bool shaped = !s.stroke.round_pen();
      if (shaped) {
        Affine2 moved;
        if (pts.data() != s.points.data()) moved = affine_fit(s.points, pts);
        pen = view * moved * s.stroke.pen;
        pen.e = pen.f = 0;
        const double k = std::sqrt(std::abs(pen.det()));
        if (k > 1e-12 && std::isfinite(k)) {
          pen = Affine2{pen.a / k, pen.b / k, pen.c / k, pen.d / k, 0, 0};
          from_pen = pen.inverse();
        } else {
          pen = from_pen = Affine2{};
        }
      }
      for (const Contour& c : s.contours) {
        if (c.count < 2) continue;  // an interior point (a solver's mesh vertex), not a line
        out.scratch.resize(static_cast<size_t>(c.count));
        for (int k = 0; k < c.count; ++k)
          out.scratch[static_cast<size_t>(k)] = from_pen.apply(view.apply(pts[static_cast<size_t>(c.begin + k)]));
        const size_t from = out.vertices.size();
        if (s.stroke.dashes.empty()) stroke_polyline(out.scratch, c.stroke_closed(), st, col, out);
        else stroke_dashes(s, c, out.scratch, st, col, out);
        if (shaped)
          for (size_t v = from; v < out.vertices.size(); ++v) {
            SDL_FPoint& q = out.vertices[v].position;
            const Vec2 p = pen.apply(Vec2(q.x, q.y));
            q = {float(p.x()), float(p.y())};
          }
      }
      if (tex) texture_stroke(s, pts, view, first_vertex, out);
      end_batch(out);
    }
  };
  if (s.stroke.under_fill) {
    draw_stroke();
    draw_fill();
  } else {
    draw_fill();
    draw_stroke();
  }
}

// The affine map that best takes a composite's shapes at rest to where they are now.
Affine2 part_motion(const Character& ch, std::span<const Points> positions, const Composite& c) {
  AffineFit fit;
  for (int k = std::max(0, c.first); k < c.end && size_t(k) < std::min(ch.shapes.size(), positions.size()); ++k) {
    const Points &rest = ch.shapes[size_t(k)].points, &now = positions[size_t(k)];
    if (rest.size() == now.size())
      for (size_t i = 0; i < rest.size(); ++i) fit.add(rest[i], now[i]);
  }
  return fit.result();
}

}  // namespace

void build_draw_list(const Character& ch, const CharacterMesh& mesh,
                     std::span<const Points> positions, const Affine2& view, double tolerance_px,
                     DrawList& out, std::span<const char> shown, float opacity) {
  // The whole drawing at `opacity`: a layer round it (outside every layer of its own), or on the
  // GPU's list the factor in every shape's alpha.
  const bool whole = opacity < 1.0f && !out.fringe;
  const size_t whole_at = out.layers.size();
  if (whole) {
    DrawList::Layer l;
    l.begin = static_cast<int>(out.indices.size());
    l.opacity = std::max(0.0f, opacity);
    out.layers.push_back(l);
  }
  auto draw = [&](size_t i) {
    const SubShape& s = ch.shapes[i];
    const Points& pts = positions.empty() ? s.points : positions[i];
    if (pts.size() != s.points.size()) return;
    float alpha = out.fringe ? std::clamp(opacity, 0.0f, 1.0f) : 1.0f;
    for (const auto& [end, a] : out.alpha_stack)
      if (size_t(end) > i) alpha *= a;
    draw_shape(s, i < mesh.shapes.size() ? &mesh.shapes[i] : nullptr, pts, view, tolerance_px, alpha, out);
  };
  // Layers (Character::composites): opened where their first shape is, closed after their last,
  // with their clip and mask shapes drawn then.
  const auto& comps = ch.composites;
  auto& open = out.layer_stack;
  open.clear();
  size_t next = 0;
  auto close_through = [&](size_t i) {
    while (!open.empty() && size_t(comps[size_t(out.layers[size_t(open.back())].composite)].end) <= i) {
      DrawList::Layer& layer = out.layers[size_t(open.back())];
      open.pop_back();
      const Composite& c = comps[size_t(layer.composite)];
      layer.content_end = static_cast<int>(out.indices.size());
      for (int k : c.clip) draw(size_t(k));
      layer.clip_end = static_cast<int>(out.indices.size());
      for (int k : c.mask) draw(size_t(k));
      layer.mask_end = static_cast<int>(out.indices.size());
    }
  };
  const double scale = std::sqrt(std::abs(view.det()));
  out.alpha_stack.clear();
  for (size_t i = 0; i <= ch.shapes.size(); ++i) {
    close_through(i);
    while (!out.alpha_stack.empty() && size_t(out.alpha_stack.back().first) <= i) out.alpha_stack.pop_back();
    for (; next < comps.size() && size_t(comps[next].first) <= i; ++next) {
      const Composite& c = comps[next];
      // (a layer that changes nothing is drawn straight; on the GPU's list, one that only has an
      // opacity has it multiplied into its shapes: a GPU draws no layers)
      const bool only_opacity = !(c.blur > 0) && c.offset.squaredNorm() == 0 && !c.shadow && c.clip.empty() && c.mask.empty();
      if (only_opacity && c.opacity >= 1.0f) continue;
      if (only_opacity && out.fringe) {
        out.alpha_stack.push_back({c.end, c.opacity});
        continue;
      }
      DrawList::Layer l;
      l.begin = static_cast<int>(out.indices.size());
      l.composite = static_cast<int>(next);
      l.opacity = c.opacity;
      // A blur and its shift go with the part: through the affine map that best fits its
      // shapes' deformation (a part drawn twice as large is blurred twice as far).
      Affine2 part;
      if (!positions.empty() && (c.blur > 0 || c.offset.squaredNorm() > 0)) part = part_motion(ch, positions, c);
      l.blur_px = static_cast<float>(c.blur * scale * std::sqrt(std::abs(part.det())));
      l.offset_px = view.apply_linear(part.apply_linear(c.offset));
      l.clipped = !c.clip.empty();
      l.masked = !c.mask.empty();
      l.mask_alpha = c.mask_alpha;
      l.shadow = c.shadow;
      l.shadow_color = to_sdl(c.shadow_color, 1.0f);
      out.layers.push_back(l);
      open.push_back(static_cast<int>(out.layers.size()) - 1);
      close_through(i);
    }
    if (i == ch.shapes.size()) break;
    // A swap member not showing, a trigger that is off; with no `shown`, an alternative the file
    // hides; a clip or mask shape (drawn with its layer).
    if (i < shown.size() ? !shown[i] : ch.shapes[i].hidden) continue;
    if (ch.shapes[i].role != ShapeRole::Paint) continue;
    draw(i);
  }
  close_through(ch.shapes.size() + 1);
  if (whole) {
    DrawList::Layer& l = out.layers[whole_at];
    l.content_end = l.clip_end = l.mask_end = static_cast<int>(out.indices.size());
  }
}

}  // namespace mar
