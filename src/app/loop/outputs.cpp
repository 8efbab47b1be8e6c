#include "app/loop/outputs.h"

#include "output/png_dump.h"
#include "output/pose_dump.h"
#ifdef MARIONETTE_HAVE_PIPEWIRE
#include "output/pipewire_out.h"
#endif
#ifdef MARIONETTE_HAVE_VIDEO
#include "output/video_out.h"
#endif

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>

namespace mar {

#ifndef MARIONETTE_HAVE_PIPEWIRE
class PipeWireOut {};  // built without it (-DMARIONETTE_WITH_PIPEWIRE=OFF)
#endif
#ifndef MARIONETTE_HAVE_VIDEO
class VideoOut {};  // built without it (-DMARIONETTE_WITH_VIDEO=OFF)
#endif

std::string check_video_take(const std::string& path, const std::string& codec) {
  if (path.empty()) return "";
#ifdef MARIONETTE_HAVE_VIDEO
  if (!video_codec_known(codec)) return "unknown codec '" + codec + "'; --codec is one of " + video_codecs();
  return "";
#else
  (void)codec;
  return path + ": this marionette was built without video takes (-DMARIONETTE_WITH_VIDEO=ON, Debian packages libavcodec-dev libavformat-dev libswscale-dev)";
#endif
}

void OutputsSpec::set_osc(const ShowConfig& show, const Rig& rig) {
  osc = show.osc_out.port > 0;
  if (!osc) return;
  osc_options = {show.osc_out.host, show.osc_out.port, show.osc_out.rate, show.osc_out.prefix};
  osc_layout = {};
  for (const RigHandle& h : rig.handles) osc_layout.handles.push_back(h.name);
  for (const RigKey& k : rig.keys) osc_layout.keys.push_back(k.name);
  for (const RigSwap& w : rig.swaps) {
    osc_layout.swaps.push_back(w.name);
    osc_layout.swap_members.push_back(w.members);
  }
  for (const RigTrigger& t : rig.triggers) osc_layout.triggers.push_back(t.name);
  for (const auto& d : show.devices) osc_layout.devices.push_back(d.name);
}

void OutputsSpec::set_osc(const ShowConfig& show, const std::vector<const Rig*>& rigs, const std::vector<std::string>& names) {
  osc = show.osc_out.port > 0;
  if (!osc) return;
  osc_options = {show.osc_out.host, show.osc_out.port, show.osc_out.rate, show.osc_out.prefix};
  ShowStateLayout& l = osc_layout;
  l = {};
  for (size_t c = 0; c < rigs.size(); ++c) {
    for (const RigHandle& h : rigs[c]->handles) {
      l.handles.push_back(h.name);
      l.handle_who.push_back(names[c]);
    }
    for (const RigKey& k : rigs[c]->keys) {
      l.keys.push_back(k.name);
      l.key_who.push_back(names[c]);
    }
    for (const RigSwap& w : rigs[c]->swaps) {
      l.swaps.push_back(w.name);
      l.swap_members.push_back(w.members);
      l.swap_who.push_back(names[c]);
    }
    for (const RigTrigger& t : rigs[c]->triggers) {
      l.triggers.push_back(t.name);
      l.trigger_who.push_back(names[c]);
    }
  }
  for (const std::string& n : names) {  // (after the rigs', as the show's triggers are)
    l.triggers.push_back("on-stage");
    l.trigger_who.push_back(n);
  }
  for (const auto& d : show.devices) l.devices.push_back(d.name);
}

FrameOutputs::FrameOutputs() = default;
FrameOutputs::~FrameOutputs() = default;

std::string FrameOutputs::relayout(const OutputsSpec& s, const Character& ch) {
  OutputsSpec next = spec_;
  next.osc = s.osc;
  next.osc_options = s.osc_options;
  next.osc_layout = s.osc_layout;
  osc_.reset();
  return open(next, ch);
}

std::string FrameOutputs::open(const OutputsSpec& s, const Character& ch) {
  spec_ = s;
  spec_.every = std::max(1, s.every);
  finished_ = false;
  if (!s.dump_poses.empty() && !poses_) {
    auto d = PoseDump::open(s.dump_poses, ch, s.lossless);
    if (!d.ok()) return d.error;
    poses_ = std::move(*d.value);
  }
  if (!s.dump_dir.empty() && !pngs_) pngs_ = std::make_unique<PngDump>(s.dump_dir, s.width, s.height, s.factor, s.lossless);
  if (!s.video.empty() && !video_) {
#ifdef MARIONETTE_HAVE_VIDEO
    VideoOptions o;
    o.path = s.video;
    o.codec = s.codec;
    o.width = s.width;
    o.height = s.height;
    o.factor = s.factor;
    o.rate = s.rate;
    o.lossless = s.lossless;
    auto v = VideoOut::open(o);
    if (!v.ok()) return v.error;
    video_ = std::move(*v.value);
#else
    return check_video_take(s.video, s.codec);
#endif
  }
  if (s.osc && !osc_) {
    std::string err;
    osc_ = OscOut::open(s.osc_options, s.osc_layout, &err);
    if (!osc_) return s.show_path + ": " + err;
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

double FrameOutputs::waited_us() const {
  double w = pngs_ ? pngs_->waited_us() : 0;
#ifdef MARIONETTE_HAVE_VIDEO
  if (video_) w += video_->waited_us();
#endif
  return w;
}

double FrameOutputs::frame(uint64_t n, int64_t t_ns, const Puppet& p, Canvas& canvas, const FrameState& state) {
  if (poses_) {  // the writer's thread formats it
    if (state.shapes.empty()) poses_->push(double(t_ns) * 1e-9, p.shapes, p.shown);
    else poses_->push(double(t_ns) * 1e-9, state.shapes, state.shown);
  }
  if (osc_) {  // the newest state to the sender's thread (a triple buffer)
    ShowState& s = osc_->state();
    s.frame = n;
    s.t = double(t_ns) * 1e-9;
    if (!state.handles.empty())
      for (size_t h = 0; h < s.handles.size() && h < state.handles.size(); ++h) s.handles[h] = state.handles[h];
    else
      for (size_t h = 0; h < s.handles.size() && h < p.solver->handle_count(); ++h) s.handles[h] = p.solver->handle_point(h);
    for (size_t k = 0; k < s.keys.size() && k < state.keys.size(); ++k) s.keys[k] = state.keys[k];
    for (size_t k = 0; k < s.swaps.size() && k < state.swaps.size(); ++k) s.swaps[k] = state.swaps[k];
    for (size_t k = 0; k < s.triggers.size() && k < state.triggers.size(); ++k) s.triggers[k] = uint8_t(state.triggers[k] != 0);
    for (size_t k = 0; k < s.devices.size() && k < state.devices.size(); ++k) s.devices[k] = uint8_t(state.devices[k]);
    if (state.latency_ms >= 0) latency_ms_ = state.latency_ms;
    s.frame_ms = state.frame_ms;
    s.latency_ms = latency_ms_;
    osc_->publish();
  }
  const bool png = pngs_ && n % uint64_t(spec_.every) == 0;
  if (!png && !video_ && !pipewire_) return 0;
  const auto start = std::chrono::steady_clock::now();
  const double waited = waited_us();
  const PixelTarget px = canvas.pixels();  // (a GPU canvas is read back here)
  if (png) pngs_->push(px.px, px.stride, n, t_ns);
#ifdef MARIONETTE_HAVE_VIDEO
  if (video_) video_->push(px.px, px.stride, n, t_ns);
#endif
#ifdef MARIONETTE_HAVE_PIPEWIRE
  if (pipewire_) pipewire_->push(px.px, px.stride, n, t_ns);
#endif
  const double us = std::max(0.0, std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count() - (waited_us() - waited));
  handover_.add(us);
  return us;
}

bool FrameOutputs::finish(bool quiet) {
  if (finished_) return true;
  finished_ = true;
  bool ok = true;
  auto failed = [&](const std::string& e) {
    if (e.empty()) return;
    std::cerr << "error: " << e << "\n";
    ok = false;
  };
  auto dropped = [](uint64_t n, const char* why) { return n ? " (" + std::to_string(n) + " dropped: " + why + ")" : std::string(); };
  if (poses_) {
    poses_->flush();
    failed(poses_->error());
    if (!quiet)
      std::cout << poses_->written() << " poses written to " << spec_.dump_poses << dropped(poses_->dropped(), poses_->error().empty() ? "the disk was slower than the show" : "the file could not be written")
                << std::endl;
  }
  if (pngs_) {
    pngs_->flush();
    failed(pngs_->error());
    if (!quiet) std::cout << pngs_->written() << " frames written to " << spec_.dump_dir << dropped(pngs_->dropped(), pngs_->error().empty() ? "the disk was slower than the show" : "a file could not be written") << std::endl;
  }
#ifdef MARIONETTE_HAVE_VIDEO
  if (video_) {
    video_->finish();
    failed(video_->error());
    if (!quiet)
      std::cout << video_->written() << " frames encoded (" << spec_.codec << ") to " << spec_.video
                << dropped(video_->dropped(), video_->error().empty() ? "the encoder was slower than the show" : "the file could not be written") << std::endl;
  }
#endif
  if (osc_) {
    osc_->stop();
    if (!quiet)
      std::cout << "OSC out to " << osc_->options().host << ":" << osc_->options().port << ": " << osc_->messages() << " messages in "
                << osc_->bundles() << " bundles" << (osc_->send_errors() ? ", " + std::to_string(osc_->send_errors()) + " sends failed" : "")
                << std::endl;
  }
#ifdef MARIONETTE_HAVE_PIPEWIRE
  if (pipewire_ && !quiet)
    std::cout << "PipeWire node " << pipewire_->node_name() << ": " << pipewire_->sent() << " frames sent, " << pipewire_->dropped()
              << " dropped (" << pipewire_->state() << ")" << std::endl;
#endif
  return ok;
}

void FrameOutputs::add_stats(nlohmann::json& j) const {
  using nlohmann::json;
  j.update(json{{"pose_dump", poses_ ? json{{"written", poses_->written()}, {"dropped", poses_->dropped()}, {"waits", poses_->waits()}} : json()},
            {"frame_dump", pngs_ ? json{{"written", pngs_->written()}, {"dropped", pngs_->dropped()}, {"waits", pngs_->waits()},
                                        {"writer_ms_per_frame", pngs_->written() ? pngs_->writer_us() * 1e-3 / double(pngs_->written()) : 0.0}}
                                 : json()},
            {"video", json()},
            {"pipewire", json()},
            {"osc_out", osc_ ? json{{"to", osc_->options().host + ":" + std::to_string(osc_->options().port)},
                                    {"messages", osc_->messages()},
                                    {"bundles", osc_->bundles()},
                                    {"send_errors", osc_->send_errors()}}
                             : json()},
            {"outputs_handover_us",
             {{"frames", handover_.count()}, {"p50", handover_.quantile(0.5)}, {"p99", handover_.quantile(0.99)}, {"max", handover_.max()}}}});
#ifdef MARIONETTE_HAVE_VIDEO
  if (video_)
    j["video"] = {{"file", spec_.video}, {"codec", spec_.codec}, {"pushed", video_->pushed()}, {"written", video_->written()},
                  {"dropped", video_->dropped()}, {"waits", video_->waits()}};
#endif
#ifdef MARIONETTE_HAVE_PIPEWIRE
  if (pipewire_)
    j["pipewire"] = {{"node", pipewire_->node_name()},
                     {"pushed", pipewire_->pushed()},
                     {"sent", pipewire_->sent()},
                     {"dropped", pipewire_->dropped()},
                     {"state", pipewire_->state()}};
#endif
}

}  // namespace mar
