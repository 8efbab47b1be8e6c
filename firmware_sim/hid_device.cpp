#include "firmware_sim/hid_device.h"

#include "base/read_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <sstream>

namespace mar {

Result<std::vector<uint8_t>> read_descriptor_file(const std::string& path) {
  using R = Result<std::vector<uint8_t>>;
  Result<std::string> file = read_file(path, kMaxDescriptorBytes, "a report descriptor");
  if (!file.ok()) return R::failure(file.error);
  std::vector<uint8_t> raw(file.value->begin(), file.value->end());
  const auto ends = [&](const char* s) {
    const std::string e = s;
    return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  if (!ends(".hex") && !ends(".txt")) return R::success(std::move(raw));
  std::vector<uint8_t> out;
  // Hex bytes separated by white space; '#' starts a comment to the end of its line.
  std::istringstream lines(std::string(raw.begin(), raw.end()));
  int line_no = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_no;
    std::istringstream text(line.substr(0, line.find('#')));
    for (std::string tok; text >> tok;) {
      char* end = nullptr;
      const unsigned long v = std::strtoul(tok.c_str(), &end, 16);
      if (*end != '\0' || v > 0xFF) return R::failure(path + ":" + std::to_string(line_no) + ": '" + tok + "' is not a hex byte");
      out.push_back(uint8_t(v));
    }
  }
  return R::success(std::move(out));
}

Result<bool> HidDeviceSim::set_descriptor(std::span<const uint8_t> bytes) {
  auto d = parse_hid_descriptor(bytes);
  if (!d.ok()) return Result<bool>::failure(d.error);
  desc_ = std::move(*d.value);
  bytes_.assign(bytes.begin(), bytes.end());
  state_.clear();
  for (const auto& r : desc_.reports) {
    std::vector<uint8_t> s(r.size_bytes(), 0);
    if (desc_.numbered && !s.empty()) s[0] = r.id;
    state_.push_back(std::move(s));
  }
  idle_state();
  return Result<bool>::success(true);
}

bool HidDeviceSim::set(uint32_t u, int32_t v) {
  for (size_t ri = 0; ri < desc_.reports.size(); ++ri) {
    const HidReport& r = desc_.reports[ri];
    if (r.type != HidReportType::Input) continue;
    for (const auto& f : r.fields) {
      if (f.is_constant() || f.is_array()) continue;
      for (size_t k = 0; k < f.usages.size(); ++k)
        if (f.usages[k] == u) {
          const int32_t c = std::clamp(v, f.logical_min, f.logical_max);
          hid_insert_bits(state_[ri], f.bit_offset + uint32_t(k) * f.bit_size, f.bit_size, uint32_t(c));
          return true;
        }
    }
  }
  return false;
}

bool HidDeviceSim::set_unit(uint32_t u, double x) {
  int element = 0;
  const HidField* f = desc_.find_usage(u, &element);
  if (!f) return false;
  const double lo = f->logical_min, hi = f->logical_max;
  return set(u, int32_t(std::lround(lo + std::clamp(x, 0.0, 1.0) * (hi - lo))));
}

void HidDeviceSim::send(int64_t t_ns, uint32_t u) {
  for (size_t ri = 0; ri < desc_.reports.size(); ++ri) {
    const HidReport& r = desc_.reports[ri];
    if (r.type != HidReportType::Input) continue;
    for (const auto& f : r.fields)
      if (std::find(f.usages.begin(), f.usages.end(), u) != f.usages.end() && !f.is_array()) {
        emit(t_ns, state_[ri]);
        return;
      }
  }
}

// --- pen tablet ------------------------------------------------------------------------

void PenTabletSim::report(int64_t t, double x, double y, double pressure, bool tip, bool range) {
  set_unit(usage::X, x);
  set_unit(usage::Y, y);
  set_unit(usage::TipPressure, tip ? pressure : 0);
  set(usage::TipSwitch, tip);
  set(usage::InRange, range);
  send(t, usage::X);
}

void PenTabletSim::stroke(const std::vector<std::pair<double, double>>& pts, double t_s, double dur_s,
                          double pressure) {
  if (pts.empty()) return;
  const int n = std::max(1, int(std::ceil(std::max(dur_s, 0.0) * rate_hz)));
  // Arc-length parametrisation so the pen moves at constant speed.
  std::vector<double> len(pts.size(), 0);
  for (size_t i = 1; i < pts.size(); ++i)
    len[i] = len[i - 1] + std::hypot(pts[i].first - pts[i - 1].first, pts[i].second - pts[i - 1].second);
  size_t i = 1;  // the segment holding s; s only grows, so the search goes on from here
  for (int k = 0; k <= n && !too_many_; ++k) {
    const double s = len.back() * k / n;
    while (i + 1 < pts.size() && len[i] < s) ++i;
    double x = pts[0].first, y = pts[0].second;
    if (pts.size() > 1) {
      const double seg = len[i] - len[i - 1], u = seg > 0 ? (s - len[i - 1]) / seg : 0;
      x = pts[i - 1].first + u * (pts[i].first - pts[i - 1].first);
      y = pts[i - 1].second + u * (pts[i].second - pts[i - 1].second);
    }
    report(to_ns(t_s + dur_s * k / n), x, y, pressure, true, true);
  }
  report(to_ns(t_s + dur_s + 1.0 / rate_hz), pts.back().first, pts.back().second, 0, false, true);
}

void PenTabletSim::hover(double x, double y, double t_s) { report(to_ns(t_s), x, y, 0, false, true); }
void PenTabletSim::leave(double t_s) { report(to_ns(t_s), 0, 0, 0, false, false); }

namespace {
bool parse_point(const std::string& s, std::pair<double, double>& p) {
  const auto comma = s.find(',');
  return comma != std::string::npos && parse_number(s.substr(0, comma), p.first) &&
         parse_number(s.substr(comma + 1), p.second);
}
}  // namespace

Result<bool> PenTabletSim::action(double t, const std::vector<std::string>& w) {
  using R = Result<bool>;
  if (w[0] == "stroke") {
    // stroke X,Y X,Y ... over SECONDS [pressure P]
    std::vector<std::pair<double, double>> pts;
    size_t i = 1;
    for (std::pair<double, double> p; i < w.size() && parse_point(w[i], p); ++i) pts.push_back(p);
    double dur = 0, pressure = 1;
    if (pts.empty() || i + 1 >= w.size() || w[i] != "over" || !parse_number(w[i + 1], dur) || dur < 0)
      return R::failure("expected 'stroke X,Y [X,Y ...] over SECONDS [pressure P]'");
    i += 2;
    if (i < w.size()) {
      if (w[i] != "pressure" || i + 2 != w.size() || !parse_number(w[i + 1], pressure) || pressure < 0 || pressure > 1)
        return R::failure("expected 'pressure P' with P in 0..1");
    }
    stroke(pts, t, dur, pressure);
    return R::success(true);
  }
  if (w[0] == "hover") {
    std::pair<double, double> p;
    if (w.size() != 2 || !parse_point(w[1], p)) return R::failure("expected 'hover X,Y'");
    hover(p.first, p.second, t);
    return R::success(true);
  }
  if (w[0] == "leave" && w.size() == 1) {
    leave(t);
    return R::success(true);
  }
  return R::failure("unknown action '" + w[0] + "' (stroke, hover, leave)");
}

// --- gamepad ---------------------------------------------------------------------------

void GamepadSim::idle_state() {
  for (uint32_t u : {usage::X, usage::Y, usage::Z, usage::Rz, usage::Rx, usage::Ry}) set_unit(u, 0.5);
  // A hat at rest reads outside its logical range (the null state).
  for (size_t ri = 0; ri < desc_.reports.size(); ++ri)
    for (const auto& f : desc_.reports[ri].fields)
      for (size_t k = 0; k < f.usages.size() && !f.is_array(); ++k)
        if (f.usages[k] == usage::Hat)
          hid_insert_bits(state_[ri], f.bit_offset + uint32_t(k) * f.bit_size, f.bit_size, uint32_t(f.logical_max + 1));
}

void GamepadSim::stick(const std::string& which, double x, double y, double t_s, double dur_s) {
  const int s = which == "right" ? 1 : 0;
  const uint32_t ux = s ? (has(usage::Z) ? usage::Z : usage::Rx) : usage::X;
  const uint32_t uy = s ? (has(usage::Rz) ? usage::Rz : usage::Ry) : usage::Y;
  const double x0 = pos_[s][0], y0 = pos_[s][1];
  const int n = std::max(1, int(std::ceil(std::max(dur_s, 0.0) * 250)));
  for (int k = 1; k <= n && !too_many_; ++k) {
    const double u = double(k) / n;
    set_unit(ux, 0.5 + 0.5 * (x0 + (x - x0) * u));
    set_unit(uy, 0.5 + 0.5 * (y0 + (y - y0) * u));
    send(to_ns(t_s + dur_s * u), ux);
  }
  pos_[s][0] = x;
  pos_[s][1] = y;
}

void GamepadSim::press(int button, double t_s, double hold_s) {
  set(usage::button(button), 1);
  send(to_ns(t_s), usage::button(button));
  set(usage::button(button), 0);
  send(to_ns(t_s + std::max(hold_s, 0.001)), usage::button(button));
}

Result<bool> GamepadSim::action(double t, const std::vector<std::string>& w) {
  using R = Result<bool>;
  if (w[0] == "stick") {
    // stick left|right X,Y [over SECONDS]
    std::pair<double, double> p;
    double dur = 0;
    if (w.size() < 3 || (w[1] != "left" && w[1] != "right") || !parse_point(w[2], p) ||
        !(w.size() == 3 || (w.size() == 5 && w[3] == "over" && parse_number(w[4], dur) && dur >= 0)))
      return R::failure("expected 'stick left|right X,Y [over SECONDS]' with X, Y in -1..1");
    stick(w[1], std::clamp(p.first, -1.0, 1.0), std::clamp(p.second, -1.0, 1.0), t, dur);
    return R::success(true);
  }
  if (w[0] == "press") {
    double b = 0, hold = 0.1;
    if (w.size() < 2 || !parse_number(w[1], b) || b < 1 || b > 64 ||
        !(w.size() == 2 || (w.size() == 4 && w[2] == "for" && parse_number(w[3], hold))))
      return R::failure("expected 'press BUTTON [for SECONDS]' with BUTTON 1-64");
    if (!has(usage::button(int(b)))) return R::failure("this descriptor has no button " + w[1]);
    press(int(b), t, hold);
    return R::success(true);
  }
  return R::failure("unknown action '" + w[0] + "' (stick, press)");
}

}  // namespace mar
