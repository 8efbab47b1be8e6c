#include "frame/feature_points.h"

#include <algorithm>
#include <cmath>

namespace mar {

std::vector<double> cumulative_length(std::span<const Vec2> pts, bool closed) {
  const size_t n = pts.size();
  std::vector<double> s(n + (closed && n > 0 ? 1 : 0), 0.0);
  for (size_t i = 1; i < n; ++i) s[i] = s[i - 1] + (pts[i] - pts[i - 1]).norm();
  if (closed && n > 0) s[n] = s[n - 1] + (pts[0] - pts[n - 1]).norm();
  return s;
}

namespace {

// Points on one side of vertex i (dir = -1 or +1) at Euclidean distance in [d_min, d_max]:
// the vertices in that range plus, on segments crossing the d_min or d_max circles, the
// crossing points, so sparse polylines (long straight edges) work as well as dense ones.
void side_points(std::span<const Vec2> pts, bool closed, int i, int dir, double d_min, double d_max,
                 std::vector<Vec2>& out) {
  out.clear();
  const int n = static_cast<int>(pts.size());
  const Vec2& p = pts[static_cast<size_t>(i)];
  auto at = [&](int k) -> const Vec2& { return pts[static_cast<size_t>(((k % n) + n) % n)]; };
  Vec2 prev = p;
  for (int k = 1; k < n; ++k) {
    const int j = i + dir * k;
    if (!closed && (j < 0 || j >= n)) break;
    const Vec2& q = at(j);
    // crossings of the segment prev -> q with the two circles
    const Vec2 d = q - prev;
    const double a = d.squaredNorm();
    if (a > 0) {
      for (double r : {d_min, d_max}) {
        const double b = 2 * (prev - p).dot(d), c = (prev - p).squaredNorm() - r * r;
        const double disc = b * b - 4 * a * c;
        if (disc < 0) continue;
        for (double sgn : {-1.0, 1.0}) {
          const double t = (-b + sgn * std::sqrt(disc)) / (2 * a);
          if (t > 0 && t <= 1) out.push_back(prev + t * d);
        }
      }
    }
    const double dq = (q - p).norm();
    if (dq >= d_min && dq <= d_max) out.push_back(q);
    if (dq > d_max && (prev - p).norm() > d_max) break;
    prev = q;
  }
}

constexpr size_t kSide = 48;
void thin(std::vector<Vec2>& v) {
  if (v.size() <= kSide) return;
  const size_t n = v.size();
  for (size_t k = 0; k < kSide; ++k) v[k] = v[k * (n - 1) / (kSide - 1)];
  v.resize(kSide);
}

}  // namespace

std::vector<int> ipan99_corners(std::span<const Vec2> pts, bool closed, double d_min, double d_max,
                                double alpha_max) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> out;
  if (n < 3 || !(d_max > 0) || d_min > d_max) return out;
  const double dmax2 = d_max * d_max;
  const double cos_max = std::cos(alpha_max);
  std::vector<double> sharp(static_cast<size_t>(n), -2.0);  // cos of the smallest angle
  std::vector<char> candidate(static_cast<size_t>(n), 0);
  auto at = [&](int i) -> const Vec2& { return pts[static_cast<size_t>(((i % n) + n) % n)]; };
  std::vector<Vec2> before, after;
  for (int i = 0; i < n; ++i) {
    if (!closed && (i == 0 || i == n - 1)) continue;
    const Vec2& p = pts[static_cast<size_t>(i)];
    side_points(pts, closed, i, -1, d_min, d_max, before);
    side_points(pts, closed, i, +1, d_min, d_max, after);
    // A densely sampled outline (a drawing flattened finely, a traced picture) puts thousands
    // of points in the window; the pairs would cost n * k^2. More than kSide a side are thinned
    // evenly (the sharpest angle moves by at most the spacing): the work stays linear in n.
    thin(before);
    thin(after);
    double best = -2;  // largest cosine = smallest angle
    for (const Vec2& a : before) {
      const Vec2 da = a - p;
      for (const Vec2& b : after) {
        const Vec2 db = b - p;
        best = std::max(best, da.dot(db) / std::sqrt(da.squaredNorm() * db.squaredNorm()));
      }
    }
    if (best >= cos_max) {
      sharp[static_cast<size_t>(i)] = best;
      candidate[static_cast<size_t>(i)] = 1;
    }
  }
  // Non-maximum suppression within d_max.
  for (int i = 0; i < n; ++i) {
    if (!candidate[static_cast<size_t>(i)]) continue;
    const double si = sharp[static_cast<size_t>(i)];
    bool keep = true;
    for (int dir : {-1, 1}) {
      for (int k = 1; k < n && keep; ++k) {
        const int j = i + dir * k;
        if (!closed && (j < 0 || j >= n)) break;
        const int jj = ((j % n) + n) % n;
        if ((at(j) - pts[static_cast<size_t>(i)]).squaredNorm() > dmax2) break;
        const double sj = sharp[static_cast<size_t>(jj)];
        // sharper neighbour wins; ties go to the lower index
        if (sj > si || (sj == si && jj < i)) keep = false;
      }
    }
    if (keep) out.push_back(i);
  }
  return out;
}

std::vector<int> inflection_points(std::span<const Vec2> pts, bool closed, double window,
                                   double hysteresis) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> out;
  if (n < 4) return out;
  // Turning at each vertex measured between chords reaching window/2 of arc length back
  // and forward: light smoothing, robust to per-vertex noise.
  auto at = [&](int i) -> const Vec2& { return pts[static_cast<size_t>(((i % n) + n) % n)]; };
  const double half = window / 2;
  std::vector<double> smooth(static_cast<size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    int reach[2] = {i, i};
    for (int side = 0; side < 2; ++side) {
      const int dir = side == 0 ? -1 : 1;
      double len = 0;
      for (int k = 1; k < n; ++k) {
        const int j = i + dir * k;
        if (!closed && (j < 0 || j >= n)) break;
        len += (at(j) - at(j - dir)).norm();
        reach[side] = j;
        if (len >= half) break;
      }
    }
    if (reach[0] == i || reach[1] == i) continue;  // truncated at an open end
    const Vec2 d0 = at(i) - at(reach[0]), d1 = at(reach[1]) - at(i);
    smooth[static_cast<size_t>(i)] = std::atan2(d0.x() * d1.y() - d0.y() * d1.x(), d0.dot(d1));
  }
  // Hysteresis state machine (for closed curves, start where the state is clear).
  int start = 0;
  if (closed) {
    while (start < n && std::abs(smooth[static_cast<size_t>(start)]) < hysteresis) ++start;
    if (start == n) return out;
  }
  int state = 0, last_strong = -1;
  for (int k = 0; k < n; ++k) {
    const int i = closed ? (start + k) % n : k;
    const double s = smooth[static_cast<size_t>(i)];
    const int sign = s >= hysteresis ? 1 : (s <= -hysteresis ? -1 : 0);
    if (sign == 0) continue;
    if (state != 0 && sign != state) {
      // midway (in index) between the last strong vertex of the old sign and this one
      int a = last_strong, b = closed && i < a ? i + n : i;
      out.push_back(((a + b) / 2) % n);
    }
    state = sign;
    last_strong = i;
  }
  if (closed && state != 0) {
    // wrap-around: compare the final state with the state at `start`
    const int first_sign = smooth[static_cast<size_t>(start)] >= hysteresis ? 1 : -1;
    if (first_sign != state) out.push_back(((last_strong + start + n) / 2) % n);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::vector<int> arc_length_samples(std::span<const Vec2> pts, bool closed, double interval) {
  const int n = static_cast<int>(pts.size());
  std::vector<int> out;
  if (n == 0) return out;
  const std::vector<double> s = cumulative_length(pts, closed);
  const double total = s.back();
  if (!(interval > 0) || !std::isfinite(total)) return {0};
  int j = 0;
  for (double target = 0; target < total - (closed ? interval * 0.5 : 0) + 1e-12; target += interval) {
    while (j + 1 < n && s[static_cast<size_t>(j + 1)] < target) ++j;
    int best = j;
    if (j + 1 < n && std::abs(s[static_cast<size_t>(j + 1)] - target) < std::abs(s[static_cast<size_t>(j)] - target)) {
      best = j + 1;
    }
    out.push_back(best);
  }
  if (!closed) out.push_back(n - 1);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace mar
