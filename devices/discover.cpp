#include "devices/discover.h"

#include "devices/backends.h"

namespace mar {

std::vector<BackendReport> discover_devices(const std::vector<ProfileId>& profiles) {
  std::vector<BackendReport> out;
  for (const BackendInfo& b : backend_table()) {
    if (!b.built) {
      out.push_back({b.type, not_built_text(b), {}});
      continue;
    }
    if (b.discover) out.push_back(b.discover(profiles));
    else out.push_back({b.type, b.note, {}});
  }
  return out;
}

}  // namespace mar
