#include "drivers/sim/segment/simulated_robot.hpp"

#include <array>

namespace rescue::drivers {
SimulatedRobot::SimulatedRobot(const RobotSegmentOptions& options, hal::Nanoseconds now) noexcept : spare_(JunctionDevice::Spare{kSpareSerial}) {
  std::array<SegmentSlave, kSlaveCount + 1> slaves{};
  status_ = describe_robot_segment(Span<SlaveDevice* const>(devices_.devices()), options, Span<SegmentSlave>(slaves.data(), kSlaveCount));
  SegmentSlave& spare = slaves[kSparePosition];
  spare.name = kSpareName;
  spare.upstream = static_cast<std::uint8_t>(kSlaveCount - 1);
  spare.upstream_port = 1;
  spare.esc = junction_esc_config();
  spare.link_delay_ns = kPhyPairDelayNs + 5;
  spare.device = &spare_;
  const std::size_t count = options.spare_slave ? kSlaveCount + 1 : kSlaveCount;
  if (status_.ok() && options.ring && options.spare_slave) {
    status_ = make_error(Errc::invalid_argument, "no spare slave in the ring configuration (the ring cable takes its port)");
  }
  if (status_.ok() && options.ring) {
    status_ = segment_.build_ring(Span<const SegmentSlave>(slaves.data(), kSlaveCount), robot_ring_cable(), now);
  } else if (status_.ok()) {
    status_ = segment_.build(Span<const SegmentSlave>(slaves.data(), count), now);
  }
  if (status_.ok() && options.spare_slave) status_ = segment_.set_power(kSparePosition, false, now);
}

}  // namespace rescue::drivers
