// CGAL's Surface_mesh_deformation (ARAP, Sorkine & Alexa 2007) on a 2D triangle mesh set in
// the z = 0 plane: the reference the benches time our solvers against. Handles are the mesh
// vertices nearest the handles' rest points; every vertex is in the region of interest.
#pragma once

#include "geom/types.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>

#include <array>
#include <chrono>
#include <memory>
#include <span>
#include <vector>

namespace bench {

class CgalArap {
 public:
  using Kernel = CGAL::Simple_cartesian<double>;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  using VD = boost::graph_traits<Mesh>::vertex_descriptor;
  using Deform = CGAL::Surface_mesh_deformation<Mesh>;

  CgalArap(std::span<const mar::Vec2> vertices, std::span<const std::array<int, 3>> triangles,
           std::span<const mar::Vec2> handle_rest) {
    std::vector<VD> vds;
    for (const mar::Vec2& p : vertices) vds.push_back(mesh_.add_vertex(Kernel::Point_3(p.x(), p.y(), 0)));
    for (const auto& t : triangles) mesh_.add_face(vds[size_t(t[0])], vds[size_t(t[1])], vds[size_t(t[2])]);
    for (const mar::Vec2& h : handle_rest) {
      size_t best = 0;
      for (size_t i = 0; i < vertices.size(); ++i)
        if ((vertices[i] - h).squaredNorm() < (vertices[best] - h).squaredNorm()) best = i;
      controls_.push_back(vds[best]);
      offset_.push_back(vertices[best] - h);
    }
    deform_ = std::make_unique<Deform>(mesh_);
    deform_->insert_roi_vertices(CGAL::vertices(mesh_).begin(), CGAL::vertices(mesh_).end());
    for (VD v : controls_) deform_->insert_control_vertex(v);
    const auto t0 = std::chrono::steady_clock::now();
    deform_->preprocess();
    preprocess_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }
  CgalArap(const CgalArap&) = delete;  // the deformation refers to the mesh
  CgalArap& operator=(const CgalArap&) = delete;
  /// One frame: the handles to `targets` (their vertices keep their offsets), then iterations.
  void frame(std::span<const mar::Vec2> targets, unsigned iterations) {
    for (size_t h = 0; h < controls_.size() && h < targets.size(); ++h) {
      const mar::Vec2 p = targets[h] + offset_[h];
      deform_->set_target_position(controls_[h], Kernel::Point_3(p.x(), p.y(), 0));
    }
    deform_->deform(iterations, 0.0);
  }
  size_t vertices() const { return mesh_.number_of_vertices(); }
  size_t faces() const { return mesh_.number_of_faces(); }
  double preprocess_ms() const { return preprocess_ms_; }

 private:
  Mesh mesh_;
  std::vector<VD> controls_;
  std::vector<mar::Vec2> offset_;
  std::unique_ptr<Deform> deform_;
  double preprocess_ms_ = 0;
};

}  // namespace bench
