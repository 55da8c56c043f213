#include "core/app/tasks/joint_demand.hpp"

namespace rescue::app {

RobotDemand demand_of(const JointManager& manager) noexcept {
  RobotDemand demand{};
  const auto& statuses = manager.statuses();
  for (std::size_t j = 0; j < kJointCount; ++j) {
    const JointStatus& s = statuses[j];
    demand[j].enable = s.drive_enabled && !s.lost;
    demand[j].mode = static_cast<std::int8_t>(s.mode);
    demand[j].position_counts = s.reference_position_counts;
  }
  return demand;
}

}  // namespace rescue::app
