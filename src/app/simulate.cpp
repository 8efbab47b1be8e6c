#include "app/simulate.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

namespace mar {
namespace {
SimulationFactory g_factory = nullptr;
}  // namespace

void set_simulation_factory(SimulationFactory f) { g_factory = f; }
bool simulation_available() { return g_factory != nullptr; }

std::unique_ptr<HardwareSimulation> make_simulation(std::string* error) {
  if (!g_factory) {
    *error = "--simulate needs the virtual bench: run it through marionette-simulate";
    return nullptr;
  }
  return g_factory(error);
}

int exec_simulator(char** argv) {
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const auto sim = self.parent_path() / "marionette-simulate";
  if (ec || !std::filesystem::exists(sim)) {
    std::cerr << "error: --simulate runs through marionette-simulate, which is not installed beside "
              << (ec ? std::string("this program") : self.string()) << "\n";
    return 1;
  }
  const std::string path = sim.string();
  argv[0] = const_cast<char*>(path.c_str());
  ::execv(path.c_str(), argv);
  std::cerr << "error: cannot run " << path << ": " << std::strerror(errno) << "\n";
  return 1;
}

}  // namespace mar
