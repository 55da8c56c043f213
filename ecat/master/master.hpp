// The EtherCAT master: brings the planned network up (scan, compare, address, configure,
// distributed clocks, INIT -> PRE-OP -> SAFE-OP) and then exchanges the logical process image
// once per cycle, taking the network to OP in the first cycles, keeping the master's cycle in
// step with the DC reference, and detecting lost slaves from the working counters.
//
// Bring-up (blocking, at start-up; docs/master.md has the sequence diagram):
//   1. count      BRD 0x0000: working counter = slaves on the wire
//   2. reset      BWR: AL control INIT+ack, FMMUs and SMs off, DC sync off, DC filters, SII to ECAT
//   3. identify   SII of every slave in parallel (APWR/APRD 0x0502..0x050F), parsed
//   4. compare    with the plan (slaves held out of service may be absent); every difference
//                 reported; fatal ones refuse to run
//   5. address    APWR 0x0010 = planned station address of every present slave, held-out ones
//                 included (a lost slave never shifts the others)
//   6. INIT       confirmed; mailbox SM0/SM1 from SII; PRE-OP
//   7. PRE-OP     start-up SDOs: each slave's PDO assignment and mapping (SlavePlan::pdo) read and,
//                 where it differs, written and read back (ecat/master/pdo_setup.hpp); then the
//                 owner's (MasterOptions::startup_sdos); SM2/SM3, FMMU0 (outputs) / FMMU1 (inputs) onto the image; DC over every present
//                 slave (held-out ones answer and forward frames): latch 0x0900,
//                 read port times, delays through the tree, offsets 0x0920 and delays 0x0928,
//                 static drift compensation (FRMW 0x0910 N times), SYNC0 (0x0981/0x0990/0x09A0)
//   8. SAFE-OP    requested and confirmed
// Cycle (cycle(), once per period, no heap, no system call but the NIC's send/receive):
//   frame = FRMW reference 0x0910 | LRW per branch | probes | service (AL control, mailbox)
//   send, receive until the deadline, check the working counters, copy inputs into the image.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "core/containers/fixed_vector.hpp"
#include "ecat/dc/dc_cycle_sync.hpp"
#include "ecat/dc/dc_delay.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/al_control.hpp"
#include "ecat/master/link_diagnostics.hpp"
#include "ecat/master/link_monitor.hpp"
#include "ecat/master/network_match.hpp"
#include "ecat/master/pdo_setup.hpp"
#include "ecat/master/slave_recovery.hpp"
#include "ecat/sii/sii_cache.hpp"
#include "ecat/sii/sii_reader.hpp"

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

// What one SyncManager of a slave looks like, from its SII.
struct SyncManagerSetup {
  std::uint16_t start{0};
  std::uint16_t length{0};
  std::uint8_t control{0};
  bool present{false};
};

struct SlaveSetup {
  std::array<SyncManagerSetup, 4> sm{};  // 0 mailbox out, 1 mailbox in, 2 outputs, 3 inputs
  bool mailbox{false};                   // standard mailbox present, CoE supported
  bool complete_access{false};           // SII general: SDO complete access supported
};

// Where bring-up time goes: when each step began and how many frames had been exchanged by then.
struct BringUpStepMark {
  const char* step{nullptr};
  hal::Nanoseconds at{0};
  std::uint64_t frames{0};
};
constexpr std::size_t kBringUpSteps = 12;

struct BringUpReport {
  const char* failed_step{nullptr};  // nullptr when bring-up succeeded
  std::array<BringUpStepMark, kBringUpSteps> steps{};  // in order; steps[step_count - 1] is the last begun
  std::uint8_t step_count{0};
  Error error{};
  std::uint16_t slaves_counted{0};
  std::uint32_t first_contact_frames{0};  // count BRDs sent until one came back
  FixedVector<FoundSlave, kMaxFoundSlaves> found{};
  NetworkMatch match{};
  AlFailure al_failure{};
  SiiReadStats sii{};
  SdoCompletion failed_sdo{};            // when the failed step is "PRE-OP SDO"
  std::uint32_t startup_sdos_done{0};
  // PDO mapping set-up (pdo_setup.hpp): transfers in all, and the slaves whose mapping was rewritten.
  std::uint32_t pdo_reads{0};
  std::uint32_t pdo_writes{0};
  SlaveMask pdo_rewritten{0};
  DcDelays delays{};
  std::uint32_t dc_max_difference_ns{0};  // max |0x092C| after static drift compensation
  std::uint32_t dc_static_frames{0};      // static drift compensation frames sent
  std::uint64_t sync0_start{0};           // system time of the first SYNC0
  hal::Nanoseconds started_at{0};
  hal::Nanoseconds safe_op_at{0};
  hal::Nanoseconds op_at{0};              // set by cycle() when every slave reached OP
  std::uint64_t frames{0};                // frames exchanged during bring-up
};

struct CycleResult {
  std::uint64_t cycle{0};
  MasterState state{MasterState::idle};
  bool frame_received{false};
  hal::Nanoseconds sent_at{0};
  hal::Nanoseconds received_at{0};
  SlaveMask valid{0};        // slaves whose inputs this frame brought
  SlaveMask out{0};          // slaves out of the exchange (not operated, lost, not operational, restored)
  std::array<std::uint16_t, kMaxBranches> branch_wkc{};
  std::array<std::uint16_t, kMaxBranches> expected_wkc{};
  std::uint64_t reference_time{0};       // DC system time of the reference as the frame passed it
  hal::Nanoseconds dc_phase_error{0};    // frame's phase error in the SYNC0 period
  hal::Nanoseconds next_wakeup{0};       // when to call cycle() next (master clock)
};

// Online recovery's counters (for tests, benches and the docs' figures).
struct RecoveryStats {
  std::uint64_t datagrams{0};            // recovery datagrams sent in all
  std::uint32_t max_datagrams_per_cycle{0};
  std::uint32_t recovered{0};
  std::uint32_t refused{0};
  std::uint32_t failed{0};
  std::uint64_t table_refusals{0};       // (state, input) pairs without a row (a bug if ever non-zero)
};

// Per-slave DC diagnostics (acyclic; for benchmarks and tests, between cycles).
struct DcSnapshot {
  std::array<std::uint32_t, kMaxSlaves> difference_ns{};  // |0x092C|
  SlaveMask answered{0};
  std::uint32_t max_difference_ns{0};
};

class Master {
 public:
  Master(hal::Nic& nic, const NetworkPlan& plan, const ProcessImageLayout& layout, ByteSpan image) noexcept;
  Master(const Master&) = delete;
  Master& operator=(const Master&) = delete;
  Master(Master&&) = delete;
  Master& operator=(Master&&) = delete;
  ~Master() = default;

  // Frames sent and received are also handed to `tap` (capture writer).
  void set_tap(FrameTapFn tap, void* context) noexcept { link_.set_tap(tap, context); }

  // Blocking bring-up to SAFE-OP with distributed clocks running. On failure the report says
  // which step and why (network differences, AL status codes).
  Status bring_up(const MasterOptions& options) noexcept;
  const BringUpReport& report() const noexcept { return report_; }

  // One cycle: call at next_wakeup(). The caller writes outputs into the image before and reads
  // inputs after (only those of `valid` slaves are fresh).
  CycleResult cycle() noexcept;
  hal::Nanoseconds next_wakeup() const noexcept { return next_wakeup_; }
  // Moves next_wakeup() to the first period start after now, in the same phase, without counting the
  // periods passed as skipped: call once before the first cycle of a periodic loop that starts some
  // time after the bring-up (that time is start-up, not missed periods).
  void realign_schedule() noexcept;
  MasterState state() const noexcept { return state_; }
  std::uint64_t cycles() const noexcept { return cycle_; }
  // Periods that had no cycle: a cycle that ended (or a wake-up that came) after the next period's
  // start skips whole periods to keep the phase. cycles() + skipped_periods() is the number of
  // periods since the first cycle, so a 2 s run at 1 ms that made 1964 cycles shows 36 here.
  std::uint64_t skipped_periods() const noexcept { return overruns_; }
  // Before OP (going to OP): the slaves not yet confirmed in OP, and the AL status and code each
  // last answered (0 when not read yet).
  SlaveMask not_in_op() const noexcept { return state_ == MasterState::op ? 0 : op_pending_; }
  std::uint16_t op_al_status(std::size_t position) const noexcept { return op_al_status_[position]; }
  std::uint16_t op_al_status_code(std::size_t position) const noexcept { return op_al_code_[position]; }

  // Re-integration of restored slaves (the explicit action after a `restored` report): their
  // FMMUs are written again, an AL error is acknowledged and OP requested, one step per cycle;
  // a `reintegrated` report (or `reintegration_failed`) follows. False when a slave of `slaves`
  // is not restored or a re-integration is already running.
  [[nodiscard]] bool reintegrate(SlaveMask slaves) noexcept;

  // Online recovery (MasterOptions::online_recovery): where each slave stands, and the counters.
  RecoveryState recovery_state(std::size_t position) const noexcept { return recovery_[position].state; }
  // When the slave's recovery state last changed (master clock; 0 = never since bring-up), and its
  // failed attempts in a row (each one doubles the hold-off before it searches again).
  hal::Nanoseconds recovery_changed_at(std::size_t position) const noexcept { return recovery_[position].changed_at; }
  std::uint8_t recovery_failures(std::size_t position) const noexcept { return recovery_[position].failures; }
  SlaveMask recovering() const noexcept;
  const RecoveryStats& recovery_stats() const noexcept { return recovery_stats_; }
  // PDO mapping writes of the slave's last recovery (0: its mapping was as planned) and its reads.
  std::uint16_t recovery_pdo_writes(std::size_t position) const noexcept { return pdo_setup_[position].writes(); }
  std::uint16_t recovery_pdo_reads(std::size_t position) const noexcept { return pdo_setup_[position].reads(); }

  // Link diagnostics: error counters per slave and port (accumulated since bring-up). A rising
  // port is reported as a `port_errors` link report (found = port, peer slave, errors).
  const LinkDiagnostics& diagnostics() const noexcept { return diagnostics_; }
  // Zeroes the link-diagnostics table of `slaves` now (between cycles, the owner's thread) and clears
  // their ESC error counters (0x0300-0x0313, written as a real ESC wants) with datagrams of the next
  // cyclic frames (sent again when a frame is lost): never blocks, no frame of its own.
  void reset_diagnostics(SlaveMask slaves) noexcept;
  // Slaves whose ESC counters still wait for their clearing write (0 once the writes were answered).
  SlaveMask diagnostics_clear_pending() const noexcept { return diag_clear_pending_ | diag_clear_in_flight_; }

  // ctl slaves -v: the identity a planned slave's SII gave at bring-up (nullptr when it did not
  // answer at its planned place), and the AL status register and code the master read last from it
  // (al_status_read(position): false when none was read since bring-up).
  const FoundSlave* identity(std::size_t position) const noexcept;
  bool al_status_read(std::size_t position) const noexcept { return (al_read_ & slave_bit(position)) != 0; }
  std::uint16_t last_al_status(std::size_t position) const noexcept { return al_status_[position]; }
  std::uint16_t last_al_status_code(std::size_t position) const noexcept { return al_code_[position]; }

  // Lost / restored / not operational reports, oldest first.
  [[nodiscard]] bool pop_report(LinkReport& out) noexcept { return monitor_.pop_report(out); }
  const LinkMonitor& monitor() const noexcept { return monitor_; }

  // Aperiodic CoE SDO transfers, one mailbox datagram pair per cycle (never blocking the cycle).
  MailboxClient& mailbox() noexcept { return mailbox_; }

  // Between cycles, in a frame of its own: every slave's DC time difference (0x092C).
  Result<DcSnapshot> read_dc_snapshot() noexcept;

  const NetworkPlan& plan() const noexcept { return plan_; }
  const ProcessImageLayout& layout() const noexcept { return layout_; }
  ByteSpan image() noexcept { return image_; }
  SlaveMask operated() const noexcept { return report_.match.operated; }
  // Slaves that answered at their planned place at bring-up (operated or held out of service).
  SlaveMask present() const noexcept { return report_.match.present; }
  const SlaveSetup& setup(std::size_t position) const noexcept { return setup_[position]; }
  DatagramLink& link() noexcept { return link_; }
  const MasterOptions& options() const noexcept { return options_; }

 private:
  // Bring-up steps (master_bring_up.cpp).
  Status count_and_reset() noexcept;
  Status identify() noexcept;
  Status assign_addresses() noexcept;
  Status configure_mailboxes() noexcept;
  Status configure_process_data() noexcept;
  Status run_startup_sdos() noexcept;
  Status set_up_pdo_mappings() noexcept;
  Status fail(const char* step, const Error& error) noexcept;
  // A slave's configuration blocks as at bring-up, written to `out`: SM0/SM1 (mailbox) and SM2/SM3
  // (2 x 8 bytes each), FMMU0/FMMU1 (2 x 16 bytes).
  void fill_mailbox_sms(std::size_t position, std::uint8_t* out) const noexcept;
  void fill_process_data_sms(std::size_t position, std::uint8_t* out) const noexcept;
  void fill_fmmus(std::size_t position, std::uint8_t* out) const noexcept;
  // The owner asked to stop (MasterOptions::stop_requested): fails the bring-up before `step`.
  Status check_stop(const char* step) noexcept;
  // Distributed clocks (master_dc.cpp).
  Status configure_dc() noexcept;
  Status compensate_static_drift() noexcept;
  Status start_sync0() noexcept;
  // Cycle (master_cycle.cpp).
  void build_cycle_frame(FrameBuilder& frame) noexcept;
  void evaluate_cycle_frame(const FrameView& frame, CycleResult& result) noexcept;
  void step_op_transition(CycleResult& result) noexcept;
  hal::Nanoseconds cycle_receive_deadline(hal::Nanoseconds sent_at) const noexcept;  // MasterOptions::cycle_receive_guard
  void silence_outputs_of_out_slaves() noexcept;
  // Online recovery (master_recovery.cpp).
  void add_recovery_datagrams(FrameBuilder& frame) noexcept;
  bool add_recovery_step(FrameBuilder& frame, std::size_t position) noexcept;
  bool add_search(FrameBuilder& frame) noexcept;
  void on_recovery_datagram(std::size_t position, const DatagramView& datagram) noexcept;
  void on_search_datagram(std::size_t position, const DatagramView& datagram) noexcept;
  void step_recovery() noexcept;
  void recovery_input(std::size_t position, RecoveryInput input) noexcept;
  void enter_recovery_state(std::size_t position, RecoveryState state) noexcept;
  void check_identity(std::size_t position) noexcept;
  // The slave being searched for whose bring-up identity is this device's (kMaxSlaves: none).
  std::size_t owner_of_identity(std::size_t finder) const noexcept;
  hal::Nanoseconds hold_off(std::uint8_t failures) const noexcept;
  // The auto-increment places the slave may be at: `first` slaves before it surely answer, up to
  // `unknown` more may (searched for, or waiting after a failure).
  struct Places {
    std::uint16_t first{0};
    std::uint16_t unknown{0};
  };
  Places expected_places(std::size_t position) const noexcept;
  // Re-integration (master_reintegration.cpp).
  void add_reintegration_datagrams(FrameBuilder& frame) noexcept;
  void on_reintegration_datagram(std::size_t position, const DatagramView& datagram) noexcept;
  void finish_reintegration_step() noexcept;
  // An answer of FPRD 0x0130 (AL status, reserved, AL status code) from slave `p`: kept for identity()'s
  // neighbours last_al_status / last_al_status_code (ctl slaves -v).
  void note_al_status(std::size_t p, const std::uint8_t* data) noexcept;
  // Re-arming slaves the watchdog check found in SAFE-OP by their watchdog (same steps, from the
  // acknowledge; they stay in the exchange meanwhile).
  void start_rearm(SlaveMask slaves) noexcept;

  enum class Role : std::uint8_t {
    reference_time,
    branch,
    probe_status,
    probe_clear,
    al_control,
    al_status,
    mailbox,
    reintegration,
    recovery,
    search,
    diagnostics,
    diagnostics_clear,  // param: the slave, or kMaxSlaves for a broadcast write to every slave
  };
  struct Planned {
    Role role;
    std::uint8_t param;  // branch or slave position
  };

  hal::Nic& nic_;
  DatagramLink link_;
  const NetworkPlan& plan_;
  const ProcessImageLayout& layout_;
  ByteSpan image_;
  MasterOptions options_{};
  MasterState state_{MasterState::idle};
  BringUpReport report_{};
  std::array<SlaveSetup, kMaxSlaves> setup_{};
  std::array<SiiImage, kMaxFoundSlaves> sii_{};  // bring-up scratch
  LinkMonitor monitor_;
  LinkDiagnostics diagnostics_;
  MailboxClient mailbox_;
  DcCycleSync dc_sync_{};

  // Cycle state.
  std::uint64_t cycle_{0};
  hal::Nanoseconds next_wakeup_{0};
  std::array<Planned, kMaxDatagramsPerFrame> planned_{};
  std::size_t planned_count_{0};
  std::array<ProbeRequest, kMaxSlaves> probes_{};
  std::array<ProbeResult, kMaxSlaves> probe_results_{};
  std::size_t probe_count_{0};
  // SAFE-OP -> OP while cycling, per slave: write OP, watch AL status, acknowledge a refusal
  // (in a frame of its own: the slave reads AL control asynchronously) and write OP again.
  enum class OpStep : std::uint8_t { request, wait, acknowledge };
  SlaveMask op_pending_{0};        // slaves not yet confirmed in OP
  std::array<OpStep, kMaxSlaves> op_step_{};
  std::array<std::uint8_t, kMaxSlaves> op_refusals_{};
  std::array<std::uint16_t, kMaxSlaves> op_al_status_{};
  std::array<std::uint16_t, kMaxSlaves> op_al_code_{};
  // The AL status and code last read from each slave (probes, the OP transition), al_read_: read once.
  std::array<std::uint16_t, kMaxSlaves> al_status_{};
  std::array<std::uint16_t, kMaxSlaves> al_code_{};
  SlaveMask al_read_{0};
  // reset_diagnostics: slaves whose ESC counters wait for their clearing write, and those written
  // in the frame under way (back to pending when it is lost or a write is not answered).
  SlaveMask diag_clear_pending_{0};
  SlaveMask diag_clear_in_flight_{0};
  hal::Nanoseconds op_deadline_{0};
  std::uint64_t bring_up_frames_before_{0};  // link exchanges when bring_up began (step marks count from it)
  // Re-integration, per slave: FMMUs, AL status, acknowledge, OP request.
  enum class ReStep : std::uint8_t { fmmus, status, acknowledge, request_op };
  SlaveMask reintegrating_{0};
  SlaveMask rearming_{0};  // re-arming after the watchdog check (link_monitor.hpp, item 5)
  std::array<ReStep, kMaxSlaves> re_step_{};
  hal::Nanoseconds re_deadline_{0};
  hal::Nanoseconds rearm_deadline_{0};
  // Online recovery, per slave.
  struct Recovery {
    RecoveryState state{RecoveryState::idle};
    std::uint8_t sub{0};             // step within the state
    std::uint8_t silent{0};          // datagrams in a row with working counter 0
    std::uint8_t words{0};           // SII words 0x08.. read so far
    bool acknowledge{false};         // next AL control write acknowledges an error
    bool withdraw{false};            // searching: first write its station address back to 0
    bool lost_address{false};        // found with station address 0: its power was cycled
    bool by_address{false};          // searching: the next search reads 0x0010 by its own station address
    std::uint8_t scan{0};            // searching: which of its possible places the next APRD reads
    std::uint16_t handover{0};       // withdrawing: the station address written instead of 0 (the device's owner)
    std::uint8_t failures{0};        // failed attempts in a row (back-off), 0 after a recovery
    std::uint8_t bounces{0};         // attempts in a row that lost the device again (gone)
    hal::Nanoseconds changed_at{0};  // when it entered its current state
    std::uint16_t adp{0};            // auto-increment address it was found at
    std::uint8_t sdos_pending{0};    // start-up SDOs: the owner's transfer in flight (0 or 1)
    std::uint16_t sdo_next{0};       // the next of options_.startup_sdos to look at
    bool sdo_refused{false};
    hal::Nanoseconds deadline{0};
    std::array<std::uint16_t, 8> sii{};  // SII words 0x08..0x0F
    std::uint64_t offset{0};         // new system time offset (clock)
    std::uint64_t started_cycle{0};
  };
  std::array<Recovery, kMaxSlaves> recovery_{};
  std::array<PdoSetup, kMaxSlaves> pdo_setup_{};  // bring-up and recovery: each slave's PDO mapping
  // Online recovery's start-up SDOs: submits what may go now (each slave one transfer at a time).
  void feed_recovery_sdos(std::size_t position) noexcept;
  bool recovery_sdos_done(std::size_t position) const noexcept;
  std::size_t sdo_rotate_{0};

  RecoveryStats recovery_stats_{};
  std::size_t recovery_rotate_{0};
  std::size_t search_rotate_{0};
  std::uint32_t recovery_datagrams_this_cycle_{0};
  std::uint64_t frame_reference_time_{0};   // this cycle's reference read (0: none yet)
  std::uint64_t latest_reference_time_{0};  // the last one read (building a frame: the previous cycle's)
  std::uint64_t overruns_{0};
  // Last reference time read (bring-up), to place the first wake-up.
  std::uint64_t last_reference_time_{0};
  hal::Nanoseconds last_reference_read_at_{0};
  std::uint16_t reference_station_{0};
  SlaveMask dc_slaves_{0};
};

}  // namespace rescue::ecat
