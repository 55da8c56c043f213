// Lost-slave detection from working counters, confirmed by probing (pure logic: the master feeds
// it what came back, it says what to probe next and what to report).
//
// 1. Each cycle, each branch's LRW returns a working counter. Every slave in OP that the frame
//    reaches adds 3, so with n slaves present on the branch (wiring order) a counter w = 3k < 3n
//    means the frame reached the first k in OP and no further: a link cut at the (k+1)-th slave
//    silences exactly it and everything after it, the link-failure set. Those first k slaves'
//    inputs are valid this cycle. A counter that is not a multiple of 3 (a slave out of OP adds
//    only 1) cannot be placed: nothing on that branch is valid this cycle. Either way every
//    present slave of a short branch becomes a suspect. Healthy branches are untouched.
// 2. Next cycle, each suspect is probed with an FPRD of its AL status (0x0130..0x0135): working
//    counter 0 means unreachable; reachable but not in OP -> reported not operational (with its AL
//    status code); reachable in OP -> a glitch, counted, nothing reported. An unreachable suspect
//    is reported lost only when kLossConfirmFrames returned frames in a row said so: the one whose
//    working counter raised the suspicion, then kLossConfirmFrames - 1 whose probe found it silent
//    (docs/master.md gives the reasoning). A frame that did not come back (late, bunched, dropped)
//    is no evidence either way: it neither confirms nor clears anything.
// 3. A slave taken out of the exchange (lost or not operational) no longer counts in the expected
//    working counter. The master clears its FMMU activation (FPWR 0x060C, 17 zero bytes: FMMU0 and
//    FMMU1 off), so it adds nothing to the LRW even if it answers again. That write is repeated
//    each cycle for lost slaves and doubles as the restoration probe: its first working counter of
//    1 means the link is back -> reported restored. A restored slave stays out of the exchange
//    until the owner re-integrates it explicitly.
// 4. No frame back at all is "late or missing": counted (frames_missing()), never a loss by itself.
//    Only frames that come back are evidence; replies are matched to their request by the frame's
//    index (DatagramLink), so a late reply of an earlier period is never read as the current one.
// 5. The master's own silence: when a frame comes back kWatchdogCheckGap or more after the previous
//    one that came back (a stalled host, or a network that returned nothing), the slaves may have
//    gone without outputs for their SyncManager watchdog (100 ms by default) and dropped to SAFE-OP
//    with AL status code 0x001B. Their working counter does not show it (SAFE-OP still exchanges
//    the process data), so every slave in the exchange is probed once (the watchdog check). One
//    found in SAFE-OP with 0x001B by that check is not a link fault: it stays in the exchange,
//    is reported `watchdog_expired`, and the master re-arms it (acknowledge, OP) until `rearmed`.
//    Anything else the check finds is what the probe of a suspect would say (not operational).
// 6. The AL state watch: a slave that leaves OP for a reason of its own (a synchronisation error, its
//    application) may still add to the working counter (drives keep exchanging process data in
//    SAFE-OP), so every slave in the exchange has its AL status read (FPRD 0x0130) in the cyclic
//    frame in turn: ceil(slaves / kAlWatchPeriods) of them per frame, so each one at least every
//    kAlWatchPeriods periods (IgH's master reads every slave's AL state cyclically too). One found
//    out of OP (or with the error bit) is reported `not_operational` with its AL status and code and
//    taken out of the exchange (online recovery takes it from there); a read that did not reach the
//    slave is no evidence (the counters judge reachability), except for a slave no counter counts
//    (a junction: no process data): it becomes a suspect, probed as in item 2 and reported lost
//    after kLossConfirmFrames silent frames (a power cycle took its station address).
#pragma once

#include <array>
#include <cstdint>

#include "core/base/span.hpp"
#include "core/containers/ring_buffer.hpp"
#include "ecat/link/network_plan.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {

enum class LinkEventKind : std::uint8_t {
  lost,             // unreachable: link failure at the first of them, or in front of them
  not_operational,  // reachable, but left OP (AL status code says why)
  restored,         // a lost slave answers again (not re-used until re-integrated)
  reintegrated,     // back in the exchange after an explicit re-integration
  reintegration_failed,  // an explicit re-integration did not bring the slave back to OP
  silent,           // alarm: no frame came back for LinkMonitor::kSilenceAlarm (slaves: those in the exchange)
  heard_again,      // a frame came back after a `silent` alarm (the probes then say what is lost)
  recovered,        // online recovery brought it back to OP and into the exchange ("available")
  recovery_refused, // online recovery found another device in its place (identity in the report)
  recovery_failed,  // online recovery gave up for now (a step timed out); it tries again from the start after a hold-off
  port_errors,      // a port's receive errors rise (found = port, slave at the cable's other end, errors)
  watchdog_expired, // reachable, in SAFE-OP by its SyncManager watchdog after the master's silence (found[0] = ms)
  rearmed,          // back in OP after a watchdog_expired (the master acknowledged and requested OP)
};
constexpr std::size_t kLinkEventKindCount = 13;
static_assert(static_cast<std::size_t>(LinkEventKind::rearmed) + 1 == kLinkEventKindCount, "every kind counted");
const char* to_string(LinkEventKind kind) noexcept;

// One report for the master's owner (fixed size, trivially copyable: goes through SPSC queues).
struct LinkReport {
  LinkEventKind kind{LinkEventKind::lost};
  std::uint8_t branch{kNoBranch};   // branch of the slaves (kNoBranch when several)
  std::uint16_t al_status{0};       // not_operational: AL status register (state, error bit)
  std::uint16_t al_status_code{0};  // not_operational: AL status code (0x0134)
  SlaveMask slaves{0};
  std::uint64_t cycle{0};           // cycle in which it was established
  std::uint64_t detected_cycle{0};  // cycle whose working counter first showed it
  hal::Nanoseconds time{0};
  // recovered: found[0] = kRecoveredAfterPowerLoss when the slave had lost its station address (its
  // power was cycled), 0 when it kept its configuration (a cable: link lost and back); found[1] =
  // SDO writes that brought its PDO mapping back to the plan (0: it held the plan);
  // recovery_refused: the SII identity found (vendor, product, revision, serial);
  // recovery_failed: found[0] = the recovery state that timed out (or lost the device in the third
  // attempt in a row), found[1] = failed attempts in a row, found[2] = hold-off before the next (ms).
  std::array<std::uint32_t, 4> found{};
};

constexpr std::uint32_t kRecoveredAfterPowerLoss = 1;

struct ProbeRequest {
  std::uint8_t position{0};
  bool clear_fmmus{false};  // also write FMMU activation off (slaves out of the exchange)
  bool watch{false};        // the AL state watch's read of a slave in the exchange (item 6)
};

struct ProbeResult {
  std::uint8_t position{0};
  bool had_clear{false};
  bool watch{false};
  std::uint16_t status_wkc{0};  // FPRD 0x0130
  std::uint16_t al_status{0};
  std::uint16_t al_status_code{0};
  std::uint16_t clear_wkc{0};   // FPWR 0x060C (when had_clear)
  // On the ring, the status read's answer was lost with a copy (answer_lost_with_a_copy): no
  // evidence either way, as for a frame that did not come back.
  bool no_evidence{false};
};

class LinkMonitor {
 public:
  // Returned frames in a row that must show a slave unreachable before it is reported lost: the
  // short working counter, then this many minus one silent probes. Detection time: a cut in cycle
  // N is reported in cycle N + kLossConfirmFrames - 1 when every frame comes back.
  static constexpr std::uint32_t kLossConfirmFrames = 3;
  static constexpr std::size_t kReportCapacity = 32;
  // No frame back for this long (from the first one that did not come back) raises the link-silence
  // alarm, once, and a returned frame ends it. Far above host jitter (frames bunched 3 ms late in
  // issue 11, injected stalls of 3-7 ms), and the default SyncManager watchdog of the drives
  // (100 ms), which by then has stopped them: the alarm says why. It is not evidence against single
  // slaves: nothing is reported lost for it (docs/master.md, "A link that returns nothing").
  static constexpr hal::Nanoseconds kSilenceAlarm = 100 * hal::kNsPerMs;
  // Returned frames this far apart (send times) start the watchdog check (item 5 above). Half the
  // ESCs' default process-data watchdog (100 ms, 0x0400 x 0x0420 at reset, which the master keeps):
  // the check costs one status read per slave, and a gap this long is already far above jitter.
  static constexpr hal::Nanoseconds kWatchdogCheckGap = 50 * hal::kNsPerMs;
  // Item 6: every slave in the exchange has its AL status read at least once in this many periods
  // (frames), so a drop out of OP is reported within kAlWatchPeriods + 1 periods: 9 ms at 1 ms.
  static constexpr std::size_t kAlWatchPeriods = 8;

  LinkMonitor(const NetworkPlan& plan, const ProcessImageLayout& layout) noexcept;

  // The slaves in the exchange at start (bring-up's operated set).
  void start(SlaveMask in_exchange) noexcept;
  // Cable redundancy: the counters are the merge of two copies (each port reaches a part of a
  // branch), so a short counter is never placed as "the first k slaves"; the probes place it.
  void set_redundant(bool on) noexcept { redundant_ = on; }

  // Probes the next frame should carry, most urgent first (suspects, then slaves out of the
  // exchange, rotating). Fills `out`, returns how many.
  std::size_t plan_probes(ProbeRequest* out, std::size_t capacity) noexcept;

  // What this cycle's frame brought back: the branches' LRW working counters and the probes that
  // plan_probes() asked for (ignored when no frame came back).
  void observe(std::uint64_t cycle, hal::Nanoseconds time, bool frame_received,
               const std::array<std::uint16_t, kMaxBranches>& branch_wkc, Span<const ProbeResult> probes) noexcept;

  // Re-integration: the owner brought these (restored) slaves back to OP with their FMMUs set.
  void reintegrated(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time) noexcept;
  // ... or could not (they stay restored, out of the exchange; AL status and code of the first).
  void reintegration_failed(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time, std::uint16_t al_status,
                            std::uint16_t al_code) noexcept;

  // Online recovery: slaves it works on are left out of the restoration probes (it talks to them);
  // recovered() puts slaves back in the exchange (from lost, restored or not operational).
  void set_recovering(SlaveMask slaves) noexcept { recovering_ = slaves; }
  // `pdo_writes`: SDO writes its recovery made to bring its PDO mapping back to the plan (found[1]).
  void recovered(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time, std::uint32_t cause,
                 std::uint32_t pdo_writes = 0) noexcept;
  void recovery_event(LinkEventKind kind, SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time,
                      const std::array<std::uint32_t, 4>& found) noexcept;

  // Watchdog check (item 5): slaves found in SAFE-OP by their watchdog that the master has not yet
  // taken over for re-arming; the master takes them (clears the set) and says how it ended.
  SlaveMask take_rearm_requests() noexcept {
    const SlaveMask taken = rearm_requests_;
    rearm_requests_ = 0;
    return taken;
  }
  void rearmed(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time) noexcept;
  // It could not be brought back to OP: out of the exchange, reported not operational.
  void rearm_failed(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time, std::uint16_t al_status,
                    std::uint16_t al_code) noexcept;
  // Watchdog checks started, and slaves found in SAFE-OP by their watchdog.
  std::uint64_t watchdog_check_rounds() const noexcept { return watchdog_check_rounds_; }
  std::uint64_t watchdog_expiries() const noexcept { return watchdog_expiries_; }

  [[nodiscard]] bool pop_report(LinkReport& out) noexcept;

  SlaveMask in_exchange() const noexcept { return present_; }
  SlaveMask out_of_exchange() const noexcept { return out_; }
  SlaveMask lost() const noexcept { return lost_; }
  SlaveMask restored() const noexcept { return restored_; }
  SlaveMask suspects() const noexcept { return suspect_; }
  // Slaves whose inputs were exchanged by this cycle's frame.
  SlaveMask valid() const noexcept { return valid_; }
  std::uint16_t expected_wkc(std::size_t branch) const noexcept;
  // Probe rounds that found every suspect reachable and in OP (a transient shortfall).
  std::uint64_t glitches() const noexcept { return glitches_; }
  // AL status reads of the AL state watch so far (item 6).
  std::uint64_t watch_reads() const noexcept { return watch_reads_; }
  std::uint64_t reports_dropped() const noexcept { return reports_dropped_; }
  // Cycles whose frame did not come back by its deadline (late or missing), and the current run.
  std::uint64_t frames_missing() const noexcept { return frames_missing_; }
  std::uint32_t frames_missing_in_row() const noexcept { return frames_missing_in_row_; }
  // The link-silence alarm is raised (no frame back for kSilenceAlarm, none since), and how often it was.
  bool silence_alarm() const noexcept { return silence_reported_; }
  std::uint64_t silences() const noexcept { return silences_; }

 private:
  // True when the probe found a suspect silent (evidence of a loss, not yet confirmed).
  bool observe_probe(const ProbeResult& probe) noexcept;
  // The AL state watch's read of a slave in the exchange (item 6).
  void observe_watch(const ProbeResult& probe, SlaveMask bit) noexcept;
  // True when the probe (of a suspect or a watchdog check) found the slave in SAFE-OP by its watchdog.
  bool expired_by_watchdog(const ProbeResult& probe, SlaveMask bit) const noexcept;
  void observe_branches(const std::array<std::uint16_t, kMaxBranches>& branch_wkc) noexcept;
  void report(LinkEventKind kind, SlaveMask slaves, std::uint64_t detected_cycle, std::uint16_t al_status = 0,
              std::uint16_t al_code = 0, const std::array<std::uint32_t, 4>& found = {}) noexcept;

  const NetworkPlan& plan_;
  const ProcessImageLayout& layout_;
  SlaveMask present_{0};       // in the exchange, counted in the expected working counter
  SlaveMask counted_{0};       // slaves some branch's working counter counts (not junctions: no process data)
  SlaveMask out_{0};           // taken out: lost, not operational or restored
  SlaveMask lost_{0};          // out and unreachable when last probed
  SlaveMask restored_{0};      // out, was lost, answers again
  SlaveMask fmmus_cleared_{0}; // out slaves whose FMMU activation is confirmed off
  SlaveMask suspect_{0};       // to probe next frame
  SlaveMask valid_{0};
  // This frame's probes of slaves in the exchange: found silent, found reachable in OP. They place a
  // short working counter: a single slave out mid-branch (its drive power-cycled) is not a cut.
  SlaveMask probed_silent_{0};
  SlaveMask probed_in_op_{0};
  SlaveMask recovering_{0};    // online recovery works on them: no restoration probes
  SlaveMask watchdog_check_{0};  // in the exchange, to probe once after the master's silence (item 5)
  SlaveMask rearm_requests_{0};  // found in SAFE-OP by their watchdog, not yet taken by the master
  SlaveMask rearming_{0};        // found so, until rearmed() or rearm_failed()
  SlaveMask pending_expired_{0}; // found so by the current frame's probes (one report)
  SlaveMask pending_rearmed_{0}; // back in OP by the current frame's answers (one report)
  hal::Nanoseconds last_returned_{-1};  // send time of the last frame that came back
  hal::Nanoseconds silence_gap_{0};     // the gap that started the current watchdog check
  std::uint64_t watchdog_check_rounds_{0};
  std::uint64_t watchdog_expiries_{0};
  std::array<std::uint64_t, kMaxSlaves> suspect_since_{};  // cycle whose counter raised the suspicion
  // Returned frames in a row that showed the slave unreachable (counter, then silent probes).
  std::array<std::uint8_t, kMaxSlaves> silent_frames_{};
  std::uint64_t frames_missing_{0};
  std::uint32_t frames_missing_in_row_{0};
  hal::Nanoseconds silent_since_{0};        // time of the first frame of the current missing run
  std::uint64_t silent_since_cycle_{0};
  bool silence_reported_{false};
  std::uint64_t silences_{0};
  std::uint64_t cycle_{0};
  hal::Nanoseconds time_{0};
  std::size_t rotate_{0};
  std::size_t watch_rotate_{0};
  std::uint64_t watch_reads_{0};
  std::uint64_t glitches_{0};
  std::uint64_t reports_dropped_{0};
  bool redundant_{false};

  // Established by the current frame's probes, merged into one report per kind.
  SlaveMask pending_lost_{0};
  SlaveMask pending_restored_{0};
  std::uint64_t pending_detected_{0};  // earliest cycle whose counter showed a pending loss

  RingBuffer<LinkReport, kReportCapacity> reports_{};
};

}  // namespace rescue::ecat
