#include "render/tessellate.h"

#include <algorithm>
#include <cmath>

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

}  // namespace

CharacterMesh prepare_mesh(const Character& ch) {
  CharacterMesh m;
  m.shapes.resize(ch.shapes.size());
  for (size_t i = 0; i < ch.shapes.size(); ++i) {
    const SubShape& s = ch.shapes[i];
    if (!s.fill.enabled) continue;
    const std::vector<Ring> rings = s.rings();
    m.shapes[i].fill = triangulate_fill(s.points, rings, s.fill.rule);
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

void build_draw_list(const Character& ch, const CharacterMesh& mesh,
                     std::span<const Points> positions, const Affine2& view, double tolerance_px,
                     DrawList& out, std::span<const char> shown) {
  const double scale = std::sqrt(std::abs(view.det()));
  for (size_t i = 0; i < ch.shapes.size(); ++i) {
    if (i < shown.size() && !shown[i]) continue;  // a swap member not showing, a trigger that is off
    const SubShape& s = ch.shapes[i];
    const Points& pts = positions.empty() ? s.points : positions[i];
    if (pts.size() != s.points.size()) continue;
    if (s.fill.enabled && i < mesh.shapes.size() && !mesh.shapes[i].fill.triangles.empty()) {
      const ShapeMesh& sm = mesh.shapes[i];
      const Texture* tex = s.fill.texture.get();
      const SDL_Color col = to_sdl(s.fill.color, s.fill.opacity);
      begin_batch(out, tex);
      out.item_starts.push_back(static_cast<int>(out.indices.size()));
      const int base = static_cast<int>(out.vertices.size());
      const size_t nv = sm.fill.vertices.size();
      out.scratch.resize(nv);
      fill_mesh_positions(sm.fill, pts, out.scratch);
      for (size_t v = 0; v < nv; ++v) {
        push_vertex(out, view.apply(out.scratch[v]), col, tex ? sm.uv[v] : SDL_FPoint{0, 0});
      }
      for (int idx : sm.fill.triangles) out.indices.push_back(base + idx);
      end_batch(out);
    }
    if (s.stroke.enabled) {
      StrokeStyle st;
      st.half_width = 0.5 * s.stroke.width * scale;
      st.join = s.stroke.join;
      st.cap = s.stroke.cap;
      st.miter_limit = s.stroke.miter_limit;
      st.tolerance = tolerance_px;
      const SDL_Color col = to_sdl(s.stroke.color, s.stroke.opacity);
      begin_batch(out, nullptr);
      out.item_starts.push_back(static_cast<int>(out.indices.size()));
      for (const Contour& c : s.contours) {
        if (c.count < 2) continue;  // an interior point (a solver's mesh vertex), not a line
        out.scratch.resize(static_cast<size_t>(c.count));
        for (int k = 0; k < c.count; ++k) out.scratch[static_cast<size_t>(k)] = view.apply(pts[static_cast<size_t>(c.begin + k)]);
        stroke_polyline(out.scratch, c.closed, st, col, out);
      }
      end_batch(out);
    }
  }
}

}  // namespace mar
