// Where a frame goes besides the window (src/output), composed by the frame in one line:
// `--dump-poses` (every frame's shapes, output/pose_dump.h), `--dump-frames` (PNG files,
// output/png_dump.h), `--video` (a video take, output/video_out.h) and `[output] pipewire = true`
// (the canvas as a PipeWire video source, output/pipewire_out.h), and `[osc_out]` (the show's
// state as OSC, output/osc_out.h). Each runs on a thread of its own
// fed through a ring the frame thread only writes: frame() allocates nothing, takes no lock and
// never waits on the wall clock; on the virtual clock the files drop nothing, so the frame waits
// for room (wall time only). What the hand-over costs the frame thread is measured.
#pragma once

#include "app/puppet.h"
#include "app/show.h"
#include "app/stats.h"
#include "devices/device.h"
#include "output/osc_out.h"
#include "render/canvas.h"

#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <span>
#include <string>

namespace mar {

class PoseDump;
class PngDump;
class VideoOut;
class PipeWireOut;

struct OutputsSpec {
  std::string dump_poses;  ///< a JSON-lines file; empty: none
  std::string dump_dir;    ///< PNG files, every `every`th frame; empty: none
  int every = 1;
  std::string video, codec = "ffv1";  ///< a video file; empty: none
  int factor = 1;          ///< the canvas's supersampling (files are box-filtered down)
  bool lossless = false;   ///< the virtual clock: files wait rather than drop
  bool pipewire = false;
  std::string show_path;   ///< names the PipeWire node after the show
  int width = 0, height = 0, rate = 60;  ///< the canvas's, the show's
  bool osc = false;
  OscOutOptions osc_options;
  ShowStateLayout osc_layout;  ///< the rig's handles, keys, swap sets, triggers; the show's devices
  /// OSC out as the show's [osc_out] says (off without it), named after `rig` and the show.
  void set_osc(const ShowConfig& show, const Rig& rig);
  /// A cast's: every character's rig (`rigs`, in the cast's order, named `names`), then each
  /// character's on-stage trigger.
  void set_osc(const ShowConfig& show, const std::vector<const Rig*>& rigs, const std::vector<std::string>& names);
};

/// What a frame knew besides its shapes (spans over the loop's own arrays).
struct FrameState {
  std::span<const double> keys;
  std::span<const Vec2> handles;  ///< a cast's handles (empty: the puppet's solver's)
  std::span<const Points> shapes; ///< a cast's shapes for the pose dump (empty: the puppet's)
  std::span<const char> shown;
  std::span<const int> swaps;
  std::span<const char> triggers;
  std::span<const DeviceState> devices;
  double frame_ms = 0;
  double latency_ms = -1;  ///< its newest input's age at frame-ready; < 0: no input this frame
};

/// Empty when a video take `path` with `codec` can be written by this build; else why not.
std::string check_video_take(const std::string& path, const std::string& codec);

class FrameOutputs {
 public:
  FrameOutputs();
  ~FrameOutputs();
  /// Opens what `s` asks for; an error names the file or the codec (PipeWire connects in the
  /// background and says so when it cannot: the show goes on without it).
  std::string open(const OutputsSpec& s, const Character& ch);
  /// A reloaded show with its rig's names in `s` (set_osc): OSC out starts again with them;
  /// the files and the stream go on.
  std::string relayout(const OutputsSpec& s, const Character& ch);
  /// The frame's shapes and canvas, after the render: frame number `n`, show time `t_ns`.
  /// Returns the µs it took the frame thread, less any wait for a file's writer on the virtual
  /// clock (wall time that is not the show's): the frame counts it as its own work.
  double frame(uint64_t n, int64_t t_ns, const Puppet& p, Canvas& canvas, const FrameState& state);
  /// Finishes writing; says what was written unless `quiet`; errors go to stderr. Returns
  /// false when a file could not be written.
  bool finish(bool quiet);
  /// Adds "pose_dump", "frame_dump", "video", "pipewire", "osc_out" (each null when off) and
  /// "outputs_handover_us" to the --stats object `j`.
  void add_stats(nlohmann::json& j) const;

 private:
  OutputsSpec spec_;
  std::unique_ptr<PoseDump> poses_;
  std::unique_ptr<PngDump> pngs_;
  std::unique_ptr<VideoOut> video_;
  std::unique_ptr<PipeWireOut> pipewire_;
  std::unique_ptr<OscOut> osc_;
  double latency_ms_ = 0;
  Histogram handover_;  ///< µs the frame thread spends reading the canvas and copying it out
  double waited_us() const;
  bool finished_ = false;
};

}  // namespace mar
