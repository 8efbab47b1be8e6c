// [[physics]] tables of a rig: chains of dangling parts (character/rig.h, motion/chain.h).
#include "base/config_toml.h"
#include "character/rig.h"

#include <cstdio>

namespace mar {

using namespace cfg;

void parse_rig_physics(const std::string& path, const toml::node& n, Rig& r) {
  const toml::array* a = n.as_array();
  if (!a) throw ConfigError{at(path, n) + ": use [[physics]] tables"};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (!t) throw ConfigError{at(path, node) + ": a physics chain must be a table"};
    check_keys(path, *t,
               {"name", "parts", "from", "model", "length", "frequency", "damping", "inertia", "mass", "gravity", "wind", "gust", "mix", "limit",
                "handle", "weight"},
               "[[physics]]");
    RigPhysics ph;
    ph.line = int(node.source().begin.line);
    const toml::node* nm = t->get("name");
    if (!nm || !nm->is_string() || nm->value<std::string>()->empty()) throw ConfigError{at(path, node) + ": a physics chain needs a name"};
    ph.name = *nm->value<std::string>();
    if (ph.name.find('.') != std::string::npos)
      throw ConfigError{at(path, *nm) + ": a physics chain's name cannot have a '.' (controls name it physics.NAME.mix)"};
    for (const RigPhysics& o : r.physics)
      if (o.name == ph.name) throw ConfigError{at(path, *nm) + ": physics chain '" + ph.name + "' defined twice"};
    const toml::node* parts = t->get("parts");
    if (!parts) throw ConfigError{at(path, node) + ": physics chain '" + ph.name + "' needs parts = \"id\" or [\"id\", ...] (the dangling parts)"};
    if (parts->is_string()) ph.parts = {*parts->value<std::string>()};
    else ph.parts = strings(path, *parts, "parts");
    if (ph.parts.empty()) throw ConfigError{at(path, *parts) + ": parts is empty"};
    for (const std::string& id : ph.parts)
      if (id.empty()) throw ConfigError{at(path, *parts) + ": a part id is empty"};
    const toml::node* from = t->get("from");
    if (!from) throw ConfigError{at(path, node) + ": physics chain '" + ph.name + "' needs from = \"part or handle\" (what it hangs from)"};
    ph.from = text(path, *from, "from");
    if (const toml::node* m = t->get("model")) {
      const std::string model = text(path, *m, "model");
      if (model != "pendulum" && model != "spring") throw ConfigError{at(path, *m) + ": model must be \"pendulum\" or \"spring\""};
      ph.spring = model == "spring";
    }
    auto in = [&](const char* key, double lo, double hi, double& v) {
      if (const toml::node* x = t->get(key)) {
        v = number(path, *x, key);
        if (v < lo || v > hi) {
          char range[64];
          std::snprintf(range, sizeof range, "%g..%g", lo, hi);
          throw ConfigError{at(path, *x) + ": " + key + " must be " + range};
        }
      }
    };
    in("length", 0, 1e6, ph.length);
    in("frequency", 0, 30, ph.frequency);
    in("damping", 0, 10, ph.damping);
    in("inertia", 0, 10, ph.inertia);
    in("mass", 0.001, 1000, ph.mass);
    in("gust", 0, 1e6, ph.gust);
    in("mix", 0, 1, ph.mix);
    in("limit", 0, 1e7, ph.limit);
    in("weight", 0.001, 1, ph.weight);
    if (const toml::node* g = t->get("gravity")) {
      ph.gravity = point(path, *g, "gravity");
      ph.has_gravity = true;
    }
    if (const toml::node* w = t->get("wind")) ph.wind = point(path, *w, "wind");
    if (const toml::node* h = t->get("handle")) {
      ph.handle = text(path, *h, "handle");
      if (r.find_handle(ph.handle) < 0) throw ConfigError{at(path, *h) + ": the rig has no handle '" + ph.handle + "' (its [[handle]] tables come first)"};
    }
    r.physics.push_back(std::move(ph));
  }
}

}  // namespace mar
