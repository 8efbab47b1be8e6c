#include "firmware_sim/sim_device.h"

#include "input/usb_midi.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace mar {

double seconds(int64_t ns) { return double(ns) * 1e-9; }
int64_t to_ns(double s) { return int64_t(std::llround(std::clamp(s, -9e9, 9e9) * 1e9)); }  // (within int64)

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
    too_many_ = false;
    return Result<bool>::failure("line " + std::to_string(n) + ": " + msg);
  };
  auto seconds_ok = [](const std::vector<std::string>& w) {  // the time, and what follows over / for / loop
    for (size_t i = 0; i < w.size(); ++i)
      if (double v = 0; (i == 0 || w[i - 1] == "over" || w[i - 1] == "for" || w[i - 1] == "loop") && parse_number(w[i], v) &&
                        std::fabs(v) > kMaxSeconds)
        return false;
    return true;
  };
  while (std::getline(in, line)) {
    ++n;
    if (auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream ls(line);
    std::vector<std::string> w;
    for (std::string tok; ls >> tok;) w.push_back(tok);
    if (w.empty()) continue;
    double t = 0;
    if (!seconds_ok(w)) return fail("a time or duration past " + std::to_string(int(kMaxSeconds)) + " s");
    if (w[0] == "loop") {
      if (w.size() != 2 || !parse_number(w[1], t) || t < kMinLoopSeconds)
        return fail("expected 'loop SECONDS' with SECONDS >= " + std::to_string(kMinLoopSeconds).substr(0, 4));
      set_loop(t);
      continue;
    }
    if (!parse_number(w[0], t) || t < 0) return fail("expected a time in seconds, got '" + w[0] + "'");
    if (w.size() < 2) return fail("missing action after the time");
    w.erase(w.begin());
    auto r = action(t, w);
    if (!r.ok()) return fail(r.error);
    if (too_many_) return fail("the script makes more than " + std::to_string(max_records_) + " records (a move over a very long time?)");
  }
  finish();
  if (loop_ns_ > 0 && loop_ns_ < end_ns()) {
    const int64_t end = end_ns();
    timeline_ = saved;
    loop_ns_ = saved_loop;
    return Result<bool>::failure("loop: the period is shorter than the script (" + std::to_string(double(end) * 1e-9) +
                                 " s); the timeline would overlap itself");
  }
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
  if (timeline_.size() >= max_records_) {
    too_many_ = true;
    return;
  }
  timeline_.push_back(WireRecord::make(t_ns, wire(), bytes));
}

bool SimDevice::reply_midi(std::span<const uint8_t> message) {
  // Packets first (to know it fits), then as many records as they fill.
  uint8_t packets[kReplyRecords * WireRecord::kMax];
  size_t n = 0;
  for (size_t at = 0; at < message.size();) {
    const size_t len = message[0] == 0xF0 ? std::min<size_t>(3, message.size() - at) : message.size();
    if (n + 4 > sizeof packets || usb_midi_encode(0, message.subspan(at, len), packets + n) != UsbMidiEncodeError::None) return false;
    n += 4;
    at += len;
  }
  size_t used = replies_used_;
  for (size_t at = 0; at < n; at += WireRecord::kMax) {
    if (used == replies_.size()) return false;
    replies_[used++] = WireRecord::make(0, wire(), std::span<const uint8_t>(packets + at, std::min(WireRecord::kMax, n - at)));
  }
  replies_used_ = used;
  return true;
}

}  // namespace mar
