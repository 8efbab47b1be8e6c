#include "app/loop/run_stats.h"

namespace mar {

const char* stage_name(Stage s) {
  static constexpr const char* kNames[] = {"inputs", "map", "poses", "motion", "solve", "render", "present"};
  return s < Stage::Count ? kNames[size_t(s)] : "?";
}

}  // namespace mar
