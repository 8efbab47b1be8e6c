#include "motion/chain.h"

#include <algorithm>
#include <cmath>

namespace mar {

namespace {

constexpr double kStall = 0.25;  // a frame longer than this resets the chain (seconds)

Vec2 dir(double a) { return {std::cos(a), std::sin(a)}; }
Vec2 rotate(const Vec2& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}

}  // namespace

Chain::Chain(std::span<const Vec2> rest, const ChainParams& p) : p_(p) {
  const size_t n = rest.size() > 1 ? rest.size() - 1 : 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 d = rest[i + 1] - rest[i];
    len_.push_back(std::max(1e-6, d.norm()));
    rest_angle_.push_back(std::atan2(d.y(), d.x()));
    rest_offset_.push_back(rest[i + 1] - rest[0]);
  }
  state_.assign(n, Link{});
  prev_ = good_ = state_;
  out_.assign(n, Vec2::Zero());
  root_.assign(n, Vec2::Zero());
  root1_ = root2_ = root_;
  if (!rest.empty()) reset(rest[0], 0);
  resets_ = 0;
}

Vec2 Chain::end_of(size_t i, const std::vector<Link>& s) const {
  Vec2 at = anchor_;
  for (size_t k = 0; k <= i && k < s.size(); ++k) at += s[k].r * dir(s[k].theta);
  return at;
}

void Chain::reset(const Vec2& anchor, double rotation) {
  anchor_ = anchor0_ = anchor;
  rotation_ = rotation0_ = rotation;
  Vec2 at = anchor;
  for (size_t i = 0; i < state_.size(); ++i) {
    state_[i] = {rest_angle_[i] + rotation, 0, len_[i], 0};
    root_[i] = root1_[i] = root2_[i] = at;
    at += len_[i] * dir(state_[i].theta);
  }
  prev_ = good_ = state_;
  for (size_t i = 0; i < out_.size(); ++i) out_[i] = anchor + rotate(rest_offset_[i], rotation);
  acc_ = 0;
  history_ = 0;
  started_ = true;
  ++resets_;
}

void Chain::step(double h, const Vec2& anchor, double rotation, double spin, const MotionWorld& w) {
  prev_ = state_;
  const double w0 = 2 * M_PI * std::max(0.0, p_.frequency);
  const Vec2 g = w.gravity + p_.gravity;
  const Vec2 wind = (w.wind + p_.wind) / std::max(1e-6, p_.mass);
  Vec2 root = anchor;
  for (size_t i = 0; i < state_.size(); ++i) {
    Link& l = state_[i];
    // Where this link hangs from, and that point's acceleration (two steps of history).
    root2_[i] = root1_[i];
    root1_[i] = root_[i];
    root_[i] = root;
    const Vec2 a = history_ >= 2 ? Vec2((root_[i] - 2 * root1_[i] + root2_[i]) / (h * h)) : Vec2(Vec2::Zero());
    const Vec2 F = g + wind - p_.inertia * a;
    const double L = len_[i];
    const double r = p_.model == ChainParams::Spring ? l.r : L;
    const Vec2 u = dir(l.theta);
    // The drawn direction turned with what it hangs from: the parent, or the link before.
    double rest = i == 0 ? rest_angle_[0] + rotation : rest_angle_[i] - rest_angle_[i - 1] + state_[i - 1].theta;
    // With a spring, the drawing is where it settles under this gravity (the parent as drawn):
    // the spring's own rest leans against gravity's pull on the drawn link.
    if (w0 > 0) rest -= std::asin(std::clamp(cross(dir(rest_angle_[i]), g) / (L * w0 * w0), -1.0, 1.0));
    const double turn = i == 0 ? spin : state_[i - 1].omega;
    const double wn = std::sqrt(w0 * w0 + g.norm() / L);
    const double alpha = cross(u, F) / r - w0 * w0 * std::sin(l.theta - rest) - 2 * p_.damping * wn * (l.omega - turn);
    // Velocities first, then the speed limit on the end's whole speed (turning and, for the
    // spring model, stretching), then the positions.
    l.omega += h * alpha;
    if (p_.model == ChainParams::Spring) {
      const double k = w0 > 0 ? w0 : wn;
      // Its rest length leans against gravity along the drawn link: the drawing is where it settles.
      const double rest_length = L - dir(rest_angle_[i]).dot(g) / (k * k);
      const double rdd = -k * k * (l.r - rest_length) - 2 * p_.damping * k * l.rdot + u.dot(F) + l.r * l.omega * l.omega;
      l.rdot += h * rdd;
    }
    const double r1 = p_.model == ChainParams::Spring ? std::clamp(l.r + h * l.rdot, 0.25 * L, 4 * L) : L;
    const double reach = std::max(l.r, r1);
    if (const double speed = portable_hypot(l.omega * reach, l.rdot); p_.limit > 0 && speed > p_.limit) {
      l.omega *= p_.limit / speed;
      l.rdot *= p_.limit / speed;
    }
    if (p_.model == ChainParams::Spring) l.r = std::clamp(l.r + h * l.rdot, 0.25 * L, 4 * L);
    else l.r = L;
    l.theta += h * l.omega;
    if (!std::isfinite(l.theta) || !std::isfinite(l.omega) || !std::isfinite(l.r) || !std::isfinite(l.rdot)) {
      l = good_[i];  // undo, and stop it
      l.omega = l.rdot = 0;
      ++reverts_;
    }
    good_[i] = l;
    root += l.r * dir(l.theta);
  }
  if (history_ < 2) ++history_;
  ++steps_;
}

void Chain::advance(double dt, double h, const Vec2& anchor, double rotation, const MotionWorld& w) {
  if (state_.empty()) return;
  if (!(dt >= 0) || dt > kStall || !(h > 0) || !anchor.allFinite() || !std::isfinite(rotation)) {
    if (anchor.allFinite() && std::isfinite(rotation)) reset(anchor, rotation);
    return;
  }
  anchor0_ = anchor_;
  rotation0_ = rotation_;
  anchor_ = anchor;
  rotation_ = rotation;
  const double before = acc_;
  acc_ += dt;
  const double spin = dt > 0 ? (rotation_ - rotation0_) / dt : 0;
  for (int k = 1; acc_ >= h; ++k) {
    // The parent moves linearly through the frame: where it is at this step's end.
    const double f = dt > 0 ? std::clamp((k * h - before) / dt, 0.0, 1.0) : 1.0;
    step(h, anchor0_ + f * (anchor_ - anchor0_), rotation0_ + f * (rotation_ - rotation0_), spin, w);
    acc_ -= h;
  }
  // Between the last two steps, anchored where the parent is now; mixed with the rigid pose.
  const double a = std::clamp(acc_ / h, 0.0, 1.0);
  const double m = std::clamp(p_.mix * w.strength, 0.0, 1.0);
  Vec2 at = anchor_;
  for (size_t i = 0; i < state_.size(); ++i) {
    const double th = prev_[i].theta + a * (state_[i].theta - prev_[i].theta);
    const double r = prev_[i].r + a * (state_[i].r - prev_[i].r);
    at += r * dir(th);
    const Vec2 rigid = anchor_ + rotate(rest_offset_[i], rotation_);
    out_[i] = rigid + m * (at - rigid);
  }
}

double smooth_noise(double t, double seed) {
  // Incommensurate frequencies (ratios of irrationals): never periodic, smooth, in [-1, 1].
  const double s = seed * 12.9898;
  return (std::sin(t * 1.0 + s) * 0.5 + std::sin(t * 2.2360679 + 1.7 * s) * 0.3 + std::sin(t * 3.6055513 + 2.3 * s) * 0.2);
}

}  // namespace mar
