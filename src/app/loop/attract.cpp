#include "app/loop/attract.h"

#include "app/loop/recording.h"

#include <algorithm>

namespace mar {

bool AttractClock::step(double dt, bool input) {
  const double rate = fade_ > 0 ? dt / fade_ : 1.0;  // linear ramp per frame
  idle_ = input ? 0 : idle_ + dt;
  switch (state_) {
    case State::Live:
      if (idle_ < after_ || input) return false;
      state_ = State::FadeIn;
      ramp_ = std::min(1.0, rate);
      if (ramp_ >= 1) state_ = State::Playing;
      return true;
    case State::FadeIn:
    case State::Playing:
      if (input) {  // the visitor takes over from wherever the fade is
        state_ = State::FadeOut;
        ramp_ = std::max(0.0, ramp_ - rate);
        if (ramp_ <= 0) state_ = State::Live;
        return false;
      }
      ramp_ = std::min(1.0, ramp_ + rate);
      if (ramp_ >= 1) state_ = State::Playing;
      return false;
    case State::FadeOut:
      ramp_ = std::max(0.0, ramp_ - rate);
      if (ramp_ <= 0) state_ = State::Live;
      return false;
  }
  return false;
}

double AttractClock::weight() const {
  const double s = ramp_;
  return s * s * (3 - 2 * s);
}

Result<std::unique_ptr<Attract>> Attract::make(const AttractConfig& c, const Mapping& fresh, const std::string& sim_kind,
                                               const std::string& descriptor, uint16_t source, int64_t debounce_ns) {
  using R = Result<std::unique_ptr<Attract>>;
  std::unique_ptr<Attract> a(new Attract(c, fresh));
  a->events_.resize(1024);
  if (!c.take.empty()) {
    auto p = Playback::open(c.take);
    if (!p.ok()) return R::failure(p.error);
    std::vector<WireRecord> wires;
    int64_t t = 0, t0 = -1;
    int iterations = 0;
    std::string error;
    const auto on_device = [&](uint16_t src, std::span<const uint8_t> description) {
      if (src >= 256 || !error.empty()) return;
      if (a->take_decoders_.size() <= src) a->take_decoders_.resize(src + 1u);
      if (a->take_decoders_[src]) return;  // a source's first connection decodes the whole take
      auto cfg = DecoderConfig::parse(description);
      if (!cfg.ok()) error = c.take + ": device " + std::to_string(src) + ": " + cfg.error;
      else a->take_decoders_[src] = make_decoder(*cfg.value, src, &error);
    };
    while ((*p.value)->next_frame(wires, t, iterations, on_device)) {
      if (t0 < 0) t0 = t;
      for (WireRecord r : wires) {
        if (a->take_.size() == kMaxTakeRecords)
          return R::failure(c.take + ": more than " + std::to_string(kMaxTakeRecords) + " records (the limit of a take)");
        r.t_ns = std::max<int64_t>(0, r.t_ns - t0);
        a->take_.push_back(r);
      }
      a->take_ns_ = t - t0;
    }
    if (!error.empty()) return R::failure(error);
    if (a->take_.empty()) return R::failure(c.take + ": the take has no input records to play");
    std::stable_sort(a->take_.begin(), a->take_.end(),
                     [](const WireRecord& x, const WireRecord& y) { return x.t_ns < y.t_ns; });
    a->take_ns_ = std::max({a->take_ns_, a->take_.back().t_ns + 1, int64_t(10'000'000)});
    return R::success(std::move(a));
  }
  auto sim = make_sim_device(sim_kind, descriptor, 0, 1);
  if (!sim.ok()) return R::failure(sim.error);
  if (auto ok = (*sim.value)->load_script(c.script); !ok.ok()) return R::failure("script " + ok.error);
  SimDevice& s = **sim.value;
  s.set_loop(c.loop > 0 ? c.loop : double(s.end_ns()) * 1e-9 + 1.0);
  s.finish();
  DecoderConfig cfg = s.decoder_config();
  cfg.gpio.debounce_ns = debounce_ns;
  std::string error;
  a->decoder_ = make_decoder(cfg, source, &error);
  if (!a->decoder_) return R::failure(error);
  a->sim_ = std::move(*sim.value);
  return R::success(std::move(a));
}

void Attract::play(int64_t until_ns) {
  EventSink ev{events_.data(), events_.size()};
  if (sim_) {
    sim_->drain(until_ns, [&](const WireRecord& r) { decoder_->feed(r, ev); });
    decoder_->settle(until_ns, ev);
  } else {
    for (;;) {
      if (next_ == take_.size()) {  // the take loops; after a stall, at most 64 periods are replayed
        next_ = 0;
        offset_ns_ += take_ns_;
        if (const int64_t behind = (until_ns - offset_ns_) / take_ns_; behind > 64) offset_ns_ += (behind - 64) * take_ns_;
      }
      const WireRecord& r = take_[next_];
      if (r.t_ns + offset_ns_ > until_ns) break;
      WireRecord at = r;
      at.t_ns += offset_ns_;
      if (r.source < take_decoders_.size() && take_decoders_[r.source]) take_decoders_[r.source]->feed(at, ev);
      ++next_;
    }
    for (auto& d : take_decoders_)
      if (d) d->settle(until_ns, ev);
  }
  for (size_t i = 0; i < ev.n; ++i) mapping_.apply(events_[i]);
}

void Attract::step(double dt, bool input) {
  const bool was_shown = clock_.shown();
  const AttractClock::State before = clock_.state();
  if (clock_.step(dt, input)) {
    // From the beginning: the take or script and the attract's controls as the show loaded them.
    ++starts_;
    mapping_ = fresh_;
    t_ns_ = 0;
    next_ = 0;
    offset_ns_ = 0;
    if (sim_) sim_->rewind();
  }
  if (input && (before == AttractClock::State::FadeIn || before == AttractClock::State::Playing)) ++handovers_;
  if (!clock_.shown() && !was_shown) return;
  t_ns_ += int64_t(dt * 1e9);
  shown_s_ += dt;
  play(t_ns_);
  mapping_.update(dt);
}

}  // namespace mar
