#include "fsm/machines/documented_machines.hpp"

#include <array>
#include <cstring>

#include "fsm/machines/joint_status_dfa.hpp"

namespace rescue::fsm {
namespace {

constexpr std::array<MachineView, 1> kMachines{{
    ViewOf<JointStatusDfa>::view(),
}};

}  // namespace

Span<const MachineView> documented_machines() noexcept { return {kMachines}; }

const MachineView* find_documented_machine(const char* name) noexcept {
  if (name == nullptr) return nullptr;
  for (const MachineView& m : kMachines) {
    if (std::strcmp(m.name, name) == 0) return &m;
  }
  return nullptr;
}

}  // namespace rescue::fsm
