#include "drivers/sim/segment/simulated_robot.hpp"

#include <array>

namespace rescue::drivers {

SimulatedRobot::SimulatedRobot(const RobotSegmentOptions& options, hal::Nanoseconds now) noexcept {
  std::array<SegmentSlave, kSlaveCount> slaves{};
  status_ = describe_robot_segment(Span<SlaveDevice* const>(devices_.devices()), options, Span<SegmentSlave>(slaves));
  if (status_.ok()) status_ = segment_.build(Span<const SegmentSlave>(slaves), now);
}

}  // namespace rescue::drivers
