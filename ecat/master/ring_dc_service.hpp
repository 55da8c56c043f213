// Distributed clocks across a break of the ring (docs/redundancy.md, "DC method"). The reference
// time reaches the other clocks by the FRMW of the main copy, which goes as NOP in the ring copy
// (redundant_merge.hpp). With the ring open, the slaves behind the break are processed by the ring
// copy only, so they would get no reference time and their drift loops would stop. This service
// gives it to them, without stopping the cycle:
//   1. latch   the first frame after the ring opens (or the break moves) carries a BWR of 0x0900:
//              each slave latches the time the copy that processed it passed its processing unit;
//   2. read    FPRD 0x0918..0x092B of the reference and of every DC slave behind the break (as many
//              a cycle as fit): receive time (local), system time offset, delay. Local + offset is
//              the system time of the passage, so lead_j = passage_j - passage_ref - delay_j is
//              where slave j's new path puts it against the reference's read, in the clocks' own
//              time (the clocks agree when the ring opens: no half round trip is assumed);
//   3. write   every cycle, per slave behind the break, a ring-side time write (NOP in the main
//              copy, FPWR 0x0910 in the ring copy) of R + lead_j, R the reference time predicted
//              for this frame: the last read plus the master's clock time since that read's frame
//              was built, scaled by the reference's rate against that clock (measured from the
//              first read on). So a late wake-up or a skipped period does not enter R. Over a
//              real link the frame leaves later than it was built, by a time that varies: so R
//              counts from when the read's frame was SENT (StampedPort, the clock just before the
//              send), and the ring port moves every write of the frame by the time between building
//              and sending it, read just before the ring copy is sent (before_ring_send), and the
//              leads leave out how far the latch frame's ring copy was sent after its main copy.
//              What is left is the jitter between the clock read and the frame's passage. The ESC
//              compares R + lead_j + delay_j with its own time as the copy passed: the same figure
//              an FRMW gives on the main path, so the drift loop goes on as before the break.
// The delay register (0x0928) is not rewritten: it stays true for the main path, so when the ring
// closes again the main copy's FRMW is right for every slave in the very first frame (the
// ring-side writes in a frame built before the repair are void: with the ring closed the ring copy
// processes no slave).
// The reference is never cut off by one break (it is behind it or before it); behind it (the master
// cable cut) it is read by FPRD from the ring copy (DcReferenceService::set_reference_behind_break)
// and every other slave behind the break is written its lead against that read. The slaves on the
// main side are then not written (none in the robot's ring: its reference is the first slave).
// Without a ring NIC, or with the ring closed, this service adds nothing.
#pragma once

#include <array>
#include <cstdint>

#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/dc_reference_service.hpp"
#include "ecat/master/ring_service.hpp"
#include "ecat/master/stamped_port.hpp"

namespace rescue::ecat {

enum class RingDcPhase : std::uint8_t { idle, latch, read, write };

// What the service did (tests and docs read it).
struct RingDcStatus {
  RingDcPhase phase{RingDcPhase::idle};
  std::uint8_t after{kRingPort};  // the break the leads are for: the first slave the ring port reaches
  SlaveMask written{0};            // slaves given the reference time by the ring copy
  bool reference_behind_break{false};
  std::uint64_t calibrations{0};   // latch-and-read rounds completed
  std::uint64_t writes{0};         // ring-side time writes sent
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

  const RingDcStatus& status() const noexcept { return status_; }

  // The ring port's frame about to leave at `now`: each ring-side time write in it (FPWR 0x0910,
  // 8 bytes) moved on by the reference time that passes between the frame's building and `now`.
  bool patches_ring_copies() const noexcept { return status_.phase == RingDcPhase::write; }
  void before_ring_send(ByteSpan frame, hal::Nanoseconds now) noexcept;

 private:
  static constexpr std::uint8_t kLatchTag = 0xFE;
  static constexpr std::uint8_t kWriteTag = 0xFD;
  // FPRD 0x0918..0x092B: receive time of the processing unit (u64), offset (u64), delay (u32).
  static constexpr std::uint16_t kReadLength = 20;

  void begin(std::uint8_t after) noexcept;
  void add_reads(CycleFrame& frame) noexcept;
  void add_writes(CycleFrame& frame) noexcept;
  void finish_calibration() noexcept;
  // The reference time this frame will read (0: none known yet).
  std::uint64_t predicted_reference() const noexcept;
  // The reference's rate against the master's clock, minus 1 (0 below kMinRateBaseline).
  double rate_excess() const noexcept;
  // When the copy that reads the reference was sent (the main copy, the ring copy with the
  // reference behind the break), the build time when the port noted none.
  hal::Nanoseconds reference_copy_sent_at() const noexcept;

  ServiceContext& ctx_;
  const RingService& ring_;
  DcReferenceService& reference_;
  const StampedPort& main_port_;
  const StampedPort& ring_port_;
  RingDcStatus status_{};
  SlaveMask behind_{0};    // DC slaves behind the break to be written (the reference excluded)
  SlaveMask to_read_{0};   // calibration reads outstanding (the reference's among them)
  std::array<std::uint64_t, kMaxSlaves> passage_{};  // system time of the latched passage
  std::array<std::uint32_t, kMaxSlaves> delay_{};
  std::array<std::int64_t, kMaxSlaves> lead_{};
  std::size_t next_write_{0};  // round robin when the writes do not all fit
  // Below this baseline the reference's rate is taken as the master clock's.
  static constexpr hal::Nanoseconds kMinRateBaseline = 100 * hal::kNsPerMs;
  // The master's clock when this frame was built; the last reference read since the path changed
  // and when its frame was built; the first read since reset() (the rate's anchor).
  hal::Nanoseconds frame_time_{0};
  std::uint64_t last_reference_{0};
  hal::Nanoseconds last_reference_at_{0};
  std::uint64_t anchor_reference_{0};
  hal::Nanoseconds anchor_at_{0};
  // How long after the reference's copy the latch frame's ring copy was sent.
  hal::Nanoseconds latch_spacing_{0};
};

}  // namespace rescue::ecat
