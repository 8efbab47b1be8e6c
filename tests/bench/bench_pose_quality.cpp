// Pose quality: how naturally each solver poses a character when rigid groups of its parts
// (an arm about its shoulder, a head about its neck) are moved. A measurement, not a test.
//
// Cases come from tests/bench/poses/*.toml (format in that folder's README). For each pose,
// handles on moved parts get their group's motion as targets; the others stay at rest.
// Metrics, per sub-shape and as % of the character's height:
//   distortion    RMS residual of the part's best rigid fit (2D Procrustes) from rest to the
//                 solved points — how much the part's own shape was bent;
//   articulation  RMS distance from the articulated ideal (every part moved by its group).
// Per pose: worst part and mean over parts of both, the worst articulation of a passive
// part (one in no moved group), the worst handle residual, and NaN/Inf counts.
//
// Methods, side by side in one run:
//   ff-rest       feature frame from rest: the best of three starts (initial_guess: as is, rigid, articulated), then
//                 the rig's iteration count;
//   ff-live       a live drag: targets move along the groups' motion over 0.5 s at 120 Hz,
//                 warm start, the live iteration count (8, the demo show's);
//   ff-converged  feature frame from rest, 1,000 iterations;
//   cgal-arap     CGAL Surface_mesh_deformation (ARAP, converged) on a constrained
//                 triangulation of the single outline around the whole character, handles on
//                 the nearest mesh vertices (the baseline seeds 000 and 003 compare against);
//   grid-live     the same rig on the rigid grid (seed 003, solver = "rigid_grid"), a live drag
//                 as ff-live;
//   arap-live     the same rig on our outline ARAP baseline (solver = "arap"), a live drag;
//   auto-rest     the automatic rig (`marionette rig`, rig/auto_rig.h) of the same character
//                 instead of the hand rig, solved as ff-rest: its handles on moved parts get
//                 their group's motion;
//   auto-reach    the automatic rig again, each limb's group turned about the automatic rig's
//                 own hinge for it (the targets the limb can reach by turning about its joint),
//                 the articulated ideal turned about the same hinges.
// (The automatic rig is skipped for a one-region raster character: it has no parts to rig.)
// A raster character's case splits its one traced region into parts by polygons (`region`).
//
// Usage: bench_pose_quality [--case NAME] [--json FILE] [--grid CASE=out.png] [--smoke]
//        [Google Benchmark flags]. Timing of each method is reported by Google Benchmark.
#include "app/puppet.h"
#include "character/load.h"
#include "rig/auto_rig.h"
#include "geom/polygon.h"
#include "geom/triangulate.h"
#include "render/canvas.h"
#include "render/image.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>
#include <benchmark/benchmark.h>
#include <toml++/toml.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>

namespace {

namespace fs = std::filesystem;
using mar::Vec2;
using Points = mar::Points;

struct Group {
  std::string name;
  std::vector<int> parts;  ///< indices into PoseCase::parts
  Vec2 pivot = Vec2::Zero();
};

struct Move {
  int group = 0;
  double angle_deg = 0;
  Vec2 translate = Vec2::Zero();
  /// The group's rigid motion at fraction f of the way (f = 1: the pose).
  Vec2 apply(const std::vector<Group>& groups, const Vec2& p, double f) const {
    const double a = f * angle_deg * M_PI / 180;
    const Vec2 d = p - groups[static_cast<size_t>(group)].pivot;
    return groups[static_cast<size_t>(group)].pivot + Vec2(std::cos(a) * d.x() - std::sin(a) * d.y(),
                                                           std::sin(a) * d.x() + std::cos(a) * d.y()) +
           f * translate;
  }
};

struct Pose {
  std::string name;
  std::vector<Move> moves;
};

/// A measured piece of the character: a sub-shape, or (a raster character, one traced
/// region) the points of a sub-shape inside a group's `region` polygon.
struct Part {
  std::string name;
  int shape = 0;
  std::vector<int> points;
};

struct PoseCase {
  std::string name;
  std::unique_ptr<mar::Puppet> puppet;                ///< the feature frame
  std::unique_ptr<mar::Puppet> grid, outline;          ///< the same rig on the rigid grid and the outline ARAP
  std::vector<Part> parts;             ///< on the feature frame's character
  std::vector<Part> grid_parts, outline_parts;  ///< the same parts on theirs (they add interior points)
  std::vector<Points> regions;         ///< the polygons of the region parts, which follow the sub-shapes'
  std::vector<Group> groups;
  std::vector<Pose> poses;
  std::vector<int> handle_part;  ///< part each handle is on
  double height = 1;
  // The automatic rig of the same character (none for a one-region raster character).
  std::unique_ptr<mar::Puppet> autorig;
  std::vector<Part> auto_parts;
  std::vector<int> auto_handle_part;
  std::vector<Group> auto_groups;  ///< the groups turned about the automatic rig's hinges
};

constexpr int kAutoRest = 6, kAutoReach = 7;

[[noreturn]] void fail(const std::string& msg) {
  std::fprintf(stderr, "bench_pose_quality: %s\n", msg.c_str());
  std::exit(2);
}

bool inside(const mar::Points& poly, const Vec2& q);

// The part of a one-region character holding q: the first region polygon around it, else the
// body (part 0).
int region_of(const PoseCase& c, const Vec2& q) {
  const size_t first = c.parts.size() - c.regions.size();
  for (size_t r = 0; r < c.regions.size(); ++r)
    if (inside(c.regions[r], q)) return static_cast<int>(first + r);
  return 0;
}

// The points of each part on a puppet's character: a sub-shape's own (not the one-point
// interior points a solver added), or a region's.
void fill_parts(const PoseCase& c, const mar::Character& ch, std::vector<Part>& parts) {
  for (Part& p : parts) p.points.clear();
  for (size_t si = 0; si < ch.shapes.size() && si < parts.size(); ++si)
    for (const mar::Contour& ct : ch.shapes[si].contours) {
      if (ct.count < 2) continue;
      for (int i = ct.begin; i < ct.begin + ct.count; ++i) {
        const int r = c.regions.empty() ? static_cast<int>(si) : region_of(c, ch.shapes[si].points[static_cast<size_t>(i)]);
        parts[static_cast<size_t>(r)].points.push_back(i);
      }
    }
}

PoseCase load_case(const fs::path& file) {
  PoseCase c;
  c.name = file.stem().string();
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    fail(file.string() + ": " + std::string(e.description()));
  }
  const std::string rig_path = (file.parent_path() / root["rig"].value_or(std::string())).lexically_normal().string();
  auto rig = mar::load_rig(rig_path);
  if (!rig.ok()) fail(rig.error);
  auto with = [&](const char* solver) {
    mar::Rig r = *rig.value;
    r.solver = solver;
    auto loaded = mar::load_puppet("", r);
    if (!loaded.ok()) fail(loaded.error);
    return std::move(*loaded.value);
  };
  c.puppet = with("feature_frame");
  c.grid = with("rigid_grid");
  c.outline = with("arap");
  const mar::Character& ch = c.puppet->character;
  c.height = ch.height > 0 ? ch.height : 1;
  auto shape_index = [&](const std::string& id) {
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      if (ch.shapes[s].id == id) return static_cast<int>(s);
    }
    fail(file.string() + ": no sub-shape '" + id + "'");
  };
  auto point = [&](const toml::node_view<const toml::node>& n) {
    return Vec2(n[0].value_or(0.0), n[1].value_or(0.0));
  };
  for (size_t si = 0; si < ch.shapes.size(); ++si) c.parts.push_back(Part{ch.shapes[si].id, static_cast<int>(si), {}});
  std::vector<Points>& regions = c.regions;
  std::map<std::string, int> group_index;
  if (const toml::array* gs = root["group"].as_array()) {
    for (const toml::node& gn : *gs) {
      const toml::node_view<const toml::node> g(gn);
      Group grp;
      grp.name = g["name"].value_or(std::string());
      if (const toml::array* parts = g["parts"].as_array()) {
        for (const toml::node& part : *parts) grp.parts.push_back(shape_index(part.value_or(std::string())));
      }
      if (const toml::array* poly = g["region"].as_array()) {  // the sub-shape's points inside it
        Points r;
        for (const toml::node& pt : *poly) r.push_back(point(toml::node_view<const toml::node>(pt)));
        if (r.size() < 3 || ch.shapes.size() != 1) fail(file.string() + ": a region is a polygon over a one-region character");
        grp.parts.push_back(static_cast<int>(c.parts.size()));
        c.parts.push_back(Part{grp.name, 0, {}});
        regions.push_back(r);
      }
      grp.pivot = point(g["pivot"]);
      group_index[grp.name] = static_cast<int>(c.groups.size());
      c.groups.push_back(grp);
    }
  }
  if (const toml::array* ps = root["pose"].as_array()) {
    for (const toml::node& pn : *ps) {
      const toml::node_view<const toml::node> p(pn);
      Pose pose;
      pose.name = p["name"].value_or(std::string());
      if (const toml::array* ms = p["move"].as_array()) {
        for (const toml::node& mn : *ms) {
          const toml::node_view<const toml::node> m(mn);
          Move mv;
          const std::string g = m["group"].value_or(std::string());
          if (!group_index.count(g)) fail(file.string() + ": pose '" + pose.name + "' names no group '" + g + "'");
          mv.group = group_index[g];
          mv.angle_deg = m["angle"].value_or(0.0);
          if (m["translate"]) mv.translate = point(m["translate"]);
          pose.moves.push_back(mv);
        }
      }
      c.poses.push_back(pose);
    }
  }
  c.grid_parts = c.outline_parts = c.parts;
  fill_parts(c, c.puppet->character, c.parts);
  fill_parts(c, c.grid->character, c.grid_parts);
  fill_parts(c, c.outline->character, c.outline_parts);
  const mar::FeatureFrameMethod* ff = c.puppet->feature_frame();
  if (regions.empty()) {
    for (const mar::ShapeParam& b : ff->bindings()) c.handle_part.push_back(ff->frame().origin[static_cast<size_t>(b.a)].shape);
  } else {
    for (const mar::RigHandle& h : c.puppet->rig.handles) c.handle_part.push_back(region_of(c, h.rest));
  }
  if (regions.empty()) {
    // The automatic rig of the hand rig's character, loaded as `marionette rig` writes it.
    const std::string character = fs::absolute(rig.value->character_path()).string();
    auto drawn = mar::load_character(character);
    if (!drawn.ok()) fail(drawn.error);
    const mar::AutoRig ar = mar::auto_rig(*drawn.value, character);
    auto parsed = mar::parse_rig(mar::write_auto_rig(ar, *drawn.value), rig_path + " (automatic)");
    if (!parsed.ok()) fail(parsed.error);
    auto loaded = mar::load_puppet("", *parsed.value);
    if (!loaded.ok()) fail(loaded.error);
    c.autorig = std::move(*loaded.value);
    c.auto_parts = c.parts;
    fill_parts(c, c.autorig->character, c.auto_parts);
    const mar::FeatureFrameMethod* aff = c.autorig->feature_frame();
    for (const mar::ShapeParam& b : aff->bindings()) c.auto_handle_part.push_back(aff->frame().origin[static_cast<size_t>(b.a)].shape);
    // Each group turned about the automatic hinge of its first limb: the hinge of a limb in the
    // group whose parent is not in it (an arm's shoulder, not its wrist); else its own pivot.
    c.auto_groups = c.groups;
    for (Group& g : c.auto_groups) {
      auto in_group = [&](const std::string& id) {
        for (int pi : g.parts)
          if (c.parts[static_cast<size_t>(pi)].name == id) return true;
        return false;
      };
      for (const mar::RigJoint& j : ar.rig.joints)
        if (in_group(j.part_a) && !in_group(j.part_b)) {
          g.pivot = j.at;
          break;
        }
    }
  }
  return c;
}

/// The move (if any) that carries sub-shape s in this pose; the last listed wins.
const Move* move_of(const PoseCase& c, const Pose& pose, int s) {
  const Move* found = nullptr;
  for (const Move& m : pose.moves) {
    const Group& g = c.groups[static_cast<size_t>(m.group)];
    if (std::find(g.parts.begin(), g.parts.end(), s) != g.parts.end()) found = &m;
  }
  return found;
}

bool automatic(int method) { return method == kAutoRest || method == kAutoReach; }

// The groups a method's targets and ideal turn about: the automatic rig's hinges for auto-reach.
const std::vector<Group>& groups_for(const PoseCase& c, int method) { return method == kAutoReach ? c.auto_groups : c.groups; }

std::vector<Vec2> targets_at(const PoseCase& c, int method, const Pose& pose, double f) {
  const mar::Puppet& p = automatic(method) ? *c.autorig : *c.puppet;
  const std::vector<int>& on = automatic(method) ? c.auto_handle_part : c.handle_part;
  std::vector<Vec2> t;
  for (size_t h = 0; h < p.rig.handles.size(); ++h) {
    const Vec2 rest = p.rig.handles[h].rest;
    const Move* m = move_of(c, pose, on[h]);
    t.push_back(m ? m->apply(groups_for(c, method), rest, f) : rest);
  }
  return t;
}

// --- metrics ----------------------------------------------------------------------------

struct PoseResult {
  double dist_max = 0, dist_mean = 0, art_max = 0, art_mean = 0, passive_max = 0, handle_max = 0;
  long nonfinite = 0;
  std::string worst_part;
};

bool g_parts = false;  // --parts: print every part's figures

PoseResult measure(const PoseCase& c, int method, const Pose& pose, const std::vector<mar::Points>& shapes,
                   const std::vector<Vec2>& handle_points) {
  PoseResult r;
  const mar::Character& ch = (method == 4 ? c.grid : method == 5 ? c.outline : automatic(method) ? c.autorig : c.puppet)->character;
  const std::vector<Part>& parts = method == 4 ? c.grid_parts : method == 5 ? c.outline_parts : automatic(method) ? c.auto_parts : c.parts;
  const double pct = 100.0 / c.height;
  int counted = 0;
  for (size_t pi = 0; pi < parts.size(); ++pi) {
    const Part& part = parts[pi];
    Points rest, got;
    for (int i : part.points) {
      rest.push_back(ch.shapes[static_cast<size_t>(part.shape)].points[static_cast<size_t>(i)]);
      got.push_back(shapes[static_cast<size_t>(part.shape)][static_cast<size_t>(i)]);
    }
    if (rest.size() < 2) continue;
    bool finite = true;
    for (const Vec2& p : got) {
      if (!p.allFinite()) {
        ++r.nonfinite;
        finite = false;
      }
    }
    if (!finite) continue;
    const Move* m = move_of(c, pose, static_cast<int>(pi));
    double art = 0;
    for (size_t i = 0; i < rest.size(); ++i) {
      const Vec2 ideal = m ? m->apply(groups_for(c, method), rest[i], 1) : rest[i];
      art += (got[i] - ideal).squaredNorm();
    }
    art = std::sqrt(art / static_cast<double>(rest.size())) * pct;
    const double dist = mar::rigid_fit_rms(rest, got) * pct;
    if (dist > r.dist_max) {
      r.dist_max = dist;
      r.worst_part = part.name;
    }
    r.dist_mean += dist;
    r.art_max = std::max(r.art_max, art);
    r.art_mean += art;
    if (!m) r.passive_max = std::max(r.passive_max, art);
    if (g_parts) std::printf("      %-16s %s dist %.3f art %.3f\n", part.name.c_str(), m ? "moved  " : "passive", dist, art);
    ++counted;
  }
  if (counted) {
    r.dist_mean /= counted;
    r.art_mean /= counted;
  }
  const std::vector<Vec2> t = targets_at(c, method, pose, 1);
  const mar::Rig& rig = (automatic(method) ? c.autorig : c.puppet)->rig;
  for (size_t h = 0; h < t.size() && h < handle_points.size(); ++h) {
    r.handle_max = std::max(r.handle_max, (handle_points[h] - t[h]).norm() * pct);
    if (g_parts && (handle_points[h] - t[h]).norm() * pct > 0.5) {
      std::printf("      handle %-10s residual %.3f\n", rig.handles[h].name.c_str(), (handle_points[h] - t[h]).norm() * pct);
    }
  }
  return r;
}

// --- methods ----------------------------------------------------------------------------

struct Solved {
  std::vector<mar::Points> shapes;
  std::vector<Vec2> handle_points;
};

constexpr int kLiveIterations = 8;
constexpr int kLiveFrames = 60;  // 0.5 s at 120 Hz
constexpr int kConverged = 1000;

Solved ff_result(mar::Puppet& p) {
  p.reconstruct();
  Solved s{p.shapes, {}};
  for (size_t h = 0; h < p.solver->handle_count(); ++h) s.handle_points.push_back(p.solver->handle_point(h));
  return s;
}

// A live drag with any puppet of the case (the rigid grid's, the outline ARAP's): targets move
// along the groups' motion over 0.5 s at 120 Hz, warm start, the live iteration count.
Solved live(const PoseCase& c, mar::Puppet& p, const Pose& pose) {
  p.solver->reset_to_rest();
  for (int k = 1; k <= kLiveFrames; ++k) p.solver->solve(targets_at(c, 1, pose, static_cast<double>(k) / kLiveFrames), kLiveIterations);
  return ff_result(p);
}

Solved ff_rest(PoseCase& c, const Pose& pose, int iterations, int method = 0) {
  mar::Puppet& p = automatic(method) ? *c.autorig : *c.puppet;
  const std::vector<Vec2> t = targets_at(c, method, pose, 1);
  p.solver->reset_to_rest();
  p.solver->initial_guess(t);
  p.solver->solve(t, iterations);
  return ff_result(p);
}


// CGAL ARAP on the union of the closed parts: a constrained triangulation of every contour,
// keeping the faces inside some closed part, so overlapping parts are one piece as a single
// outline makes them. Points outside every kept face (open strokes) follow the nearest face
// by barycentric coordinates.
using Kernel = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VD = boost::graph_traits<Mesh>::vertex_descriptor;
using Deform = CGAL::Surface_mesh_deformation<Mesh>;

bool inside(const mar::Points& poly, const Vec2& q) {
  bool in = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &a = poly[i], &b = poly[j];
    if ((a.y() > q.y()) != (b.y() > q.y()) && q.x() < (b.x() - a.x()) * (q.y() - a.y()) / (b.y() - a.y()) + a.x()) in = !in;
  }
  return in;
}

struct ArapBaseline {
  Mesh mesh;
  std::vector<VD> vds;
  Points rest;
  std::vector<VD> controls;
  struct Bind {
    int tri = -1;  ///< face index into tris (barycentric) or -1: vertex
    int vertex = 0;
    double u = 0, v = 0, w = 0;
  };
  std::vector<std::vector<Bind>> binds;  ///< per shape, per point
  std::vector<std::array<int, 3>> tris;
  std::unique_ptr<Deform> deform;
  size_t faces = 0;
};

std::unique_ptr<ArapBaseline> make_arap(const PoseCase& c) {
  auto out = std::make_unique<ArapBaseline>();
  const mar::Character& ch = c.puppet->character;
  Points pts;
  std::vector<mar::Ring> rings;
  std::vector<char> closed;
  std::vector<Points> closed_polys;
  for (const mar::SubShape& sh : ch.shapes) {
    for (const mar::Contour& ct : sh.contours) {
      rings.push_back({static_cast<int>(pts.size()) + ct.begin, ct.count});
      closed.push_back(ct.closed ? 1 : 0);
      if (ct.closed && sh.fill.enabled) {
        closed_polys.emplace_back(sh.points.begin() + ct.begin, sh.points.begin() + ct.begin + ct.count);
      }
    }
    pts.insert(pts.end(), sh.points.begin(), sh.points.end());
  }
  const mar::HullMesh hm = mar::triangulate_hull(pts, rings, closed);
  std::vector<int> keep_index(hm.vertices.size(), -1);
  for (size_t t = 0; t + 2 < hm.triangles.size(); t += 3) {
    const Vec2 centroid = (hm.vertices[static_cast<size_t>(hm.triangles[t])] + hm.vertices[static_cast<size_t>(hm.triangles[t + 1])] +
                           hm.vertices[static_cast<size_t>(hm.triangles[t + 2])]) / 3.0;
    bool in = false;
    for (const Points& poly : closed_polys) in = in || inside(poly, centroid);
    if (!in) continue;
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const int vi = hm.triangles[t + static_cast<size_t>(k)];
      if (keep_index[static_cast<size_t>(vi)] < 0) {
        keep_index[static_cast<size_t>(vi)] = static_cast<int>(out->rest.size());
        out->rest.push_back(hm.vertices[static_cast<size_t>(vi)]);
        out->vds.push_back(out->mesh.add_vertex(Kernel::Point_3(hm.vertices[static_cast<size_t>(vi)].x(),
                                                                hm.vertices[static_cast<size_t>(vi)].y(), 0)));
      }
      tri[static_cast<size_t>(k)] = keep_index[static_cast<size_t>(vi)];
    }
    if (out->mesh.add_face(out->vds[static_cast<size_t>(tri[0])], out->vds[static_cast<size_t>(tri[1])],
                           out->vds[static_cast<size_t>(tri[2])]) != Mesh::null_face()) {
      out->tris.push_back(tri);
    }
  }
  out->faces = out->tris.size();
  // Bind every shape point: to a mesh vertex at the same place, else to the nearest face.
  for (const mar::SubShape& sh : ch.shapes) {
    std::vector<ArapBaseline::Bind> b;
    for (const Vec2& q : sh.points) {
      ArapBaseline::Bind bind;
      double best = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < out->rest.size(); ++i) {
        const double d = (out->rest[i] - q).squaredNorm();
        if (d < best) {
          best = d;
          bind.vertex = static_cast<int>(i);
        }
      }
      if (best > 1e-12) {
        double bd = std::numeric_limits<double>::infinity();
        for (size_t t = 0; t < out->tris.size(); ++t) {
          const Vec2 a = out->rest[static_cast<size_t>(out->tris[t][0])], bb = out->rest[static_cast<size_t>(out->tris[t][1])],
                     cc = out->rest[static_cast<size_t>(out->tris[t][2])];
          const double d = ((a + bb + cc) / 3.0 - q).squaredNorm();
          if (d < bd) {
            bd = d;
            const double det = (bb - a).x() * (cc - a).y() - (bb - a).y() * (cc - a).x();
            const Vec2 r = q - a;
            bind.tri = static_cast<int>(t);
            bind.v = (r.x() * (cc - a).y() - r.y() * (cc - a).x()) / det;
            bind.w = ((bb - a).x() * r.y() - (bb - a).y() * r.x()) / det;
            bind.u = 1 - bind.v - bind.w;
          }
        }
      }
      b.push_back(bind);
    }
    out->binds.push_back(std::move(b));
  }
  out->deform = std::make_unique<Deform>(out->mesh);
  out->deform->insert_roi_vertices(vertices(out->mesh).begin(), vertices(out->mesh).end());
  for (const mar::RigHandle& h : c.puppet->rig.handles) {
    size_t best = 0;
    for (size_t i = 0; i < out->rest.size(); ++i) {
      if ((out->rest[i] - h.rest).squaredNorm() < (out->rest[best] - h.rest).squaredNorm()) best = i;
    }
    out->controls.push_back(out->vds[best]);
    out->deform->insert_control_vertex(out->vds[best]);
  }
  out->deform->preprocess();
  return out;
}

Solved arap_solve(const PoseCase& c, ArapBaseline& a, const Pose& pose) {
  a.deform->reset();
  const std::vector<Vec2> t = targets_at(c, 3, pose, 1);
  for (size_t h = 0; h < a.controls.size(); ++h) {
    const Vec2 rest = a.rest[a.controls[h].idx()];
    const Vec2 p = rest + (t[h] - c.puppet->rig.handles[h].rest);
    a.deform->set_target_position(a.controls[h], Kernel::Point_3(p.x(), p.y(), 0));
  }
  a.deform->deform(kConverged, 1e-9);
  Points now(a.rest.size());
  for (size_t i = 0; i < a.vds.size(); ++i) {
    const Kernel::Point_3& q = a.mesh.point(a.vds[i]);
    now[i] = Vec2(q.x(), q.y());
  }
  Solved s;
  for (const auto& binds : a.binds) {
    Points sh;
    for (const ArapBaseline::Bind& b : binds) {
      if (b.tri < 0) {
        sh.push_back(now[static_cast<size_t>(b.vertex)]);
      } else {
        const auto& tri = a.tris[static_cast<size_t>(b.tri)];
        sh.push_back(b.u * now[static_cast<size_t>(tri[0])] + b.v * now[static_cast<size_t>(tri[1])] +
                     b.w * now[static_cast<size_t>(tri[2])]);
      }
    }
    s.shapes.push_back(std::move(sh));
  }
  for (size_t h = 0; h < a.controls.size(); ++h) {
    s.handle_points.push_back(now[a.controls[h].idx()] - a.rest[a.controls[h].idx()] + c.puppet->rig.handles[h].rest);
  }
  return s;
}

// --- the run ----------------------------------------------------------------------------

const char* const kMethods[] = {"ff-rest", "ff-live", "ff-converged", "cgal-arap", "grid-live", "arap-live", "auto-rest", "auto-reach"};
constexpr int kMethodCount = 8;

struct Options {
  std::string only_case, json_path = "bench_pose_quality.json";
  std::map<std::string, std::string> grids;
  bool smoke = false;
};

std::vector<PoseCase>& all_cases() {
  static std::vector<PoseCase> cases;
  return cases;
}
std::vector<std::unique_ptr<ArapBaseline>>& arap_of() {
  static std::vector<std::unique_ptr<ArapBaseline>> a;
  return a;
}

Solved run_method(size_t ci, int method, const Pose& pose) {
  PoseCase& c = all_cases()[ci];
  switch (method) {
    case 0: return ff_rest(c, pose, c.puppet->rig.iterations);
    case 1: return live(c, *c.puppet, pose);
    case 2: return ff_rest(c, pose, kConverged);
    case 3: return arap_solve(c, *arap_of()[ci], pose);
    case 4: return live(c, *c.grid, pose);
    case 5: return live(c, *c.outline, pose);
    default: return ff_rest(c, pose, c.autorig->rig.iterations, method);
  }
}

// The puppet whose character (and fill mesh) a method's shapes belong to: the rigid grid and
// the outline ARAP add interior points to theirs.
const mar::Puppet& puppet_of(const PoseCase& c, int method) {
  return method == 4 ? *c.grid : method == 5 ? *c.outline : automatic(method) ? *c.autorig : *c.puppet;
}

void render_cell(const mar::Puppet& p, const std::vector<Points>& shapes, int size, std::vector<std::uint8_t>& grid,
                 int grid_w, int x0, int y0) {
  const int ss = 2;
  auto canvas = mar::Canvas::offscreen(size * ss, size * ss);
  if (!canvas.ok()) fail(canvas.error);
  mar::Canvas& cv = **canvas.value;
  cv.clear(mar::Rgba{1, 1, 1, 1});
  mar::DrawList list;
  const mar::Character& ch = p.character;
  // Room around the character for limbs that leave its rest box.
  const double w = ch.width * 1.6, h = ch.height * 1.4;
  const mar::Affine2 view = mar::fit_view(w, h, size * ss, size * ss) * mar::Affine2::translate(ch.width * 0.3, ch.height * 0.2);
  mar::build_draw_list(ch, p.mesh, shapes, view, 0.2 * ss, list);
  if (std::string err = cv.draw(list); !err.empty()) fail(err);
  const std::vector<std::uint8_t> px = cv.read_premultiplied();
  const mar::Image img = mar::downsample_premultiplied(px.data(), size, size, ss);
  for (int y = 0; y < size; ++y) {
    std::copy_n(img.rgba.begin() + 4 * y * size, 4 * size, grid.begin() + 4 * ((y0 + y) * grid_w + x0));
  }
}

void write_grid(size_t ci, const std::string& path) {
  PoseCase& c = all_cases()[ci];
  const int size = 180, gap = 4;
  const int cols = static_cast<int>(c.poses.size()) + 1, rows = kMethodCount;
  const int gw = cols * (size + gap), gh = rows * (size + gap);
  std::vector<std::uint8_t> grid(static_cast<size_t>(4 * gw * gh), 255);
  for (int m = 0; m < rows; ++m) {
    if (automatic(m) && !c.autorig) continue;
    const mar::Puppet& pup = puppet_of(c, m);
    std::vector<Points> rest;
    for (const mar::SubShape& s : pup.character.shapes) rest.push_back(s.points);
    render_cell(pup, rest, size, grid, gw, 0, m * (size + gap));
    for (size_t p = 0; p < c.poses.size(); ++p) {
      render_cell(pup, run_method(ci, m, c.poses[p]).shapes, size, grid, gw, static_cast<int>(p + 1) * (size + gap), m * (size + gap));
    }
  }
  mar::Image img{gw, gh, std::move(grid)};
  if (std::string err = mar::write_png(path, img); !err.empty()) fail(err);
  std::printf("wrote %s (columns: rest, %zu poses; rows:", path.c_str(), c.poses.size());
  for (const char* m : kMethods) std::printf(" %s", m);
  std::printf(")\n");
}

void BM_method(benchmark::State& st) {
  const size_t ci = static_cast<size_t>(st.range(0));
  const int method = static_cast<int>(st.range(1));
  PoseCase& c = all_cases()[ci];
  size_t k = 0;
  for (auto _ : st) {
    Solved s = run_method(ci, method, c.poses[k++ % c.poses.size()]);
    benchmark::DoNotOptimize(s.shapes.data());
  }
  st.SetLabel(c.name + " " + kMethods[method] + " (one pose)");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--case" && i + 1 < argc) {
      o.only_case = argv[++i];
    } else if (a == "--json" && i + 1 < argc) {
      o.json_path = argv[++i];
    } else if (a == "--grid" && i + 1 < argc) {
      const std::string g = argv[++i];
      const size_t eq = g.find('=');
      if (eq == std::string::npos) fail("--grid takes CASE=out.png");
      o.grids[g.substr(0, eq)] = g.substr(eq + 1);
    } else if (a == "--parts") {
      g_parts = true;
    } else if (a == "--smoke") {
      o.smoke = true;
    } else {
      rest.push_back(argv[i]);
    }
  }
  const fs::path dir = fs::path(MARIONETTE_SOURCE_DIR) / "tests" / "bench" / "poses";
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".toml" && (o.only_case.empty() || e.path().stem() == o.only_case)) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) fail("no case named '" + o.only_case + "' in " + dir.string());
  for (const fs::path& f : files) {
    all_cases().push_back(load_case(f));
    arap_of().push_back(make_arap(all_cases().back()));
  }

  std::ofstream json(o.json_path);
  json << "{\n  \"unit\": \"% of character height\",\n  \"cases\": [\n";
  long nonfinite = 0;
  std::printf("pose quality, %% of the character's height (dist = distortion, art = articulation error, "
              "passive = worst part in no moved group, handle = worst handle residual)\n");
  for (size_t ci = 0; ci < all_cases().size(); ++ci) {
    PoseCase& c = all_cases()[ci];
    std::printf("\n%s (%zu sub-shapes, %zu handles, %zu joints, ARAP mesh %zu vertices / %zu faces)\n", c.name.c_str(),
                c.puppet->character.shapes.size(), c.handle_part.size(), c.puppet->feature_frame()->frame().joints.size(),
                arap_of()[ci]->rest.size(), arap_of()[ci]->faces);
    if (c.autorig) {  // where the automatic rig's hinges are against the pivots the case picked
      std::printf("  automatic rig's hinges off the case's pivots, %% of the height:");
      for (size_t g = 0; g < c.groups.size(); ++g)
        if (c.auto_groups[g].pivot != c.groups[g].pivot)
          std::printf(" %s %.2f", c.groups[g].name.c_str(), (c.auto_groups[g].pivot - c.groups[g].pivot).norm() * 100.0 / c.height);
      std::printf("\n");
    }
    if (g_parts) {
      for (const mar::FrameJoint& j : c.puppet->feature_frame()->frame().joints) {
        std::printf("  joint %s - %s at (%.1f, %.1f)\n", c.puppet->character.shapes[static_cast<size_t>(j.shape_a)].id.c_str(),
                    c.puppet->character.shapes[static_cast<size_t>(j.shape_b)].id.c_str(), j.at.x(), j.at.y());
      }
      for (size_t h = 0; h < c.handle_part.size(); ++h) {
        std::printf("  handle %s on %s\n", c.puppet->rig.handles[h].name.c_str(),
                    c.puppet->character.shapes[static_cast<size_t>(c.handle_part[h])].id.c_str());
      }
    }
    std::printf("  %-22s %-13s %8s %8s %8s %8s %8s %8s  %s\n", "pose", "method", "dist max", "dist avg", "art max",
                "art avg", "passive", "handle", "worst part");
    json << (ci ? ",\n" : "") << "    {\"name\": \"" << c.name << "\", \"poses\": [\n";
    for (size_t p = 0; p < c.poses.size(); ++p) {
      json << (p ? ",\n" : "") << "      {\"name\": \"" << c.poses[p].name << "\"";
      for (int m = 0; m < kMethodCount; ++m) {
        if (automatic(m) && !c.autorig) continue;
        const Solved s = run_method(ci, m, c.poses[p]);
        const PoseResult r = measure(c, m, c.poses[p], s.shapes, s.handle_points);
        nonfinite += r.nonfinite;
        std::printf("  %-22s %-13s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f  %s%s\n", m == 0 ? c.poses[p].name.c_str() : "",
                    kMethods[m], r.dist_max, r.dist_mean, r.art_max, r.art_mean, r.passive_max, r.handle_max,
                    r.worst_part.c_str(), r.nonfinite ? "  NON-FINITE" : "");
        json << ", \"" << kMethods[m] << "\": {\"dist_max\": " << r.dist_max << ", \"dist_mean\": " << r.dist_mean
             << ", \"art_max\": " << r.art_max << ", \"art_mean\": " << r.art_mean << ", \"passive_max\": " << r.passive_max
             << ", \"handle_max\": " << r.handle_max << ", \"nonfinite\": " << r.nonfinite << ", \"worst_part\": \""
             << r.worst_part << "\"}";
      }
      json << "}";
    }
    json << "\n    ]}";
  }
  json << "\n  ]\n}\n";
  std::printf("\nwrote %s\n", o.json_path.c_str());
  for (const auto& [name, path] : o.grids) {
    bool found = false;
    for (size_t ci = 0; ci < all_cases().size(); ++ci) {
      if (all_cases()[ci].name == name) {
        write_grid(ci, path);
        found = true;
      }
    }
    if (!found) fail("--grid: no case '" + name + "'");
  }
  if (nonfinite) {
    std::fprintf(stderr, "bench_pose_quality: %ld non-finite output points\n", nonfinite);
    return 1;
  }
  if (o.smoke) return 0;
  for (size_t ci = 0; ci < all_cases().size(); ++ci) {
    for (int m = 0; m < kMethodCount; ++m) {
      if (automatic(m) && !all_cases()[ci].autorig) continue;
      benchmark::RegisterBenchmark(("pose/" + all_cases()[ci].name + "/" + kMethods[m]).c_str(), BM_method)
          ->Args({static_cast<long>(ci), m})
          ->Unit(benchmark::kMillisecond);
    }
  }
  int bargc = static_cast<int>(rest.size());
  benchmark::Initialize(&bargc, rest.data());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
