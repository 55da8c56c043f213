#include "core/app/sim/simulated_robot_instance.hpp"

namespace rescue::app {

drivers::SimulatedRobot& simulated_robot(hal::Nanoseconds now) noexcept {
  // Static storage: about a megabyte of ESC memories, never on a stack, never on the heap.
  // With the spare slave, so `sim --iface` and `run --nic sim` take the fault command `extra-slave`.
  static drivers::SimulatedRobot robot(drivers::RobotSegmentOptions{1, 100.0, true}, now);
  return robot;
}

Result<std::size_t> SegmentFrameProcessor::process(ByteSpan frame, hal::Nanoseconds arrival) noexcept {
  const Result<drivers::FrameOutcome> outcome = segment_.process(frame, arrival);
  if (!outcome.ok()) return outcome.error();
  if (!outcome.value().returned) return make_error(Errc::not_found, "frame lost in the segment");
  return frame.size();
}

}  // namespace rescue::app
