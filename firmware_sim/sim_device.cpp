#include "firmware_sim/sim_device.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mar {

double seconds(int64_t ns) { return double(ns) * 1e-9; }
int64_t to_ns(double s) { return int64_t(std::llround(s * 1e9)); }

bool parse_number(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(out);
}

Result<bool> SimDevice::load_script(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  int n = 0;
  const auto saved = timeline_;
  const int64_t saved_loop = loop_ns_;
  auto fail = [&](const std::string& msg) {
    timeline_ = saved;
    loop_ns_ = saved_loop;
    return Result<bool>::failure("line " + std::to_string(n) + ": " + msg);
  };
  while (std::getline(in, line)) {
    ++n;
    if (auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream ls(line);
    std::vector<std::string> w;
    for (std::string tok; ls >> tok;) w.push_back(tok);
    if (w.empty()) continue;
    double t = 0;
    if (w[0] == "loop") {
      if (w.size() != 2 || !parse_number(w[1], t) || t <= 0) return fail("expected 'loop SECONDS' with SECONDS > 0");
      set_loop(t);
      continue;
    }
    if (!parse_number(w[0], t) || t < 0) return fail("expected a time in seconds, got '" + w[0] + "'");
    if (w.size() < 2) return fail("missing action after the time");
    w.erase(w.begin());
    auto r = action(t, w);
    if (!r.ok()) return fail(r.error);
  }
  finish();
  return Result<bool>::success(true);
}

void SimDevice::set_loop(double period_s) { loop_ns_ = period_s > 0 ? to_ns(period_s) : 0; }

void SimDevice::finish() {
  std::stable_sort(timeline_.begin(), timeline_.end(),
                   [](const WireRecord& a, const WireRecord& b) { return a.t_ns < b.t_ns; });
  rewind();
}

int64_t SimDevice::end_ns() const { return timeline_.empty() ? 0 : timeline_.back().t_ns; }

void SimDevice::emit(int64_t t_ns, std::span<const uint8_t> bytes) {
  timeline_.push_back(WireRecord::make(t_ns, wire(), bytes));
}

}  // namespace mar
