#include "rig/limb_geometry.h"

#include "geom/polygon.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace mar {

Vec2 ring_centroid(const Points& r) {
  double a = 0;
  Vec2 c = Vec2::Zero();
  for (size_t i = 0; i < r.size(); ++i) {
    const Vec2& p = r[i];
    const Vec2& q = r[(i + 1) % r.size()];
    const double k = cross(p, q);
    a += k;
    c += (p + q) * k;
  }
  if (std::abs(a) < 1e-12) {
    Vec2 m = Vec2::Zero();
    for (const Vec2& p : r) m += p;
    return r.empty() ? m : Vec2(m / double(r.size()));
  }
  return c / (3 * a);
}

std::vector<Vec2> crossings(const Points& a, const Points& b) {
  std::vector<Vec2> out;
  for (size_t i = 0; i < a.size(); ++i) {
    const Vec2 &p = a[i], &p2 = a[(i + 1) % a.size()];
    const Vec2 r = p2 - p;
    const Vec2 alo = p.cwiseMin(p2), ahi = p.cwiseMax(p2);
    for (size_t j = 0; j < b.size(); ++j) {
      const Vec2 &q = b[j], &q2 = b[(j + 1) % b.size()];
      if (std::max(q.x(), q2.x()) < alo.x() || std::min(q.x(), q2.x()) > ahi.x() || std::max(q.y(), q2.y()) < alo.y() ||
          std::min(q.y(), q2.y()) > ahi.y())
        continue;
      const Vec2 s = q2 - q;
      const double d = cross(r, s);
      if (std::abs(d) < 1e-12) continue;
      const double t = cross(q - p, s) / d, u = cross(q - p, r) / d;
      if (t >= 0 && t < 1 && u >= 0 && u < 1) out.push_back(p + t * r);
    }
  }
  return out;
}

double ring_distance(const Points& a, const Points& b) {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec2& p : a)
    for (size_t j = 0; j < b.size(); ++j) best = std::min(best, point_segment_distance(p, b[j], b[(j + 1) % b.size()]));
  return best;
}

bool ring_holds(const Points& r, const Vec2& q, double tol) {
  if (r.size() < 3) return false;
  if (winding_number(r, q) != 0) return true;
  for (size_t a = 0; a < r.size(); ++a)
    if (point_segment_distance(q, r[a], r[(a + 1) % r.size()]) <= tol) return true;
  return false;
}

double ring_gap(const Points& a, const Points& b, Vec2* mid) {
  double best = std::numeric_limits<double>::infinity();
  const size_t step = std::max<size_t>(1, a.size() / 32);
  for (size_t k = 0; k < a.size(); k += step)
    for (size_t j = 0; j < b.size(); ++j) {
      const Vec2 e = b[(j + 1) % b.size()] - b[j];
      const double t = e.squaredNorm() > 0 ? std::clamp((a[k] - b[j]).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
      const Vec2 q = b[j] + t * e;
      if (const double d = (q - a[k]).norm(); d < best) {
        best = d;
        if (mid) *mid = 0.5 * (q + a[k]);
      }
    }
  return best;
}

std::vector<Vec2> medial_path(const Points& ring, const Vec2& attached) {
  Vec2 lo = ring[0], hi = ring[0];
  for (const Vec2& p : ring) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double size = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  if (!(size > 0)) return {};
  const double h = size / 96;
  const int nx = std::max(1, int(std::ceil((hi.x() - lo.x()) / h))), ny = std::max(1, int(std::ceil((hi.y() - lo.y()) / h)));
  auto centre = [&](int x, int y) { return Vec2(lo.x() + (x + 0.5) * h, lo.y() + (y + 0.5) * h); };
  std::vector<char> in(size_t(nx) * size_t(ny), 0);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) in[size_t(y) * size_t(nx) + size_t(x)] = winding_number(ring, centre(x, y)) != 0;
  auto nearest_cell = [&](const Vec2& p) {
    int best = -1;
    double bd = std::numeric_limits<double>::infinity();
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x)
        if (in[size_t(y) * size_t(nx) + size_t(x)] && (centre(x, y) - p).squaredNorm() < bd) {
          bd = (centre(x, y) - p).squaredNorm();
          best = y * nx + x;
        }
    return best;
  };
  auto walk = [&](int start) {
    std::vector<double> dist(in.size(), std::numeric_limits<double>::infinity());
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> q;
    dist[size_t(start)] = 0;
    q.push({0.0, start});
    while (!q.empty()) {
      const auto [d, c] = q.top();
      q.pop();
      if (d > dist[size_t(c)]) continue;
      const int cx = c % nx, cy = c / nx;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int x = cx + dx, y = cy + dy;
          if ((dx == 0 && dy == 0) || x < 0 || y < 0 || x >= nx || y >= ny || !in[size_t(y) * size_t(nx) + size_t(x)]) continue;
          const double nd = d + ((dx != 0 && dy != 0) ? M_SQRT2 : 1.0);
          const size_t k = size_t(y) * size_t(nx) + size_t(x);
          if (nd < dist[k]) {
            dist[k] = nd;
            q.push({nd, int(k)});
          }
        }
    }
    return dist;
  };
  const int a = nearest_cell(attached);
  if (a < 0) return {};
  const std::vector<double> from_a = walk(a);
  double far = 0;
  for (double d : from_a)
    if (std::isfinite(d)) far = std::max(far, d);
  Vec2 sum = Vec2::Zero();
  int count = 0;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
      if (const double d = from_a[size_t(y) * size_t(nx) + size_t(x)]; std::isfinite(d) && d >= 0.9 * far) {
        sum += centre(x, y);
        ++count;
      }
  const int f = nearest_cell(sum / std::max(1, count));
  const std::vector<double> dist = walk(f);
  const double band = 2.0;  // cells
  std::vector<Vec2> bsum;
  std::vector<int> bcount;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const double d = dist[size_t(y) * size_t(nx) + size_t(x)];
      if (!std::isfinite(d)) continue;
      const size_t b = size_t(d / band);
      if (b >= bsum.size()) {
        bsum.resize(b + 1, Vec2::Zero());
        bcount.resize(b + 1, 0);
      }
      bsum[b] += centre(x, y);
      ++bcount[b];
    }
  std::vector<Vec2> path;
  for (size_t b = 0; b < bsum.size(); ++b)
    if (bcount[b] > 0) path.push_back(bsum[b] / bcount[b]);
  return path;
}

}  // namespace mar
