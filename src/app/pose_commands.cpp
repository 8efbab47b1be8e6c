// inspect --rig and pose: the commands that load a puppet (character + rig).
#include "app/commands.h"
#include "solve/arap.h"
#include "solve/rigid_grid.h"
#include "app/keys.h"
#include "app/puppet.h"
#include "render/canvas.h"
#include "render/overlay.h"
#include "rig/edit.h"

#include "base/read_file.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>

namespace mar {
namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

// Renders the puppet's current shapes (and optionally its frame) into a PNG.
int write_picture(Puppet& p, const std::string& path, int w, int h, const Rgba& bg, bool overlay,
                  std::span<const Vec2> handle_points) {
  const int ss = 2;
  auto canvas = Canvas::offscreen(w * ss, h * ss);
  if (!canvas.ok()) {
    std::cerr << "error: " << canvas.error << "\n";
    return kExitRuntime;
  }
  Canvas& c = **canvas.value;
  c.clear(bg);
  DrawList list;
  const Affine2 view = fit_view(p.character.width, p.character.height, w * ss, h * ss);
  build_draw_list(p.character, p.mesh, p.shapes, view, 0.2 * ss, list, p.shown);
  if (overlay) append_solver_overlay(p, handle_points, view, list);
  if (std::string err = c.draw(list); !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return kExitRuntime;
  }
  const std::vector<std::uint8_t> px = c.read_premultiplied();
  if (std::string err = write_png(path, downsample_premultiplied(px.data(), w, h, ss)); !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return kExitRuntime;
  }
  return kExitOk;
}

namespace {

nlohmann::ordered_json handles_json(const Rig& rig) {
  nlohmann::ordered_json hs = nlohmann::ordered_json::array();
  for (const RigHandle& h : rig.handles) hs.push_back({{"name", h.name}, {"rest", {h.rest.x(), h.rest.y()}}});
  return hs;
}

void print_handles(const Rig& rig) {
  std::printf("handles:");
  for (const RigHandle& h : rig.handles) std::printf(" %s(%.1f, %.1f)", h.name.c_str(), h.rest.x(), h.rest.y());
  std::printf("\n");
}

}  // namespace

std::pair<int, int> doc_size(const Character& ch) {
  return {std::clamp(static_cast<int>(std::ceil(ch.width)), 1, 8192), std::clamp(static_cast<int>(std::ceil(ch.height)), 1, 8192)};
}

// inspect --rig for the rigid grid: seed 003 Table 1's columns (VER, NOD, w, PRE, OPT with
// and without the fast summation; medians of 7 runs of the rig's iteration count from rest).
int inspect_grid_rig(const InspectArgs& a, Puppet& p, const RigidGrid& grid) {
  const std::vector<Vec2> targets = p.rest_targets();
  std::vector<double> pre{p.prefactor_ms}, opt1, opt2;
  const int iterations = p.rig.iterations;
  for (int k = 0; k < 7; ++k) {
    auto reloaded = load_puppet(a.input, a.rig, a.mask);  // prepare inserts interior points: start from the file
    if (!reloaded.ok()) break;
    Puppet& q = **reloaded.value;
    pre.push_back(q.prefactor_ms);
    auto* g = dynamic_cast<RigidGrid*>(q.solver.get());
    for (const bool fast : {true, false}) {
      g->reset_to_rest();
      g->set_fast_summation(fast);
      const auto t0 = std::chrono::steady_clock::now();
      g->solve(targets, iterations);
      (fast ? opt1 : opt2).push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  }
  size_t junction = 0;
  for (char j : grid.junction()) junction += j ? 1 : 0;
  const size_t nod = grid.grid_nodes() + grid.boundary_nodes();
  if (a.json) {
    nlohmann::ordered_json j = inspect_json(p.character);
    j["table1"] = {{"solver", p.rig.solver},
                   {"VER", grid.mesh_vertices()},
                   {"NOD", nod},
                   {"w", grid.half_width()},
                   {"stride", grid.stride()},
                   {"PRE_ms", median(pre)},
                   {"OPT1_ms", median(opt1)},
                   {"OPT2_ms", median(opt2)},
                   {"iterations", iterations},
                   {"cell", grid.cell()},
                   {"grid_nodes", grid.grid_nodes()},
                   {"boundary_nodes", grid.boundary_nodes()},
                   {"free_vertices", grid.free_vertices()},
                   {"mesh_triangles", grid.mesh_triangles().size()},
                   {"junction_triangles", junction},
                   {"factor_nonzeros", grid.factor_nonzeros()}};
    j["handles"] = handles_json(p.rig);
    std::cout << j.dump(2) << "\n";
  } else {
    print_inspect_text(p.character);
    std::printf(
        "\nrigid grid (rig %s): cell %.2f, %zu grid + %zu boundary nodes, %zu of %zu mesh triangles junction, "
        "regions on every %d%s grid node\n",
        p.rig.path.c_str(), grid.cell(), grid.grid_nodes(), grid.boundary_nodes(), junction, grid.mesh_triangles().size(),
        grid.stride(), grid.stride() == 1 ? "st" : grid.stride() == 2 ? "nd" : grid.stride() == 3 ? "rd" : "th");
    std::printf("%6s %6s %3s %9s %9s %9s   (ms; OPT = %d iterations, 1 with / 2 without fast summation)\n", "VER", "NOD", "w",
                "PRE", "OPT1", "OPT2", iterations);
    std::printf("%6zu %6zu %3d %9.3f %9.3f %9.3f\n", grid.mesh_vertices(), nod, grid.half_width(), median(pre), median(opt1),
                median(opt2));
    print_handles(p.rig);
  }
  if (!a.overlay.empty()) {
    const auto [w2, h2] = doc_size(p.character);
    return write_picture(p, a.overlay, w2, h2, Rgba{1, 1, 1, 1}, true, targets);
  }
  return kExitOk;
}

// inspect --rig for a mesh solver (the outline ARAP baseline): its triangulation, handles
// and the cost of preparing it and of 12 iterations.
int inspect_mesh_rig(const InspectArgs& a, Puppet& p) {
  if (const auto* grid = dynamic_cast<const RigidGrid*>(p.solver.get())) return inspect_grid_rig(a, p, *grid);
  const auto* arap = dynamic_cast<const OutlineArap*>(p.solver.get());
  if (!arap) {
    std::cerr << "error: inspect --rig cannot show solver '" << p.rig.solver << "' yet\n";
    return kExitBadInput;
  }
  const std::vector<Vec2> targets = p.rest_targets();
  std::vector<double> pre{p.prefactor_ms}, sol;
  for (int k = 0; k < 7; ++k) {
    auto reloaded = load_puppet(a.input, a.rig, a.mask);  // prepare inserts interior points: start from the file
    if (!reloaded.ok()) break;
    Puppet& q = **reloaded.value;
    pre.push_back(q.prefactor_ms);
    const auto t0 = std::chrono::steady_clock::now();
    q.solver->solve(targets, 12);
    sol.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
  }
  size_t interior = 0;
  for (const SubShape& s : p.character.shapes)
    for (const Contour& c : s.contours) interior += c.count == 1 ? 1 : 0;
  if (a.json) {
    nlohmann::ordered_json j = inspect_json(p.character);
    j["mesh"] = {{"solver", p.rig.solver},
                 {"vertices", arap->rest().size()},
                 {"triangles", arap->triangles().size()},
                 {"interior_points", interior},
                 {"PRE_ms", median(pre)},
                 {"SOL_ms", median(sol)}};
    j["handles"] = handles_json(p.rig);
    std::cout << j.dump(2) << "\n";
  } else {
    print_inspect_text(p.character);
    std::printf("\noutline ARAP mesh (rig %s)\n", p.rig.path.c_str());
    std::printf("%9s %9s %9s %9s %9s\n", "vertices", "triangles", "interior", "PRE ms", "SOL ms");
    std::printf("%9zu %9zu %9zu %9.3f %9.3f\n", arap->rest().size(), arap->triangles().size(), interior, median(pre),
                median(sol));
    print_handles(p.rig);
  }
  if (!a.overlay.empty()) {
    const auto [w2, h2] = doc_size(p.character);
    return write_picture(p, a.overlay, w2, h2, Rgba{1, 1, 1, 1}, true, targets);
  }
  return kExitOk;
}

int cmd_inspect_rig(const InspectArgs& a) {
  auto loaded = load_puppet(a.input, a.rig, a.mask);
  if (!loaded.ok()) {
    std::cerr << "error: " << loaded.error << "\n";
    return kExitBadInput;
  }
  Puppet& p = **loaded.value;  // (inspect lists the character's warnings itself)
  const FeatureFrameMethod* ff = p.feature_frame();
  if (!ff) return inspect_mesh_rig(a, p);
  // PRE and SOL: medians of 7 runs (the first prepare happened in load_puppet).
  std::vector<double> pre{p.prefactor_ms}, sol;
  const SolverWeights w = p.weights();
  const std::vector<Vec2> targets = p.rest_targets();
  for (int k = 0; k < 7; ++k) {
    FeatureFrameSolver s;
    const auto t0 = std::chrono::steady_clock::now();
    s.prepare(ff->frame(), ff->bindings(), w);
    const auto t1 = std::chrono::steady_clock::now();
    s.solve(targets, 12);
    const auto t2 = std::chrono::steady_clock::now();
    pre.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    sol.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  const FeatureFrame& f = ff->frame();
  for (const std::string& warning : f.warnings) std::cerr << "warning: " << warning << "\n";
  if (a.json) {
    nlohmann::ordered_json j = inspect_json(p.character);
    j["table1"] = {{"S.VER", f.shape_vertices},
                   {"F.LINES", f.lines.size()},
                   {"sewing_total", f.sewing_lines},
                   {"sewing_user", f.user_sewing_lines},
                   {"F.VER", f.rest.size()},
                   {"joints", f.joints.size()},
                   {"PRE_ms", median(pre)},
                   {"SOL_ms", median(sol)}};
    j["handles"] = handles_json(p.rig);
    j["frame_warnings"] = f.warnings;
    std::cout << j.dump(2) << "\n";
  } else {
    print_inspect_text(p.character);
    std::printf("\nfeature frame (rig %s)\n", p.rig.path.c_str());
    std::printf("%8s  %-22s %6s %9s %9s\n", "S.VER", "F.LINES (sewing, user)", "F.VER", "PRE ms", "SOL ms");
    const std::string lines = std::to_string(f.lines.size()) + " (" + std::to_string(f.sewing_lines) + ", " +
                              std::to_string(f.user_sewing_lines) + ")";
    std::printf("%8zu  %-22s %6zu %9.3f %9.3f\n", f.shape_vertices, lines.c_str(), f.rest.size(), median(pre),
                median(sol));
    std::printf("joints:");
    for (const FrameJoint& j : f.joints) {
      std::printf(" %s|%s(%.1f, %.1f)%s", p.character.shapes[static_cast<size_t>(j.shape_a)].id.c_str(),
                  p.character.shapes[static_cast<size_t>(j.shape_b)].id.c_str(), j.at.x(), j.at.y(), j.automatic ? "" : "*");
    }
    bool from_rig = false;
    for (const FrameJoint& j : f.joints) from_rig = from_rig || !j.automatic;
    std::printf("%s\n", f.joints.empty() ? " none" : from_rig ? "  (* from the rig)" : "");
    print_handles(p.rig);
  }
  if (!a.overlay.empty()) {
    const auto [w2, h2] = doc_size(p.character);
    const int rc = write_picture(p, a.overlay, w2, h2, Rgba{1, 1, 1, 1}, true, targets);
    if (rc != kExitOk) return rc;
  }
  return kExitOk;
}

int cmd_pose(const PoseArgs& a) {
  auto loaded = load_puppet(a.input, a.rig, a.mask);
  if (!loaded.ok()) {
    std::cerr << "error: " << loaded.error << "\n";
    return kExitBadInput;
  }
  Puppet& p = **loaded.value;
  print_warnings(p.character);
  std::vector<Vec2> targets = p.rest_targets();
  for (const std::string& t : a.targets) {
    const size_t eq = t.find('=');
    double x = 0, y = 0;
    char extra = 0;
    if (eq == std::string::npos || std::sscanf(t.c_str() + eq + 1, "%lf,%lf%c", &x, &y, &extra) != 2 ||
        !std::isfinite(x) || !std::isfinite(y)) {
      std::cerr << "error: --target must be NAME=X,Y, got '" << t << "'\n";
      return kExitBadInput;
    }
    const std::string name = t.substr(0, eq);
    const int h = p.rig.find_handle(name);
    if (h < 0) {
      std::string names;
      for (const RigHandle& rh : p.rig.handles) names += (names.empty() ? "" : ", ") + rh.name;
      std::cerr << "error: no handle named '" << name << "' in " << a.rig << " (handles: " << names << ")\n";
      return kExitBadInput;
    }
    targets[static_cast<size_t>(h)] = {x, y};
  }
  if (!a.settings.empty()) {  // solver parameters, as a show's solver.NAME settings would turn them
    auto params = p.solver->parameters();
    std::vector<double> values;
    for (const SolverParameter& sp : params) values.push_back(sp.value);
    for (const std::string& s : a.settings) {
      const size_t eq = s.find('=');
      double v = 0;
      char extra = 0;
      size_t k = 0;
      while (eq != std::string::npos && k < params.size() && params[k].name != s.substr(0, eq)) ++k;
      if (eq == std::string::npos || std::sscanf(s.c_str() + eq + 1, "%lf%c", &v, &extra) != 1 || !std::isfinite(v) || k == params.size()) {
        std::string names;
        for (const SolverParameter& sp : params) names += (names.empty() ? "" : ", ") + sp.name;
        std::cerr << "error: --set must be NAME=VALUE with NAME one of this rig's solver parameters (" << names << "), got '" << s
                  << "'\n";
        return kExitBadInput;
      }
      if (v < params[k].lo || v > params[k].hi) {
        std::cerr << "error: --set " << params[k].name << " must be " << params[k].lo << ".." << params[k].hi << ", got " << v << "\n";
        return kExitBadInput;
      }
      values[k] = v;
    }
    std::string err;
    if (!p.solver->set_parameters(values, &err)) {
      std::cerr << "error: " << err << "\n";
      return kExitBadInput;
    }
  }
  if (!a.save_key.empty()) {  // append the targets as a key pose (the rig's text is kept as written)
    RigKey k;
    k.name = a.save_key;
    for (const std::string& t : a.targets) {
      const std::string name = t.substr(0, t.find('='));
      k.targets.push_back({name, targets[size_t(p.rig.find_handle(name))]});
    }
    if (find_key(p.rig, k.name) != -2 || k.targets.empty()) {
      std::cerr << "error: --save-key needs a new name (not 'rest' nor an existing key) and at least one --target\n";
      return kExitBadInput;
    }
    if (const std::string err = append_atomically(a.rig, "\n" + key_toml(k)); !err.empty()) {
      std::cerr << "error: " << err << "\n";
      return kExitRuntime;
    }
  }
  if (a.iterations != -1 && (a.iterations < 1 || a.iterations > 100000)) {
    std::cerr << "error: --iterations must be 1..100000\n";
    return kExitBadInput;
  }
  const int iterations = a.iterations > 0 ? a.iterations : p.rig.iterations;
  std::vector<double> energies(static_cast<size_t>(iterations) + 1);
  p.solver->initial_guess(targets);
  if (FeatureFrameMethod* ff = p.feature_frame()) {
    ff->core().solve(targets, iterations, energies);  // with the energy of every accepted iterate
  } else {  // one iteration at a time, as the same solve would go, with its energy after each
    energies[0] = p.solver->energy(targets);
    for (int it = 1; it <= iterations; ++it) {
      p.solver->solve(targets, 1);
      energies[size_t(it)] = p.solver->energy(targets);
    }
  }
  p.reconstruct();
  // A handle's residual is where the drawing it is bound to is against its target (a rigid
  // grid's handle on a stroke is the stroke's point: solve/rigid_grid.h).
  auto residual = [&](size_t h) { return (p.solver->handle_point(h) - targets[h]).norm(); };
  if (!a.dump.empty()) {
    nlohmann::ordered_json j;
    nlohmann::ordered_json subs = nlohmann::ordered_json::array();
    for (size_t s = 0; s < p.shapes.size(); ++s) {
      nlohmann::ordered_json pts = nlohmann::ordered_json::array();
      for (const Vec2& q : p.shapes[s]) pts.push_back({q.x(), q.y()});
      subs.push_back({{"id", p.character.shapes[s].id}, {"points", pts}});
    }
    j["subshapes"] = subs;
    nlohmann::ordered_json fv = nlohmann::ordered_json::array();
    if (const FeatureFrameMethod* ff = p.feature_frame()) {
      for (const Vec2& q : ff->core().vertices()) fv.push_back({q.x(), q.y()});
    }
    j["frame_vertices"] = fv;
    j["energy_per_iteration"] = std::vector<double>(energies.begin() + 1, energies.end());
    nlohmann::ordered_json res = nlohmann::ordered_json::object();
    for (size_t h = 0; h < p.solver->handle_count(); ++h) {
      res[p.rig.handles[h].name] = residual(h);
    }
    j["handle_residuals"] = res;
    if (const std::string e = write_file(a.dump, j.dump(1) + "\n"); !e.empty()) {
      std::cerr << "error: " << e << "\n";
      return kExitRuntime;
    }
  }
  if (!a.output.empty()) {
    auto [w, h] = doc_size(p.character);
    Rgba bg{0, 0, 0, 0};
    if (!apply_picture_flags(a.size, a.background, w, h, bg)) return kExitBadInput;
    const int rc = write_picture(p, a.output, w, h, bg, a.overlay, targets);
    if (rc != kExitOk) return rc;
  }
  if (a.dump.empty() && a.output.empty()) {
    for (size_t h = 0; h < p.solver->handle_count(); ++h) {
      std::printf("%s: residual %.4f\n", p.rig.handles[h].name.c_str(), residual(h));
    }
  }
  // What was written: a new user sees the files, not silence (as render and interp say theirs).
  if (!a.output.empty()) std::cout << a.output << "\n";
  if (!a.dump.empty()) std::cout << a.dump << "\n";
  return kExitOk;
}

}  // namespace mar
