// The single CGAL translation unit of the project.
#include "geom/triangulate.h"

#include "geom/polygon.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_face_base_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <queue>
#include <unordered_map>

namespace mar {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
// 1-based index of the input point; 0 marks an intersection (Steiner) vertex. A struct
// with an initialiser, because CGAL leaves a plain int info uninitialised.
struct VertexInfo {
  int index = 0;
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, K>;
struct FaceInfo {
  int winding = 0;
  bool seen = false;
};
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact_predicates_tag: crossing constraints are allowed; their intersection points
// are computed (approximately) and inserted as new vertices.
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
using CDTP = CGAL::Constrained_triangulation_plus_2<CDT>;
using VH = CDTP::Vertex_handle;

// Net number of constraint traversals u->w minus w->u over the sub-constraint (u, w).
int directed_multiplicity(const CDTP& cdt, VH u, VH w) {
  int net = 0;
  for (auto it = cdt.contexts_begin(u, w); it != cdt.contexts_end(u, w); ++it) {
    auto cur = it->current();
    auto nxt = std::next(cur);
    if (nxt == it->vertices_end()) continue;
    if (*cur == u && *nxt == w) {
      ++net;
    } else if (*cur == w && *nxt == u) {
      --net;
    }
  }
  return net;
}

}  // namespace

FillMesh triangulate_fill(std::span<const Vec2> points, std::span<const Ring> rings,
                          FillRule rule) {
  FillMesh mesh;
  CDTP cdt;
  for (const Ring& r : rings) {
    if (r.begin < 0 || static_cast<size_t>(r.begin + r.count) > points.size()) continue;
    if (r.count == 1) {  // an interior point: a vertex of the fill, no edge
      const Vec2& p = points[static_cast<size_t>(r.begin)];
      if (p.allFinite()) cdt.insert(K::Point_2(p.x(), p.y()))->info().index = r.begin + 1;
      continue;
    }
    if (r.count < 3) continue;
    std::vector<VH> handles;
    handles.reserve(static_cast<size_t>(r.count));
    for (int k = 0; k < r.count; ++k) {
      const Vec2& p = points[static_cast<size_t>(r.begin + k)];
      if (!p.allFinite()) continue;
      VH vh = cdt.insert(K::Point_2(p.x(), p.y()));
      vh->info().index = r.begin + k + 1;  // 1-based; 0 = Steiner (intersection) vertex
      if (handles.empty() || handles.back() != vh) handles.push_back(vh);
    }
    while (handles.size() > 1 && handles.back() == handles.front()) handles.pop_back();
    if (handles.size() < 2) continue;
    // Each edge is its own two-vertex constraint: direction of traversal is then simply
    // the order of the pair, which the winding flood below relies on.
    for (size_t k = 0; k < handles.size(); ++k) {
      VH a = handles[k], b = handles[(k + 1) % handles.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  if (cdt.dimension() < 2) return mesh;

  // Flood the winding number from the infinite faces across edges; crossing a
  // constrained edge from its left side to its right side lowers the winding by the
  // net number of contours running along it.
  std::queue<CDTP::Face_handle> queue;
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
    f->info() = FaceInfo{};
  }
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) {
    if (cdt.is_infinite(f)) {
      f->info().seen = true;
      queue.push(f);
    }
  }
  while (!queue.empty()) {
    auto f = queue.front();
    queue.pop();
    for (int i = 0; i < 3; ++i) {
      auto g = f->neighbor(i);
      if (g->info().seen) continue;
      int w = f->info().winding;
      if (cdt.is_constrained(CDTP::Edge(f, i))) {
        VH u = f->vertex(CDTP::ccw(i)), v = f->vertex(CDTP::cw(i));
        // f lies to the left of u->v.
        w -= directed_multiplicity(cdt, u, v);
      }
      g->info().winding = w;
      g->info().seen = true;
      queue.push(g);
    }
  }

  // Collect vertices of filled faces.
  std::unordered_map<const void*, int> index;
  auto vertex_index = [&](VH vh) {
    auto [it, fresh] = index.try_emplace(&*vh, static_cast<int>(mesh.vertices.size()));
    if (!fresh) return it->second;
    const Vec2 p(vh->point().x(), vh->point().y());
    mesh.vertices.push_back(p);
    if (vh->info().index > 0) {
      mesh.src_a.push_back(vh->info().index - 1);
      mesh.src_b.push_back(vh->info().index - 1);
      mesh.src_t.push_back(0.0);
    } else {
      // Intersection point: express it on the nearest input segment.
      int best_a = 0, best_b = 0;
      double best_d = std::numeric_limits<double>::infinity(), best_t = 0;
      for (const Ring& r : rings) {
        for (int k = 0; k < r.count; ++k) {
          const int ia = r.begin + k, ib = r.begin + (k + 1) % r.count;
          const Vec2& a = points[static_cast<size_t>(ia)];
          const Vec2& b = points[static_cast<size_t>(ib)];
          const double d = point_segment_distance(p, a, b);
          if (d < best_d) {
            const double len2 = (b - a).squaredNorm();
            best_d = d;
            best_a = ia;
            best_b = ib;
            best_t = len2 > 0 ? std::clamp((p - a).dot(b - a) / len2, 0.0, 1.0) : 0.0;
          }
        }
      }
      mesh.src_a.push_back(best_a);
      mesh.src_b.push_back(best_b);
      mesh.src_t.push_back(best_t);
    }
    return it->second;
  };
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    const int w = f->info().winding;
    const bool filled = rule == FillRule::NonZero ? w != 0 : (w % 2) != 0;
    if (!filled) continue;
    for (int i = 0; i < 3; ++i) mesh.triangles.push_back(vertex_index(f->vertex(i)));
  }
  return mesh;
}

HullMesh triangulate_hull(std::span<const Vec2> points, std::span<const Ring> rings, std::span<const char> closed) {
  HullMesh out;
  CDTP cdt;
  for (size_t r = 0; r < rings.size(); ++r) {
    const Ring& ring = rings[r];
    std::vector<VH> hs;
    for (int k = 0; k < ring.count; ++k) {
      const Vec2& p = points[static_cast<size_t>(ring.begin + k)];
      if (p.allFinite()) hs.push_back(cdt.insert(K::Point_2(p.x(), p.y())));
    }
    const bool close = r < closed.size() && closed[r];
    for (size_t k = 0; k + 1 < hs.size() || (close && k < hs.size() && hs.size() > 2); ++k) {
      VH a = hs[k], b = hs[(k + 1) % hs.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  std::unordered_map<const void*, int> index;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    index[&*v] = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back(v->point().x(), v->point().y());
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    for (int i = 0; i < 3; ++i) out.triangles.push_back(index[&*f->vertex(i)]);
  }
  return out;
}

void fill_mesh_positions(const FillMesh& mesh, std::span<const Vec2> points, std::span<Vec2> out) {
  const size_t n = mesh.vertices.size();
  for (size_t i = 0; i < n && i < out.size(); ++i) {
    const Vec2& a = points[static_cast<size_t>(mesh.src_a[i])];
    const Vec2& b = points[static_cast<size_t>(mesh.src_b[i])];
    out[i] = a + mesh.src_t[i] * (b - a);
  }
}

double fill_mesh_area(const FillMesh& mesh) {
  double area = 0;
  for (size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const Vec2& a = mesh.vertices[static_cast<size_t>(mesh.triangles[t])];
    const Vec2& b = mesh.vertices[static_cast<size_t>(mesh.triangles[t + 1])];
    const Vec2& c = mesh.vertices[static_cast<size_t>(mesh.triangles[t + 2])];
    area += 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
  }
  return area;
}

}  // namespace mar
