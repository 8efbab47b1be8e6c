#include "app/loop/key_poses.h"

#include "app/show.h"
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

std::string KeyPoseStage::prepare(const Puppet& p, const std::vector<Points>& keys) {
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
  }
  return jump;
}

void KeyPoseStage::offset(std::span<Vec2> targets) const {
  for (size_t h = 0; h < base_offset_.size() && h < targets.size(); ++h) targets[h] += base_offset_[h];
}

}  // namespace mar
