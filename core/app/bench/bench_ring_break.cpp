// A ring cable cut and restored during bench master's measured run, and the clocks' figures.
#include "core/app/bench/bench_ring_break.hpp"

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>

#include "core/robot/robot.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::app {
namespace {

constexpr std::int64_t kSettleCycles = 100;  // 100 ms at the 1 ms period

std::uint32_t max_difference(const drivers::SimulatedSegment& segment) noexcept {
  std::uint32_t worst = 0;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    worst = std::max(worst, segment.esc(p).register_u32(ecat::reg::kDcSystemTimeDifference) & 0x7FFFFFFFU);
  }
  return worst;
}

// Each slave's system time against the reference's (position 0) at `now`.
void offsets(const drivers::SimulatedSegment& segment, hal::Nanoseconds now, std::array<std::int64_t, kSlaveCount>& out) noexcept {
  (void)segment.true_clock_offsets(now, Span<std::int64_t>(out));
}

}  // namespace

void RingBreakRun::plan(std::size_t cable, std::int64_t cycles) noexcept {
  planned_ = true;
  cable_ = cable;
  cut_at_ = cycles / 3;
  restore_at_ = 2 * cycles / 3;
}

void RingBreakRun::after_cycle(std::int64_t i, drivers::SimulatedSegment& segment, hal::Nanoseconds now) noexcept {
  if (!planned_) return;
  const bool ring_cable = cable_ == kSlaveCount;
  const auto note = [this](const Status& st) {
    if (!st.ok() && refused_ == nullptr) refused_ = st.error().what;
  };
  if (i < cut_at_ && i >= cut_at_ - kSettleCycles) difference_before_break_ = std::max(difference_before_break_, max_difference(segment));
  if (i == cut_at_) {
    offsets(segment, now, before_);
    note(ring_cable ? segment.cut_ring_cable() : segment.cut_link(cable_));
    return;
  }
  if (i > cut_at_ && i <= restore_at_) {
    std::array<std::int64_t, kSlaveCount> now_offsets{};
    offsets(segment, now, now_offsets);
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind == SlaveKind::joint_drive) sync0_moved_ = std::max(sync0_moved_, std::abs(now_offsets[p] - before_[p]));
    }
    if (i > cut_at_ + kSettleCycles) difference_after_break_ = std::max(difference_after_break_, max_difference(segment));
  }
  if (i == restore_at_) note(ring_cable ? segment.restore_ring_cable() : segment.restore_link(cable_));
  if (i > restore_at_ + kSettleCycles) difference_after_repair_ = std::max(difference_after_repair_, max_difference(segment));
}

void RingBreakRun::print() const noexcept {
  if (!planned_) {
    (void)std::printf("ring_cut: none (--ring-cut none)\n");
    return;
  }
  const bool ring_cable = cable_ == kSlaveCount;
  (void)std::printf("ring_cut: %s%s, cut after cycle %" PRId64 ", restored after cycle %" PRId64 "\n",
                    ring_cable ? "the ring-return cable" : "the cable into ", ring_cable ? "" : kSlaves[cable_].name,
                    cut_at_, restore_at_);
  if (refused_ != nullptr) (void)std::printf("ring_cut_refused: %s\n", refused_);
  (void)std::printf("ring_dc_max_difference_before_break: %" PRIu32 " ns (max |0x092C|, the 100 ms before the cut)\n",
                    difference_before_break_);
  (void)std::printf("ring_dc_max_difference_after_break: %" PRIu32 " ns (max |0x092C|, 100 ms after the cut to the repair)\n",
                    difference_after_break_);
  (void)std::printf("ring_dc_sync0_moved_max: %" PRId64 " ns (largest move of a drive's SYNC0 edge, the cut to the repair)\n",
                    sync0_moved_);
  (void)std::printf("ring_dc_max_difference_after_repair: %" PRIu32 " ns (max |0x092C|, 100 ms after the repair to the end)\n",
                    difference_after_repair_);
}

}  // namespace rescue::app
