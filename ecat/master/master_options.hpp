// What the master's owner chooses (MasterOptions) and where the master stands (MasterState): shared
// by the master and its cyclic services (cyclic_service.hpp), so they sit apart from master.hpp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/al_control.hpp"
#include "ecat/sii/sii_cache.hpp"
#include "ecat/sii/sii_reader.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {

// Room the cyclic frame keeps beyond the process image: probes, AL datagrams, a mailbox step.
constexpr std::size_t kCycleFrameReserve = 400;

// What a bring-up waits for (MasterOptions::waiting).
struct BringUpWait {
  const char* step{""};            // "count": first contact (no frame has come back yet)
  hal::Nanoseconds waited{0};      // since the step began
  std::uint32_t frames{0};         // frames sent for it (count: BRDs)
  hal::Nanoseconds limit{0};       // when it gives up (first_contact_timeout), 0 or less: never
};

struct MasterOptions {
  hal::Nanoseconds cycle_time{hal::kNsPerMs};
  hal::Nanoseconds frame_timeout{2 * hal::kNsPerMs};           // bring-up round trips
  // A bring-up exchange sent again after frame_timeout gives up only after its attempts and this much
  // silence since its first send (DatagramLink::set_repeat_silence): over veth a simulator the loaded
  // host did not run for more than 3 x 2 ms failed `run --check` at identify (issue 35). A real
  // segment answers in microseconds; a dead one costs a failing bring-up this much more.
  hal::Nanoseconds repeat_silence{250 * hal::kNsPerMs};
  // First contact: the count BRD is sent again every frame_timeout until a frame comes back or this
  // much time has passed (a segment just powered, a simulator just started or long idle, a link
  // still negotiating). Only then does bring-up fail, saying that nothing answered.
  // 0 or less: keep trying until stop_requested says stop.
  hal::Nanoseconds first_contact_timeout{5 * hal::kNsPerSec};
  // Called about once a second while the bring-up waits for first contact (a bring-up is never
  // silent: the owner says what it waits for); nullptr: nobody is told.
  void (*waiting)(const BringUpWait& wait, void* context) noexcept {nullptr};
  void* waiting_context{nullptr};
  // The cyclic frame is waited for until just before the next period's send: until
  // cycle_receive_guard before the next period starts (the guard leaves the caller the rest of its
  // period's work after the frame), and never less than cycle_receive_timeout after sending (a cycle
  // that started late) nor more than one period after it (unless cycle_receive_timeout says more).
  // A frame later than that is counted as late or missing (frames_missing()), and dropped as stale
  // when it turns up in a later period (LinkStats::stale_frames): the next frame's inputs are newer.
  hal::Nanoseconds cycle_receive_timeout{700 * hal::kNsPerUs};
  hal::Nanoseconds cycle_receive_guard{100 * hal::kNsPerUs};
  // With a ring NIC, an exchange repeated because the ring changed while its frame was in flight
  // (DatagramLink, ExchangeDeadlines) may run into the guard, up to this before the next period
  // starts: a host that held the first copies until the receive deadline still gets the repeat.
  // The handler's own work after the frame is 3-8 us (docs/master.md, "The cyclic frame's deadline").
  hal::Nanoseconds cycle_repeat_guard{20 * hal::kNsPerUs};
  AlOptions al{};
  SiiReadOptions sii{};
  // Whole SII images of devices seen before (ecat/sii/sii_cache.hpp): a slave whose first 32 EEPROM
  // bytes (configuration area, vendor, product, revision, serial) equal a cached image's is not read
  // further; every image read whole that parses is taken in (its owner saves the cache where it
  // likes). nullptr: every image is read whole.
  SiiCache* sii_cache{nullptr};
  // Static drift compensation before cycling: FRMW of the reference time back to back, at most
  // drift_compensation_frames (ETG.1020's 15000), ended early once every DC slave's system time
  // difference (0x092C) has been at most drift_compensation_target_ns in two checks in a row,
  // drift_compensation_check_every frames apart: the cyclic FRMW goes on compensating from there.
  // Target 0: every frame is sent.
  unsigned drift_compensation_frames{15000};
  unsigned drift_compensation_check_every{500};
  // Its frames on their way at a time (1..DatagramLink::kMaxStreamInFlight; 1: each waits for the
  // one before): a frame is about 7 us on the wire and 28 us round the robot's segment. Measured with
  // `bench master` (docs/master.md "Figures"): 2 ends after 1000 frames (14 ms) with the clocks as
  // close as 1500 frames one by one (42 ms); 4 or 8 also end after 1000 (7 ms) but with the SYNC0
  // spread of the first cycles at 66-71 ns instead of 45.
  unsigned drift_compensation_in_flight{2};
  std::uint32_t drift_compensation_target_ns{5};
  hal::Nanoseconds sync0_start_margin{10 * hal::kNsPerMs};
  hal::Nanoseconds sync0_target_phase{-1};    // frame at the reference this long after SYNC0; -1 = cycle/2
  // SAFE-OP -> OP while cycling: after this long the failure is reported (report().failed_step "OP",
  // the slave and its AL status code) and the slaves not in OP are asked again, acknowledged first.
  hal::Nanoseconds op_timeout{3 * hal::kNsPerSec};
  // Slaves kept out of service (the owner's choice, e.g. their joints are recorded lost). They and the
  // slaves behind them may be absent; one that answers is brought into the topology and the
  // distributed clocks and never operated. Bring-up never fails for them.
  SlaveMask held_out{0};
  // SDO downloads done in PRE-OP, before SAFE-OP (IgH's slave-config SDOs): e.g. joint limits.
  // Requests to slaves that are not operated are skipped. Any refusal fails the bring-up.
  Span<const SdoRequest> startup_sdos{};
  // Polled between the bring-up's steps and inside its long loops: true stops the bring-up at once
  // (failed step "stopped", Errc::refused), slaves left in their current (not operational) state.
  bool (*stop_requested)() noexcept {nullptr};
  hal::Nanoseconds startup_sdo_timeout{5 * hal::kNsPerSec};
  // Online recovery (ecat/master/slave_recovery.hpp, docs/master.md): an operated slave out of the
  // exchange is looked for at its position and, when it answers, configured again and brought back
  // to OP while cycling. Off: a restored slave waits for reintegrate().
  bool online_recovery{false};
  // Extra datagrams the recovery adds to one cyclic frame, all slaves together (search included).
  unsigned recovery_datagrams_per_cycle{2};
  hal::Nanoseconds recovery_step_timeout{hal::kNsPerSec};  // per state
  // After a failure, before searching again; doubled after each failure in a row, up to
  // recovery_hold_off_max (a recovery that cannot finish is retried from the start, never left stuck).
  hal::Nanoseconds recovery_hold_off{hal::kNsPerSec};
  hal::Nanoseconds recovery_hold_off_max{8 * hal::kNsPerSec};
  // Link diagnostics (ecat/master/link_diagnostics.hpp): one slave's error counters read (and
  // cleared) by one datagram in every this many cycles, round robin over the slaves in the
  // exchange; 0 = off. 10 at 1 ms: each of 23 slaves every 230 ms.
  unsigned diag_interval_cycles{10};
};

enum class MasterState : std::uint8_t { idle, failed, safe_op, going_op, op };
const char* to_string(MasterState state) noexcept;


}  // namespace rescue::ecat
