// bench master --nic sim --ring-nic sim: one cable of the ring cut during the measured run and
// restored (issue 34 item 3, docs/redundancy.md "DC method"), and what it did to the clocks, read
// in the simulator: the largest |0x092C| from 100 ms after the cut to the repair, the largest move
// of a drive's SYNC0 edge (its clock's offset from the reference's against the offset before the
// cut), and the largest |0x092C| from 100 ms after the repair to the end; beside them the largest
// |0x092C| of the 100 ms before the cut (the no-fault figure at that time of the run).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/robot/robot.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

class RingBreakRun {
 public:
  // `cable`: the cable into that position's port 0, or kSlaveCount for the ring-return cable. Cut a
  // third into the run of `cycles`, restored at two thirds.
  void plan(std::size_t cable, std::int64_t cycles) noexcept;
  bool planned() const noexcept { return planned_; }
  // After cycle `i` of the measured run: cuts or restores on schedule (a refusal is kept and
  // printed) and measures the clocks.
  void after_cycle(std::int64_t i, drivers::SimulatedSegment& segment, hal::Nanoseconds now) noexcept;
  void print() const noexcept;

 private:
  bool planned_{false};
  const char* refused_{nullptr};  // why the simulator refused the cut or the restore
  std::size_t cable_{0};
  std::int64_t cut_at_{0};      // the cable is cut after this cycle
  std::int64_t restore_at_{0};  // ... and restored after this one
  std::array<std::int64_t, kSlaveCount> before_{};
  std::uint32_t difference_before_break_{0};
  std::uint32_t difference_after_break_{0};
  std::int64_t sync0_moved_{0};
  std::uint32_t difference_after_repair_{0};
};

}  // namespace rescue::app
