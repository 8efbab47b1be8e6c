#include "character/svg_text.h"

#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include FT_FREETYPE_H
#include FT_OUTLINE_H
#include <hb-ft.h>
#include <hb.h>

#include <algorithm>
#include <map>
#include <tuple>

namespace mar::svg {

namespace {

constexpr size_t kMaxFaces = 16;
constexpr size_t kMaxRequests = 64;  // fonts asked for (each a fontconfig match, 0.1-0.2 ms)

// The families of a font-family list, unquoted.
std::vector<std::string> families_of(std::string_view list) {
  std::vector<std::string> out;
  size_t i = 0;
  while (i <= list.size()) {
    const size_t comma = std::min(list.find(',', i), list.size());
    std::string_view f = list.substr(i, comma - i);
    while (!f.empty() && (f.front() == ' ' || f.front() == '\t' || f.front() == '\n')) f.remove_prefix(1);
    while (!f.empty() && (f.back() == ' ' || f.back() == '\t' || f.back() == '\n')) f.remove_suffix(1);
    if (f.size() >= 2 && (f.front() == '\'' || f.front() == '"') && f.back() == f.front()) f = f.substr(1, f.size() - 2);
    if (!f.empty()) out.emplace_back(f);
    i = comma + 1;
  }
  return out;
}

// Glyph outline -> path commands, in font units (y up), placed by the caller's map.
struct OutlineSink {
  std::vector<PathCmd>* out;
  double scale;
  Vec2 at;
  bool open = false;
  Vec2 start = Vec2::Zero(), last = Vec2::Zero();
  Vec2 map(const FT_Vector* v) const { return {at.x() + scale * double(v->x), at.y() - scale * double(v->y)}; }
  void close() {
    if (open) out->push_back(PathCmd::to(PathCmd::Close, start));
    open = false;
  }
};

int move_to(const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  s->close();
  s->start = s->last = s->map(to);
  s->out->push_back(PathCmd::to(PathCmd::Move, s->start));
  s->open = true;
  return 0;
}
int line_to(const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  s->last = s->map(to);
  s->out->push_back(PathCmd::to(PathCmd::Line, s->last));
  return 0;
}
int conic_to(const FT_Vector* control, const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  const Vec2 c = s->map(control), p = s->map(to);
  s->out->push_back({PathCmd::Cubic, s->last + (2.0 / 3.0) * (c - s->last), p + (2.0 / 3.0) * (c - p), p});
  s->last = p;
  return 0;
}
int cubic_to(const FT_Vector* c1, const FT_Vector* c2, const FT_Vector* to, void* user) {
  auto* s = static_cast<OutlineSink*>(user);
  s->last = s->map(to);
  s->out->push_back({PathCmd::Cubic, s->map(c1), s->map(c2), s->last});
  return 0;
}

}  // namespace

struct TextShaper::Impl {
  FT_Library ft = nullptr;
  // fontconfig's configuration and font list, this shaper's own (3-17 ms to read from the
  // caches; its process-wide default would be kept, and lost, until exit)
  FcConfig* fc = nullptr;
  struct Face {
    FT_Face ft = nullptr;
    hb_font_t* hb = nullptr;
    double upem = 1000;
  };
  std::map<std::pair<std::string, int>, size_t> by_file;      // (file, index) -> faces
  std::map<std::tuple<std::string, int, bool>, long> by_request;  // -> faces, -1 = none found
  std::vector<Face> faces;
  hb_buffer_t* buffer = hb_buffer_create();

  ~Impl() {
    for (Face& f : faces) {
      hb_font_destroy(f.hb);
      FT_Done_Face(f.ft);
    }
    hb_buffer_destroy(buffer);
    if (ft) FT_Done_FreeType(ft);
    if (fc) FcConfigDestroy(fc);
  }

  // The face fontconfig picks for the request, opened once; null when there is none.
  Face* face(const FontRequest& r, std::string& problem) {
    const auto key = std::make_tuple(r.family, r.weight, r.italic);
    if (auto it = by_request.find(key); it != by_request.end()) {
      if (it->second < 0) problem = "no font for font-family \"" + r.family + "\"";
      return it->second < 0 ? nullptr : &faces[size_t(it->second)];
    }
    if (by_request.size() >= kMaxRequests) {  // (a file asking for thousands of fonts)
      problem = "more than " + std::to_string(kMaxRequests) + " fonts asked for; \"" + r.family + "\" drawn in the first found";
      return faces.empty() ? nullptr : &faces.front();
    }
    long found = -1;
    if (!ft && FT_Init_FreeType(&ft) != 0) ft = nullptr;
    if (!fc) fc = FcInitLoadConfigAndFonts();
    FcPattern* pat = FcPatternCreate();
    for (const std::string& f : families_of(r.family)) FcPatternAddString(pat, FC_FAMILY, reinterpret_cast<const FcChar8*>(f.c_str()));
    FcPatternAddInteger(pat, FC_WEIGHT, FcWeightFromOpenType(std::clamp(r.weight, 1, 1000)));
    FcPatternAddInteger(pat, FC_SLANT, r.italic ? FC_SLANT_ITALIC : FC_SLANT_ROMAN);
    FcPatternAddBool(pat, FC_OUTLINE, FcTrue);
    FcConfigSubstitute(fc, pat, FcMatchPattern);
    FcDefaultSubstitute(pat);
    FcResult result = FcResultNoMatch;
    FcPattern* match = ft && fc ? FcFontMatch(fc, pat, &result) : nullptr;
    FcChar8* file = nullptr;
    int index = 0;
    if (match && FcPatternGetString(match, FC_FILE, 0, &file) == FcResultMatch && file) {
      FcPatternGetInteger(match, FC_INDEX, 0, &index);
      const auto fkey = std::make_pair(std::string(reinterpret_cast<const char*>(file)), index);
      if (auto it = by_file.find(fkey); it != by_file.end()) {
        found = long(it->second);
      } else if (faces.size() < kMaxFaces) {
        Face f;
        if (FT_New_Face(ft, fkey.first.c_str(), index, &f.ft) == 0 && (f.ft->face_flags & FT_FACE_FLAG_SCALABLE)) {
          f.upem = f.ft->units_per_EM > 0 ? f.ft->units_per_EM : 1000;
          hb_face_t* hf = hb_ft_face_create_referenced(f.ft);
          f.hb = hb_font_create(hf);
          hb_face_destroy(hf);
          hb_font_set_scale(f.hb, int(f.upem), int(f.upem));
          faces.push_back(f);
          found = long(faces.size() - 1);
          by_file[fkey] = size_t(found);
        } else if (f.ft) {
          FT_Done_Face(f.ft);
        }
      }
    }
    if (match) FcPatternDestroy(match);
    FcPatternDestroy(pat);
    by_request[key] = found;
    if (found < 0) problem = "no font for font-family \"" + r.family + "\"";
    return found < 0 ? nullptr : &faces[size_t(found)];
  }
};

TextShaper::TextShaper() : impl_(std::make_unique<Impl>()) {}
TextShaper::~TextShaper() = default;

bool TextShaper::shape(const FontRequest& font, double size, std::string_view utf8, double letter_spacing, const Vec2& origin,
                       std::vector<PathCmd>* out, size_t max_commands, double& advance, std::string& problem) {
  advance = 0;
  problem.clear();
  Impl::Face* f = impl_->face(font, problem);
  if (!f) return false;
  hb_buffer_t* b = impl_->buffer;
  hb_buffer_reset(b);
  hb_buffer_add_utf8(b, utf8.data(), int(utf8.size()), 0, int(utf8.size()));
  hb_buffer_guess_segment_properties(b);
  hb_shape(f->hb, b, nullptr, 0);
  unsigned n = 0;
  const hb_glyph_info_t* info = hb_buffer_get_glyph_infos(b, &n);
  const hb_glyph_position_t* pos = hb_buffer_get_glyph_positions(b, &n);
  const double k = size / f->upem;
  static const FT_Outline_Funcs funcs = {move_to, line_to, conic_to, cubic_to, 0, 0};
  double x = 0;
  for (unsigned i = 0; i < n; ++i) {
    if (out && out->size() > max_commands) out = nullptr;  // (past the budget: the advance only)
    const Vec2 at = origin + Vec2(x + k * pos[i].x_offset, -k * pos[i].y_offset);
    if (out && info[i].codepoint != 0 &&
        FT_Load_Glyph(f->ft, info[i].codepoint, FT_LOAD_NO_SCALE | FT_LOAD_NO_HINTING | FT_LOAD_NO_BITMAP) == 0 &&
        f->ft->glyph->format == FT_GLYPH_FORMAT_OUTLINE) {
      OutlineSink sink{out, k, at};
      FT_Outline_Decompose(&f->ft->glyph->outline, &funcs, &sink);
      sink.close();
    }
    x += k * pos[i].x_advance;
    // (letter-spacing after each character: after the last glyph of each cluster)
    if (i + 1 == n || info[i + 1].cluster != info[i].cluster) x += letter_spacing;
  }
  advance = x;
  return true;
}

std::string collapse_white_space(std::string_view utf8, bool& space_before) {
  std::string out;
  out.reserve(utf8.size());
  for (char c : utf8) {
    if (c == '\n' || c == '\r') continue;
    if (c == '\t') c = ' ';
    if (c == ' ' && space_before) continue;
    out.push_back(c);
    space_before = c == ' ';
  }
  return out;
}

}  // namespace mar::svg
