// `marionette rig`: the automatic rig of a character, written as a commented rig file.
#include "app/commands.h"
#include "app/puppet.h"
#include "character/load.h"
#include "rig/auto_rig.h"
#include "rig/edit.h"
#include "rig/starter_show.h"

#include <filesystem>
#include <fstream>
#include <iostream>

namespace mar {

namespace fs = std::filesystem;

int cmd_rig(const RigArgs& a) {
  if (!a.show.empty() && a.output.empty()) {
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
  const fs::path dir = a.output.empty() ? fs::current_path() : fs::absolute(a.output).parent_path();
  auto relative = [&](const std::string& p) {
    if (p.empty()) return p;
    std::error_code ec;
    const fs::path r = fs::relative(fs::absolute(p), dir, ec);
    return ec || r.empty() ? fs::absolute(p).string() : r.generic_string();
  };
  const AutoRig ar = auto_rig(*ch.value, relative(a.input), relative(a.mask));
  const std::string text = write_auto_rig(ar, *ch.value);
  // What it wrote must load as a show would load it.
  auto parsed = parse_rig(text, a.output.empty() ? "(printed rig)" : a.output);
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
  if (a.output.empty()) {
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
  size_t limbs = 0;
  for (const AutoRigPart& p : ar.parts) limbs += p.kind == AutoRigPart::Limb;
  std::ostream& say = a.output.empty() ? std::cerr : std::cout;
  if (!a.show.empty()) say << "starter show for a " << a.device << " -> " << a.show << " (marionette run " << a.show << ")\n";
  say << "rigged " << a.input << ": " << ar.rig.handles.size() << " handles, " << ar.rig.joints.size() << " hinges (" << limbs << " limbs), "
      << ar.rig.swaps.size() << " swap sets, " << ar.rig.triggers.size() << " triggers" << (a.output.empty() ? "" : " -> " + a.output) << "\n";
  for (const std::string& n : ar.notes) say << "note: " << n << "\n";
  return kExitOk;
}

}  // namespace mar
