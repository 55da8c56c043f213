// The ring's state, from each cycle's returning copies (pure logic; docs/redundancy.md, "The ring
// state"). With a ring NIC (cable redundancy, ecat/link/redundant_merge.hpp) each cyclic frame
// carries a BRD of the DL status (0x0110): every slave a copy passes through its processing unit
// adds 1 to that copy's working counter. So one returned frame says, for a segment of n slaves in
// processing order:
//   closed  the main copy came back on the ring NIC (it went through every slave and out at the
//           far end);
//   open    the main copy reached the first m slaves (its BRD counter), the ring copy the last r,
//           m + r = n: the break lies between segment position m - 1 and m (slave "before" and
//           "after"; the master's own port when m = 0 or r = 0);
//   lost    m + r < n: positions m .. n - r - 1 are reachable from neither port (two breaks).
// No copy back is no evidence (the state stays), nor are copies that contradict each other (a cable
// changed while the frame was in flight: one copy went round the closed ring, the other turned at a
// break). Each change of state or place is reported once: `opened` (the place), `split` (the
// unreachable slaves), `closed` (the place repaired). The decision is the cycle's own: a cut shows
// in the first frame after it; slaves reachable from neither port only when a second frame in a row
// shows the same (one copy lost in flight looks like that for one frame). The DL status of the two
// slaves beside the break (read by the ring service while the ring is not closed) names the port
// whose link is down; it confirms the place and is shown to the operator, it does not decide.
// Losses of slaves stay the link monitor's (link_monitor.hpp): it counts the merged working
// counters, so only a slave reachable from neither port is short in them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/containers/ring_buffer.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/link/redundant_merge.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {

enum class RingState : std::uint8_t {
  none,    // no ring NIC: a single-port master
  closed,  // every slave reachable from both ports
  open,    // one break: every slave reachable from one port
  lost,    // slaves reachable from neither port (two breaks or more)
};
const char* to_string(RingState state) noexcept;

// A place on the ring: a planned slave position, or one of the master's ports.
constexpr std::uint8_t kMainPort = 0xFE;
constexpr std::uint8_t kRingPort = 0xFD;

struct RingStatus {
  RingState state{RingState::none};
  // open / lost: the last slave reached from the main port and the first reached from the ring port
  // (planned positions, or kMainPort / kRingPort when the break is at the master's port).
  std::uint8_t before{kMainPort};
  std::uint8_t after{kRingPort};
  SlaveMask unreachable{0};  // lost: reachable from neither port (planned positions)
  std::uint16_t reached_main{0};  // slaves the main copy reached (last evidence)
  std::uint16_t reached_ring{0};  // ... the ring copy
  std::uint64_t since_cycle{0};   // the cycle whose frame showed this state
  // The DL status (0x0110) of `before` and `after` as last read while the ring was not closed.
  bool before_dl_read{false};
  bool after_dl_read{false};
  std::uint16_t before_dl_status{0};
  std::uint16_t after_dl_status{0};
  std::uint64_t breaks{0};   // transitions out of closed
  std::uint64_t repairs{0};  // transitions back to closed
  // Frames whose returns were no evidence of a still ring: a cable changing while the frame was in
  // flight (copies that contradict each other), or slaves reachable from neither port shown by one
  // frame only.
  std::uint64_t transients{0};
};

enum class RingEventKind : std::uint8_t { opened, split, closed };
const char* to_string(RingEventKind kind) noexcept;

struct RingReport {
  RingEventKind kind{RingEventKind::opened};
  std::uint8_t before{kMainPort};  // opened / split: the new place; closed: the place repaired
  std::uint8_t after{kRingPort};
  SlaveMask unreachable{0};        // split
  std::uint64_t cycle{0};
  hal::Nanoseconds time{0};
};

class RingMonitor {
 public:
  static constexpr std::size_t kReportCapacity = 16;

  // Starts watching a closed ring of the segment's slaves: `planned_of_segment[i]` is the planned
  // position of the slave at segment position i (kNoSlavePosition when none), `slaves` of them.
  static constexpr std::uint8_t kNoSlavePosition = 0xFF;
  void start(const std::array<std::uint8_t, kMaxSlaves>& planned_of_segment, std::size_t slaves) noexcept;
  void stop() noexcept { status_ = RingStatus{}; }

  // One cycle's evidence: where the copies came back and the DL-status BRD's counter in each.
  void observe(std::uint64_t cycle, hal::Nanoseconds time, const CopyReturns& returns, std::uint16_t main_brd_wkc,
               std::uint16_t ring_brd_wkc) noexcept;
  // The DL status read of the slave at planned position `position` (wkc 1: it answered).
  void observe_dl_status(std::uint8_t position, std::uint16_t wkc, std::uint16_t dl_status) noexcept;

  const RingStatus& status() const noexcept { return status_; }
  [[nodiscard]] bool pop_report(RingReport& out) noexcept { return reports_.pop(out); }
  std::uint64_t reports_dropped() const noexcept { return reports_dropped_; }

 private:
  std::uint8_t planned(std::size_t segment_position) const noexcept;
  void report(RingEventKind kind, std::uint8_t before, std::uint8_t after, SlaveMask unreachable) noexcept;
  void drop_pending_lost() noexcept;  // an unconfirmed loss: counted as a transient

  std::array<std::uint8_t, kMaxSlaves> planned_of_segment_{};
  std::size_t slaves_{0};
  RingStatus status_{};
  // A loss seen in one frame, waiting for the next to confirm it (same place).
  bool pending_lost_{false};
  std::uint8_t pending_before_{kMainPort};
  std::uint8_t pending_after_{kRingPort};
  std::uint64_t pending_cycle_{0};
  hal::Nanoseconds pending_time_{0};
  std::uint64_t cycle_{0};
  hal::Nanoseconds time_{0};
  RingBuffer<RingReport, kReportCapacity> reports_{};
  std::uint64_t reports_dropped_{0};
};

// One line for the log: "ring open between l_hip (position 7) and l_knee (position 8)", "ring closed
// again between ...", "ring split: 3 slaves reachable from neither port, between ... and ...".
// Returns the characters written (truncated to `size` - 1).
std::size_t describe(const RingReport& report, const NetworkPlan& plan, char* out, std::size_t size) noexcept;

}  // namespace rescue::ecat
