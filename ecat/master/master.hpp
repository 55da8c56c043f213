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
// Cycle (cycle(), once per period, no heap, no system call but the NIC's send/receive): a schedule
// of cyclic services (cyclic_service.hpp), each adding its datagrams to the one frame and handling
// its own answers; per slave, one record (slave_record.hpp):
//   frame = DC reference FRMW 0x0910 | process data LRW per branch | ring watch and DC across a break (redundant only) | link probes and AL watch |
//           re-integration | online recovery | ESC diagnostics | OP step | register read | AL states | rescan | mailbox
//   send, receive until the deadline, each answer to its service, then every service settles.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "ecat/dc/dc_cycle_sync.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/mailbox/mailbox_client.hpp"
#include "ecat/master/cyclic_service.hpp"
#include "ecat/master/dc_reference_service.hpp"
#include "ecat/master/esc_diagnostics_service.hpp"
#include "ecat/master/link_diagnostics.hpp"
#include "ecat/master/link_monitor.hpp"
#include "ecat/master/link_probe_service.hpp"
#include "ecat/master/mailbox_service.hpp"
#include "ecat/master/master_options.hpp"
#include "ecat/master/master_reports.hpp"
#include "ecat/master/op_step_service.hpp"
#include "ecat/master/pdo_setup_service.hpp"
#include "ecat/master/process_data_service.hpp"
#include "ecat/master/recovery_service.hpp"
#include "ecat/master/register_read_service.hpp"
#include "ecat/master/reintegration_service.hpp"
#include "ecat/master/rescan_service.hpp"
#include "ecat/master/ring_dc_service.hpp"
#include "ecat/master/ring_service.hpp"
#include "ecat/master/slave_record.hpp"
#include "ecat/master/slave_state_service.hpp"
#include "ecat/master/stamped_port.hpp"
#include "ecat/sii/sii_reader.hpp"

namespace rescue::ecat {

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

  // Cable redundancy (docs/redundancy.md): every frame also goes out on `ring`, the second master port
  // cabled to the segment's far end; the copies are merged (ecat/link/redundant_merge.hpp). Call
  // before bring_up(), which then refuses a ring that does not close. `ring` shares the NIC's clock.
  void use_ring(hal::Nic& ring) noexcept {
    ring_port_.attach(ring);
    ring_port_.stamp_sends();
    main_port_.stamp_sends();
    link_.set_ring(&ring_port_);
  }
  // The ring's state (RingState::none without a ring NIC) and its changes, each reported once.
  const RingStatus& ring_status() const noexcept { return ring_.monitor().status(); }
  [[nodiscard]] bool pop_ring_report(RingReport& out) noexcept { return ring_.pop_report(out); }
  // DC across a break: what the ring copy gives the clocks behind it (ring_dc_service.hpp).
  const RingDcStatus& ring_dc_status() const noexcept { return ring_dc_.status(); }
  // How long the sends of each port took (StampedPort): the part of a frame's departure the master
  // cannot see, which bounds the DC error across a break over a real link. Counted with a ring only.
  const StampedPort::SendDurations& send_durations(bool ring_port) const noexcept {
    return ring_port ? ring_port_.send_durations() : main_port_.send_durations();
  }

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
  SlaveMask not_in_op() const noexcept { return state_ == MasterState::op ? 0 : op_step_.pending(); }
  std::uint16_t op_al_status(std::size_t position) const noexcept { return slaves_[position].op.al_status; }
  std::uint16_t op_al_status_code(std::size_t position) const noexcept { return slaves_[position].op.al_code; }

  // Re-integration of restored slaves (the explicit action after a `restored` report): their
  // FMMUs are written again, an AL error is acknowledged and OP requested, one step per cycle;
  // a `reintegrated` report (or `reintegration_failed`) follows. False when a slave of `slaves`
  // is not restored or a re-integration is already running.
  [[nodiscard]] bool reintegrate(SlaveMask slaves) noexcept { return reintegration_.reintegrate(slaves); }

  // Online recovery (MasterOptions::online_recovery): where each slave stands, and the counters.
  RecoveryState recovery_state(std::size_t position) const noexcept { return slaves_[position].recovery.state(); }
  // When the slave's recovery state last changed (master clock; 0 = never since bring-up), and its
  // failed attempts in a row (each one doubles the hold-off before it searches again).
  hal::Nanoseconds recovery_changed_at(std::size_t position) const noexcept { return slaves_[position].recovery.changed_at; }
  std::uint8_t recovery_failures(std::size_t position) const noexcept { return slaves_[position].recovery.failures; }
  SlaveMask recovering() const noexcept { return recovery_.recovering(); }
  const RecoveryStats& recovery_stats() const noexcept { return recovery_.stats(); }
  // PDO mapping writes of the slave's last recovery (0: its mapping was as planned) and its reads.
  std::uint16_t recovery_pdo_writes(std::size_t position) const noexcept { return slaves_[position].pdo.writes(); }
  std::uint16_t recovery_pdo_reads(std::size_t position) const noexcept { return slaves_[position].pdo.reads(); }

  // Link diagnostics: error counters per slave and port (accumulated since bring-up). A rising
  // port is reported as a `port_errors` link report (found = port, peer slave, errors).
  const LinkDiagnostics& diagnostics() const noexcept { return diagnostics_.table(); }
  // Zeroes the link-diagnostics table of `slaves` now (between cycles, the owner's thread) and clears
  // their ESC error counters (0x0300-0x0313, written as a real ESC wants) with datagrams of the next
  // cyclic frames (sent again when a frame is lost): never blocks, no frame of its own.
  void reset_diagnostics(SlaveMask slaves) noexcept { diagnostics_.reset_slaves(slaves); }
  // Slaves whose ESC counters still wait for their clearing write (0 once the writes were answered).
  SlaveMask diagnostics_clear_pending() const noexcept { return diagnostics_.clear_pending(); }

  // ctl slaves -v: the identity a planned slave's SII gave at bring-up (nullptr when it did not
  // answer at its planned place), and the AL status register and code the master read last from it
  // (al_status_read(position): false when none was read since bring-up).
  const FoundSlave* identity(std::size_t position) const noexcept;
  // The SII image the master read from the planned slave at `position` at bring-up (as read: a
  // Strings category it skipped reads 0), or nullptr when no slave was identified there.
  const SiiImage* sii_image(std::size_t position) const noexcept;
  bool al_status_read(std::size_t position) const noexcept { return slaves_[position].al.read; }
  std::uint16_t last_al_status(std::size_t position) const noexcept { return slaves_[position].al.status; }
  std::uint16_t last_al_status_code(std::size_t position) const noexcept { return slaves_[position].al.code; }
  // Everything the master keeps about one planned slave (slave_record.hpp).
  const SlaveRecord& slave(std::size_t position) const noexcept { return slaves_[position]; }

  // Lost / restored / not operational reports, oldest first.
  [[nodiscard]] bool pop_report(LinkReport& out) noexcept { return monitor_.pop_report(out); }
  const LinkMonitor& monitor() const noexcept { return monitor_; }

  // Aperiodic CoE SDO transfers, one mailbox datagram pair per cycle (never blocking the cycle).
  MailboxClient& mailbox() noexcept { return mailbox_; }
  const MailboxClient& mailbox() const noexcept { return mailbox_; }

  // ctl reg_read: one ESC register read of a planned slave, by FPRD in the next cyclic frames
  // (register_read_service.hpp); false when one is under way or the arguments are out of range.
  // Its result is taken a period or more later (once).
  [[nodiscard]] bool request_register_read(std::size_t position, std::uint16_t address, std::uint16_t length) noexcept {
    return register_read_.request(position, address, length);
  }
  [[nodiscard]] bool take_register_read(RegisterReadResult& out) noexcept { return register_read_.take(out); }

  // ctl states: an AL state for slaves the owner judged out of service, by AL control writes and
  // status reads in the next cyclic frames (slave_state_service.hpp: below OP parks them, away from
  // the online recovery; OP hands them back to it). Its result is taken a period or more later (once).
  [[nodiscard]] SlaveStateService::Refusal request_slave_state(SlaveMask slaves, reg::AlState target) noexcept {
    return slave_states_.request(slaves, target);
  }
  [[nodiscard]] bool take_slave_state(SlaveStateResult& out) noexcept { return slave_states_.take(out); }
  SlaveMask parked() const noexcept { return slave_states_.parked(); }

  // ctl rescan: the segment identified again (SII by auto-increment position) and compared with the
  // plan, in the next cyclic frames (rescan_service.hpp). take_rescan() is true once when it is done;
  // rescan() then describes it until the next request.
  [[nodiscard]] RescanService::Refusal request_rescan() noexcept { return rescan_.request(); }
  [[nodiscard]] bool take_rescan() noexcept { return rescan_.take(); }
  const RescanService& rescan() const noexcept { return rescan_; }

  // Between cycles, in a frame of its own: every slave's DC time difference (0x092C).
  Result<DcSnapshot> read_dc_snapshot() noexcept;

  const NetworkPlan& plan() const noexcept { return plan_; }
  const ProcessImageLayout& layout() const noexcept { return layout_; }
  ByteSpan image() noexcept { return image_; }
  SlaveMask operated() const noexcept { return report_.match.operated; }
  // Slaves that answered at their planned place at bring-up (operated or held out of service).
  SlaveMask present() const noexcept { return report_.match.present; }
  const SlaveSetup& setup(std::size_t position) const noexcept { return slaves_[position].setup; }
  DatagramLink& link() noexcept { return link_; }
  const MasterOptions& options() const noexcept { return options_; }

 private:
  // Bring-up steps (master_bring_up.cpp).
  Status count_and_reset() noexcept;
  Status check_ring_closes() noexcept;  // redundant: the first contact's copies went round the ring
  Status identify() noexcept;
  Status assign_addresses() noexcept;
  Status configure_mailboxes() noexcept;
  Status configure_process_data() noexcept;
  Status run_startup_sdos() noexcept;
  Status set_up_pdo_mappings() noexcept;
  Status fail(const char* step, const Error& error) noexcept;
  // The owner asked to stop (MasterOptions::stop_requested): fails the bring-up before `step`.
  Status check_stop(const char* step) noexcept;
  // Distributed clocks (master_dc.cpp).
  Status configure_dc() noexcept;
  // Redundant only: the ring's end closed for the DC latch and reopened after it (master_dc.cpp).
  Result<std::uint32_t> close_ring_end() noexcept;
  Status reopen_ring_end(std::uint32_t before) noexcept;
  Status compensate_static_drift() noexcept;
  Status start_sync0() noexcept;
  // Cycle (master_cycle.cpp).
  // The cyclic frame's receive deadline and repeat limit (MasterOptions::cycle_receive_guard, cycle_repeat_guard).
  ExchangeDeadlines cycle_deadlines(hal::Nanoseconds sent_at) const noexcept;
  // The bring-up's match, into the slave records: each planned slave's identity as it answered.
  void record_identities() noexcept;

  hal::Nic& nic_;
  // The two ports as the link sends through them: each notes when it sent (RingDcService).
  StampedPort main_port_;
  StampedPort ring_port_;
  DatagramLink link_;
  const NetworkPlan& plan_;
  const ProcessImageLayout& layout_;
  ByteSpan image_;
  MasterOptions options_{};
  MasterState state_{MasterState::idle};
  BringUpReport report_{};
  SlaveRecords slaves_{};
  std::array<SiiImage, kMaxFoundSlaves> sii_{};  // bring-up scratch
  LinkMonitor monitor_;
  MailboxClient mailbox_;
  DcCycleSync dc_sync_{};
  std::uint64_t cycle_{0};
  hal::Nanoseconds next_wakeup_{0};
  std::uint64_t bring_up_frames_before_{0};  // link exchanges when bring_up began (step marks count from it)
  std::uint64_t overruns_{0};
  // Last reference time read (bring-up), to place the first wake-up.
  std::uint64_t last_reference_time_{0};
  hal::Nanoseconds last_reference_read_at_{0};
  std::uint16_t reference_station_{0};
  std::uint16_t ring_end_station_{0};  // the slave whose ring port close_ring_end closed
  SlaveMask dc_slaves_{0};

  // The cyclic services (cyclic_service.hpp) and their schedule (for_each_service): the order in
  // which they add their datagrams to each frame and settle after it. A new service: its member
  // here, a line in for_each_service.
  ServiceContext context_;
  DcReferenceService dc_reference_;
  ProcessDataService process_data_;
  RingService ring_;
  RingDcService ring_dc_;
  LinkProbeService probes_;
  ReintegrationService reintegration_;
  PdoSetupService pdo_setup_;
  RecoveryService recovery_;
  EscDiagnosticsService diagnostics_;
  OpStepService op_step_;
  RegisterReadService register_read_;
  SlaveStateService slave_states_;
  RescanService rescan_;
  MailboxService mailbox_service_;
  CycleFrame frame_{};

  // The schedule. Each call names a final class, so it is a direct call (no virtual dispatch in
  // the cycle but the answers' handles).
  template <typename Visit>
  void for_each_service(Visit&& visit) noexcept {
    visit(dc_reference_);
    visit(process_data_);
    visit(ring_);
    visit(ring_dc_);
    visit(probes_);
    visit(reintegration_);
    visit(pdo_setup_);
    visit(recovery_);
    visit(diagnostics_);
    visit(op_step_);
    visit(register_read_);
    visit(slave_states_);
    visit(rescan_);
    visit(mailbox_service_);
  }
};

}  // namespace rescue::ecat
