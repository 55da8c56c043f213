// Distributed clocks across a break of the ring (docs/redundancy.md, "DC method"). The reference
// time reaches the other clocks by the FRMW of the main copy, which goes as NOP in the ring copy
// (redundant_merge.hpp). With the ring open, the slaves behind the break are processed by the ring
// copy only, so they would get no reference time and their drift loops would stop. This service
// keeps them together, without stopping the cycle, as an island that takes its time from its first
// clock (the island reference: the first DC slave behind the break) within the ring copy:
//   1. latch   the first frame after the ring opens (or the break moves) carries a BWR of 0x0900:
//              each slave latches the time the copy that processed it passed its processing unit;
//   2. read    FPRD 0x0918..0x092B of the reference and of every DC slave behind the break (as
//              many a cycle as fit):
//              receive time (local), system time offset, delay. Local + offset is the system time
//              of the passage, so passage_j - passage_island is the ring copy's way from the island
//              reference to slave j in the clocks' own time (they agree when the ring opens), both
//              from one copy: no host delay between the two copies enters it;
//   3. ways    an FPWR of each island slave's 0x0928 with that way (once; both copies carry it, but
//              while the ring is open only the ring copy reaches the island);
//   4. island  every cycle an island time read: a NOP in the main copy, an FRMW of the island
//              reference's 0x0910 in the ring copy. Each island clock's drift loop compares against
//              the island reference's time carried in the same frame, as on the main path.
// So that the main copy's FRMW never meets a way (a repair while a frame is in flight), every frame
// while a way may be set restores the main path's delay BEFORE the reference's FRMW
// (add_before_reference(), first in the frame): an APWR of 0x0928 by position, which the ring copy
// carries as NOP (so the ways stay for the island) and the main copy lands only on a slave it
// reaches, i.e. once the ring is whole there. A restore stops when it has been answered. Positions
// are those of the plan, so a restore is sent only while every slave up to it is present; and only
// when the last frame left room for it (budget from the room the previous frame had).
// The island reference itself gets no time write: its drift loop was converged before the break,
// so it runs on its learned rate, and its error against the reference grows with its residual rate
// times the break's duration. It is steered slowly, by its system time offset (0x0920: a phase move
// of exactly the step written, no host delay in it), from the difference between its time in the
// ring copy and the reference's in the main copy, less the stamped spacing of the two sends. That
// difference carries the two copies' host transit times (over veth 1.4-468 us apart from frame to
// frame, its mean wandering), so it is held against its mean over the first cycles of the break
// (its bias, the transit difference on average, cannot be told from a phase), filtered, and only
// what lies beyond a dead band of a few of its deviations is steered (steer()), and only when that
// band is narrow enough to hold a SYNC0 edge within 1 us at all. With quiet copies (virtual time)
// the loop follows a crystal's step; over veth the band is microseconds wide, so it does not act and
// the island reference runs free (where it acted, it chased the transit's wander).
// The reference behind the break (the master cable cut) is the island reference: the island then
// takes the true reference time, each slave with its main path delay (the way from the reference
// is the main path's), and DcReferenceService reads the reference by FPRD
// (set_reference_behind_break). The slaves on the main side are then not written (none in the
// robot's ring: its reference is the first slave).
// Without a ring NIC, or with the ring closed, this service adds nothing.
#pragma once

#include <array>
#include <cstdint>

#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/dc_reference_service.hpp"
#include "ecat/master/ring_service.hpp"
#include "ecat/master/stamped_port.hpp"

namespace rescue::ecat {

enum class RingDcPhase : std::uint8_t { idle, latch, read, island };

// What the service did (tests and docs read it).
struct RingDcStatus {
  RingDcPhase phase{RingDcPhase::idle};
  std::uint8_t after{kRingPort};  // the break the island is for: the first slave the ring port reaches
  SlaveMask written{0};            // the island: DC slaves behind the break, its reference among them
  std::uint8_t island_reference{kMaxSlaves};  // its position (kMaxSlaves: none)
  bool reference_behind_break{false};
  std::uint64_t calibrations{0};   // latch-and-read rounds completed
  std::uint64_t island_reads{0};   // island time reads sent
  std::uint64_t island_skipped{0};  // cycles whose frame had no room for the island's datagrams
  std::uint64_t bad_ways{0};       // island slaves latched before their island reference (dropped)
  std::uint64_t restores_skipped{0};  // frames whose restores did not fit or could not be addressed
  SlaveMask ways_set{0};           // slaves whose 0x0928 may hold a way (restored until answered)
  std::uint64_t steps{0};          // offset steps written to the island reference
  std::int64_t steered_ns{0};      // their sum since the island began
  std::int64_t noise_ns{0};        // the difference's standard deviation over the baseline's cycles (0: n/a yet)
  std::uint64_t rebaselines{0};    // baselines taken again since the island began: the difference moved to another level
};

class RingDcService final : public CyclicService {
 public:
  // `main_port` and `ring_port`: the master's two ports as the link sends through them.
  RingDcService(ServiceContext& context, const RingService& ring, DcReferenceService& reference,
                const StampedPort& main_port, const StampedPort& ring_port) noexcept
      : ctx_(context), ring_(ring), reference_(reference), main_port_(main_port), ring_port_(ring_port) {}

  void reset() noexcept;

  void add_datagrams(CycleFrame& frame) noexcept override;
  void on_answer(std::uint8_t tag, const DatagramView& datagram) noexcept override;
  void settle(CycleResult& result) noexcept override;
  // The delay restores (see above); the master calls it before the services add their datagrams.
  void add_before_reference(CycleFrame& frame) noexcept;

  const RingDcStatus& status() const noexcept { return status_; }

 private:
  static constexpr std::uint8_t kLatchTag = 0xFE;
  static constexpr std::uint8_t kIslandTag = 0xFD;
  static constexpr std::uint8_t kOffsetTag = 0xFB;
  static constexpr std::uint8_t kWayTag = 0x40;      // | position
  static constexpr std::uint8_t kRestoreTag = 0x80;  // | position
  static_assert(kMaxSlaves < 0x40, "a position fits beside the way and restore tags");
  // FPRD 0x0918..0x092B: receive time of the processing unit (u64), offset (u64), delay (u32).
  static constexpr std::uint16_t kReadLength = 20;

  void begin(std::uint8_t after) noexcept;
  void add_reads(CycleFrame& frame) noexcept;
  void add_island(CycleFrame& frame) noexcept;
  void add_ways(CycleFrame& frame) noexcept;
  void finish_calibration() noexcept;
  // One cycle's difference of the island reference against the reference, into the loop.
  void steer(std::int64_t difference) noexcept;
  void restart_baseline() noexcept;
  hal::Nanoseconds copy_spacing() const noexcept;

  ServiceContext& ctx_;
  const RingService& ring_;
  DcReferenceService& reference_;
  const StampedPort& main_port_;
  const StampedPort& ring_port_;
  RingDcStatus status_{};
  SlaveMask behind_{0};    // DC slaves behind the break, the island reference among them
  SlaveMask island_{0};    // those that take the island reference's time (it excluded)
  SlaveMask to_read_{0};   // calibration reads outstanding
  SlaveMask ways_to_write_{0};
  std::size_t island_reference_{kMaxSlaves};
  bool rewrites_delays_{false};  // false when the island reference is the reference
  // The room left in the frame where this service began adding, last frame, and the restores' bytes
  // in that frame (the budget of the next restores).
  std::size_t room_{0};
  std::size_t restore_bytes_{0};
  std::array<std::uint64_t, kMaxSlaves> passage_{};  // system time of the latched passage
  std::array<std::uint32_t, kMaxSlaves> delay_{};     // 0x0928 on the main path
  std::array<std::uint32_t, kMaxSlaves> way_{};       // the ring copy's way from the island reference
  std::array<std::uint64_t, kMaxSlaves> offset_{};    // 0x0920 as read at the latch
  // The steering of the island reference (steer()).
  hal::Nanoseconds latch_spacing_{0};  // how long after the main copy the latch frame's ring copy was sent
  std::int64_t expected_{0};           // island time minus reference time in a frame, at the latch
  std::uint64_t island_time_{0};       // this frame's island time read (0: none)
  std::uint32_t samples_{0};
  double baseline_sum_{0.0};
  double baseline_square_sum_{0.0};
  double baseline_{0.0};
  double noise_{0.0};                  // standard deviation over the baseline's cycles
  double filtered_{0.0};
  std::uint32_t clipped_above_{0};     // samples in a row cut to the clip above the filtered value
  std::uint32_t clipped_below_{0};     // and below it
  std::uint64_t offset_now_{0};        // the island reference's 0x0920 as last written
  std::int64_t pending_step_{0};       // to be written in the next frame
};

}  // namespace rescue::ecat
