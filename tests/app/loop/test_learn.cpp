#include "app/loop/learn.h"

#include <gtest/gtest.h>

namespace mar {
namespace {

ShowConfig show_with(std::vector<std::pair<std::string, std::string>> devices) {
  ShowConfig s = default_show();
  for (auto& [type, sim] : devices) {
    ShowDevice d;
    d.name = type + "-" + sim;
    d.type = type;
    d.sim = sim;
    s.devices.push_back(d);
  }
  return s;
}

Event ev(uint16_t source, ControlKind k, uint32_t number, uint8_t channel = 0) {
  Event e;
  e.source = source;
  e.kind = k;
  e.number = number;
  e.channel = channel;
  return e;
}

TEST(Learn, TheFirstControlThatMovesIsWrittenInTheShowGrammar) {
  const ShowConfig s = show_with({{"sim", "nanokontrol2"}, {"gpio", ""}, {"hid", "gamepad"}});
  Learned l;
  const Event cc[] = {ev(0, ControlKind::MidiCC, 16, 2)};
  ASSERT_TRUE(learn_control(cc, s, l));
  EXPECT_EQ(l.device, 0u);
  ControlSpec back;
  ASSERT_TRUE(parse_control(l.control, back).ok()) << l.control;  // learn prints what parse reads
  EXPECT_EQ(back.kind, ControlSpec::CC);
  EXPECT_EQ(back.number, 16u);
  EXPECT_EQ(back.channel, 2);
  const Event enc[] = {ev(1, ControlKind::EncoderDelta, 2)};
  ASSERT_TRUE(learn_control(enc, s, l));
  EXPECT_EQ(l.control, "encoder 2");
  const Event jog[] = {ev(2, ControlKind::EncoderDelta, usage::kWheel)};  // a HID relative axis is its usage
  ASSERT_TRUE(learn_control(jog, s, l));
  ASSERT_TRUE(parse_control(l.control, back).ok()) << l.control;
  EXPECT_EQ(back.kind, ControlSpec::Hid);
  EXPECT_EQ(back.number, usage::kWheel);
}

TEST(Learn, EventsThatNameNoControlAreSkipped) {
  const ShowConfig s = show_with({{"sim", "nanokontrol2"}});
  Learned l;
  const Event none[] = {ev(0, ControlKind::MidiProgram, 3), ev(7, ControlKind::MidiCC, 1)};  // unbindable; unknown device
  EXPECT_FALSE(learn_control(none, s, l));
  const Event later[] = {ev(0, ControlKind::MidiProgram, 3), ev(0, ControlKind::MidiNoteOn, 36)};
  ASSERT_TRUE(learn_control(later, s, l));
  EXPECT_EQ(l.control.rfind("note 36", 0), 0u) << l.control;
}

}  // namespace
}  // namespace mar
