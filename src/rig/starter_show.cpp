#include "rig/starter_show.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

namespace mar {
namespace {

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f", v);
  return buf;
}

// A limb chain that carries a handle: the handle, and the hinge it turns about (the chain's
// first joint: the shoulder of an arm that ends in a hand).
struct Chain {
  std::string handle;
  std::string part;  ///< the first part's id, for comments
  Vec2 pivot{0, 0};
  int outward = 1;  ///< the sign of a turn away from the body
  bool stroke = false;  ///< a stroke hanging by one end (a whisker), not a part
};

std::vector<Chain> chains_of(const AutoRig& a, const Character& ch) {
  // What "away from the body" is measured from: the middle of the body's shape, not its handle
  // (a silhouette's body handle can sit off to one side of the chest, over one leg, and that leg
  // swung in across the other); without a body, each limb's own hinge.
  const AutoRigPart* body = nullptr;
  for (const AutoRigPart& q : a.parts)
    if (q.kind == AutoRigPart::Body) body = &q;
  std::optional<Vec2> middle;
  if (body && body->shape >= 0 && size_t(body->shape) < ch.shapes.size())
    if (const Bounds b = ch.shapes[size_t(body->shape)].bounds(); !b.empty()) middle = 0.5 * (b.lo + b.hi);
  std::vector<Chain> out;
  for (const AutoRigPart& p : a.parts) {
    if (p.kind != AutoRigPart::Limb || p.handle.empty()) continue;
    // (a chain's end swings on its own: secondary motion drives it)
    if (std::any_of(a.rig.physics.begin(), a.rig.physics.end(), [&](const RigPhysics& ph) { return ph.handle == p.handle; })) continue;
    const AutoRigPart* root = &p;
    while (root->parent >= 0 && a.parts[size_t(root->parent)].kind == AutoRigPart::Limb) root = &a.parts[size_t(root->parent)];
    Chain c{p.handle, ch.shapes[size_t(root->shape)].id, root->joint, 1, !ch.shapes[size_t(p.shape)].fill.enabled};
    // The turn that swings it away from the body: a small clockwise turn (positive, y down)
    // moves the handle by angle * (-dy, dx).
    const Vec2 centre = middle.value_or(c.pivot);
    for (const RigHandle& h : a.rig.handles)
      if (h.name == p.handle) {
        const Vec2 d = h.rest - c.pivot;
        c.outward = (h.rest.x() - centre.x()) * -d.y() >= 0 ? 1 : -1;
      }
    out.push_back(c);
  }
  // Limbs that are parts before strokes (an arm before a curl of hair), then top to bottom,
  // then left to right (arms before legs on the first knobs).
  std::stable_sort(out.begin(), out.end(), [](const Chain& x, const Chain& y) {
    if (x.stroke != y.stroke) return !x.stroke;
    if (std::abs(x.pivot.y() - y.pivot.y()) > 1e-6) return x.pivot.y() < y.pivot.y();
    return x.pivot.x() < y.pivot.x();
  });
  return out;
}

const AutoRigPart* first_of(const AutoRig& a, AutoRigPart::Kind k) {
  for (const AutoRigPart& p : a.parts)
    if (p.kind == k && !p.handle.empty()) return &p;
  return nullptr;
}

void binding(std::ostringstream& o, const std::string& device, const std::string& control, const std::string& target,
             const std::string& extra = "") {
  o << "\n[[binding]]\ndevice = \"" << device << "\"\ncontrol = \"" << control << "\"\ntarget = \"" << target << "\"\n" << extra;
}

}  // namespace

Result<std::string> starter_show(const AutoRig& a, const Character& ch, const std::string& rig_path, const std::string& device) {
  const bool known = std::any_of(std::begin(kStarterDevices), std::end(kStarterDevices), [&](const char* d) { return device == d; });
  if (!known) {
    std::string list;
    for (const char* d : kStarterDevices) list += (list.empty() ? "" : ", ") + std::string(d);
    return Result<std::string>::failure("no starter show for a device '" + device + "' (there are: " + list + ")");
  }
  const std::vector<Chain> chains = chains_of(a, ch);
  const AutoRigPart* body = first_of(a, AutoRigPart::Body);
  const AutoRigPart* head = first_of(a, AutoRigPart::Head);
  // Swap members and triggers, each a button.
  struct Press {
    std::string target, what;
  };
  std::vector<Press> presses;
  for (const RigTrigger& t : a.rig.triggers) presses.push_back({"trigger." + t.name, "fires " + t.name + " while held"});
  for (const RigSwap& s : a.rig.swaps)
    for (const std::string& m : s.members) presses.push_back({"swap." + s.name + "." + m, "shows " + m + " in " + s.name});

  std::ostringstream o;
  const int h = 640, w = std::clamp(int(std::lround(640.0 * ch.width / std::max(1e-9, ch.height))), 160, 1920);
  o << "# Starter show (marionette rig --show) for " << rig_path << " on a " << device << ".\n"
    << "# It runs at once with the device's simulator (the script below); for the real device,\n"
    << "# replace the [[device]] table's sim and script as docs/devices.md shows.\n"
    << "[show]\nrig = \"" << rig_path << "\"\nrate = 60\niterations = 8\n\n[display]\nwidth = " << w << "\nheight = " << h << "\n";
  // A group per chain: its handle turns about the chain's first hinge, which goes where the
  // body goes (a knob turns an arm about the shoulder the body's fader has moved). The head and
  // the limbs no knob turns go with the body too: left where they were, they would pull it back.
  const std::string follow = body ? "follow = \"" + body->handle + "\"\n" : "";
  auto groups = [&](size_t count) {
    for (size_t k = 0; k < std::min(count, chains.size()); ++k)
      o << "\n# " << chains[k].part << " about its hinge\n[[group]]\nname = \"" << chains[k].handle << "\"\nhandles = [\"" << chains[k].handle
        << "\"]\npivot = [" << num(chains[k].pivot.x()) << ", " << num(chains[k].pivot.y()) << "]\n" << follow;
    if (!body) return;
    std::string along;
    for (const AutoRigPart& p : a.parts) {
      if ((p.kind != AutoRigPart::Head && p.kind != AutoRigPart::Limb) || p.handle.empty()) continue;
      bool turned = false;
      for (size_t k = 0; k < std::min(count, chains.size()); ++k) turned = turned || chains[k].handle == p.handle;
      const bool swings = std::any_of(a.rig.physics.begin(), a.rig.physics.end(), [&](const RigPhysics& ph) { return ph.handle == p.handle; });
      if (!turned && !swings) along += (along.empty() ? "\"" : ", \"") + p.handle + "\"";
    }
    for (const RigHandle& bh : a.rig.handles)
      if (!along.empty() && bh.name == body->handle)
        o << "\n# what no knob turns goes with the body\n[[group]]\nname = \"with-" << body->handle << "\"\nhandles = [" << along
          << "]\npivot = [" << num(bh.rest.x()) << ", " << num(bh.rest.y()) << "]\n" << follow;
  };
  std::ostringstream script;
  if (device == "nanokontrol2") {
    // knobs turn limbs, faders move the body and the head, solo/mute buttons swap and trigger
    const size_t n = std::min<size_t>(8, chains.size());
    for (size_t k = 0; k < n; ++k) {
      const std::string knob = "knob" + std::to_string(k + 1);
      const double t = 0.2 + 0.5 * double(k);
      const double out = 0.5 + 0.3 * chains[k].outward, in = 0.5 - 0.15 * chains[k].outward;
      script << "0.0 move " << knob << " 0.5\n" << t << " move " << knob << " " << out << " over 0.8\n" << t + 0.8 << " move " << knob << " "
             << in << " over 1.2\n" << t + 2.0 << " move " << knob << " 0.5 over 0.6\n";
    }
    if (body) script << "0.0 move fader1 0.5\n0.5 move fader1 0.6 over 1.0\n1.5 move fader1 0.5 over 1.0\n";
    const size_t np = std::min<size_t>(16, presses.size());
    for (size_t k = 0; k < np; ++k)
      script << 1.0 + 0.6 * double(k) << " press " << (k < 8 ? "solo" : "mute") << (k % 8 + 1) << " for 0.3\n";
    o << "\n[[device]]\nname = \"korg\"\nsim = \"nanokontrol2\"\nscript = \"\"\"\n" << script.str() << "\"\"\"\n";
    groups(n);
    // A 7-bit knob's middle is 63 or 64 of 127, never 0.5: a narrow dead zone about the
    // centre puts a knob turned back to its middle exactly at rest.
    const std::string centre = "deadzone = 0.02\n";
    for (size_t k = 0; k < n; ++k) binding(o, "korg", "cc " + std::to_string(16 + k), "rotate." + chains[k].handle, centre);
    if (body) {
      binding(o, "korg", "cc 0", "handle." + body->handle + ".x", centre);
      binding(o, "korg", "cc 1", "handle." + body->handle + ".y", centre);
    }
    if (head) {
      binding(o, "korg", "cc 2", "handle." + head->handle + ".x", centre);
      binding(o, "korg", "cc 3", "handle." + head->handle + ".y", centre);
    }
    for (size_t k = 0; k < np; ++k)
      binding(o, "korg", "cc " + std::to_string((k < 8 ? 32 : 48) + int(k % 8)), presses[k].target, "# " + presses[k].what + "\n");
  } else if (device == "gamepad") {
    // the sticks drag the first two limbs' handles, buttons swap and trigger
    script << "0.2 stick left -1,-1 over 0.8\n0.6 stick right 1,-0.5 over 0.8\n1.8 stick left 0,0 over 0.5\n2.0 stick right 0,0 over 0.5\n";
    const size_t np = std::min<size_t>(10, presses.size());
    for (size_t k = 0; k < np; ++k) script << 1.0 + 0.6 * double(k) << " press " << k + 1 << " for 0.3\n";
    o << "\n[[device]]\nname = \"pad\"\nsim = \"gamepad\"\nscript = \"\"\"\n" << script.str() << "\"\"\"\n";
    const char* axes[2][2] = {{"usage x", "usage y"}, {"usage z", "usage rz"}};
    for (size_t k = 0; k < std::min<size_t>(2, chains.size()); ++k) {
      binding(o, "pad", axes[k][0], "handle." + chains[k].handle + ".x", "deadzone = 0.1\ntakeover = false\n");
      binding(o, "pad", axes[k][1], "handle." + chains[k].handle + ".y", "deadzone = 0.1\ntakeover = false\n");
    }
    for (size_t k = 0; k < np; ++k)
      binding(o, "pad", "usage button" + std::to_string(k + 1), presses[k].target, "# " + presses[k].what + "\n");
  } else if (device == "pen_tablet") {
    // the pen grabs the handle (or the point) under it and drags it
    const Bounds b = ch.bounds();
    Vec2 at = b.empty() ? Vec2(0.5, 0.5) : Vec2(0.5 * (b.lo + b.hi));
    if (!chains.empty()) {
      for (const RigHandle& hd : a.rig.handles)
        if (hd.name == chains[0].handle) at = hd.rest;
    }
    const Vec2 size = b.empty() ? Vec2(1, 1) : Vec2((b.hi - b.lo).cwiseMax(Vec2(1e-9, 1e-9)));
    const Vec2 u = b.empty() ? Vec2(0.5, 0.5) : Vec2((at - b.lo).cwiseQuotient(size));
    auto c = [](double v) { return num(std::clamp(v, 0.02, 0.98)).substr(0, 4); };
    script << "0.2 hover " << c(u.x()) << "," << c(u.y()) << "\n0.4 stroke " << c(u.x()) << "," << c(u.y()) << " " << c(u.x() - 0.1) << ","
           << c(u.y() - 0.2) << " " << c(u.x() + 0.1) << "," << c(u.y() - 0.1) << " " << c(u.x()) << "," << c(u.y()) << " over 2.0 pressure 0.6\n";
    o << "\n[[device]]\nname = \"pen\"\nsim = \"pen_tablet\"\nscript = \"\"\"\n" << script.str() << "\"\"\"\n";
    binding(o, "pen", "pointer", "grab");
  } else {  // knob_box
    // four encoders turn four limbs; button 1 brings the rest pose back, the others trigger
    const size_t n = std::min<size_t>(4, chains.size());
    for (size_t k = 0; k < n; ++k)
      script << 0.2 + 0.3 * double(k) << " turn " << k + 1 << " " << 12 * chains[k].outward << " over 1.2\n";
    script << "2.5 press 1 for 0.2\n";
    const size_t np = std::min<size_t>(3, presses.size());
    for (size_t k = 0; k < np; ++k) script << 3.0 + 0.5 * double(k) << " press " << k + 2 << " for 0.3\n";
    o << "\n[[device]]\nname = \"knobs\"\nsim = \"knob_box\"\nscript = \"\"\"\n" << script.str() << "\"\"\"\n";
    groups(n);
    o << "\n# the rest pose of the handles the encoders turn\n[[pose]]\nname = \"rest\"\nhandles = { ";
    for (size_t k = 0; k < n; ++k)
      for (const RigHandle& hd : a.rig.handles)
        if (hd.name == chains[k].handle) o << (k ? ", " : "") << hd.name << " = [" << num(hd.rest.x()) << ", " << num(hd.rest.y()) << "]";
    o << " }\n";
    for (size_t k = 0; k < n; ++k)
      binding(o, "knobs", "encoder " + std::to_string(k + 1), "rotate." + chains[k].handle, "mode = \"delta\"\nstep = 4.0\n");
    binding(o, "knobs", "button 1", "pose.rest", "# the rest pose, eased back\n");
    for (size_t k = 0; k < np; ++k) binding(o, "knobs", "button " + std::to_string(k + 2), presses[k].target, "# " + presses[k].what + "\n");
  }
  return Result<std::string>::success(o.str());
}

}  // namespace mar
