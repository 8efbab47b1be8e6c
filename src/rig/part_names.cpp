// Names as hints (rig/part_names.h): what a part's or a group's words say, and what the
// automatic rig makes of them — swap sets and triggers, and chains that swing.
#include "rig/part_names.h"

#include <algorithm>
#include <cctype>
#include <map>

namespace mar {

std::vector<std::string> name_words(const std::string& name) {
  std::vector<std::string> out;
  std::string cur;
  auto flush = [&] {
    if (!cur.empty()) out.push_back(cur);
    cur.clear();
  };
  for (size_t i = 0; i < name.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (!std::isalnum(c)) {
      flush();
      continue;
    }
    // camelCase and letter/digit boundaries split words
    if (!cur.empty() && ((std::isupper(c) && std::islower(static_cast<unsigned char>(cur.back()))) ||
                         (std::isdigit(c) != 0) != (std::isdigit(static_cast<unsigned char>(cur.back())) != 0)))
      flush();
    cur.push_back(static_cast<char>(std::tolower(c)));
  }
  flush();
  return out;
}

Hint hint_of(const std::vector<std::string>& words) {
  static const std::map<std::string, Hint> kWords = {
      {"head", Hint::Head},   {"face", Hint::Head},   {"body", Hint::Body},  {"torso", Hint::Body}, {"chest", Hint::Body},
      {"arm", Hint::Limb},    {"leg", Hint::Limb},    {"tail", Hint::Limb},  {"ear", Hint::Limb},   {"hair", Hint::Limb},
      {"wing", Hint::Limb},   {"fin", Hint::Limb},    {"antenna", Hint::Limb}, {"hand", Hint::Hand}, {"foot", Hint::Hand},
      {"feet", Hint::Hand},   {"paw", Hint::Hand},    {"mouth", Hint::Mouth}, {"eye", Hint::Eye},   {"eyes", Hint::Eye}};
  for (const std::string& w : words) {
    // plurals and numbered parts ("arms", "ears", "leg2") read as their word
    std::string s = w;
    if (s.size() > 3 && s.back() == 's' && !kWords.count(s)) s.pop_back();
    if (auto it = kWords.find(s); it != kWords.end()) return it->second;
  }
  return Hint::None;
}

bool has_word(const std::vector<std::string>& words, std::initializer_list<const char*> any) {
  for (const std::string& w : words)
    for (const char* a : any)
      if (w == a) return true;
  return false;
}

// An id the loader made up ("path-L12") or an editor's default ("path1234", "g12"): no name.
bool made_up(const std::string& id) {
  static const char* kTags[] = {"path", "rect", "circle", "ellipse", "line", "polyline", "polygon", "region", "image", "g", "use", "layer"};
  for (const char* t : kTags) {
    const std::string tag = t;
    if (id.rfind(tag, 0) != 0) continue;
    std::string rest = id.substr(tag.size());
    if (!rest.empty() && rest[0] == '-') rest.erase(0, 1);
    if (!rest.empty() && rest[0] == 'L') rest.erase(0, 1);
    if (rest.empty() || std::all_of(rest.begin(), rest.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '-'; }))
      return true;
  }
  return false;
}

// A handle name from a part's id: lower case, words joined by '-'.
std::string handle_name(const std::string& id) {
  std::string out;
  for (const std::string& w : name_words(id)) out += (out.empty() ? "" : "-") + w;
  return out;
}

std::string unique_name(std::set<std::string>& used, const std::string& base) {
  std::string name = base;
  for (int k = 2; used.count(name); ++k) name = base + "-" + std::to_string(k);
  used.insert(name);
  return name;
}

std::set<int> swaps_and_triggers(const Character& ch, Rig& rig) {
  std::set<int> members;  // shapes a swap or trigger shows and hides
  {
    std::vector<int> mouths, open_eyes, shut_eyes;
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      const auto w = name_words(ch.shapes[s].label.empty() ? ch.shapes[s].id : ch.shapes[s].label);
      if (w.size() >= 2 && w[0] == "mouth") mouths.push_back(int(s));
      if (hint_of(w) != Hint::Eye && has_word(w, {"blink"})) shut_eyes.push_back(int(s));  // a blink layer
      if (hint_of(w) == Hint::Eye) {
        if (has_word(w, {"closed", "close", "shut", "blink"})) shut_eyes.push_back(int(s));
        else if (has_word(w, {"open"})) open_eyes.push_back(int(s));
      }
    }
    // Groups (Character Animator's way): a group named mouth whose children are visemes; a
    // group of eyes with open and closed children; a shape or group named blink.
    std::map<int, std::vector<int>> children;  // innermost group -> its shapes
    std::map<int, std::vector<std::string>> group_words;
    for (size_t s = 0; s < ch.shapes.size(); ++s) {
      const SubShape& sh = ch.shapes[s];
      if (sh.group_key < 0) continue;
      children[sh.group_key].push_back(int(s));
      const size_t slash = sh.group.rfind('/');
      group_words[sh.group_key] = name_words(slash == std::string::npos ? sh.group : sh.group.substr(slash + 1));
    }
    for (const auto& [key, kids] : children) {
      const auto& gw = group_words[key];
      if (mouths.size() < 2 && kids.size() >= 2 && has_word(gw, {"mouth", "mouths", "visemes", "viseme"})) mouths = kids;
      if (hint_of(gw) == Hint::Eye || has_word(gw, {"blink"}))
        for (int s : kids) {
          const auto w = name_words(ch.shapes[size_t(s)].label.empty() ? ch.shapes[size_t(s)].id : ch.shapes[size_t(s)].label);
          const bool shut = has_word(w, {"closed", "close", "shut", "blink"}) || has_word(gw, {"blink"});
          auto& list = shut ? shut_eyes : open_eyes;
          if ((shut || has_word(w, {"open"})) && std::find(list.begin(), list.end(), s) == list.end()) list.push_back(s);
        }
    }
    // Any other group of alternatives: shapes of one group, one showing and the others hidden
    // by the file (display: none). The hidden ones follow the parts they lie on.
    std::set<std::string> names;
    for (const auto& [key, kids] : children) {
      size_t hidden = 0;
      for (int k : kids) hidden += ch.shapes[size_t(k)].hidden;
      if (kids.size() < 2 || hidden == 0 || hidden == kids.size()) continue;
      if (kids == mouths || std::find(open_eyes.begin(), open_eyes.end(), kids[0]) != open_eyes.end() ||
          std::find(shut_eyes.begin(), shut_eyes.end(), kids[0]) != shut_eyes.end())
        continue;
      RigSwap sw;
      for (const std::string& w : group_words[key]) sw.name += (sw.name.empty() ? "" : "-") + w;
      if (sw.name.empty()) sw.name = "swap";
      const std::string base = sw.name;
      for (int n = 2; names.count(sw.name) || sw.name == "mouth" || sw.name == "eyes"; ++n) sw.name = base + "-" + std::to_string(n);
      names.insert(sw.name);
      for (int k : kids) {
        sw.members.push_back(ch.shapes[size_t(k)].id);
        if (ch.shapes[size_t(k)].hidden) members.insert(k);
      }
      for (size_t m = 0; m < kids.size(); ++m)
        if (!ch.shapes[size_t(kids[m])].hidden) {
          sw.default_member = int(m);
          break;
        }
      rig.swaps.push_back(sw);
    }
    if (mouths.size() >= 2) {
      RigSwap sw;
      sw.name = "mouth";
      for (int s : mouths) {
        sw.members.push_back(ch.shapes[size_t(s)].id);
        const SubShape& m = ch.shapes[size_t(s)];
        if (has_word(name_words(m.label.empty() ? m.id : m.label), {"neutral", "rest", "closed"})) sw.default_member = int(sw.members.size()) - 1;
        members.insert(s);
      }
      rig.swaps.push_back(sw);
    }
    if (!shut_eyes.empty() && open_eyes.empty()) {  // a blink layer over the eyes: shown while it fires
      RigTrigger tr;
      tr.name = "blink";
      for (int s : shut_eyes) {
        tr.shapes.push_back(ch.shapes[size_t(s)].id);
        members.insert(s);
      }
      rig.triggers.push_back(tr);
    }
    if (!shut_eyes.empty() && !open_eyes.empty()) {
      RigSwap sw;
      sw.name = "eyes";
      RigTrigger tr;
      tr.name = "blink";
      for (int s : open_eyes) sw.members.push_back(ch.shapes[size_t(s)].id);
      for (int s : shut_eyes) {
        sw.members.push_back(ch.shapes[size_t(s)].id);
        tr.shapes.push_back(ch.shapes[size_t(s)].id);
      }
      for (int s : open_eyes) members.insert(s);
      for (int s : shut_eyes) members.insert(s);
      rig.swaps.push_back(sw);
      rig.triggers.push_back(tr);
    }
  }
  return members;
}

void add_named_chains(const Character& ch, AutoRig& out) {
  Rig& rig = out.rig;
  // Secondary motion (motion/chain.h): a limb or a stroke named hair, ear, tail or antenna
  // swings in a show, hanging from its parent, its handle the chain's end.
  for (const AutoRigPart& p : out.parts) {
    if (p.kind != AutoRigPart::Limb || p.parent < 0 || p.handle.empty()) continue;
    const SubShape& sh = ch.shapes[size_t(p.shape)];
    const auto w = name_words(sh.label.empty() ? sh.id : sh.label);
    if (!has_word(w, {"hair", "ear", "ears", "tail", "antenna", "antennae", "ponytail", "pigtail", "braid", "curl", "tuft"})) continue;
    const int from = out.parts[size_t(p.parent)].shape;
    if (from < 0 || from == p.shape) continue;
    RigPhysics ph;
    ph.name = p.handle;
    ph.parts = {sh.id};
    ph.from = ch.shapes[size_t(from)].id;
    ph.handle = p.handle;
    ph.frequency = 2;
    ph.damping = 0.15;
    rig.physics.push_back(ph);
  }
}

}  // namespace mar
