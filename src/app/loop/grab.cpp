#include "app/loop/grab.h"

#include <chrono>
#include <cmath>

namespace mar {
namespace {
double now_us() {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

void Grab::set(bool down, const Vec2& g, Puppet& p) {
  const double t0 = now_us();
  handle_ = -1;
  if (down) {
    double nearest = INFINITY;
    for (size_t h = 0; h < p.solver->handle_count(); ++h) {
      const Vec2 at = p.solver->handle_point(h);
      if (double d = (at - g).norm(); d < nearest) {
        nearest = d;
        handle_ = int(h);
        offset_ = at - g;
      }
    }
    if (nearest > 0.05 * p.diagonal) handle_ = -1;
  }
  if (down && handle_ >= 0) {
    p.solver->release();
  } else if (down) {
    double best = INFINITY;
    Vec2 rest = Vec2::Zero();
    for (size_t s = 0; s < p.shapes.size(); ++s)
      for (size_t k = 0; k < p.shapes[s].size(); ++k)
        if (double d = (p.shapes[s][k] - g).squaredNorm(); d < best) {
          best = d;
          rest = p.character.shapes[s].points[k];
        }
    p.solver->grab(rest);
  } else {
    p.solver->release();
  }
  cost_us_.add(now_us() - t0);
  ++count_;
  active_ = down;
}

void Grab::restore(const Vec2& point, Puppet& p) {
  if (!active_) return;
  active_ = false;
  set(true, point, p);
}

size_t Grab::apply(const Vec2& point, std::span<Vec2> handles, Vec2& temporary) const {
  if (!active_) return handles.size();
  if (handle_ >= 0) {
    handles[size_t(handle_)] = point + offset_;
    return handles.size();
  }
  temporary = point;
  return handles.size() + 1;
}

}  // namespace mar
