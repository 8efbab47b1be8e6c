// The rig studio's sculpting tools (studio.h): the show's brush and drawn curve on the studio's
// puppet, and a sculpted pose saved as a key.
#include "app/studio/studio.h"

#include "rig/auto_rig.h"
#include "rig/edit.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

namespace mar {

namespace fs = std::filesystem;

std::string Studio::prepare_tools() {
  brush_ = BrushStage{};
  curve_ = CurveStage{};
  line_ = ContourStage{};
  from_ = -1;
  chain_.clear();
  stroke_.clear();
  pen_ = Mapping::Pen{};
  pen_was_down_ = false;
  line_spec_.fit = ShowCurve::Contour;
  line_spec_.strength = 1.0;
  line_spec_.release = ShowBrush::Hold;
  if (tool_ == Tool::Brush) return brush_.prepare(*puppet_);
  if (tool_ == Tool::Line) return line_.prepare(*puppet_, line_spec_, "");
  return "";
}

std::string Studio::set_tool(Tool t) {
  if (t != Tool::Pose && !puppet_->feature_frame())
    return "the brush and the curve sculpt the feature frame; this rig's solver is " + puppet_->rig.solver;
  const Tool was = tool_;
  tool_ = t;
  if (t != Tool::Pose && spacing_ < kSculptSpacing) {  // the finer frame: load again, keeping the pose
    spacing_ = kSculptSpacing;
    if (std::string err = load(text_.text(), state().targets); !err.empty()) {
      tool_ = was;
      return err;
    }
    return "";
  }
  // One tool's shape at a time (they share the solve's soft targets): another's lets go, and
  // the chosen one's stage is made (the curve makes its own as each stroke names its chain).
  const bool other = (t != Tool::Brush && brush_.prepared()) || (t != Tool::Curve && curve_.prepared()) ||
                     (t != Tool::Line && line_.prepared());
  const bool ready = t == Tool::Curve || (t == Tool::Brush && brush_.prepared()) || (t == Tool::Line && line_.prepared());
  if (t == Tool::Pose || (ready && !other)) return "";
  const std::string err = clear_sculpt();
  if (!err.empty()) tool_ = was;
  return err;
}

double Studio::brush_radius(double pressure) const {
  const double lo = 0.02 * puppet_->diagonal, hi = 0.08 * puppet_->diagonal;
  return brush_scale_ * (lo + std::clamp(pressure, 0.0, 1.0) * (hi - lo));
}

void Studio::scale_brush(double factor) { brush_scale_ = std::clamp(brush_scale_ * factor, 0.25, 4.0); }

bool Studio::sculpted() const { return !brush_.points().empty() || curve_.active() || line_.active(); }

std::string Studio::clear_sculpt() {
  if (FeatureFrameMethod* ff = puppet_->feature_frame()) ff->core().clear_soft();
  return prepare_tools();
}

void Studio::pen(const Vec2& p, bool down, double pressure) {
  // The brush takes its radius from the pressure at the touch, in character units (the show's
  // radius is canvas pixels: here one unit is one "pixel").
  const double r = brush_radius(pressure);
  brush_spec_.radius_lo = brush_spec_.radius_hi = r;
  brush_spec_.release = ShowBrush::Hold;
  pen_.point = p;
  pen_.pressure = pressure;
  pen_.down = down;
  if (tool_ == Tool::Line) {
    if (down && !pen_was_down_) stroke_.assign(1, p);
    else if (down) stroke_.push_back(p);
  }
  if (tool_ == Tool::Curve) {
    if (down && !pen_was_down_) {  // a new stroke: its chain hangs from the part it starts on
      if (curve_.prepared()) puppet_->feature_frame()->core().clear_soft();
      curve_ = CurveStage{};
      from_ = part_at(p);
      chain_.clear();
      stroke_.assign(1, p);
      leaves_ = -1;
    } else if (down) {
      stroke_.push_back(p);
      if (leaves_ < 0 && part_at(p) != from_) leaves_ = int(stroke_.size()) - 1;
      pen_curve(p);
    }
  }
  pen_was_down_ = down;
}

// The part under a stroke's new point joins the chain when it hangs from the chain's last part
// (or takes the last one's place: a detail drawn over a limb, a collar on a neck); the curve is
// prepared again on the longer chain and the stroke so far laid along it.
void Studio::pen_curve(const Vec2& p) {
  if (from_ < 0) return;
  const int k = part_at(p);
  if (k < 0 || k == from_ || std::find(chain_.begin(), chain_.end(), k) != chain_.end()) return;
  auto attempt = [&](std::vector<int> chain) {
    ShowCurve spec;
    spec.from = puppet_->character.shapes[size_t(from_)].id;
    for (int c : chain) spec.parts.push_back(puppet_->character.shapes[size_t(c)].id);
    spec.strength = 1.0;
    spec.release = ShowBrush::Hold;
    CurveStage next;
    if (!next.prepare(*puppet_, spec, "the studio: ").empty()) return false;
    puppet_->feature_frame()->core().clear_soft();
    curve_ = std::move(next);
    curve_spec_ = spec;
    chain_ = std::move(chain);
    // The stroke so far, laid along the new chain (its soft targets set once it has a direction),
    // from its last point on the part the chain hangs from: the chain hangs there, and a start
    // drawn further in would lay the chain's root back into that part.
    Mapping::Pen down;
    down.down = true;
    for (size_t i = size_t(std::max(0, leaves_ - 1)); i < stroke_.size(); ++i) {
      down.point = stroke_[i];
      curve_.step(down, &curve_spec_, 1.0 / 60, false, targets_, *puppet_);
    }
    return true;
  };
  std::vector<int> longer = chain_;
  longer.push_back(k);
  if (attempt(longer) || chain_.empty()) return;
  std::vector<int> replaced = chain_;
  replaced.back() = k;
  attempt(replaced);
}

std::vector<std::string> Studio::curve_chain() const {
  std::vector<std::string> out;
  if (from_ < 0) return out;
  out.push_back(part_name(from_));
  for (int c : chain_) out.push_back(part_name(c));
  return out;
}

// A sculpted key: every shape's outline as posed (per contour, each point's rest and where it
// is: app/keys.cpp reads it onto a frame of any density and flattening), in a JSON file beside
// the rig (written now, atomically), and a [[key]] naming it appended to `base`.
std::string Studio::save_sculpt(const RigText& base, const std::string& name, RigText& out) {
  std::string stem;
  for (const std::string& w : name_words(name)) stem += (stem.empty() ? "" : "-") + w;
  if (stem.empty()) stem = "key";
  const fs::path rig = fs::absolute(rig_path_);
  std::string file = rig.stem().string() + "." + stem + ".key.json";
  std::error_code ec;
  for (int n = 2; fs::exists(rig.parent_path() / file, ec); ++n)
    file = rig.stem().string() + "." + stem + "-" + std::to_string(n) + ".key.json";
  nlohmann::json shapes = nlohmann::json::object();
  for (size_t k = 0; k < puppet_->character.shapes.size(); ++k) {
    const SubShape& sh = puppet_->character.shapes[k];
    nlohmann::json contours = nlohmann::json::array();
    for (const Contour& c : sh.contours) {
      nlohmann::json pts = nlohmann::json::array();
      for (int i = c.begin; i < c.begin + c.count; ++i) {
        const Vec2& r = sh.points[size_t(i)];
        const Vec2& q = puppet_->shapes[k][size_t(i)];
        pts.push_back({r.x(), r.y(), q.x(), q.y()});
      }
      contours.push_back(std::move(pts));
    }
    shapes[sh.id] = std::move(contours);
  }
  const std::string json = nlohmann::json{{"key", name}, {"shapes", std::move(shapes)}}.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  if (std::string err = write_atomically((rig.parent_path() / file).string(), json); !err.empty()) return err;
  out = base;
  out.append("key", "name = " + toml_string(name) + "\nshapes = " + toml_string(file) + "\n");
  return "";
}

}  // namespace mar
