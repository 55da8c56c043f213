// The in-process loopback NIC: hal::Nic over a SimulatedSegment, on the caller's clock (virtual time
// in tests and `run --nic sim`). A frame sent at time t leaves when the wire is free (frames are
// serialised at 100 Mbit/s with the inter-frame gap), goes through the segment, and can be received
// once its last bit is back: its round trip is the segment's cable, PHY and ESC delays plus its own
// length on the wire, as on a real network. receive() sleeps on the clock until then (a virtual
// clock just jumps), so an hour of robot time runs in seconds. On the wall clock a sleep of a few
// microseconds costs a wake-up (tens to hundreds of microseconds on a loaded host): with a
// receive spin, a frame due back within it is waited for by reading the clock, as a master's raw
// socket spins (hal::RawSocketSettings::receive_spin), so the simulated robot answers as fast in
// wall time as the model says.
//
// On a ring segment two of them (SimulatedNicPair) stand for the master's two ports: a frame sent on
// one goes into the segment from that master port and is received on whichever NIC it comes back
// to (the ring closed: the other one).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "ecat/codec/frame.hpp"
#include "hal/time/clock.hpp"
#include "hal/net/nic.hpp"

namespace rescue::drivers {

class SimulatedNic final : public hal::Nic {
 public:
  // Frames on their way back at once (a NIC's receive ring); more are dropped and counted.
  static constexpr std::size_t kQueueDepth = 16;
  static constexpr std::size_t kMaxFrame = ecat::kMaxFrameSize + ecat::kVlanTagSize;

  // `receive_spin`: a frame due back at most this long from now is waited for by reading the clock
  // (0: always sleep; the only sensible value on a virtual clock).
  SimulatedNic(SimulatedSegment& segment, hal::Clock& clock, hal::Nanoseconds receive_spin = 0) noexcept
      : segment_(segment), clock_(clock), receive_spin_(receive_spin) {}
  // One port of a SimulatedNicPair.
  SimulatedNic(SimulatedSegment& segment, hal::Clock& clock, MasterPort port, hal::Nanoseconds receive_spin) noexcept
      : segment_(segment), clock_(clock), receive_spin_(receive_spin), port_(port) {}

  Status send(ConstByteSpan frame) noexcept override;
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override;
  hal::Clock& clock() noexcept override { return clock_; }
  const char* name() const noexcept override { return port_ == MasterPort::ring ? "sim-ring" : "sim"; }
  hal::NicStats stats() const noexcept override { return stats_; }

  SimulatedSegment& segment() noexcept { return segment_; }
  MasterPort port() const noexcept { return port_; }

 private:
  friend class SimulatedNicPair;
  // Paired: the frame goes round the segment in `scratch_` and is queued on the NIC it comes back to.
  void send_paired(ConstByteSpan frame, hal::Nanoseconds sent_at) noexcept;
  void enqueue(ConstByteSpan frame, hal::Nanoseconds ready_at) noexcept;

  struct Pending {
    std::array<std::uint8_t, kMaxFrame> bytes{};
    std::size_t length{0};
    hal::Nanoseconds ready_at{0};
  };

  SimulatedSegment& segment_;
  void wait_until(hal::Nanoseconds at) noexcept;
  static constexpr unsigned kSpinReadsOfAStillClock = 64;  // then the clock is virtual: sleep_until moves it

  hal::Clock& clock_;
  hal::Nanoseconds receive_spin_{0};
  std::array<Pending, kQueueDepth> queue_{};
  std::size_t head_{0};
  std::size_t count_{0};
  hal::Nanoseconds wire_free_at_{0};
  hal::NicStats stats_{};
  MasterPort port_{MasterPort::main};
  SimulatedNic* peer_{nullptr};
  std::array<std::uint8_t, kMaxFrame> scratch_{};
};

// The master's two ports on a ring segment (SimulatedSegment::build_ring, the simulated robot with
// RobotSegmentOptions::ring): main() sends into the first ESC's port 0, ring() into the ring
// cable's ESC; each receives the frames that come back on its port. One segment, one clock.
// status() refuses a segment without a ring cable (the ring NIC would never see a frame).
class SimulatedNicPair {
 public:
  SimulatedNicPair(SimulatedSegment& segment, hal::Clock& clock, hal::Nanoseconds receive_spin = 0) noexcept;
  SimulatedNicPair(const SimulatedNicPair&) = delete;
  SimulatedNicPair& operator=(const SimulatedNicPair&) = delete;
  SimulatedNicPair(SimulatedNicPair&&) = delete;
  SimulatedNicPair& operator=(SimulatedNicPair&&) = delete;
  ~SimulatedNicPair() = default;

  const Status& status() const noexcept { return status_; }
  SimulatedNic& main() noexcept { return main_; }
  SimulatedNic& ring() noexcept { return ring_; }

 private:
  SimulatedNic main_;
  SimulatedNic ring_;
  Status status_;
};

}  // namespace rescue::drivers
