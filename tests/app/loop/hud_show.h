// A small show for the HUD's tests: a USB-MIDI controller and a GPIO knob box, and one binding
// (cc 7 on the controller -> handle.head.y, 0..100) in the show and in its mapping.
#pragma once

#include "app/show.h"
#include "input/mapping.h"

namespace mar::test {

struct HudShow {
  ShowConfig show;
  Mapping m;
  HudShow() {
    ShowDevice korg;
    korg.name = "korg";
    korg.type = "usb_midi";
    ShowDevice knobs;
    knobs.name = "knobs";
    knobs.type = "gpio";
    show.devices = {korg, knobs};
    m.set_handles({"head"}, {Vec2(0, 0)});
    Binding b;
    b.control.kind = ControlSpec::CC;
    b.control.number = 7;
    b.control.text = "cc 7";
    b.control.device = 0;
    b.target = TargetKind::HandleY;
    b.target_text = "handle.head.y";
    b.tf.lo = 0;
    b.tf.hi = 100;
    show.bindings.push_back(b);
    m.add_binding(b);
  }
};

}  // namespace mar::test
