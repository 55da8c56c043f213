// The program's one simulated robot (drivers/sim/segment/simulated_robot.hpp) in static storage, shared by
// `run --nic sim` (the loopback NIC) and `sim --iface` (served on a raw socket), and the adapter
// that lets the frame server push frames through its segment.
#pragma once

#include <cstddef>

#include "core/app/sim/frame_server.hpp"
#include "core/base/result.hpp"
#include "drivers/sim/segment/simulated_robot.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

// Built on first use with the segment's time starting at `now` (later calls ignore `now`).
drivers::SimulatedRobot& simulated_robot(hal::Nanoseconds now) noexcept;

class SegmentFrameProcessor final : public FrameProcessor {
 public:
  explicit SegmentFrameProcessor(drivers::SimulatedSegment& segment) noexcept : segment_(segment) {}
  std::size_t slave_count() const noexcept override { return segment_.slave_count(); }
  // A frame the segment loses (cut cable, open port, fault) is an error: nothing goes back.
  Result<std::size_t> process(ByteSpan frame, hal::Nanoseconds arrival) noexcept override;
  // The ESCs' clocks, SYNC0 pulses and devices run up to `now`.
  void idle(hal::Nanoseconds now) noexcept override { segment_.advance_to(now); }

 private:
  drivers::SimulatedSegment& segment_;
};

}  // namespace rescue::app
