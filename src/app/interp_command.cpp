// interp: in-betweens of two key poses of a rig (src/interp), as pictures and JSON.
#include "app/commands.h"
#include "app/keys.h"
#include "app/puppet.h"
#include "interp/interpolation.h"

#include "base/read_file.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace mar {

int cmd_interp(const InterpArgs& a) {
  const bool one = a.t >= 0;
  if (one == (a.steps > 0) || (one && !(a.t <= 1)) || (!one && (a.steps < 2 || a.steps > 10000))) {
    std::cerr << "error: give either --t T (0..1) or --steps N (2..10000 pictures, from t = 0 to t = 1)\n";
    return kExitBadInput;
  }
  if ((!a.output.empty() && !one) || (!a.out_dir.empty() && one)) {
    std::cerr << "error: -o goes with --t, --out-dir with --steps\n";
    return kExitBadInput;
  }
  auto loaded = load_puppet(a.input, a.rig, a.mask);
  if (!loaded.ok()) {
    std::cerr << "error: " << loaded.error << "\n";
    return kExitBadInput;
  }
  Puppet& p = **loaded.value;
  print_warnings(p.character);
  const int from = find_key(p.rig, a.from), to = find_key(p.rig, a.to);
  if (from == -2 || to == -2) {
    std::string names = "rest";
    for (const RigKey& k : p.rig.keys) names += ", " + k.name;
    std::cerr << "error: no key named '" << (from == -2 ? a.from : a.to) << "' in " << a.rig << " (keys: " << names << ")\n";
    return kExitBadInput;
  }
  auto keys = solve_keys(p);
  if (!keys.ok()) {
    std::cerr << "error: " << keys.error << "\n";
    return kExitBadInput;
  }
  const FeatureFrameMethod* ff = p.feature_frame();
  if (!ff) {
    std::cerr << "error: " << a.rig << ": interp needs the feature frame (solver = \"feature_frame\")\n";
    return kExitBadInput;
  }
  KeyInterpolator interp;
  std::string err;
  if (!interp.prepare(ff->frame(), &err)) {
    std::cerr << "error: " << err << "\n";
    return kExitBadInput;
  }
  for (const Points& k : *keys.value) interp.add_key(k);
  int w = 0, h = 0;
  Rgba bg{0, 0, 0, 0};
  std::tie(w, h) = doc_size(p.character);
  if (!apply_picture_flags(a.size, a.background, w, h, bg)) return kExitBadInput;
  if (!a.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(a.out_dir, ec);
    if (ec) {
      std::cerr << "error: cannot create " << a.out_dir << ": " << ec.message() << "\n";
      return kExitRuntime;
    }
  }
  nlohmann::ordered_json steps = nlohmann::ordered_json::array();
  Points v(ff->frame().rest.size());
  const int n = one ? 1 : a.steps;  // --steps N: N pictures, t = 0 ... 1
  std::string first, last;
  for (int s = 0; s < n; ++s) {
    const double t = one ? a.t : double(s) / (n - 1);
    if (a.linear) interp.linear_morph(from, to, t, v);
    else interp.morph(from, to, t, v);
    ff->place(v, p.shapes);
    if (!a.dump.empty()) {
      nlohmann::ordered_json fv = nlohmann::ordered_json::array(), subs = nlohmann::ordered_json::array();
      for (const Vec2& q : v) fv.push_back({q.x(), q.y()});
      for (size_t k = 0; k < p.shapes.size(); ++k) {
        nlohmann::ordered_json pts = nlohmann::ordered_json::array();
        for (const Vec2& q : p.shapes[k]) pts.push_back({q.x(), q.y()});
        subs.push_back({{"id", p.character.shapes[k].id}, {"points", pts}});
      }
      steps.push_back({{"t", t}, {"frame_vertices", fv}, {"subshapes", subs}});
    }
    std::string png = a.output;
    if (!a.out_dir.empty()) {
      char name[32];
      std::snprintf(name, sizeof name, "step_%03d.png", s);
      png = (std::filesystem::path(a.out_dir) / name).string();
    }
    if (!png.empty()) {
      const int rc = write_picture(p, png, w, h, bg, false, {});
      if (rc != kExitOk) return rc;
      if (first.empty()) first = png;
      last = png;
    }
  }
  if (!a.dump.empty()) {
    nlohmann::ordered_json j;
    j["from"] = a.from;
    j["to"] = a.to;
    j["method"] = a.linear ? "linear" : "arap";
    j["triangles"] = interp.triangles();
    j["steps"] = steps;
    if (const std::string e = write_file(a.dump, j.dump(1) + "\n"); !e.empty()) {
      std::cerr << "error: " << e << "\n";
      return kExitRuntime;
    }
  }
  // What was written: a new user sees the files, not silence.
  const std::string what = a.from + " -> " + a.to + (a.linear ? " (linear)" : "");
  if (one && !first.empty()) std::cout << "wrote " << first << ": " << what << " at t = " << a.t << "\n";
  if (!one && !first.empty())
    std::cout << "wrote " << n << " pictures of " << what << " from t = 0 to 1: " << first << " ... " << last << "\n";
  if (!a.dump.empty()) std::cout << "wrote " << a.dump << ": " << n << (n == 1 ? " step" : " steps") << "\n";
  if (first.empty() && a.dump.empty()) std::cout << "nothing written: give -o, --out-dir or --dump\n";
  if (a.dump.empty() && a.output.empty() && a.out_dir.empty())
    std::printf("%d in-betweens from %s to %s (%zu triangles)\n", n, a.from.c_str(), a.to.c_str(), interp.triangles());
  return kExitOk;
}

}  // namespace mar
