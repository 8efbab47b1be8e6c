#include "app/loop/outputs.h"

#ifdef MARIONETTE_HAVE_PIPEWIRE
#include "output/pipewire_out.h"
#endif

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>

namespace mar {

#ifndef MARIONETTE_HAVE_PIPEWIRE
class PipeWireOut {};  // built without it (-DMARIONETTE_WITH_PIPEWIRE=OFF)
#endif

FrameOutputs::FrameOutputs() = default;
FrameOutputs::~FrameOutputs() = default;

std::string FrameOutputs::open(const OutputsSpec& s, const Character& ch) {
  spec_ = s;
  if (!s.dump_poses.empty() && !poses_) {
    auto d = PoseDump::open(s.dump_poses, ch, s.lossless);
    if (!d.ok()) return d.error;
    poses_ = std::move(*d.value);
  }
  if (s.pipewire && !pipewire_) {
#ifdef MARIONETTE_HAVE_PIPEWIRE
    const std::string stem = std::filesystem::path(s.show_path).stem().string();
    PipeWireOptions o;
    o.node_name = "marionette-" + stem;
    o.description = "marionette: " + stem;
    o.width = s.width;
    o.height = s.height;
    o.rate = s.rate;
    pipewire_ = PipeWireOut::open(o);
#else
    return s.show_path + ": [output] pipewire = true, but this marionette was built without PipeWire (-DMARIONETTE_WITH_PIPEWIRE=ON, Debian package libpipewire-0.3-dev)";
#endif
  }
  return "";
}

void FrameOutputs::frame(uint64_t n, int64_t t_ns, const Puppet& p, Canvas& canvas) {
  if (poses_) poses_->push(double(t_ns) * 1e-9, p.shapes, p.shown);  // the writer's thread formats it
#ifdef MARIONETTE_HAVE_PIPEWIRE
  if (pipewire_) {
    const PixelTarget px = canvas.pixels();
    pipewire_->push(px.px, px.stride, n, t_ns);
  }
#else
  (void)n;
  (void)canvas;
#endif
}

bool FrameOutputs::finish(bool quiet) {
  bool ok = true;
  if (poses_) {
    poses_->flush();
    if (const std::string e = poses_->error(); !e.empty()) {
      std::cerr << "error: " << e << "\n";
      ok = false;
    }
    if (!quiet)
      std::cout << poses_->written() << " poses written to " << spec_.dump_poses
                << (poses_->dropped() ? " (" + std::to_string(poses_->dropped()) + " dropped: the disk was slower than the show)" : "")
                << std::endl;
  }
#ifdef MARIONETTE_HAVE_PIPEWIRE
  if (pipewire_ && !quiet)
    std::cout << "PipeWire node " << pipewire_->node_name() << ": " << pipewire_->sent() << " frames sent, " << pipewire_->dropped()
              << " dropped (" << pipewire_->state() << ")" << std::endl;
#endif
  return ok;
}

std::string FrameOutputs::stats_json() const {
  using nlohmann::json;
  json j = {{"pose_dump", poses_ ? json{{"written", poses_->written()}, {"dropped", poses_->dropped()}, {"waits", poses_->waits()}} : json()},
            {"pipewire", json()}};
#ifdef MARIONETTE_HAVE_PIPEWIRE
  if (pipewire_)
    j["pipewire"] = {{"node", pipewire_->node_name()},
                     {"pushed", pipewire_->pushed()},
                     {"sent", pipewire_->sent()},
                     {"dropped", pipewire_->dropped()},
                     {"state", pipewire_->state()}};
#endif
  return j.dump();
}

}  // namespace mar
