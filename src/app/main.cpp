// marionette — live 2D puppeteering controller. Command-line entry point, built twice:
// `marionette` (ships; no virtual bench) and `marionette-simulate` (MARIONETTE_SIMULATE:
// links the umockdev bench for `run --simulate`).
#include "app/alloc_count.h"
#include "app/commands.h"
#include "app/live.h"
#include "app/simulate.h"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  mar::set_allocation_counter(&mar::heap_allocation_count);
  CLI::App app{"marionette — live 2D puppeteering controller"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("marionette ") + MARIONETTE_VERSION);

  mar::RenderArgs render;
  CLI::App* r = app.add_subcommand("render", "Render a character to a PNG file");
  r->add_option("character", render.input, "Character file (.svg or .png)")->required();
  r->add_option("-o,--output", render.output, "Output PNG")->required();
  r->add_option("--size", render.size, "Output size WxH (default: document size)");
  r->add_option("--background", render.background, "RRGGBB or transparent (default)");
  r->add_option("--mask", render.mask, "Mask PNG for a PNG character (non-black = figure)");
  r->add_option("--supersample", render.supersample, "1, 2 or 4 samples per axis (smooth edges)");

  mar::InspectArgs inspect;
  CLI::App* i = app.add_subcommand("inspect", "List a character's sub-shapes, layers and warnings");
  i->add_option("character", inspect.input, "Character file (.svg or .png)")->required();
  i->add_option("--mask", inspect.mask, "Mask PNG for a PNG character");
  i->add_flag("--json", inspect.json, "Machine-readable output");
  i->add_option("--rig", inspect.rig, "Rig file: add the solver's statistics (seed 000 or seed 003 Table 1) and handles");
  i->add_option("-o,--output", inspect.overlay, "With --rig: PNG of the solver's structure over the character (feature frame, mesh, or grid)");

  mar::PoseArgs pose;
  CLI::App* p = app.add_subcommand("pose", "Solve a pose from rest for handle targets");
  p->add_option("character", pose.input, "Character file")->required();
  p->add_option("--rig", pose.rig, "Rig file")->required();
  p->add_option("--target", pose.targets, "NAME=X,Y (repeatable); other handles stay at rest");
  p->add_option("--iterations", pose.iterations, "Solver iterations (default: the rig's)");
  p->add_option("--dump", pose.dump, "JSON with deformed sub-shapes, frame vertices, energies, residuals");
  p->add_option("-o,--output", pose.output, "PNG of the posed character");
  p->add_option("--size", pose.size, "PNG size WxH (default: document size)");
  p->add_option("--background", pose.background, "RRGGBB or transparent (default)");
  p->add_flag("--overlay", pose.overlay, "Draw the deformed feature frame and handles too");
  p->add_option("--mask", pose.mask, "Mask PNG for a PNG character (non-black = figure)");
  p->add_option("--set", pose.settings, "NAME=VALUE (repeatable): a parameter of the rig's solver, e.g. half_width=6");
  p->add_option("--save-key", pose.save_key, "Append this pose's targets to the rig as a key pose named NAME");

  mar::InterpArgs interp;
  CLI::App* ip = app.add_subcommand("interp", "In-betweens of two key poses (structure-preserving ARAP interpolation)");
  ip->add_option("character", interp.input, "Character file")->required();
  ip->add_option("--rig", interp.rig, "Rig file with [[key]] poses")->required();
  ip->add_option("--mask", interp.mask, "Mask PNG for a PNG character");
  ip->add_option("--from", interp.from, "Key name (default: rest)");
  ip->add_option("--to", interp.to, "Key name")->required();
  ip->add_option("--t", interp.t, "One in-between at t (0..1)");
  ip->add_option("--steps", interp.steps, "N pictures from t = 0 to t = 1 (2..10000)");
  ip->add_flag("--linear", interp.linear, "The naive linear blend of frame vertices instead (for comparison)");
  ip->add_option("--dump", interp.dump, "JSON: per step, t, frame vertices and deformed sub-shapes");
  ip->add_option("-o,--output", interp.output, "PNG of the in-between (with --t)");
  ip->add_option("--out-dir", interp.out_dir, "Folder for one PNG per step (with --steps)");
  ip->add_option("--size", interp.size, "PNG size WxH (default: document size)");
  ip->add_option("--background", interp.background, "RRGGBB or transparent (default)");

  mar::ViewArgs view;
  CLI::App* v = app.add_subcommand("view", "Show characters in a window, or write PNGs when there is no display");
  v->add_option("characters", view.inputs, "Character files")->required();
  v->add_option("--out-dir", view.out_dir, "Where PNGs go without a display");
  v->add_option("--size", view.size, "Tile size per character WxH (default 384x384)");
  v->add_option("--seconds", view.seconds, "Close the window after this many seconds");
  v->add_flag("--headless", view.headless, "Never open a window");
  v->add_flag("--software", view.software, "Use SDL's software renderer in the window");
  v->add_option("--supersample", view.supersample, "Headless PNGs: 1, 2 or 4 samples per axis");
  v->add_option("--screenshot", view.screenshot, "Window mode: save the first frame as PNG");

  mar::RunArgs run;
  CLI::App* run_cmd = app.add_subcommand("run", "Run a live show (window, or headless with --headless or no display)");
  run_cmd->add_option("show", run.show, "Show file (TOML)")->required();
  run_cmd->add_flag("--headless", run.headless, "Offscreen with a fixed-rate clock");
  run_cmd->add_flag("--kiosk", run.kiosk,
                    "Unattended: fullscreen, cursor hidden, no HUD, no quit keys (the show's [kiosk] exit_chord or a signal ends it)");
  run_cmd->add_option("--frames", run.frames, "Stop after N frames (headless default: until the scripts end)");
  run_cmd->add_option("--rate", run.rate, "Frame rate in Hz (default: the show's)");
  run_cmd->add_option("--stats", run.stats, "Write frame statistics as JSON");
  run_cmd->add_option("--record", run.record, "Record the raw wire data with timestamps");
  run_cmd->add_option("--dump-frames", run.dump_frames, "Write frames as PNG into this folder");
  run_cmd->add_option("--every", run.every, "With --dump-frames: every Kth frame");
  run_cmd->add_option("--dump-poses", run.dump_poses, "Write every frame's shapes as JSON lines to this file (t, subshapes: id, points)");
  run_cmd->add_option("--learn", run.learn, "Bind the next control that moves to TARGET and write it into the show");
  run_cmd->add_flag("--simulate", run.simulate,
                    "Present the hardware devices' simulators at the kernel interface (umockdev): no hardware needed");
  run_cmd->add_option("--supersample", run.supersample,
                      "Draw the canvas at N x and box-filter it down (1..8): the reference the anti-aliasing is measured against");
  run_cmd->add_flag("--aliased", run.aliased, "Draw with SDL's aliased triangles instead of anti-aliased (to compare)");
  run_cmd->add_option("--screenshot", run.screenshot,
                      "Window mode: save what the window shows (HUD included) at the last frame as PNG (needs --frames)");
  run_cmd->add_option("--video", run.video, "Record the canvas into a video file (.mkv, .mov, .mp4) as the show plays, encoded on its own thread");
  run_cmd->add_option("--codec", run.codec, "With --video: ffv1 (lossless, alpha; the default), prores4444 (alpha) or h264");
  run_cmd->add_flag("--realtime", run.realtime,
                    "Headless on the wall clock (frame times, the budget governor, --simulate's players as they come): "
                    "not reproducible; the default headless clock is virtual and every run gives the same run_hash");

  mar::DevicesArgs devs;
  CLI::App* devices_cmd = app.add_subcommand("devices", "List the input devices every backend finds, their status and problems");
  devices_cmd->add_flag("--json", devs.json, "Machine-readable output");

  mar::RigArgs rigargs;
  CLI::App* rig_cmd = app.add_subcommand("rig", "The automatic rig of a character: hinges at its drawn joints, handles, swap sets and triggers");
  rig_cmd->add_option("character", rigargs.input, "Character file (.svg or .png); not with --show SHOW --character NAME");
  rig_cmd->add_option("-o,--output", rigargs.output, "Rig file to write ('-': print it); without -o the rig studio opens");
  rig_cmd->add_option("--mask", rigargs.mask, "Mask PNG for a PNG character (non-black = figure)");
  rig_cmd->add_option("--show", rigargs.show, "Also write a starter show that binds the rig to --device (needs -o); with --character, the show whose character the studio opens");
  rig_cmd->add_option("--character", rigargs.character_name, "Studio: open this character of --show's cast ([[character]] name), its rig and drawing");
  rig_cmd->add_option("--preview", rigargs.preview, "Also draw what was found into this PNG: body, limbs, hinges, handles, what was left out");
  rig_cmd->add_flag("--bones", rigargs.bones, "A long, straight limb inside one shape turns whole at its joint ([[bone]]) instead of bending in the grid");
  rig_cmd->add_option("--device", rigargs.device, "The starter show's device: nanokontrol2 (default), gamepad, pen_tablet, knob_box");
  rig_cmd->add_option("--rig", rigargs.rig, "Studio: the rig to edit and save (default: <character>.toml in this folder; the automatic rig if it does not exist)");
  rig_cmd->add_option("--size", rigargs.size, "Studio: canvas size WxH (default 960x720)");
  rig_cmd->add_option("--seconds", rigargs.seconds, "Studio: close after this many seconds");
  rig_cmd->add_flag("--software", rigargs.software, "Studio: SDL's software renderer");
  rig_cmd->add_option("--screenshot", rigargs.screenshot, "Studio: save the first frame's window as a PNG");

  mar::CalibrateArgs calibrate;
  CLI::App* cal_cmd = app.add_subcommand("calibrate", "A voice's vowel templates from a recording of a, i, u, e, o (prints the calibrate line)");
  cal_cmd->add_option("wav", calibrate.wav, "WAV file: the performer saying a, i, u, e, o in order, a pause between")->required();

  mar::RunArgs replay;
  CLI::App* replay_cmd = app.add_subcommand("replay", "Replay a recording through a show");
  replay_cmd->add_option("recording", replay.replay, "File written by run --record")->required();
  replay_cmd->add_option("--show", replay.show, "Show file")->required();
  replay_cmd->add_option("--stats", replay.stats, "Write frame statistics as JSON");
  replay_cmd->add_option("--dump-frames", replay.dump_frames, "Write frames as PNG into this folder");
  replay_cmd->add_option("--every", replay.every, "With --dump-frames: every Kth frame");
  replay_cmd->add_option("--dump-poses", replay.dump_poses, "Write every frame's shapes as JSON lines to this file (t, subshapes: id, points)");
  replay_cmd->add_option("--video", replay.video, "Render the take into a video file (.mkv, .mov, .mp4), each frame at its time");
  replay_cmd->add_option("--codec", replay.codec, "With --video: ffv1 (lossless, alpha; the default), prores4444 (alpha) or h264");
  replay_cmd->add_option("--size", replay.size, "The canvas WxH (default: the show's [output] or [display] size)");
  replay_cmd->add_flag("--force", replay.force, "Play a take recorded with another show (other devices)");
  replay.headless = true;

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return mar::kExitBadInput;
  }
  if (r->parsed()) return mar::cmd_render(render);
  if (i->parsed()) return mar::cmd_inspect(inspect);
  if (p->parsed()) return mar::cmd_pose(pose);
  if (ip->parsed()) return mar::cmd_interp(interp);
  if (v->parsed()) return mar::cmd_view(view);
  if (run_cmd->parsed()) {
    if (run.simulate) {
#ifdef MARIONETTE_SIMULATE
      mar::enable_virtual_bench(argv);  // re-executes under umockdev's preload
#else
      return mar::exec_simulator(argv);  // the bench is not linked into this program
#endif
    }
    return mar::cmd_run(run);
  }
  if (devices_cmd->parsed()) return mar::cmd_devices(devs);
  if (rig_cmd->parsed()) return mar::cmd_rig(rigargs);
  if (replay_cmd->parsed()) return mar::cmd_run(replay);
  if (cal_cmd->parsed()) return mar::cmd_calibrate(calibrate);
  return mar::kExitBadInput;
}
