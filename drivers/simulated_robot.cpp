#include "drivers/simulated_robot.hpp"

#include <array>

namespace rescue::drivers {

SimulatedRobot::SimulatedRobot(const RobotSegmentOptions& options, hal::Nanoseconds now) noexcept {
  for (std::size_t j = 0; j < kJointCount; ++j) (void)drives_.emplace_back(slave_position_of_joint(j));
  std::array<SlaveDevice*, kSlaveCount> devices{};
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (kSlaves[p].kind == SlaveKind::junction) {
      devices[p] = junctions_.emplace_back(p);
    } else {
      devices[p] = &drives_[kSlaves[p].joint];
    }
  }
  std::array<SegmentSlave, kSlaveCount> slaves{};
  status_ = describe_robot_segment(Span<SlaveDevice* const>(devices), options, Span<SegmentSlave>(slaves));
  if (status_.ok()) status_ = segment_.build(Span<const SegmentSlave>(slaves), now);
}

}  // namespace rescue::drivers
