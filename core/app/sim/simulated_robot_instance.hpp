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
// The robot in its ring configuration (core/robot/robot_ring.hpp; no spare slave), for
// `sim --ring-iface` and a redundant master on the in-process NICs (drivers::SimulatedNicPair).
drivers::SimulatedRobot& simulated_ring_robot(hal::Nanoseconds now) noexcept;

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

// One master port of a ring segment, served on its own interface (`sim --iface A --ring-iface B`):
// a frame received there enters the segment from that port. One that comes back on this port is
// handed back to the server; one that comes back on the other port (the ring closed) is marked and
// sent out of the other port's interface here, and the server counts it as not returned on its own.
class RingPortFrameProcessor final : public FrameProcessor {
 public:
  RingPortFrameProcessor(drivers::SimulatedSegment& segment, drivers::MasterPort port, hal::Nic& other_port) noexcept
      : segment_(segment), port_(port), other_port_(other_port) {}
  std::size_t slave_count() const noexcept override { return segment_.slave_count(); }
  Result<std::size_t> process(ByteSpan frame, hal::Nanoseconds arrival) noexcept override;
  void idle(hal::Nanoseconds now) noexcept override { segment_.advance_to(now); }
  // Frames that came back on the other port and were sent there, or could not be.
  std::uint64_t sent_on_other_port() const noexcept { return crossed_; }
  std::uint64_t other_port_send_errors() const noexcept { return crossed_send_errors_; }

 private:
  drivers::SimulatedSegment& segment_;
  drivers::MasterPort port_;
  hal::Nic& other_port_;
  std::uint64_t crossed_{0};
  std::uint64_t crossed_send_errors_{0};
};

}  // namespace rescue::app
