#include "character/svg_parse.h"

#include <cctype>
#include <charconv>

namespace mar::svg {
namespace {

bool is_ws(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f'; }
bool is_digit(char c) { return c >= '0' && c <= '9'; }

void skip_ws(std::string_view s, size_t& pos) {
  while (pos < s.size() && is_ws(s[pos])) ++pos;
}

}  // namespace

void skip_separators(std::string_view s, size_t& pos) {
  skip_ws(s, pos);
  if (pos < s.size() && s[pos] == ',') {
    ++pos;
    skip_ws(s, pos);
  }
}

std::optional<double> read_number(std::string_view s, size_t& pos) {
  size_t i = pos;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  const size_t int_start = i;
  while (i < s.size() && is_digit(s[i])) ++i;
  bool digits = i > int_start;
  if (i < s.size() && s[i] == '.') {
    ++i;
    const size_t frac_start = i;
    while (i < s.size() && is_digit(s[i])) ++i;
    digits = digits || i > frac_start;
  }
  if (!digits) return std::nullopt;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    size_t j = i + 1;
    if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
    const size_t exp_start = j;
    while (j < s.size() && is_digit(s[j])) ++j;
    if (j > exp_start) i = j;  // otherwise 'e' belongs to what follows (e.g. "em")
  }
  size_t begin = pos;
  if (s[begin] == '+') ++begin;  // from_chars rejects a leading '+'
  double v = 0;
  auto [ptr, ec] = std::from_chars(s.data() + begin, s.data() + i, v);
  if (ec == std::errc::result_out_of_range) {
    v = (s[pos] == '-') ? -std::numeric_limits<double>::max() : std::numeric_limits<double>::max();
  } else if (ec != std::errc() || ptr != s.data() + i) {
    return std::nullopt;
  }
  pos = i;
  return v;
}

PathData parse_path(std::string_view d, size_t max_commands) {
  PathData out;
  Vec2 cur = Vec2::Zero(), start = Vec2::Zero();
  Vec2 last_c2 = Vec2::Zero();  // for S/s reflection
  Vec2 last_q = Vec2::Zero();   // for T/t reflection
  char prev_cmd = 0;
  bool have_current = false;
  size_t pos = 0;
  char cmd = 0;
  std::vector<CubicSeg> arc;

  auto fail = [&](size_t at, std::string msg) {
    out.error = std::move(msg);
    out.error_pos = at;
    return out;
  };
  auto cubic = [&](const Vec2& c1, const Vec2& c2, const Vec2& p) {
    out.cmds.push_back({PathCmd::Cubic, c1, c2, p});
  };

  skip_ws(d, pos);
  while (true) {
    skip_ws(d, pos);
    if (pos >= d.size()) break;
    if (out.cmds.size() > max_commands) {
      out.cmds.clear();  // too complex to draw at all: the loader rejects the file
      out.too_long = true;
      return fail(pos, "more than " + std::to_string(max_commands) + " path commands");
    }
    const char c = d[pos];
    const size_t cmd_pos = pos;
    if (std::isalpha(static_cast<unsigned char>(c))) {
      if (std::string_view("MmLlHhVvCcSsQqTtAaZz").find(c) == std::string_view::npos) {
        return fail(pos, std::string("unknown path command '") + c + "'");
      }
      cmd = c;
      ++pos;
    } else if (cmd == 0) {
      return fail(pos, "path data must start with a moveto");
    } else if (cmd == 'Z' || cmd == 'z') {
      return fail(pos, "number after closepath");
    }
    // implicit repeat: the same command (moveto repeats as lineto) with new numbers
    if (!have_current && cmd != 'M' && cmd != 'm') {
      return fail(cmd_pos, "path data must start with a moveto");
    }
    const bool rel = std::islower(static_cast<unsigned char>(cmd)) != 0;
    const Vec2 base = rel ? cur : Vec2::Zero();
    auto num = [&](double& v) {
      skip_ws(d, pos);
      auto r = read_number(d, pos);
      if (!r) return false;
      v = *r;
      skip_separators(d, pos);
      return true;
    };
    auto flag = [&](bool& f) {
      skip_ws(d, pos);
      if (pos < d.size() && (d[pos] == '0' || d[pos] == '1')) {
        f = d[pos] == '1';
        ++pos;
        skip_separators(d, pos);
        return true;
      }
      return false;
    };
    auto bad_args = [&]() {
      return fail(cmd_pos, std::string("bad or missing arguments for '") + cmd + "'");
    };
    const char up = static_cast<char>(std::toupper(static_cast<unsigned char>(cmd)));
    switch (up) {
      case 'M': {
        double x, y;
        if (!num(x) || !num(y)) return bad_args();
        cur = base + Vec2(x, y);
        start = cur;
        out.cmds.push_back(PathCmd::to(PathCmd::Move, cur));
        have_current = true;
        cmd = rel ? 'l' : 'L';  // subsequent pairs are implicit linetos
        prev_cmd = 'M';
        continue;
      }
      case 'L': {
        double x, y;
        if (!num(x) || !num(y)) return bad_args();
        cur = base + Vec2(x, y);
        out.cmds.push_back(PathCmd::to(PathCmd::Line, cur));
        break;
      }
      case 'H': {
        double x;
        if (!num(x)) return bad_args();
        cur = Vec2(rel ? cur.x() + x : x, cur.y());
        out.cmds.push_back(PathCmd::to(PathCmd::Line, cur));
        break;
      }
      case 'V': {
        double y;
        if (!num(y)) return bad_args();
        cur = Vec2(cur.x(), rel ? cur.y() + y : y);
        out.cmds.push_back(PathCmd::to(PathCmd::Line, cur));
        break;
      }
      case 'C': {
        double x1, y1, x2, y2, x, y;
        if (!num(x1) || !num(y1) || !num(x2) || !num(y2) || !num(x) || !num(y)) return bad_args();
        const Vec2 c1 = base + Vec2(x1, y1), c2 = base + Vec2(x2, y2);
        cur = base + Vec2(x, y);
        cubic(c1, c2, cur);
        last_c2 = c2;
        break;
      }
      case 'S': {
        double x2, y2, x, y;
        if (!num(x2) || !num(y2) || !num(x) || !num(y)) return bad_args();
        const Vec2 c1 = (prev_cmd == 'C' || prev_cmd == 'S') ? Vec2(2 * cur - last_c2) : cur;
        const Vec2 c2 = base + Vec2(x2, y2);
        cur = base + Vec2(x, y);
        cubic(c1, c2, cur);
        last_c2 = c2;
        break;
      }
      case 'Q': {
        double x1, y1, x, y;
        if (!num(x1) || !num(y1) || !num(x) || !num(y)) return bad_args();
        const Vec2 q = base + Vec2(x1, y1), p0 = cur;
        cur = base + Vec2(x, y);
        cubic(p0 + (2.0 / 3.0) * (q - p0), cur + (2.0 / 3.0) * (q - cur), cur);
        last_q = q;
        break;
      }
      case 'T': {
        double x, y;
        if (!num(x) || !num(y)) return bad_args();
        const Vec2 p0 = cur;
        const Vec2 q = (prev_cmd == 'Q' || prev_cmd == 'T') ? Vec2(2 * cur - last_q) : cur;
        cur = base + Vec2(x, y);
        cubic(p0 + (2.0 / 3.0) * (q - p0), cur + (2.0 / 3.0) * (q - cur), cur);
        last_q = q;
        break;
      }
      case 'A': {
        double rx, ry, rot, x, y;
        bool large = false, sweep = false;
        if (!num(rx) || !num(ry) || !num(rot) || !flag(large) || !flag(sweep) || !num(x) ||
            !num(y)) {
          return bad_args();
        }
        const Vec2 p0 = cur;
        cur = base + Vec2(x, y);
        arc.clear();
        arc_to_cubics(p0, rx, ry, rot, large, sweep, cur, arc);
        for (const CubicSeg& s : arc) cubic(s.c1, s.c2, s.p);
        break;
      }
      case 'Z': {
        out.cmds.push_back(PathCmd::to(PathCmd::Close, start));
        cur = start;
        skip_separators(d, pos);
        break;
      }
      default:
        return fail(cmd_pos, "unexpected character");
    }
    prev_cmd = up;
  }
  return out;
}

std::optional<Affine2> parse_transform(std::string_view s) {
  Affine2 m;
  size_t pos = 0;
  skip_ws(s, pos);
  while (pos < s.size()) {
    size_t name_end = pos;
    while (name_end < s.size() && std::isalpha(static_cast<unsigned char>(s[name_end]))) ++name_end;
    const std::string_view name = s.substr(pos, name_end - pos);
    pos = name_end;
    skip_ws(s, pos);
    if (pos >= s.size() || s[pos] != '(') return std::nullopt;
    ++pos;
    double a[6];
    int n = 0;
    skip_ws(s, pos);
    while (pos < s.size() && s[pos] != ')') {
      if (n == 6) return std::nullopt;
      auto v = read_number(s, pos);
      if (!v) return std::nullopt;
      a[n++] = *v;
      skip_separators(s, pos);
    }
    // A last transform whose ')' is missing at the very end is read as closed, as librsvg does
    // (drawings saved that way look as their authors saw them there).
    if (pos < s.size()) ++pos;  // ')'
    Affine2 t;
    if (name == "matrix" && n == 6) {
      t = {a[0], a[1], a[2], a[3], a[4], a[5]};
    } else if (name == "translate" && (n == 1 || n == 2)) {
      t = Affine2::translate(a[0], n == 2 ? a[1] : 0.0);
    } else if (name == "scale" && (n == 1 || n == 2)) {
      t = Affine2::scale(a[0], n == 2 ? a[1] : a[0]);
    } else if (name == "rotate" && n == 1) {
      t = Affine2::rotate(a[0]);
    } else if (name == "rotate" && n == 3) {
      t = Affine2::translate(a[1], a[2]) * Affine2::rotate(a[0]) * Affine2::translate(-a[1], -a[2]);
    } else if (name == "skewX" && n == 1) {
      t = Affine2::skew_x(a[0]);
    } else if (name == "skewY" && n == 1) {
      t = Affine2::skew_y(a[0]);
    } else {
      return std::nullopt;
    }
    m = m * t;
    skip_separators(s, pos);
  }
  return m;
}

std::vector<Vec2> parse_points(std::string_view s, bool* odd) {
  std::vector<double> nums;
  size_t pos = 0;
  skip_ws(s, pos);
  while (pos < s.size()) {
    auto v = read_number(s, pos);
    if (!v) break;
    nums.push_back(*v);
    skip_separators(s, pos);
  }
  if (odd) *odd = nums.size() % 2 != 0;
  std::vector<Vec2> pts;
  for (size_t i = 0; i + 1 < nums.size(); i += 2) pts.emplace_back(nums[i], nums[i + 1]);
  return pts;
}

namespace {
std::string_view trim_ws(std::string_view s) {
  while (!s.empty() && is_ws(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_ws(s.back())) s.remove_suffix(1);
  return s;
}
}  // namespace

std::optional<double> parse_number(std::string_view v) {
  v = trim_ws(v);
  size_t pos = 0;
  auto r = read_number(v, pos);
  if (!r || !std::isfinite(*r)) return std::nullopt;
  return r;
}

double parse_opacity(std::string_view v, double fallback) {
  v = trim_ws(v);
  const bool pct = !v.empty() && v.back() == '%';
  if (pct) v.remove_suffix(1);
  auto r = parse_number(v);
  if (!r) return fallback;
  return std::clamp(pct ? *r / 100.0 : *r, 0.0, 1.0);
}

std::optional<double> parse_length(std::string_view v, int axis, double vp_w, double vp_h, double font_size) {
  v = trim_ws(v);
  size_t pos = 0;
  auto r = read_number(v, pos);
  if (!r) return std::nullopt;
  const std::string_view unit = trim_ws(v.substr(pos));
  double k = 1;
  if (unit.empty() || unit == "px") {
    k = 1;
  } else if (unit == "%") {
    const double ref = axis == 0 ? vp_w : axis == 1 ? vp_h : std::sqrt((vp_w * vp_w + vp_h * vp_h) / 2.0);
    k = ref / 100.0;
  } else if (unit == "in") {
    k = 96;
  } else if (unit == "cm") {
    k = 96 / 2.54;
  } else if (unit == "mm") {
    k = 96 / 25.4;
  } else if (unit == "pt") {
    k = 96.0 / 72.0;
  } else if (unit == "pc") {
    k = 16;
  } else if (unit == "em") {
    k = font_size;
  } else if (unit == "ex") {
    k = font_size / 2;
  } else {
    return std::nullopt;
  }
  const double out = *r * k;
  if (!std::isfinite(out)) return std::nullopt;
  return out;
}

std::vector<std::string_view> split_list(std::string_view s, size_t max_items) {
  std::vector<std::string_view> out;
  size_t pos = 0;
  while (out.size() < max_items) {
    while (pos < s.size() && (is_ws(s[pos]) || s[pos] == ',')) ++pos;
    if (pos >= s.size()) break;
    size_t end = pos;
    while (end < s.size() && !is_ws(s[end]) && s[end] != ',') ++end;
    out.push_back(s.substr(pos, end - pos));
    pos = end;
  }
  return out;
}

bool system_language_matches(std::string_view l) {
  size_t pos = 0;
  while (pos <= l.size()) {
    const size_t comma = l.find(',', pos);
    const std::string_view tag = trim_ws(l.substr(pos, comma == std::string_view::npos ? l.npos : comma - pos));
    if (tag == "en" || tag.rfind("en-", 0) == 0) return true;
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return false;
}

std::optional<std::array<double, 4>> parse_viewbox(std::string_view v) {
  std::array<double, 4> vb{};
  size_t pos = 0;
  skip_separators(v, pos);
  for (double& x : vb) {
    auto r = read_number(v, pos);
    if (!r || !std::isfinite(*r)) return std::nullopt;
    x = *r;
    skip_separators(v, pos);
  }
  if (vb[2] <= 0 || vb[3] <= 0) return std::nullopt;
  return vb;
}

Affine2 viewbox_transform(const std::array<double, 4>& vb, double w, double h, std::string_view par) {
  while (!par.empty() && is_ws(par.front())) par.remove_prefix(1);
  if (par.rfind("defer", 0) == 0) par.remove_prefix(5);
  while (!par.empty() && is_ws(par.front())) par.remove_prefix(1);
  const double sx = w / vb[2], sy = h / vb[3];
  if (par.rfind("none", 0) == 0) return Affine2::scale(sx, sy) * Affine2::translate(-vb[0], -vb[1]);
  std::string_view align = par.substr(0, par.find(' '));
  if (align.empty()) align = "xMidYMid";
  const bool slice = par.find("slice") != std::string_view::npos;
  const double s = slice ? std::max(sx, sy) : std::min(sx, sy);
  double tx = -vb[0] * s, ty = -vb[1] * s;
  const double ex = w - vb[2] * s, ey = h - vb[3] * s;
  if (align.find("xMid") != std::string_view::npos) tx += ex / 2;
  if (align.find("xMax") != std::string_view::npos) tx += ex;
  if (align.find("YMid") != std::string_view::npos) ty += ey / 2;
  if (align.find("YMax") != std::string_view::npos) ty += ey;
  return Affine2::translate(tx, ty) * Affine2::scale(s, s);
}

namespace {
void quarter_arc(std::vector<PathCmd>& cmds, Vec2 from, double rx, double ry, Vec2 to) {
  std::vector<CubicSeg> segs;
  arc_to_cubics(from, rx, ry, 0, false, true, to, segs);
  for (const CubicSeg& s : segs) cmds.push_back({PathCmd::Cubic, s.c1, s.c2, s.p});
}
}  // namespace

std::vector<PathCmd> rect_path(double x, double y, double w, double h, double rx, double ry) {
  std::vector<PathCmd> c;
  if (rx <= 0 || ry <= 0) {
    c = {PathCmd::to(PathCmd::Move, {x, y}), PathCmd::to(PathCmd::Line, {x + w, y}),
         PathCmd::to(PathCmd::Line, {x + w, y + h}), PathCmd::to(PathCmd::Line, {x, y + h}),
         PathCmd::to(PathCmd::Close, {x, y})};
    return c;
  }
  c.push_back(PathCmd::to(PathCmd::Move, {x + rx, y}));
  c.push_back(PathCmd::to(PathCmd::Line, {x + w - rx, y}));
  quarter_arc(c, {x + w - rx, y}, rx, ry, {x + w, y + ry});
  c.push_back(PathCmd::to(PathCmd::Line, {x + w, y + h - ry}));
  quarter_arc(c, {x + w, y + h - ry}, rx, ry, {x + w - rx, y + h});
  c.push_back(PathCmd::to(PathCmd::Line, {x + rx, y + h}));
  quarter_arc(c, {x + rx, y + h}, rx, ry, {x, y + h - ry});
  c.push_back(PathCmd::to(PathCmd::Line, {x, y + ry}));
  quarter_arc(c, {x, y + ry}, rx, ry, {x + rx, y});
  c.push_back(PathCmd::to(PathCmd::Close, {x + rx, y}));
  return c;
}

std::vector<PathCmd> ellipse_path(double cx, double cy, double rx, double ry) {
  std::vector<PathCmd> c{PathCmd::to(PathCmd::Move, {cx + rx, cy})};
  quarter_arc(c, {cx + rx, cy}, rx, ry, {cx, cy + ry});
  quarter_arc(c, {cx, cy + ry}, rx, ry, {cx - rx, cy});
  quarter_arc(c, {cx - rx, cy}, rx, ry, {cx, cy - ry});
  quarter_arc(c, {cx, cy - ry}, rx, ry, {cx + rx, cy});
  c.push_back(PathCmd::to(PathCmd::Close, {cx + rx, cy}));
  return c;
}

std::vector<unsigned char> base64_decode(std::string_view in) {
  std::vector<unsigned char> out;
  unsigned buf = 0;
  int bits = 0;
  for (char ch : in) {
    int v;
    if (ch >= 'A' && ch <= 'Z') {
      v = ch - 'A';
    } else if (ch >= 'a' && ch <= 'z') {
      v = ch - 'a' + 26;
    } else if (ch >= '0' && ch <= '9') {
      v = ch - '0' + 52;
    } else if (ch == '+' || ch == '-') {
      v = 62;
    } else if (ch == '/' || ch == '_') {
      v = 63;
    } else {
      continue;  // whitespace, padding
    }
    buf = (buf << 6) | static_cast<unsigned>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buf >> bits) & 0xff));
    }
  }
  return out;
}

std::vector<FlatContour> flatten_path(const std::vector<PathCmd>& cmds, const Affine2& m, double tolerance,
                                      size_t max_points, bool* over) {
  std::vector<FlatContour> out;
  FlatContour cur;
  Vec2 pen = Vec2::Zero();
  size_t done = 0;  // points in finished contours
  auto finish = [&]() {
    done += cur.points.size();
    if (!cur.points.empty()) out.push_back(std::move(cur));
    cur = FlatContour{};
  };
  for (const PathCmd& c : cmds) {
    if (done + cur.points.size() > max_points) {
      if (over) *over = true;
      return {};
    }
    switch (c.kind) {
      case PathCmd::Move:
        finish();
        pen = m.apply(c.p);
        cur.points.push_back(pen);
        break;
      case PathCmd::Line:
        if (cur.points.empty()) cur.points.push_back(pen);
        pen = m.apply(c.p);
        cur.points.push_back(pen);
        break;
      case PathCmd::Cubic: {
        if (cur.points.empty()) cur.points.push_back(pen);
        const Vec2 p0 = pen;
        pen = m.apply(c.p);
        // One point past the budget is enough to see it is over.
        const size_t room = max_points - std::min(max_points, done);
        flatten_cubic(p0, m.apply(c.c1), m.apply(c.c2), pen, tolerance, cur.points,
                      room == SIZE_MAX ? SIZE_MAX : room + 1);
        break;
      }
      case PathCmd::Close:
        if (!cur.points.empty()) {
          cur.closed = true;
          finish();
        }
        // A drawing command after Z starts a new sub-path at the same start point.
        pen = m.apply(c.p);
        break;
    }
  }
  finish();
  if (done > max_points) {
    if (over) *over = true;
    return {};
  }
  // A lone moveto draws nothing.
  std::erase_if(out, [](const FlatContour& f) { return f.points.size() < 2; });
  return out;
}

}  // namespace mar::svg
