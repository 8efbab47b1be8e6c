// CGAL's Surface_mesh_deformation (ARAP, Sorkine & Alexa 2007) on a 2D triangle mesh set in
// the z = 0 plane: the reference the benches time our solvers against. Handles are the mesh
// vertices nearest the handles' rest points; every vertex is in the region of interest.
// CGAL's headers are compiled once, in cgal_arap.cpp (they took 40 s to compile in each benchmark that includes this).
#pragma once

#include "geom/types.h"

#include <array>
#include <memory>
#include <span>

namespace bench {

class CgalArap {
 public:
  CgalArap(std::span<const mar::Vec2> vertices, std::span<const std::array<int, 3>> triangles,
           std::span<const mar::Vec2> handle_rest);
  ~CgalArap();
  CgalArap(const CgalArap&) = delete;  // the deformation refers to the mesh
  CgalArap& operator=(const CgalArap&) = delete;
  /// One frame: the handles to `targets` (their vertices keep their offsets), then iterations.
  void frame(std::span<const mar::Vec2> targets, unsigned iterations);
  size_t vertices() const;
  size_t faces() const;
  double preprocess_ms() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bench
