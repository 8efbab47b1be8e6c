// `marionette rig`: the automatic rig of a character, written as a commented rig file.
#include "app/commands.h"
#include "app/puppet.h"
#include "app/show.h"
#include "app/rig_preview.h"
#include "app/rig_trial.h"
#include "app/studio/studio_window.h"
#include "character/load.h"
#include "rig/auto_rig.h"
#include "rig/edit.h"
#include "rig/starter_show.h"
#include "render/image.h"

#include <SDL2/SDL_timer.h>

#include <filesystem>
#include <fstream>
#include <iostream>

namespace mar {

namespace fs = std::filesystem;

namespace {

// The rig studio (studio_window.h) until the performer quits.
int run_studio(const RigArgs& a) {
  int w = 960, h = 720;
  if (!a.size.empty()) {
    auto sz = parse_size(a.size);
    if (!sz) {
      std::cerr << "error: --size must be WxH\n";
      return kExitBadInput;
    }
    std::tie(w, h) = *sz;
  }
  if (!display_available()) {
    std::cerr << "error: the rig studio needs a display (DISPLAY or WAYLAND_DISPLAY is unset); -o RIG.toml writes the automatic "
                 "rig without one (-o - prints it)\n";
    return kExitBadInput;
  }
  const std::string rig = a.rig.empty() ? fs::path(a.input).stem().string() + ".toml" : a.rig;
  auto studio = Studio::open(a.input, rig, a.mask);
  if (!studio.ok()) {
    std::cerr << "error: " << studio.error << "\n";
    return kExitBadInput;
  }
  print_warnings((*studio.value)->puppet().character);
  WindowOptions wo;
  wo.title = "marionette rig studio - " + rig;
  wo.software = a.software;
  std::string note;
  auto win = StudioWindow::open(**studio.value, wo, w, h, &note);
  if (!win.ok()) {
    std::cerr << "error: " << win.error << "\n";
    return kExitRuntime;
  }
  if (!note.empty()) std::cerr << "note: " << note << "\n";
  StudioWindow& sw = **win.value;
  const Uint64 start = SDL_GetTicks64();
  bool first = true;
  while (sw.frame()) {
    if (first && !a.screenshot.empty()) {
      const std::vector<std::uint8_t> px = sw.canvas().read_window();
      if (std::string err = write_png(a.screenshot, downsample_premultiplied(px.data(), sw.canvas().window_width(), sw.canvas().window_height(), 1));
          !err.empty()) {
        std::cerr << "error: " << err << "\n";
        return kExitRuntime;
      }
    }
    sw.present();
    if (first)  // once the window shows its first frame
      std::cout << ((*studio.value)->on_disk() ? "editing " + rig : "the automatic rig of " + a.input + "; S saves it as " + rig)
                << ": drag handles and hinges, click to add a handle, S saves, Esc quits" << std::endl;
    first = false;
    if (a.seconds > 0 && double(SDL_GetTicks64() - start) >= a.seconds * 1000) break;
    SDL_Delay(8);
  }
  if ((*studio.value)->dirty()) std::cout << "closed with unsaved changes (" << rig << " is as it was)\n";
  return kExitOk;
}

// `rig --show SHOW --character NAME`: the studio on one character of a show's cast.
int cast_studio(RigArgs a) {
  if (!a.output.empty() || !a.input.empty() || a.show.empty()) {
    std::cerr << "error: --character opens the studio on a character of --show's cast: rig --show SHOW.toml --character NAME "
                 "(no character file, no -o)\n";
    return kExitBadInput;
  }
  auto show = read_show_cast(a.show);
  if (!show.ok()) {
    std::cerr << "error: " << show.error << "\n";
    return kExitBadInput;
  }
  std::string names;
  for (const ShowCharacter& c : show.value->cast) {
    names += (names.empty() ? "" : ", ") + c.name;
    if (c.name != a.character_name) continue;
    a.rig = c.rig;
    a.input = c.character;
    if (a.input.empty()) {  // the rig's own drawing
      auto rig = load_rig(c.rig);
      if (!rig.ok()) {
        std::cerr << "error: " << rig.error << "\n";
        return kExitBadInput;
      }
      a.input = rig.value->character_path();
      if (a.mask.empty()) a.mask = rig.value->mask_path();
    }
    a.show.clear();
    return run_studio(a);
  }
  std::cerr << "error: " << a.show << ": no character '" << a.character_name << "' in its cast"
            << (names.empty() ? std::string(" (it has no [[character]] tables)") : " (" + names + ")") << "\n";
  return kExitBadInput;
}

}  // namespace

int cmd_rig(const RigArgs& a) {
  if (!a.character_name.empty()) return cast_studio(a);
  if (a.input.empty()) {
    std::cerr << "error: rig needs a character file (or --show SHOW --character NAME)\n";
    return kExitBadInput;
  }
  if (a.output.empty()) {
    if (!a.show.empty()) {
      std::cerr << "error: --show needs -o RIG.toml (the show names the rig file)\n";
      return kExitBadInput;
    }
    return run_studio(a);
  }
  if (!a.show.empty() && a.output == "-") {
    std::cerr << "error: --show needs -o RIG.toml (the show names the rig file)\n";
    return kExitBadInput;
  }
  LoadOptions lo;
  lo.mask_path = a.mask;
  auto ch = load_character(a.input, lo);
  if (!ch.ok()) {
    std::cerr << "error: " << ch.error << "\n";
    return kExitBadInput;
  }
  print_warnings(*ch.value);
  // Paths in the rig are relative to the rig's folder (printed: to the current one).
  const bool print = a.output == "-";
  const fs::path dir = print ? fs::current_path() : fs::absolute(a.output).parent_path();
  auto relative = [&](const std::string& p) {
    if (p.empty()) return p;
    std::error_code ec;
    const fs::path r = fs::relative(fs::absolute(p), dir, ec);
    return ec || r.empty() ? fs::absolute(p).string() : r.generic_string();
  };
  AutoRigOptions options;
  options.bones = a.bones;
  // (tried on its starter show: a rig from the parts that tears there may hold on the grid)
  const AutoRig ar = auto_rig_tried(*ch.value, a.input, a.mask, relative(a.input), relative(a.mask), options);
  if (ar.rig.handles.empty()) {  // nothing to perform with: say why and what to change
    std::cerr << "error: " << a.input << ": nothing to rig";
    for (const std::string& n : ar.notes) std::cerr << ": " << n;
    std::cerr << "\n  a part is a filled shape (closed or not); draw the character in filled shapes, or give a PNG with "
                 "transparency (or --mask) so its figure can be found\n";
    return kExitBadInput;
  }
  const std::string text = write_auto_rig(ar, *ch.value);
  // What it wrote must load as a show would load it.
  auto parsed = parse_rig(text, print ? "(printed rig)" : a.output);
  if (!parsed.ok()) {
    std::cerr << "error: the automatic rig does not load (" << parsed.error << "); please report this with the character\n";
    return kExitRuntime;
  }
  std::string show_text;
  if (!a.show.empty()) {
    std::error_code ec;
    fs::path rel = fs::relative(fs::absolute(a.output), fs::absolute(a.show).parent_path(), ec);
    if (ec || rel.empty()) rel = fs::absolute(a.output);
    auto show = starter_show(ar, *ch.value, rel.generic_string(), a.device);
    if (!show.ok()) {
      std::cerr << "error: " << show.error << "\n";
      return kExitBadInput;
    }
    show_text = *show.value;
  }
  if (print) {
    std::cout << text;
  } else {
    for (const auto& [file, body] : {std::pair{a.output, text}, std::pair{a.show, show_text}}) {
      if (file.empty()) continue;
      if (const std::string err = write_atomically(file, body); !err.empty()) {
        std::cerr << "error: " << err << "\n";
        return kExitRuntime;
      }
    }
  }
  std::ostream& say = print ? std::cerr : std::cout;
  if (!a.show.empty()) say << "starter show for a " << a.device << " -> " << a.show << " (marionette run " << a.show << ")\n";
  say << "rigged " << a.input << (print ? "" : " -> " + a.output) << ":\n";
  for (const std::string& line : rig_summary(ar, *ch.value)) say << "  " << line << "\n";
  for (const std::string& n : ar.notes) say << "note: " << n << "\n";
  if (!a.preview.empty()) {
    if (const std::string e = write_rig_preview(a.preview, *ch.value, ar); !e.empty()) {
      std::cerr << "error: " << e << "\n";
      return kExitRuntime;
    }
    say << "preview -> " << a.preview << "\n";
  }
  return kExitOk;
}

}  // namespace mar
