// CGAL's straight skeleton, its second translation unit (triangulate.cpp is the first).
#include "geom/skeleton.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/create_straight_skeleton_from_polygon_with_holes_2.h>

#include <map>

namespace mar {

namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polygon = CGAL::Polygon_2<K>;
using PolygonWithHoles = CGAL::Polygon_with_holes_2<K>;

Polygon polygon_of(std::span<const Vec2> ring) {
  Polygon p;
  for (const Vec2& v : ring) p.push_back(K::Point_2(v.x(), v.y()));
  return p;
}
}  // namespace

SkeletonGraph straight_skeleton(std::span<const Vec2> outer, std::span<const Points> holes, size_t max_vertices) {
  SkeletonGraph g;
  size_t total = outer.size();
  for (const Points& h : holes) total += h.size();
  if (outer.size() < 3) {
    g.error = "an outline of fewer than 3 points";
    return g;
  }
  if (total > max_vertices) {
    g.error = "an outline of " + std::to_string(total) + " points (at most " + std::to_string(max_vertices) + ")";
    return g;
  }
  Polygon o = polygon_of(outer);
  if (!o.is_simple()) {
    g.error = "an outline that crosses itself";
    return g;
  }
  if (o.is_clockwise_oriented()) o.reverse_orientation();
  PolygonWithHoles pwh(o);
  for (const Points& h : holes) {
    if (h.size() < 3) continue;
    Polygon p = polygon_of(h);
    if (!p.is_simple()) continue;  // (a hole that crosses itself is left out)
    if (p.is_counterclockwise_oriented()) p.reverse_orientation();
    bool inside = true;
    for (const auto& v : p.vertices()) inside = inside && o.bounded_side(v) == CGAL::ON_BOUNDED_SIDE;
    if (inside) pwh.add_hole(p);
  }
  const auto ss = CGAL::create_interior_straight_skeleton_2(pwh);
  if (!ss) {
    g.error = "no skeleton could be made of the outline";
    return g;
  }
  std::map<const void*, int> index;
  auto node = [&](const auto& v) {
    const void* key = &*v;
    auto [it, fresh] = index.try_emplace(key, int(g.nodes.size()));
    if (fresh) {
      g.nodes.emplace_back(CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()));
      g.radius.push_back(CGAL::to_double(v->time()));
    }
    return it->second;
  };
  for (auto h = ss->halfedges_begin(); h != ss->halfedges_end(); ++h) {
    if (!h->is_inner_bisector()) continue;
    const auto a = h->opposite()->vertex(), b = h->vertex();
    if (&*a > &*b) continue;  // (each edge once, from one of its two halves)
    g.edges.emplace_back(node(a), node(b));
  }
  return g;
}

}  // namespace mar
