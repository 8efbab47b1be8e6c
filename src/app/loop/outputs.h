// Where a frame goes besides the window (src/output), composed by the frame in one line:
// `--dump-poses` (every frame's shapes, output/pose_dump.h) and `[output] pipewire = true` (the
// canvas as a PipeWire video source, output/pipewire_out.h). Each runs on a thread of its own fed
// through a ring the frame thread only writes: frame() allocates nothing, takes no lock and
// never waits, except the pose dump on the virtual clock (nothing dropped there; wall time only).
#pragma once

#include "app/puppet.h"
#include "output/pose_dump.h"
#include "render/canvas.h"

#include <memory>
#include <string>

namespace mar {

class PipeWireOut;

struct OutputsSpec {
  std::string dump_poses;  ///< a JSON-lines file; empty: none
  bool lossless = false;   ///< the virtual clock: the pose dump waits rather than drops
  bool pipewire = false;
  std::string show_path;   ///< names the PipeWire node after the show
  int width = 0, height = 0, rate = 60;  ///< the canvas's, the show's
};

class FrameOutputs {
 public:
  FrameOutputs();
  ~FrameOutputs();
  /// Opens what `s` asks for; an error names the file (PipeWire connects in the background and
  /// says so when it cannot: the show goes on without it).
  std::string open(const OutputsSpec& s, const Character& ch);
  /// The frame's shapes and canvas, after the render: frame number `n`, show time `t_ns`.
  void frame(uint64_t n, int64_t t_ns, const Puppet& p, Canvas& canvas);
  /// Finishes writing; says what was written unless `quiet`; errors go to stderr. Returns
  /// false when a dump could not be written.
  bool finish(bool quiet);
  /// {"pose_dump": {...} | null, "pipewire": {...} | null} for --stats.
  std::string stats_json() const;
  bool pipewire() const { return pipewire_ != nullptr; }

 private:
  OutputsSpec spec_;
  std::unique_ptr<PoseDump> poses_;
  std::unique_ptr<PipeWireOut> pipewire_;
};

}  // namespace mar
