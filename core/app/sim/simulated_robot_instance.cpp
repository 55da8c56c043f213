#include "core/app/sim/simulated_robot_instance.hpp"

namespace rescue::app {

drivers::SimulatedRobot& simulated_robot(hal::Nanoseconds now) noexcept {
  // Static storage: about a megabyte of ESC memories, never on a stack, never on the heap.
  // With the spare slave, so `sim --iface` and `run --nic sim` take the fault command `extra-slave`.
  static drivers::SimulatedRobot robot(drivers::RobotSegmentOptions{1, 100.0, true}, now);
  return robot;
}

drivers::SimulatedRobot& simulated_ring_robot(hal::Nanoseconds now) noexcept {
  drivers::RobotSegmentOptions options{1, 100.0, false};
  options.ring = true;
  static drivers::SimulatedRobot robot(options, now);
  return robot;
}

Result<std::size_t> RingPortFrameProcessor::process(ByteSpan frame, hal::Nanoseconds arrival) noexcept {
  const Result<drivers::FrameOutcome> outcome = segment_.process(frame, arrival, port_);
  if (!outcome.ok()) return outcome.error();
  if (!outcome.value().returned) return make_error(Errc::not_found, "frame lost in the segment");
  if (outcome.value().port == port_) return frame.size();
  mark_processed_by_esc(frame);
  if (other_port_.send(ConstByteSpan(frame.data(), frame.size())).ok()) {
    ++crossed_;
  } else {
    ++crossed_send_errors_;
  }
  return make_error(Errc::not_found, "frame came back on the other port");
}

Result<std::size_t> SegmentFrameProcessor::process(ByteSpan frame, hal::Nanoseconds arrival) noexcept {
  const Result<drivers::FrameOutcome> outcome = segment_.process(frame, arrival);
  if (!outcome.ok()) return outcome.error();
  if (!outcome.value().returned) return make_error(Errc::not_found, "frame lost in the segment");
  return frame.size();
}

}  // namespace rescue::app
