#include "app/studio/studio.h"
#include "app/rig_trial.h"

#include "character/load.h"
#include "geom/triangulate.h"
#include "base/read_file.h"
#include "rig/auto_rig.h"
#include "rig/edit.h"
#include "rig/part_names.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <sstream>

namespace mar {

namespace fs = std::filesystem;

namespace {

// Iterations that bring a pose loaded again (an edit, an undo) back to where it was.
constexpr int kSettle = 80;

// A handle name from a part's: its words joined by '-' ("Left Arm" -> "left-arm").
std::string handle_base(const std::string& part) {
  std::string out;
  for (const std::string& w : name_words(part)) out += (out.empty() ? "" : "-") + w;
  return out.empty() ? "handle" : out;
}

// What each shape is to the automatic rig, as a handle name for a part the drawing does not
// name (an editor's `ellipse1042`): body, head, limb-left or limb-right by its side of the
// body, and a detail as what it rides on.
std::vector<std::string> part_roles(const Character& ch) {
  std::vector<std::string> roles(ch.shapes.size());
  const AutoRig ar = auto_rig(ch, "", "", AutoRigOptions{false, true});
  Vec2 body = Vec2::Zero();
  for (const AutoRigPart& p : ar.parts)
    if (p.kind == AutoRigPart::Body && size_t(p.shape) < ch.shapes.size()) {
      const Bounds b = ch.shapes[size_t(p.shape)].bounds();
      body = 0.5 * (b.lo + b.hi);
    }
  std::function<std::string(size_t, int)> role = [&](size_t i, int depth) -> std::string {
    const AutoRigPart& p = ar.parts[i];
    switch (p.kind) {
      case AutoRigPart::Body: return "body";
      case AutoRigPart::Head: return "head";
      case AutoRigPart::Limb: {
        const Bounds b = ch.shapes[size_t(p.shape)].bounds();
        return 0.5 * (b.lo.x() + b.hi.x()) < body.x() ? "limb-left" : "limb-right";
      }
      case AutoRigPart::Detail:
        if (p.parent >= 0 && size_t(p.parent) < ar.parts.size() && depth < 16) return role(size_t(p.parent), depth + 1);
    }
    return "";
  };
  for (size_t i = 0; i < ar.parts.size(); ++i)
    if (size_t(ar.parts[i].shape) < roles.size()) roles[size_t(ar.parts[i].shape)] = role(i, 0);
  return roles;
}

}  // namespace

Result<std::unique_ptr<Studio>> Studio::open(const std::string& character, const std::string& rig_path, const std::string& mask) {
  using R = Result<std::unique_ptr<Studio>>;
  std::unique_ptr<Studio> s(new Studio());
  s->character_ = character;
  s->rig_path_ = rig_path;
  s->mask_ = mask;
  std::error_code ec;
  std::string text;
  if (fs::exists(rig_path, ec)) {
    Result<std::string> read = read_file(rig_path, kMaxTomlBytes, "a rig");
    if (!read.ok()) return R::failure(read.error);
    text = std::move(*read.value);
    s->saved_ = text;
    s->on_disk_ = true;
  } else {
    LoadOptions lo;
    lo.mask_path = mask;
    auto ch = load_character(character, lo);
    if (!ch.ok()) return R::failure(ch.error);
    // Paths in the rig are relative to the rig's folder.
    const fs::path dir = fs::absolute(rig_path).parent_path();
    auto relative = [&](const std::string& p) {
      if (p.empty()) return p;
      const fs::path r = fs::relative(fs::absolute(p), dir, ec);
      return ec || r.empty() ? fs::absolute(p).string() : r.generic_string();
    };
    // (the rig `marionette rig -o` writes: tried on its starter show, app/rig_trial.h)
    text = write_auto_rig(auto_rig_tried(*ch.value, character, mask, relative(character), relative(mask), {}), *ch.value);
  }
  if (std::string err = s->load(text, {}); !err.empty()) return R::failure(err);
  s->history_ = {s->state()};
  s->at_ = 0;
  return R::success(std::move(s));
}

std::string Studio::load(const std::string& text, const std::vector<std::pair<std::string, Vec2>>& targets) {
  auto rig = parse_rig(text, rig_path_);
  if (!rig.ok()) return rig.error;
  Rig file_rig = *rig.value;
  rig.value->max_spacing = std::max(spacing_, sculpt_spacing(*rig.value));  // (a sculpting tool's finer frame)
  auto p = load_puppet(character_, std::move(*rig.value), mask_);
  if (!p.ok()) return p.error;
  Puppet& pp = **p.value;
  if (FeatureFrameMethod* ff = pp.feature_frame()) ff->core().reserve_soft(kSoftTargets);  // (the tools' targets)
  std::vector<Vec2> t = pp.rest_targets();
  bool posed = false;
  for (size_t h = 0; h < t.size(); ++h)
    for (const auto& [name, at] : targets)
      if (name == pp.rig.handles[h].name && (at - t[h]).norm() > 0) {
        t[h] = at;
        posed = true;
      }
  if (posed) {
    pp.solver->initial_guess(t);
    pp.solver->solve(t, kSettle);
    pp.reconstruct();
  }
  puppet_ = std::move(*p.value);
  if (roles_.size() != puppet_->character.shapes.size()) roles_ = part_roles(puppet_->character);
  file_rig_ = std::move(file_rig);
  text_ = RigText(text);
  targets_ = std::move(t);
  return prepare_tools();
}

Studio::State Studio::state() const {
  State s;
  s.text = text_.text();
  for (size_t h = 0; h < targets_.size(); ++h) s.targets.push_back({puppet_->rig.handles[h].name, targets_[h]});
  return s;
}

void Studio::push() {
  history_.resize(at_ + 1);
  history_.push_back(state());
  at_ = history_.size() - 1;
}

std::string Studio::edit(const RigText& changed, std::vector<std::pair<std::string, Vec2>> targets) {
  if (std::string err = load(changed.text(), targets); !err.empty()) return err;
  push();
  return "";
}

void Studio::set_target(size_t h, const Vec2& p) {
  if (h < targets_.size()) targets_[h] = p;
}

void Studio::step() {
  // The tools step as a show's do (Actor::solve): the brush, the curve, then the curve's hold
  // on the handles of its chain.
  const ShowBrush* b = tool_ == Tool::Brush ? &brush_spec_ : nullptr;
  const ShowCurve* c = tool_ == Tool::Curve && from_ >= 0 && !chain_.empty() ? &curve_spec_ : nullptr;
  if (brush_.prepared()) brush_.step(pen_, b, 1.0, 1.0 / 60, false, targets_, *puppet_);
  if (curve_.prepared()) curve_.step(pen_, c, 1.0 / 60, false, targets_, *puppet_);
  if (line_.prepared()) line_.step(pen_, tool_ == Tool::Line ? &line_spec_ : nullptr, 1.0 / 60, false, targets_, *puppet_);
  solve_targets_ = targets_;
  if (curve_.prepared()) curve_.drive_handles(solve_targets_);
  puppet_->solver->solve(solve_targets_, puppet_->rig.iterations);
  puppet_->reconstruct();
}

void Studio::commit_pose() {
  const State s = state();
  if (s.targets != history_[at_].targets) push();
}

void Studio::reset_pose() {
  clear_sculpt();
  targets_ = puppet_->rest_targets();
  puppet_->solver->reset_to_rest();
  puppet_->reconstruct();
  commit_pose();
}

void Studio::restore(const State& s) {
  if (s.text != text_.text()) {
    load(s.text, s.targets);  // it loaded before
    return;
  }
  for (size_t h = 0; h < targets_.size(); ++h) {
    targets_[h] = puppet_->rig.handles[h].rest;
    for (const auto& [name, at] : s.targets)
      if (name == puppet_->rig.handles[h].name) targets_[h] = at;
  }
  puppet_->solver->solve(targets_, kSettle);
  puppet_->reconstruct();
}

bool Studio::undo() {
  if (at_ == 0) return false;
  restore(history_[--at_]);
  return true;
}

bool Studio::redo() {
  if (at_ + 1 >= history_.size()) return false;
  restore(history_[++at_]);
  return true;
}

int Studio::handle_at(const Vec2& p, double radius) const {
  int best = -1;
  double bd = radius * radius;
  for (size_t h = 0; h < targets_.size(); ++h)
    if (const double d = (handle_point(h) - p).squaredNorm(); d <= bd) {
      bd = d;
      best = int(h);
    }
  return best;
}

std::vector<StudioHinge> Studio::hinges() const {
  std::vector<StudioHinge> out;
  const FeatureFrameMethod* ff = puppet_->feature_frame();
  if (!ff) return out;
  const auto v = ff->core().vertices();
  for (const FrameJoint& jt : ff->frame().joints) {
    StudioHinge h;
    h.at = v[size_t(jt.va)];
    h.rest = ff->frame().rest[size_t(jt.va)];
    h.shape_a = jt.shape_a;
    h.shape_b = jt.shape_b;
    h.label = part_name(jt.shape_a) + " / " + part_name(jt.shape_b);
    out.push_back(std::move(h));
  }
  return out;
}

int Studio::hinge_at(const Vec2& p, double radius) const {
  int best = -1;
  double bd = radius * radius;
  const std::vector<StudioHinge> hs = hinges();
  for (size_t j = 0; j < hs.size(); ++j)
    if (const double d = (hs[j].at - p).squaredNorm(); d <= bd) {
      bd = d;
      best = int(j);
    }
  return best;
}

int Studio::part_at(const Vec2& p) const {
  const Character& ch = puppet_->character;
  for (size_t k = ch.shapes.size(); k-- > 0;)
    if (puppet_->shown[k] && ch.shapes[k].closed() && ch.shapes[k].contains(p, puppet_->shapes[k])) return int(k);
  return -1;
}

double Studio::stiffness(int part) const {
  if (part < 0 || size_t(part) >= puppet_->character.shapes.size()) return 1;
  if (const FeatureFrameMethod* ff = puppet_->feature_frame())
    if (size_t(part) < ff->frame().shape_stiffness.size()) return ff->frame().shape_stiffness[size_t(part)];
  for (const RigPart& rp : puppet_->rig.parts)
    if (rp.id == puppet_->character.shapes[size_t(part)].id) return rp.stiffness;
  return 1;
}

std::string Studio::part_name(int part) const {
  if (part < 0 || size_t(part) >= puppet_->character.shapes.size()) return "";
  const SubShape& s = puppet_->character.shapes[size_t(part)];
  return s.label.empty() ? s.id : s.label;
}

bool Studio::to_rest(const Vec2& p, Vec2& rest) const {
  const Character& ch = puppet_->character;
  const int k = part_at(p);
  if (k >= 0) {  // the fill triangle p is in, mapped back to the drawing
    const FillMesh& fm = puppet_->mesh.shapes[size_t(k)].fill;
    std::vector<Vec2> posed(fm.vertices.size());
    fill_mesh_positions(fm, puppet_->shapes[size_t(k)], posed);
    for (size_t t = 0; t + 2 < fm.triangles.size(); t += 3) {
      const size_t a = size_t(fm.triangles[t]), b = size_t(fm.triangles[t + 1]), c = size_t(fm.triangles[t + 2]);
      const Vec2 e1 = posed[b] - posed[a], e2 = posed[c] - posed[a], d = p - posed[a];
      const double det = e1.x() * e2.y() - e1.y() * e2.x();
      if (std::abs(det) < 1e-12) continue;
      const double u = (d.x() * e2.y() - d.y() * e2.x()) / det, w = (e1.x() * d.y() - e1.y() * d.x()) / det;
      if (u < -1e-9 || w < -1e-9 || u + w > 1 + 1e-9) continue;
      rest = fm.vertices[a] + u * (fm.vertices[b] - fm.vertices[a]) + w * (fm.vertices[c] - fm.vertices[a]);
      return true;
    }
  }
  // Near an outline or a stroke: the nearest drawn point, and p's offset from it.
  const double reach = 0.02 * puppet_->diagonal;
  double bd = reach * reach;
  bool found = false;
  for (size_t s = 0; s < ch.shapes.size(); ++s) {
    if (!puppet_->shown[s]) continue;
    for (size_t i = 0; i < puppet_->shapes[s].size(); ++i)
      if (const double d = (puppet_->shapes[s][i] - p).squaredNorm(); d < bd) {
        bd = d;
        rest = ch.shapes[s].points[i] + (p - puppet_->shapes[s][i]);
        found = true;
      }
  }
  return found;
}

std::string Studio::add_handle(const Vec2& p) {
  Vec2 rest;
  if (!to_rest(p, rest)) return "click on the character to add a handle there";
  const int part = part_at(p);
  // (after the part's name; a part its editor named `ellipse1042` after what it is)
  const std::string named = part >= 0 ? part_name(part) : "";
  const std::string role = part >= 0 && size_t(part) < roles_.size() ? roles_[size_t(part)] : "";
  const std::string base = handle_base(!named.empty() && (!made_up(named) || role.empty()) ? named : role.empty() ? "handle" : role);
  std::string name = base;
  for (int n = 2; puppet_->rig.find_handle(name) >= 0; ++n) name = base + "-" + std::to_string(n);
  RigText t = text_;
  t.append("handle", "name = " + toml_string(name) + "\nrest = " + toml_point(rest.x(), rest.y()) + "\n");
  State s = state();
  bool posed = false;
  for (size_t h = 0; h < targets_.size(); ++h) posed = posed || targets_[h] != puppet_->rig.handles[h].rest;
  if (posed) s.targets.push_back({name, p});  // it holds the part where it is (at rest: its rest, as written)
  if (std::string err = edit(t, s.targets); !err.empty()) return err;
  return "";
}

std::string Studio::remove_handle(size_t h) {
  if (h >= puppet_->rig.handles.size()) return "no such handle";
  const std::string name = puppet_->rig.handles[h].name;
  for (const RigKey& k : file_rig_.keys)
    for (const auto& [hn, at] : k.targets)
      if (hn == name) return "handle '" + name + "' is in key '" + k.name + "' (line " + std::to_string(k.line) + "): take it out of the key first";
  if (puppet_->rig.handles.size() == 1) return "a rig needs a handle: add another before removing '" + name + "'";
  RigText t = text_;
  if (!t.remove("handle", h)) return "handle '" + name + "' is not in the rig's text";
  return edit(t, state().targets);
}

std::string Studio::move_hinge(size_t j, const Vec2& p) {
  const std::vector<StudioHinge> hs = hinges();
  if (j >= hs.size()) return "no such hinge";
  Vec2 rest;
  if (!to_rest(p, rest)) return "a hinge goes on the parts it joins";
  const Character& ch = puppet_->character;
  const std::string a = ch.shapes[size_t(hs[j].shape_a)].id, b = ch.shapes[size_t(hs[j].shape_b)].id;
  const std::string parts = "[" + toml_string(a) + ", " + toml_string(b) + "]";
  RigText t = text_;
  int found = -1;
  for (size_t n = 0; n < file_rig_.joints.size() && found < 0; ++n) {
    const RigJoint& rj = file_rig_.joints[n];
    if (rj.weld) continue;
    const bool named = (rj.part_a == a && rj.part_b == b) || (rj.part_a == b && rj.part_b == a);
    const bool placed = rj.part_a.empty() && rj.has_at && (rj.at - hs[j].rest).norm() < 0.005 * puppet_->diagonal;
    if (named || placed) found = int(n);
  }
  if (found >= 0) {
    t.set("joint", size_t(found), "at", toml_point(rest.x(), rest.y()));
    if (file_rig_.joints[size_t(found)].part_a.empty()) t.set("joint", size_t(found), "parts", parts);
  } else {
    t.append("joint", "at = " + toml_point(rest.x(), rest.y()) + "\nparts = " + parts + "\nkind = \"hinge\"\n");
  }
  return edit(t, state().targets);
}

std::string Studio::scale_stiffness(int part, double factor) {
  if (!puppet_->feature_frame()) return "stiffness by part is the feature frame's; this rig's solver is " + puppet_->rig.solver;
  if (part < 0 || size_t(part) >= puppet_->character.shapes.size()) return "scroll over a part to change its stiffness";
  const std::string id = puppet_->character.shapes[size_t(part)].id;
  const double v = std::clamp(stiffness(part) * factor, 0.05, 50.0);
  RigText t = text_;
  int found = -1;
  for (size_t n = 0; n < file_rig_.parts.size() && found < 0; ++n)
    if (file_rig_.parts[n].id == id) found = int(n);
  if (found >= 0) t.set("part", size_t(found), "stiffness", toml_number(v));
  else t.append("part", "id = " + toml_string(id) + "\nstiffness = " + toml_number(v) + "\n");
  return edit(t, state().targets);
}

std::string Studio::save_key(const std::string& raw) {
  std::string name = raw;
  while (!name.empty() && std::isspace(static_cast<unsigned char>(name.back()))) name.pop_back();
  while (!name.empty() && std::isspace(static_cast<unsigned char>(name.front()))) name.erase(name.begin());
  if (name.empty()) return "a key needs a name";
  if (name == "rest") return "'rest' is every handle at rest already; choose another name";
  for (const RigKey& k : file_rig_.keys)
    if (k.name == name) return "there is a key '" + name + "' already (line " + std::to_string(k.line) + ")";
  RigText t = text_;
  if (sculpted()) {
    if (std::string err = save_sculpt(text_, name, t); !err.empty()) return err;
  } else {
    RigKey k;
    k.name = name;
    for (size_t h = 0; h < targets_.size(); ++h)
      if ((targets_[h] - puppet_->rig.handles[h].rest).norm() > 1e-9) k.targets.push_back({puppet_->rig.handles[h].name, targets_[h]});
    if (k.targets.empty()) return "move a handle or sculpt first: a key is where the handles are, or a sculpted shape";
    std::string body = "name = " + toml_string(name) + "\ntargets = { ";
    for (size_t i = 0; i < k.targets.size(); ++i)
      body += (i ? ", " : "") + toml_string(k.targets[i].first) + " = [" + toml_number(k.targets[i].second.x()) + ", " +
              toml_number(k.targets[i].second.y()) + "]";
    body += " }\n";
    t.append("key", body);
  }
  // (the pose stays as it is, sculpt and all: the puppet is not loaded again for a key)
  auto parsed = parse_rig(t.text(), rig_path_);
  if (!parsed.ok()) return parsed.error;
  file_rig_ = std::move(*parsed.value);
  text_ = t;
  push();
  return "";
}

std::string Studio::save() {
  if (std::string err = write_atomically(rig_path_, text_.text()); !err.empty()) return err;
  saved_ = text_.text();
  on_disk_ = true;
  return "";
}

}  // namespace mar
