#include "render/overlay.h"

#include <cmath>
#include <vector>

namespace mar {

namespace {
// The overlay's triangles as one untextured batch (merged into the last if it is one).
void close_batch(DrawList& out, int first) {
  if (!out.batches.empty() && out.batches.back().texture == nullptr) {
    out.batches.back().index_count = static_cast<int>(out.indices.size()) - out.batches.back().first_index;
  } else {
    out.batches.push_back({nullptr, first, static_cast<int>(out.indices.size()) - first});
  }
}

// Vertices as dots, then handles as rings over them.
void dots_and_rings(std::span<const Vec2> v, const StrokeStyle& dot, SDL_Color point, std::span<const Vec2> handles,
                    const StrokeStyle& ring, SDL_Color handle, const Affine2& view, DrawList& out) {
  Vec2 seg[2];
  for (const Vec2& p : v) {
    seg[0] = seg[1] = view.apply(p);
    stroke_polyline(seg, false, dot, point, out);
  }
  for (const Vec2& h : handles) {
    seg[0] = seg[1] = view.apply(h);
    stroke_polyline(seg, false, ring, handle, out);
  }
}
}  // namespace

void append_frame_overlay(const FeatureFrame& frame, std::span<const Vec2> v, std::span<const Vec2> handles,
                          const Affine2& view, DrawList& out) {
  const int first = static_cast<int>(out.indices.size());
  StrokeStyle thin, thick, user, dot, ring;
  thin.half_width = 1.0;
  thick.half_width = 2.0;
  user.half_width = 2.0;
  thin.cap = thick.cap = user.cap = LineCap::Round;
  dot.half_width = 3.5;
  dot.cap = LineCap::Round;
  ring.half_width = 6.0;
  ring.cap = LineCap::Round;
  const SDL_Color feature{40, 90, 220, 255}, sewing{240, 140, 0, 255}, usersew{220, 30, 30, 255},
      point{20, 20, 20, 255}, handle{0, 170, 80, 200}, spoke{150, 150, 150, 255}, joint{140, 40, 200, 230};
  Vec2 seg[2];
  for (size_t j = 0; j < frame.lines.size(); ++j) {
    const FrameLine& l = frame.lines[j];
    seg[0] = view.apply(v[static_cast<size_t>(l.a)]);
    seg[1] = view.apply(v[static_cast<size_t>(l.b)]);
    if (l.kind == FrameLine::Joint) continue;  // drawn as a ring below
    if (l.kind == FrameLine::Spoke || l.kind == FrameLine::Spring) {
      stroke_polyline(seg, false, thin, spoke, out);
      continue;
    }
    const bool is_feature = l.kind == FrameLine::Feature;
    stroke_polyline(seg, false, is_feature ? thin : (l.kind == FrameLine::UserSewing ? user : thick),
                    is_feature ? feature : (l.kind == FrameLine::UserSewing ? usersew : sewing), out);
  }
  // Hinges: a ring at each joint (purple), over the lines.
  StrokeStyle hinge = ring;
  hinge.half_width = 5.0;
  for (const FrameJoint& jt : frame.joints) {
    seg[0] = seg[1] = view.apply(v[static_cast<size_t>(jt.va)]);
    stroke_polyline(seg, false, hinge, joint, out);
  }
  dots_and_rings(v, dot, point, handles, ring, handle, view, out);
  close_batch(out, first);
}

void append_markers(std::span<const Vec2> handles, std::span<const Vec2> hinges, int selected, const Affine2& view, DrawList& out) {
  const int first = static_cast<int>(out.indices.size());
  StrokeStyle hinge, ring, big;
  hinge.half_width = 5.0;
  ring.half_width = 6.0;
  big.half_width = 8.0;
  hinge.cap = ring.cap = big.cap = LineCap::Round;
  const SDL_Color joint{140, 40, 200, 230}, handle{0, 170, 80, 220}, chosen{0, 110, 50, 240};
  Vec2 seg[2];
  for (const Vec2& h : hinges) {
    seg[0] = seg[1] = view.apply(h);
    stroke_polyline(seg, false, hinge, joint, out);
  }
  for (size_t i = 0; i < handles.size(); ++i) {
    seg[0] = seg[1] = view.apply(handles[i]);
    const bool sel = static_cast<int>(i) == selected;
    stroke_polyline(seg, false, sel ? big : ring, sel ? chosen : handle, out);
  }
  close_batch(out, first);
}

void append_pen_marks(const Vec2& at, double radius, std::span<const Vec2> stroke, const Affine2& view, DrawList& out) {
  const int first = static_cast<int>(out.indices.size());
  StrokeStyle line;
  line.half_width = 1.5;
  line.cap = LineCap::Round;
  if (radius > 0) {
    constexpr int kSides = 64;
    Vec2 ring[kSides];
    for (int i = 0; i < kSides; ++i) {
      const double a = 2 * M_PI * i / kSides;
      ring[i] = view.apply(at + radius * Vec2(std::cos(a), std::sin(a)));
    }
    stroke_polyline(ring, true, line, SDL_Color{200, 60, 40, 220}, out);
  }
  if (stroke.size() >= 2) {
    std::vector<Vec2> mapped(stroke.size());
    for (size_t i = 0; i < stroke.size(); ++i) mapped[i] = view.apply(stroke[i]);
    line.half_width = 2.0;
    stroke_polyline(mapped, false, line, SDL_Color{30, 90, 220, 230}, out);
  }
  close_batch(out, first);
}

void append_mesh_overlay(std::span<const Vec2> v, std::span<const std::array<int, 3>> triangles,
                         std::span<const Vec2> handles, const Affine2& view, DrawList& out) {
  const int first = static_cast<int>(out.indices.size());
  StrokeStyle edge, dot, ring;
  edge.half_width = 0.6;
  dot.half_width = 1.5;
  dot.cap = edge.cap = LineCap::Round;
  ring.half_width = 6.0;
  ring.cap = LineCap::Round;
  const SDL_Color line{90, 90, 110, 200}, point{20, 20, 20, 255}, handle{0, 170, 80, 200};
  Vec2 seg[2];
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      if (a > b) continue;  // each shared edge once (its other triangle has it the other way round)
      seg[0] = view.apply(v[size_t(a)]);
      seg[1] = view.apply(v[size_t(b)]);
      stroke_polyline(seg, false, edge, line, out);
    }
  dots_and_rings(v, dot, point, handles, ring, handle, view, out);
  close_batch(out, first);
}

void append_grid_overlay(std::span<const Vec2> v, size_t grid_count, std::span<const std::array<int, 2>> grid_edges,
                         std::span<const std::array<int, 3>> junction_triangles, std::span<const Vec2> handles,
                         const Affine2& view, DrawList& out) {
  const int first = static_cast<int>(out.indices.size());
  StrokeStyle edge, dot, ring;
  edge.half_width = 0.6;
  dot.half_width = 1.4;
  dot.cap = edge.cap = LineCap::Round;
  ring.half_width = 6.0;
  ring.cap = LineCap::Round;
  const SDL_Color grid{40, 90, 220, 220}, junction{235, 120, 20, 200}, boundary{150, 20, 30, 255}, handle{0, 170, 80, 200};
  Vec2 seg[2];
  for (const auto& t : junction_triangles)
    for (int k = 0; k < 3; ++k) {
      seg[0] = view.apply(v[size_t(t[size_t(k)])]);
      seg[1] = view.apply(v[size_t(t[size_t((k + 1) % 3)])]);
      stroke_polyline(seg, false, edge, junction, out);
    }
  for (const auto& e : grid_edges) {
    seg[0] = view.apply(v[size_t(e[0])]);
    seg[1] = view.apply(v[size_t(e[1])]);
    stroke_polyline(seg, false, edge, grid, out);
  }
  dots_and_rings(v.subspan(std::min(grid_count, v.size())), dot, boundary, handles, ring, handle, view, out);
  close_batch(out, first);
}

}  // namespace mar
