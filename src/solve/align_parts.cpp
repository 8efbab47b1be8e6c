// FeatureFrameSolver::align_parts: the articulated initial guess (docs/algorithms.md §7).
#include "solve/feature_frame.h"

#include <cmath>
#include <limits>
#include <numeric>

namespace mar {

void FeatureFrameSolver::build_bodies() {
  const FeatureFrame& f = *frame_;
  const size_t q = f.rest.size();
  std::vector<int> parent(q);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[static_cast<size_t>(x)] != x) x = parent[static_cast<size_t>(x)] = parent[static_cast<size_t>(parent[static_cast<size_t>(x)])];
    return x;
  };
  for (const FrameLine& l : f.lines) {
    if (l.kind == FrameLine::Joint || l.kind == FrameLine::Spring) continue;
    parent[static_cast<size_t>(find(l.a))] = find(l.b);
  }
  std::vector<int> index(q, -1);
  body_of_.assign(q, 0);
  int bodies = 0;
  for (size_t i = 0; i < q; ++i) {
    const int r = find(static_cast<int>(i));
    if (index[static_cast<size_t>(r)] < 0) index[static_cast<size_t>(r)] = bodies++;
    body_of_[i] = index[static_cast<size_t>(r)];
  }
  const size_t nb = static_cast<size_t>(bodies);
  body_handles_.assign(nb, {});
  body_hinges_.assign(nb, {});
  for (size_t h = 0; h < handles_.size(); ++h) body_handles_[static_cast<size_t>(body_of_[static_cast<size_t>(handles_[h].a)])].push_back(static_cast<int>(h));
  for (const FrameJoint& j : f.joints) {
    const int a = body_of_[static_cast<size_t>(j.va)], b = body_of_[static_cast<size_t>(j.vb)];
    if (a == b) continue;
    body_hinges_[static_cast<size_t>(a)].push_back({b, j.va, j.vb});
    body_hinges_[static_cast<size_t>(b)].push_back({a, j.vb, j.va});
  }
  body_c_.assign(nb, 1.0);
  body_s_.assign(nb, 0.0);
  body_t_.assign(nb, Vec2::Zero());
  body_placed_.assign(nb, 0);
  body_queue_.assign(nb, 0);
  guess_v_.assign(2 * q, Vec2::Zero());
  // Reach chains: from a handle's body (its only handle, one hinge) through handle-less
  // links with two hinges to the anchoring body.
  reach_anchor_.assign(handles_.size(), -1);
  reach_min_.assign(handles_.size(), 0.0);
  reach_max_.assign(handles_.size(), 0.0);
  reach_targets_.assign(handles_.size() + 1, Vec2::Zero());
  reach_used_ = 0;
  jump_prev_.assign(handles_.size() + 1, Vec2::Zero());
  jump_prev_n_ = 0;
  jumps_ = 0;
  for (size_t h = 0; h < handles_.size() && w_.reach_stretch >= 0; ++h) {
    const int b0 = body_of_[static_cast<size_t>(handles_[h].a)];
    if (body_handles_[static_cast<size_t>(b0)].size() != 1 || body_hinges_[static_cast<size_t>(b0)].size() != 1) continue;
    Vec2 p = eval_param(handles_[h], f.rest);
    int cur = b0, from = -1, anchor = -1;
    double sum = 0, longest = 0;
    for (size_t step = 0; step < nb; ++step) {
      const auto& hs = body_hinges_[static_cast<size_t>(cur)];
      if (cur != b0 && (!body_handles_[static_cast<size_t>(cur)].empty() || hs.size() != 2)) break;  // anchor reached
      const Hinge* next = nullptr;
      for (const Hinge& hg : hs) {
        if (hg.other != from) next = &hg;
      }
      if (!next) {
        anchor = -1;
        break;
      }
      const double len = (p - f.rest[static_cast<size_t>(next->v_here)]).norm();
      sum += len;
      longest = std::max(longest, len);
      p = f.rest[static_cast<size_t>(next->v_here)];
      anchor = next->v_there;
      from = cur;
      cur = next->other;
    }
    if (anchor < 0 || !(sum > 0)) continue;
    reach_anchor_[h] = anchor;
    reach_max_[h] = sum;
    reach_min_[h] = std::max(0.0, longest - (sum - longest));
  }
}

void FeatureFrameSolver::apply_reach(std::span<const Vec2> targets) {
  const size_t n = std::min(targets.size(), reach_targets_.size());
  std::copy(targets.begin(), targets.begin() + static_cast<long>(n), reach_targets_.begin());
  reach_used_ = n;
  if (w_.reach_stretch < 0) return;
  for (size_t h = 0; h < handles_.size() && h < n; ++h) {
    const int a = reach_anchor_[h];
    if (a < 0 || !targets[h].allFinite()) continue;
    // The joint where the anchoring body's best rigid fit puts it: a joint vertex pulled
    // by the limb does not drag the reach along (that would feed back frame after frame).
    const size_t body = static_cast<size_t>(body_of_[static_cast<size_t>(a)]);
    Vec2 cr = Vec2::Zero(), cv = Vec2::Zero();
    int n_body = 0;
    for (size_t i = 0; i < v_.size(); ++i) {
      if (static_cast<size_t>(body_of_[i]) != body) continue;
      cr += frame_->rest[i];
      cv += v_[i];
      ++n_body;
    }
    cr /= n_body;
    cv /= n_body;
    double re = 0, im = 0;
    for (size_t i = 0; i < v_.size(); ++i) {
      if (static_cast<size_t>(body_of_[i]) != body) continue;
      const Vec2 p = frame_->rest[i] - cr, q = v_[i] - cv;
      re += q.x() * p.x() + q.y() * p.y();
      im += q.y() * p.x() - q.x() * p.y();
    }
    const double len = portable_hypot(re, im);
    const double c = len > 1e-300 ? re / len : 1.0, sn = len > 1e-300 ? im / len : 0.0;
    const Vec2 r = frame_->rest[static_cast<size_t>(a)] - cr;
    const Vec2 anchor = cv + Vec2(c * r.x() - sn * r.y(), sn * r.x() + c * r.y());
    const Vec2 d = targets[h] - anchor;
    const double dist = d.norm();
    const double soft = std::max(1e-9, w_.reach_stretch * reach_max_[h]);
    double want = dist;
    if (dist > reach_max_[h]) want = reach_max_[h] + soft * std::tanh((dist - reach_max_[h]) / soft);
    if (dist < reach_min_[h]) want = reach_min_[h] - soft * std::tanh((reach_min_[h] - dist) / soft);
    if (want != dist && dist > 1e-12) reach_targets_[h] = anchor + d * (want / dist);
  }
}

void FeatureFrameSolver::align_parts(std::span<const Vec2> targets) {
  if (!frame_ || v_.empty() || targets.size() < handles_.size()) return;
  const FeatureFrame& f = *frame_;
  const size_t nb = body_c_.size();
  auto rest_of = [&](int h) { return eval_param(handles_[static_cast<size_t>(h)], f.rest); };
  auto usable = [&](int h) { return targets[static_cast<size_t>(h)].allFinite(); };
  std::fill(body_placed_.begin(), body_placed_.end(), 0);
  size_t head = 0, tail = 0;
  auto place = [&](size_t b, double c, double s, const Vec2& t) {
    body_c_[b] = c;
    body_s_[b] = s;
    body_t_[b] = t;
    body_placed_[b] = 1;
    body_queue_[tail++] = static_cast<int>(b);
  };
  // Best rigid fit of a body's handles: rotation (c, s) and translation.
  auto fit = [&](size_t b, double& c, double& s, Vec2& t) {
    Vec2 cp = Vec2::Zero(), ct = Vec2::Zero();
    int n = 0;
    for (int h : body_handles_[b]) {
      if (!usable(h)) continue;
      cp += rest_of(h);
      ct += targets[static_cast<size_t>(h)];
      ++n;
    }
    if (n == 0) return 0;
    cp /= n;
    ct /= n;
    double re = 0, im = 0;
    for (int h : body_handles_[b]) {
      if (!usable(h)) continue;
      const Vec2 p = rest_of(h) - cp, q = targets[static_cast<size_t>(h)] - ct;
      re += q.x() * p.x() + q.y() * p.y();
      im += q.y() * p.x() - q.x() * p.y();
    }
    const double len = portable_hypot(re, im);
    c = n >= 2 && len > 1e-300 ? re / len : 1.0;
    s = n >= 2 && len > 1e-300 ? im / len : 0.0;
    t = ct - Vec2(c * cp.x() - s * cp.y(), s * cp.x() + c * cp.y());
    // Handles that did not move rigidly (the body is being bent, not moved): keep its
    // orientation and follow the handle that moved least.
    double resid = 0, moved = 0, least = std::numeric_limits<double>::infinity();
    Vec2 least_delta = Vec2::Zero();
    for (int h : body_handles_[b]) {
      if (!usable(h)) continue;
      const Vec2 r = rest_of(h), delta = targets[static_cast<size_t>(h)] - r;
      resid += (Vec2(c * r.x() - s * r.y(), s * r.x() + c * r.y()) + t - targets[static_cast<size_t>(h)]).squaredNorm();
      moved += delta.squaredNorm();
      if (delta.norm() < least) {
        least = delta.norm();
        least_delta = delta;
      }
    }
    if (resid > 0.01 * moved) {
      c = 1;
      s = 0;
      t = least_delta;
    }
    return n;
  };
  // The best rigid motion of all handles, used for a root when its residual is small
  // against the handles' motion (the whole character moved).
  double gc = 1, gs = 0;
  bool global_ok = false;
  {
    Vec2 cp = Vec2::Zero(), ct = Vec2::Zero();
    int n = 0;
    for (size_t h = 0; h < handles_.size(); ++h) {
      if (!usable(static_cast<int>(h))) continue;
      cp += rest_of(static_cast<int>(h));
      ct += targets[h];
      ++n;
    }
    if (n >= 2) {
      cp /= n;
      ct /= n;
      double re = 0, im = 0, moved = 0;
      for (size_t h = 0; h < handles_.size(); ++h) {
        if (!usable(static_cast<int>(h))) continue;
        const Vec2 p = rest_of(static_cast<int>(h)) - cp, q = targets[h] - ct;
        re += q.x() * p.x() + q.y() * p.y();
        im += q.y() * p.x() - q.x() * p.y();
        moved += (targets[h] - rest_of(static_cast<int>(h))).squaredNorm();
      }
      const double len = portable_hypot(re, im);
      if (len > 1e-300 && std::isfinite(len)) {
        gc = re / len;
        gs = im / len;
        double resid = 0;
        for (size_t h = 0; h < handles_.size(); ++h) {
          if (!usable(static_cast<int>(h))) continue;
          const Vec2 p = rest_of(static_cast<int>(h)) - cp;
          resid += (ct + Vec2(gc * p.x() - gs * p.y(), gs * p.x() + gc * p.y()) - targets[h]).squaredNorm();
        }
        global_ok = resid <= 0.01 * moved;
      }
    }
  }
  for (;;) {
    // Roots: unplaced bodies with two or more handles; failing that, the one with a handle
    // that moved least (the best anchor).
    size_t best = nb;
    int best_n = 0;
    double best_move = std::numeric_limits<double>::infinity();
    for (size_t b = 0; b < nb; ++b) {
      if (body_placed_[b]) continue;
      int n = 0;
      for (int h : body_handles_[b]) n += usable(h) ? 1 : 0;
      if (n >= 2) {
        double c, s;
        Vec2 t;
        fit(b, c, s, t);
        place(b, c, s, t);
      } else if (n == 1) {
        double move = 0;
        for (int h : body_handles_[b]) {
          if (usable(h)) move = (targets[static_cast<size_t>(h)] - rest_of(h)).norm();
        }
        if (n > best_n || move < best_move) {
          best_n = n;
          best_move = move;
          best = b;
        }
      }
    }
    if (head == tail && best < nb) {
      double c, s;
      Vec2 t;
      fit(best, c, s, t);
      if (global_ok) {  // the whole moved nearly rigidly: the root turns with it
        c = gc;
        s = gs;
        const int h = body_handles_[best][0];
        const Vec2 r = rest_of(h);
        t = targets[static_cast<size_t>(h)] - Vec2(c * r.x() - s * r.y(), s * r.x() + c * r.y());
      }
      place(best, c, s, t);
    }
    if (head == tail) break;
    // Across hinges: the child turns about the placed joint towards its handles.
    while (head < tail) {
      const size_t b = static_cast<size_t>(body_queue_[head++]);
      for (const Hinge& hg : body_hinges_[b]) {
        const size_t o = static_cast<size_t>(hg.other);
        if (body_placed_[o]) continue;
        const Vec2 jr = f.rest[static_cast<size_t>(hg.v_there)];
        const Vec2 jh = f.rest[static_cast<size_t>(hg.v_here)];
        const Vec2 P = Vec2(body_c_[b] * jh.x() - body_s_[b] * jh.y(), body_s_[b] * jh.x() + body_c_[b] * jh.y()) + body_t_[b];
        double re = 0, im = 0;
        for (int h : body_handles_[o]) {
          if (!usable(h)) continue;
          const Vec2 p = rest_of(h) - jr, q = targets[static_cast<size_t>(h)] - P;
          re += q.x() * p.x() + q.y() * p.y();
          im += q.y() * p.x() - q.x() * p.y();
        }
        if (body_handles_[o].empty()) {
          // A link with no handle (an upper arm whose hand carries it): aim the chain
          // straight at the first handle down it.
          int cur = static_cast<int>(o), from = static_cast<int>(b);
          for (size_t step = 0; step < nb; ++step) {
            const auto& hs = body_hinges_[static_cast<size_t>(cur)];
            if (!body_handles_[static_cast<size_t>(cur)].empty() || hs.size() != 2) break;
            const int next = hs[0].other == from ? hs[1].other : hs[0].other;
            from = cur;
            cur = next;
          }
          for (int h : body_handles_[static_cast<size_t>(cur)]) {
            if (!usable(h) || cur == static_cast<int>(o)) continue;
            const Vec2 p = rest_of(h) - jr, q = targets[static_cast<size_t>(h)] - P;
            re += q.x() * p.x() + q.y() * p.y();
            im += q.y() * p.x() - q.x() * p.y();
          }
        }
        double c = body_c_[b], s = body_s_[b];
        const double len = portable_hypot(re, im);
        if (len > 1e-300 && std::isfinite(len)) {
          c = re / len;
          s = im / len;
        }
        place(o, c, s, P - Vec2(c * jr.x() - s * jr.y(), s * jr.x() + c * jr.y()));
      }
    }
  }
  for (size_t i = 0; i < v_.size(); ++i) {
    const size_t b = static_cast<size_t>(body_of_[i]);
    const Vec2& r = f.rest[i];
    v_[i] = Vec2(body_c_[b] * r.x() - body_s_[b] * r.y(), body_s_[b] * r.x() + body_c_[b] * r.y()) + body_t_[b];
    vert_c_[i] = body_c_[b];
    vert_s_[i] = body_s_[b];
  }
  for (int j = 0; j < f.feature_lines; ++j) {
    const size_t b = static_cast<size_t>(body_of_[static_cast<size_t>(f.lines[static_cast<size_t>(j)].a)]);
    line_c_[static_cast<size_t>(j)] = body_c_[b];
    line_s_[static_cast<size_t>(j)] = body_s_[b];
  }
}

void FeatureFrameSolver::initial_guess(std::span<const Vec2> targets) {
  if (!frame_ || v_.empty()) return;
  const size_t q = v_.size();
  // The pose will answer these targets: the next solve neither follows nor jumps from them.
  const size_t n = std::min(targets.size(), jump_prev_.size());
  std::copy(targets.begin(), targets.begin() + static_cast<long>(n), jump_prev_.begin());
  jump_prev_n_ = n;
  auto save = [&](size_t slot) {
    std::copy(v_.begin(), v_.end(), guess_v_.begin() + static_cast<long>(slot * q));
  };
  // Candidate 0: the pose as it is; 1: moved rigidly (align_to); 2: articulated.
  double best_e = energy(targets);
  size_t best = 0;
  save(0);
  align_to(targets);
  if (const double e = energy(targets); e < best_e) {
    best_e = e;
    best = 1;
  }
  save(1);
  align_parts(targets);
  if (const double e = energy(targets); e < best_e) {
    best_e = e;
    best = 2;
  }
  if (best != 2) {
    std::copy(guess_v_.begin() + static_cast<long>(best * q), guess_v_.begin() + static_cast<long>((best + 1) * q), v_.begin());
  }
  // Rotations follow the chosen pose (the next local step recomputes them from it).
  optimal_rotations(v_, scratch_line_, scratch_vert_);
  for (size_t j = 0; j < line_c_.size(); ++j) {
    line_c_[j] = std::cos(scratch_line_[j]);
    line_s_[j] = std::sin(scratch_line_[j]);
  }
  for (size_t i = 0; i < q; ++i) {
    vert_c_[i] = std::cos(scratch_vert_[i]);
    vert_s_[i] = std::sin(scratch_vert_[i]);
  }
}

}  // namespace mar
