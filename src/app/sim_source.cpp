#include "app/sim_source.h"

namespace mar {

SimSource::SimSource(SimDevice& sim, const DeviceSpec& spec, uint16_t source, int64_t debounce_ns)
    : Backend(spec, source), sim_(&sim), debounce_ns_(debounce_ns) {}

DeviceState SimSource::open() {
  config_ = sim_->decoder_config();
  config_.gpio.debounce_ns = debounce_ns_;
  identity_ = std::string("simulated ") + sim_->kind();
  problem_.clear();
  return DeviceState::Connected;
}

bool SimSource::poll(int64_t now_ns, WireSink& out) {
  // Simulated time is show time: the timeline's records are already on the show clock.
  sim_->drain(now_ns, [&](const WireRecord& rec) {
    WireRecord r = rec;
    r.source = source_;
    emit(r, out);
  });
  return true;
}

}  // namespace mar
