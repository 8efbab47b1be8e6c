#include "solve/feature_frame_method.h"

#include <algorithm>
#include <cmath>

namespace mar {

bool FeatureFrameMethod::prepare(Character& ch, const Rig& rig, std::span<const Vec2> handle_rest, const SolverWeights& w,
                                 std::string* error) {
  if (!prepare_riders(ch, rig, error)) return false;
  // The riding shapes are out of the frame while it is built (their points stay theirs).
  std::vector<std::vector<Contour>> contours(ch.shapes.size());
  for (size_t si = 0; si < ch.shapes.size(); ++si)
    if (!carried_rest_[si].empty()) {
      ch.shapes[si].points.clear();
      std::swap(contours[si], ch.shapes[si].contours);
    }
  const FrameOptions fo = frame_options_from_rig(rig);
  refine_for_frame(ch, fo);
  frame_ = build_feature_frame(ch, fo);
  framed_ = ch;
  for (size_t si = 0; si < ch.shapes.size(); ++si)
    if (!carried_rest_[si].empty()) {
      ch.shapes[si].points = carried_rest_[si];
      std::swap(contours[si], ch.shapes[si].contours);
    }
  // What each rider follows: its host's points near where it is on it (within twice its own
  // reach from `at`, at least a tenth of the host's), at most 64 of them, evenly.
  for (Carried& c : carried_) {
    const Points& host = c.host >= 0 && carried_rest_[size_t(c.host)].empty() ? framed_.shapes[size_t(c.host)].points
                                                                               : carried_rest_[size_t(c.host)];
    double reach = 0;
    for (const Vec2& q : carried_rest_[size_t(c.shape)]) reach = std::max(reach, (q - c.at).norm());
    Bounds hb;
    for (const Vec2& q : host) hb.add(q);
    const double r = std::max(2 * reach, hb.empty() ? 0.0 : 0.1 * (hb.hi - hb.lo).norm());
    std::vector<int> near;
    for (size_t k = 0; k < host.size(); ++k)
      if ((host[k] - c.at).norm() <= r) near.push_back(int(k));
    if (near.size() < 3) {
      near.clear();
      for (size_t k = 0; k < host.size(); ++k) near.push_back(int(k));
    }
    const size_t step = std::max<size_t>(1, near.size() / 64);
    c.follow.clear();
    c.follow_rest.clear();
    for (size_t k = 0; k < near.size(); k += step) {
      c.follow.push_back(near[k]);
      c.follow_rest.push_back(host[size_t(near[k])]);
    }
  }
  bindings_.clear();
  for (const Vec2& p : handle_rest) bindings_.push_back(bind_point(frame_, framed_, p));
  weights_ = w;
  return s_.prepare(frame_, bindings_, w, error);
}

bool FeatureFrameMethod::prepare_riders(const Character& ch, const Rig& rig, std::string* error) {
  carried_.clear();
  carried_rest_.assign(ch.shapes.size(), {});
  auto shape_of = [&](const std::string& id) {
    for (size_t s = 0; s < ch.shapes.size(); ++s)
      if (ch.shapes[s].id == id) return int(s);
    return -1;
  };
  auto at = [&](const RigRider& d) { return (rig.path.empty() ? std::string("rig") : rig.path) + ":" + std::to_string(d.line) + ": rider '" + d.part + "'"; };
  std::vector<char> taken(ch.shapes.size(), 0);
  for (const RigRider& d : rig.riders) {
    Carried c;
    c.shape = shape_of(d.part);
    c.host = shape_of(d.on);
    c.at = d.at;
    if (c.shape < 0 || c.host < 0) {
      if (error) *error = at(d) + (c.shape < 0 ? " is not a sub-shape of the character" : " rides on '" + d.on + "', which is not a sub-shape of the character");
      return false;
    }
    if (c.host == c.shape) {
      if (error) *error = at(d) + " rides on itself";
      return false;
    }
    for (const std::string& id : d.with) {
      const int k = shape_of(id);
      if (k < 0) {
        if (error) *error = at(d) + ": '" + id + "' (with) is not a sub-shape of the character";
        return false;
      }
      c.with.push_back(k);
    }
    std::vector<int> mine = c.with;
    mine.push_back(c.shape);
    for (int k : mine) {
      if (taken[size_t(k)]) {
        if (error) *error = at(d) + ": '" + ch.shapes[size_t(k)].id + "' rides twice";
        return false;
      }
      taken[size_t(k)] = 1;
    }
    carried_.push_back(std::move(c));
  }
  // Hosts first (a pupil on its eye on the face); one riding, through others, on itself is refused.
  std::vector<int> rider_of(ch.shapes.size(), -1);
  for (size_t r = 0; r < carried_.size(); ++r) {
    rider_of[size_t(carried_[r].shape)] = int(r);
    for (int k : carried_[r].with) rider_of[size_t(k)] = int(r);
  }
  std::vector<int> order;
  std::vector<char> placed(carried_.size(), 0);
  while (order.size() < carried_.size()) {
    const size_t before = order.size();
    for (size_t r = 0; r < carried_.size(); ++r) {
      const int up = rider_of[size_t(carried_[r].host)];
      if (!placed[r] && (up < 0 || placed[size_t(up)])) placed[r] = 1, order.push_back(int(r));
    }
    if (order.size() == before) {
      for (size_t r = 0; r < carried_.size(); ++r)
        if (!placed[r]) {
          if (error) *error = at(rig.riders[r]) + " rides, through riders, on itself";
          return false;
        }
    }
  }
  for (const Carried& c : carried_) {
    carried_rest_[size_t(c.shape)] = ch.shapes[size_t(c.shape)].points;
    for (int k : c.with) carried_rest_[size_t(k)] = ch.shapes[size_t(k)].points;
  }
  order_ = std::move(order);
  return true;
}

void FeatureFrameMethod::shape_points(std::vector<Points>& out) const { place(s_.vertices(), out); }

void FeatureFrameMethod::place(std::span<const Vec2> v, std::vector<Points>& out) const {
  reconstruct_shapes(frame_, v, out);
  // Each rider, its host first: the best rigid motion of the host's points it follows (2D
  // Procrustes, in place), applied to its own rest points and those riding with it.
  for (int r : order_) {
    const Carried& c = carried_[size_t(r)];
    if (size_t(c.host) >= out.size()) continue;
    const Points& host = out[size_t(c.host)];
    Vec2 a = Vec2::Zero(), b = Vec2::Zero();
    size_t n = 0;
    for (size_t k = 0; k < c.follow.size(); ++k)
      if (size_t(c.follow[k]) < host.size()) a += c.follow_rest[k], b += host[size_t(c.follow[k])], ++n;
    if (n == 0) continue;
    a /= double(n), b /= double(n);
    double dot = 0, crs = 0;
    for (size_t k = 0; k < c.follow.size(); ++k) {
      if (size_t(c.follow[k]) >= host.size()) continue;
      const Vec2 p = c.follow_rest[k] - a, q = host[size_t(c.follow[k])] - b;
      dot += p.dot(q);
      crs += p.x() * q.y() - p.y() * q.x();
    }
    const double len = portable_hypot(dot, crs), cs = len > 1e-300 ? dot / len : 1.0, sn = len > 1e-300 ? crs / len : 0.0;
    auto place = [&](int shape) {
      const Points& rest = carried_rest_[size_t(shape)];
      if (size_t(shape) >= out.size()) return;
      Points& o = out[size_t(shape)];
      for (size_t k = 0; k < rest.size() && k < o.size(); ++k) {
        const Vec2 d = rest[k] - a;
        o[k] = b + Vec2(cs * d.x() - sn * d.y(), sn * d.x() + cs * d.y());
      }
    };
    place(c.shape);
    for (int k : c.with) place(k);
  }
}

std::vector<SolverParameter> FeatureFrameMethod::parameters() const {
  return {{"rigidity", weights_.rigidity, 1e-6, 1e9}, {"coupling", weights_.coupling, 1e-6, 1e9},
          {"position", weights_.position, 1e-6, 1e9}};
}

bool FeatureFrameMethod::set_parameters(std::span<const double> v, std::string* error) {
  if (v.size() != 3) {
    if (error) *error = "feature_frame has 3 parameters (rigidity, coupling, position)";
    return false;
  }
  SolverWeights w = weights_;
  w.rigidity = v[0];
  w.coupling = v[1];
  w.position = v[2];
  return set_weights(w, error);
}

bool FeatureFrameMethod::set_weights(const SolverWeights& w, std::string* error) {
  const std::vector<Vec2> pose(s_.vertices().begin(), s_.vertices().end());
  const bool ok = s_.prepare(frame_, bindings_, w, error);
  if (ok) weights_ = w;
  s_.set_vertices(pose);
  return ok;
}

}  // namespace mar
