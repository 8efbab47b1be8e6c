#include "cgal_arap.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>

#include <chrono>
#include <vector>

namespace bench {

struct CgalArap::Impl {
  using Kernel = CGAL::Simple_cartesian<double>;
  using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
  using VD = boost::graph_traits<Mesh>::vertex_descriptor;
  using Deform = CGAL::Surface_mesh_deformation<Mesh>;

  Mesh mesh;
  std::vector<VD> controls;
  std::vector<mar::Vec2> offset;
  std::unique_ptr<Deform> deform;
  double preprocess_ms = 0;
};

CgalArap::CgalArap(std::span<const mar::Vec2> vertices, std::span<const std::array<int, 3>> triangles,
                   std::span<const mar::Vec2> handle_rest)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  std::vector<Impl::VD> vds;
  for (const mar::Vec2& p : vertices) vds.push_back(m.mesh.add_vertex(Impl::Kernel::Point_3(p.x(), p.y(), 0)));
  for (const auto& t : triangles) m.mesh.add_face(vds[size_t(t[0])], vds[size_t(t[1])], vds[size_t(t[2])]);
  for (const mar::Vec2& h : handle_rest) {
    size_t best = 0;
    for (size_t i = 0; i < vertices.size(); ++i)
      if ((vertices[i] - h).squaredNorm() < (vertices[best] - h).squaredNorm()) best = i;
    m.controls.push_back(vds[best]);
    m.offset.push_back(vertices[best] - h);
  }
  m.deform = std::make_unique<Impl::Deform>(m.mesh);
  m.deform->insert_roi_vertices(CGAL::vertices(m.mesh).begin(), CGAL::vertices(m.mesh).end());
  for (Impl::VD v : m.controls) m.deform->insert_control_vertex(v);
  const auto t0 = std::chrono::steady_clock::now();
  m.deform->preprocess();
  m.preprocess_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

CgalArap::~CgalArap() = default;

void CgalArap::frame(std::span<const mar::Vec2> targets, unsigned iterations) {
  Impl& m = *impl_;
  for (size_t h = 0; h < m.controls.size() && h < targets.size(); ++h) {
    const mar::Vec2 p = targets[h] + m.offset[h];
    m.deform->set_target_position(m.controls[h], Impl::Kernel::Point_3(p.x(), p.y(), 0));
  }
  m.deform->deform(iterations, 0.0);
}

size_t CgalArap::vertices() const { return impl_->mesh.number_of_vertices(); }
size_t CgalArap::faces() const { return impl_->mesh.number_of_faces(); }
double CgalArap::preprocess_ms() const { return impl_->preprocess_ms; }

}  // namespace bench
