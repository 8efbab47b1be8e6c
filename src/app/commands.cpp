#include "app/commands.h"

#include "character/color.h"
#include "character/load.h"
#include "render/canvas.h"

#include <SDL2/SDL.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace mar {

std::optional<std::pair<int, int>> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
    return std::nullopt;
  }
  if (w < 1 || h < 1 || w > 8192 || h > 8192) return std::nullopt;
  return std::make_pair(w, h);
}

std::optional<Rgba> parse_background(const std::string& s) {
  if (s == "transparent" || s == "none") return Rgba{0, 0, 0, 0};
  const std::string hex = (!s.empty() && s[0] == '#') ? s : "#" + s;
  if (hex.size() != 7) return std::nullopt;
  return parse_color(hex);
}

void print_warnings(const Character& ch) {
  for (const std::string& w : ch.warnings) std::cerr << "warning: " << w << "\n";
}

bool apply_picture_flags(const std::string& size, const std::string& background, int& w, int& h, Rgba& bg) {
  if (!size.empty()) {
    auto sz = parse_size(size);
    if (!sz) {
      std::cerr << "error: --size must be WxH with 1..8192 pixels each, got '" << size << "'\n";
      return false;
    }
    w = sz->first;
    h = sz->second;
  }
  if (!background.empty()) {
    auto b = parse_background(background);
    if (!b) {
      std::cerr << "error: --background must be RRGGBB or transparent, got '" << background << "'\n";
      return false;
    }
    bg = *b;
  }
  return true;
}

int cmd_render(const RenderArgs& a) {
  RenderOptions ro;
  if (!apply_picture_flags(a.size, a.background, ro.width, ro.height, ro.background)) return kExitBadInput;
  if (a.supersample != 1 && a.supersample != 2 && a.supersample != 4) {
    std::cerr << "error: --supersample must be 1, 2 or 4\n";
    return kExitBadInput;
  }
  ro.supersample = a.supersample;
  LoadOptions lo;
  lo.mask_path = a.mask;
  if (ro.width > 0 && ro.height > 0)  // (curves within 0.1 px at the picture's size)
    lo.pixels_per_unit = [&ro](double w, double h) { return fit_view(w, h, ro.width, ro.height).max_scale(); };
  Result<Character> ch = load_character(a.input, lo);
  if (!ch.ok()) {
    std::cerr << "error: " << ch.error << "\n";
    return kExitBadInput;
  }
  print_warnings(*ch.value);
  const CharacterMesh mesh = prepare_mesh(*ch.value);
  Result<Image> img = render_character(*ch.value, mesh, ro);
  if (!img.ok()) {
    std::cerr << "error: " << img.error << "\n";
    return kExitRuntime;
  }
  if (std::string err = write_png(a.output, *img.value); !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return kExitRuntime;
  }
  std::cout << a.output << "\n";
  return kExitOk;
}

nlohmann::ordered_json inspect_json(const Character& ch) {
  size_t closed = 0;
  for (const SubShape& s : ch.shapes) closed += s.closed() ? 1 : 0;
  nlohmann::ordered_json j;
  j["source"] = ch.source;
  j["width"] = ch.width;
  j["height"] = ch.height;
  j["layers"] = ch.layers;
  nlohmann::ordered_json shapes = nlohmann::ordered_json::array();
  for (const SubShape& s : ch.shapes) {
    const Bounds b = s.bounds();
    nlohmann::ordered_json o;
    o["id"] = s.id;
    o["element"] = s.element;
    o["closed"] = s.closed();
    o["contours"] = s.contours.size();
    o["vertices"] = s.points.size();
    o["layer"] = s.layer;
    o["layer_name"] = ch.layers[static_cast<size_t>(s.layer)];
    o["bounds"] = {b.lo.x(), b.lo.y(), b.hi.x(), b.hi.y()};
    o["fill"] = s.fill.enabled ? (s.fill.texture ? "texture" : color_hex(s.fill.color)) : "none";
    o["stroke"] = s.stroke.enabled ? color_hex(s.stroke.color) : "none";
    shapes.push_back(o);
  }
  j["subshapes"] = shapes;
  const Bounds b = ch.bounds();
  j["totals"] = {{"subshapes", ch.shapes.size()},
                 {"closed", closed},
                 {"open", ch.shapes.size() - closed},
                 {"vertices", ch.vertex_count()},
                 {"layers", ch.layers.size()},
                 {"bounds", b.empty() ? nlohmann::ordered_json::array()
                                      : nlohmann::ordered_json{b.lo.x(), b.lo.y(), b.hi.x(), b.hi.y()}}};
  j["warnings"] = ch.warnings;
  j["dropped"] = ch.dropped;
  j["approximated"] = ch.approximated;
  return j;
}

void print_inspect_text(const Character& ch) {
  size_t closed = 0;
  for (const SubShape& s : ch.shapes) closed += s.closed() ? 1 : 0;
  std::printf("%s  (%g x %g, %zu layers)\n", ch.source.c_str(), ch.width, ch.height, ch.layers.size());
  std::printf("%-28s %-8s %-6s %8s %5s  %s\n", "id", "element", "kind", "vertices", "layer", "bounds");
  for (const SubShape& s : ch.shapes) {
    const Bounds b = s.bounds();
    std::printf("%-28s %-8s %-6s %8zu %5d  [%.1f, %.1f] - [%.1f, %.1f]\n", s.id.c_str(), s.element.c_str(),
                s.closed() ? "closed" : "open", s.points.size(), s.layer, b.lo.x(), b.lo.y(), b.hi.x(), b.hi.y());
  }
  std::printf("totals: %zu sub-shapes (%zu closed, %zu open), %zu vertices, %zu layers\n", ch.shapes.size(), closed,
              ch.shapes.size() - closed, ch.vertex_count(), ch.layers.size());
  for (const auto& [what, counts] : {std::pair{"dropped (not drawn)", &ch.dropped}, {"approximated", &ch.approximated}}) {
    if (counts->empty()) continue;
    int n = 0;
    for (const auto& [reason, k] : *counts) n += k;
    std::printf("%s: %d (", what, n);
    bool first = true;
    for (const auto& [reason, k] : *counts) {
      std::printf("%s%s: %d", first ? "" : ", ", reason.c_str(), k);
      first = false;
    }
    std::printf(")\n");
  }
  if (!ch.warnings.empty()) {
    std::printf("warnings (%zu):\n", ch.warnings.size());
    for (const std::string& w : ch.warnings) std::printf("  %s\n", w.c_str());
  }
}

int cmd_inspect(const InspectArgs& a) {
  if (!a.rig.empty()) return cmd_inspect_rig(a);
  if (!a.overlay.empty()) {
    std::cerr << "error: -o (frame overlay) needs --rig\n";
    return kExitBadInput;
  }
  LoadOptions lo;
  lo.mask_path = a.mask;
  Result<Character> r = load_character(a.input, lo);
  if (!r.ok()) {
    std::cerr << "error: " << r.error << "\n";
    return kExitBadInput;
  }
  if (a.json) {
    std::cout << inspect_json(*r.value).dump(2) << "\n";
  } else {
    print_inspect_text(*r.value);
  }
  return kExitOk;
}

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wl && *wl);
}

namespace {

// Both targets draw through this: characters side by side on white, 8 px margins
// (scaled by `k` when supersampling offscreen).
void draw_tiles(Canvas& c, const std::vector<Character>& chars, const std::vector<CharacterMesh>& meshes,
                double k, DrawList& list) {
  c.clear(Rgba{1, 1, 1, 1});
  list.clear();
  list.fringe = c.wants_fringe();
  const int n = static_cast<int>(chars.size());
  const int tw = c.width() / n;
  for (int i = 0; i < n; ++i) {
    const auto u = static_cast<size_t>(i);
    const Affine2 view = Affine2::translate(i * tw, 0) * fit_view(chars[u].width, chars[u].height, tw, c.height(), 8 * k);
    build_draw_list(chars[u], meshes[u], {}, view, 0.25 * k, list);
  }
}

}  // namespace

int cmd_view(const ViewArgs& a) {
  int tile_w = 384, tile_h = 384;
  if (!a.size.empty()) {
    auto sz = parse_size(a.size);
    if (!sz) {
      std::cerr << "error: --size must be WxH\n";
      return kExitBadInput;
    }
    tile_w = sz->first;
    tile_h = sz->second;
  }
  if (a.supersample != 1 && a.supersample != 2 && a.supersample != 4) {
    std::cerr << "error: --supersample must be 1, 2 or 4\n";
    return kExitBadInput;
  }
  std::vector<Character> chars;
  std::vector<CharacterMesh> meshes;
  for (const std::string& in : a.inputs) {
    Result<Character> r = load_character(in);
    if (!r.ok()) {
      std::cerr << "error: " << r.error << "\n";
      return kExitBadInput;
    }
    print_warnings(*r.value);
    meshes.push_back(prepare_mesh(*r.value));
    chars.push_back(std::move(*r.value));
  }
  if (chars.empty()) {
    std::cerr << "error: no characters given\n";
    return kExitBadInput;
  }
  DrawList list;

  if (!a.headless && display_available()) {
    const int n = static_cast<int>(chars.size());
    WindowOptions wo;
    wo.title = "marionette - characters";
    wo.software = a.software;
    auto win = Canvas::window(wo, tile_w * n, tile_h);
    if (win.ok()) {
      Canvas& c = **win.value;
      std::cout << "showing " << n << " characters in a window; press Esc or close it to quit" << std::endl;
      const auto start = std::chrono::steady_clock::now();
      bool running = true, first = true;
      while (running) {
        SDL_Event ev;
        while (SDL_PollEvent(&ev)) {
          if (ev.type == SDL_QUIT) running = false;
          if (ev.type == SDL_KEYDOWN && (ev.key.keysym.sym == SDLK_ESCAPE || ev.key.keysym.sym == SDLK_q)) {
            running = false;
          }
        }
        draw_tiles(c, chars, meshes, 1.0, list);
        if (std::string err = c.draw(list); !err.empty()) {
          std::cerr << "error: " << err << "\n";
          return kExitRuntime;
        }
        if (first && !a.screenshot.empty()) {  // what the window shows, read back from its renderer
          const std::vector<std::uint8_t> px = c.read_window();
          if (std::string err = write_png(a.screenshot, downsample_premultiplied(px.data(), c.window_width(), c.window_height(), 1));
              !err.empty()) {
            std::cerr << "error: " << err << "\n";
            return kExitRuntime;
          }
        }
        first = false;
        c.present();
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (a.seconds > 0 && elapsed >= a.seconds) running = false;
        SDL_Delay(16);
      }
      return kExitOk;
    }
    std::cerr << "note: " << win.error << "; writing PNG files instead\n";
  } else if (!a.headless) {
    std::cout << "no display found (DISPLAY/WAYLAND_DISPLAY unset); writing PNG files\n";
  }

  std::error_code ec;
  std::filesystem::create_directories(a.out_dir, ec);
  if (ec) {
    std::cerr << "error: cannot create " << a.out_dir << ": " << ec.message() << "\n";
    return kExitRuntime;
  }
  const int k = a.supersample;
  for (size_t i = 0; i < chars.size(); ++i) {
    auto canvas = Canvas::offscreen(tile_w * k, tile_h * k);
    if (!canvas.ok()) {
      std::cerr << "error: " << canvas.error << "\n";
      return kExitRuntime;
    }
    draw_tiles(**canvas.value, {chars[i]}, {meshes[i]}, k, list);
    if (std::string err = (*canvas.value)->draw(list); !err.empty()) {
      std::cerr << "error: " << err << "\n";
      return kExitRuntime;
    }
    const std::vector<std::uint8_t> px = (*canvas.value)->read_premultiplied();
    const std::string stem = std::filesystem::path(a.inputs[i]).stem().string();
    const std::string out = (std::filesystem::path(a.out_dir) / (stem + ".png")).string();
    if (std::string err = write_png(out, downsample_premultiplied(px.data(), tile_w, tile_h, k)); !err.empty()) {
      std::cerr << "error: " << err << "\n";
      return kExitRuntime;
    }
    std::cout << std::filesystem::absolute(out).string() << "\n";
  }
  return kExitOk;
}

}  // namespace mar
