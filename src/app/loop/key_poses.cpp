#include "app/loop/key_poses.h"

#include "app/show.h"
#include "geom/polygon.h"
#include "solve/solver.h"

#include <algorithm>

namespace mar {

void KeyPoseStage::add_settings(Mapping& m, int keys) {
  for (int a = -1; a < keys; ++a)
    for (int b = -1; b < keys; ++b)
      if (a != b) settings_.push_back({m.add_setting({0, 0, 1, false}), a, b});
  for (int k = 0; k < keys; ++k) settings_.push_back({m.add_setting({0, 0, 1, false}), -2, k});
}

bool KeyPoseStage::keep_driven(const ShowConfig& sh, int who) {
  std::erase_if(settings_, [&](const KeySetting& k) {
    for (const Binding& b : sh.bindings)
      if (b.target == TargetKind::Setting && b.index == k.setting) return false;
    for (const ShowBehavior& b : sh.behaviors)  // (a key an idle behaviour breathes counts too)
      if (b.target == TargetKind::Setting && b.index == k.setting) return false;
    return true;
  });
  bool recalls = false;
  for (const Binding& b : sh.bindings) recalls = recalls || (b.target == TargetKind::Recall && b.member == who);
  return !settings_.empty() || recalls;
}

std::string KeyPoseStage::prepare(const Puppet& p, const std::vector<Points>& keys, const std::vector<Points>* details) {
  if (!p.feature_frame()) return p.rig.path + ": key poses need the feature frame solver";
  interp_ = std::make_unique<KeyInterpolator>();
  std::string err;
  if (!interp_->prepare(p.feature_frame()->frame(), &err)) {
    interp_.reset();
    return p.rig.path + ": " + err;
  }
  for (const Points& k : keys) interp_->add_key(k);
  puppet_ = &p;
  const size_t n = p.rig.keys.size();
  weights_.assign(n, 0.0);
  last_weights_.assign(n, -1.0);
  base_frame_.assign(p.feature_frame()->frame().rest.size(), Vec2::Zero());
  base_offset_.assign(p.rig.handles.size(), Vec2::Zero());
  for (auto* v : {&recall_w_, &recall_from_, &recall_to_}) v->assign(n, 0.0);
  const FeatureFrame& f = p.feature_frame()->frame();
  details_.assign(n, Points{});
  bool any = false;
  for (size_t k = 0; details && k < n && k < details->size(); ++k)
    if ((*details)[k].size() == f.rest.size()) {
      details_[k] = (*details)[k];
      any = true;
    }
  detail_.clear();
  part_vertices_.clear();
  if (any) {
    detail_.assign(f.rest.size(), Vec2::Zero());
    part_vertices_.assign(p.character.shapes.size(), {});
    size_t most = 0;
    for (size_t i = 0; i < f.rest.size(); ++i) part_vertices_[size_t(f.origin[i].shape)].push_back(int(i));
    for (const auto& pv : part_vertices_) most = std::max(most, pv.size());
    from_.assign(most, Vec2::Zero());
    to_.assign(most, Vec2::Zero());
  }
  return {};
}

bool KeyPoseStage::step(double dt, std::span<const double> values, const Recall* recall) {
  if (!interp_) return false;
  std::fill(weights_.begin(), weights_.end(), 0.0);
  for (size_t i = 0; i < settings_.size() && i < values.size(); ++i) {
    const KeySetting& k = settings_[i];
    const double v = values[i];
    if (k.from == -2) {
      weights_[size_t(k.to)] += v;
      continue;
    }
    if (v == 0 && k.from < 0) continue;
    if (k.from >= 0) weights_[size_t(k.from)] += 1 - v;
    if (k.to >= 0) weights_[size_t(k.to)] += v;
  }
  bool jump = false;
  if (recall) {
    recall_from_ = recall_w_;  // (same sizes: no allocation)
    for (size_t k = 0; k < recall_to_.size(); ++k) recall_to_[k] = (int(k) == recall->key ? 1.0 : 0.0) - weights_[k];
    recall_t_ = 0;
    recall_seconds_ = recall->seconds;
    recall_ease_ = recall->ease;
    recall_on_ = true;
    jump = recall->seconds <= 0;
  }
  if (recall_on_) {
    recall_t_ += dt;
    const bool done = recall_t_ >= recall_seconds_ * (1 - 1e-9);
    const double e = done ? 1.0 : ease(recall_ease_, recall_t_ / recall_seconds_);
    for (size_t k = 0; k < recall_w_.size(); ++k) recall_w_[k] = recall_from_[k] + e * (recall_to_[k] - recall_from_[k]);
    recall_on_ = !done;
  }
  for (size_t k = 0; k < weights_.size(); ++k) weights_[k] += recall_w_[k];
  if (weights_ != last_weights_) {
    std::copy(weights_.begin(), weights_.end(), last_weights_.begin());
    interp_->blend(weights_, base_frame_);
    const FeatureFrameMethod& ff = *puppet_->feature_frame();
    for (size_t h = 0; h < base_offset_.size() && h < ff.bindings().size(); ++h)
      base_offset_[h] = eval_param(ff.bindings()[h], base_frame_) - puppet_->rig.handles[h].rest;
    detailed_ = false;
    if (!detail_.empty()) {
      std::fill(detail_.begin(), detail_.end(), Vec2::Zero());
      for (size_t k = 0; k < details_.size(); ++k)
        if (!details_[k].empty() && weights_[k] != 0) {
          detailed_ = true;
          for (size_t i = 0; i < detail_.size(); ++i) detail_[i] += weights_[k] * details_[k][i];
        }
    }
  }
  return jump;
}

void KeyPoseStage::detail_onto(std::span<const Vec2> v, std::span<Vec2> out) const {
  for (size_t i = 0; i < v.size() && i < out.size(); ++i) out[i] = v[i];
  if (!detailed_) return;
  for (const std::vector<int>& part : part_vertices_) {
    if (part.empty()) continue;
    size_t n = 0;
    for (int i : part) {
      from_[n] = base_frame_[size_t(i)] - detail_[size_t(i)];  // (what the handles make of the base)
      to_[n++] = v[size_t(i)];
    }
    const RigidMotion m = rigid_fit(std::span<const Vec2>(from_.data(), n), std::span<const Vec2>(to_.data(), n));
    for (int i : part)
      if (size_t(i) < out.size()) out[size_t(i)] += m.turn(detail_[size_t(i)]);
  }
}

void KeyPoseStage::offset(std::span<Vec2> targets) const {
  for (size_t h = 0; h < base_offset_.size() && h < targets.size(); ++h) targets[h] += base_offset_[h];
}

}  // namespace mar
