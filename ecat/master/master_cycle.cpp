// Master cycle: one frame per period, built, sent, received with a deadline and evaluated.
// No heap, no system call but the NIC's send and receive, bounded loops only.
#include <algorithm>
#include <cstring>

#include "ecat/master/master.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/slave_config.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kAlStatusReadLength = 6;  // status, reserved, code
constexpr std::size_t kProbeBytes = 2 * kDatagramOverhead + kAlStatusReadLength + kFmmuActivationOffLength;
constexpr std::array<std::uint8_t, kFmmuActivationOffLength> kZeros{};
constexpr std::size_t kOpStatusBytes = kDatagramOverhead + kAlStatusReadLength;
constexpr std::size_t kMailboxReserve = 2 * kDatagramOverhead + 1 + 256;
constexpr std::size_t kDiagnosticsBytes = kDatagramOverhead + LinkDiagnostics::kReadLength;
constexpr std::uint16_t kReadWriteWkc = 3;  // FPRW: read (1) + write (2)
constexpr std::array<std::uint8_t, LinkDiagnostics::kReadLength> kCounterClear{};
// ctl diag --reset: one slave's counters cleared by FPWR, more than this many by one BWR to every slave.
constexpr int kMaxClearWritesPerFrame = 3;

int count_bits(SlaveMask m) noexcept {
  int n = 0;
  for (; m != 0; m &= m - 1) ++n;
  return n;
}

}  // namespace

void Master::silence_outputs_of_out_slaves() noexcept {
  // Slaves not operated or taken out of the exchange get all-zero outputs (controlword 0:
  // disable voltage): should one answer again before its FMMUs are off, it receives no motion.
  const SlaveMask silent = ~operated() | monitor_.out_of_exchange();
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((silent & slave_bit(p)) == 0 || plan_[p].output_bytes == 0) continue;
    std::memset(image_.data() + layout_.slaves[p].output_offset, 0, plan_[p].output_bytes);
  }
}

void Master::build_cycle_frame(FrameBuilder& frame) noexcept {
  planned_count_ = 0;
  probe_count_ = 0;
  const std::uint8_t index = link_.index();
  // Capacity was checked at start-up (the frame with every branch always fits), so the adds of
  // the fixed part cannot fail; the optional parts are added only while they fit.
  const auto note = [&](Role role, std::size_t param, bool added) {
    if (added) planned_[planned_count_++] = Planned{role, static_cast<std::uint8_t>(param)};
  };
  note(Role::reference_time, 0,
       frame.add(Command::FRMW, index, make_address(reference_station_, reg::kDcSystemTime), 8).ok());
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    const BranchLayout& branch = layout_.branches[b];
    if (branch.length == 0) continue;
    note(Role::branch, b,
         frame.add(Command::LRW, index, branch.logical_start, branch.length,
                   ConstByteSpan(image_.data() + branch.logical_start, branch.length)).ok());
  }
  // Optional datagrams leave room for a mailbox step.
  const auto fits = [&](std::size_t bytes) { return frame.remaining_data_capacity() >= bytes + kMailboxReserve; };
  if (state_ == MasterState::op) {
    probe_count_ = monitor_.plan_probes(probes_.data(), probes_.size());
    std::size_t kept = 0;
    for (std::size_t i = 0; i < probe_count_ && fits(kProbeBytes); ++i, ++kept) {
      const ProbeRequest& probe = probes_[i];
      const std::uint16_t station = plan_[probe.position].station_address;
      probe_results_[i] = ProbeResult{probe.position, probe.clear_fmmus, probe.watch, 0, 0, 0, 0};
      note(Role::probe_status, i, frame.add(Command::FPRD, index, make_address(station, reg::kAlStatus), kAlStatusReadLength).ok());
      if (probe.clear_fmmus) {
        note(Role::probe_clear, i,
             frame.add(Command::FPWR, index, make_address(station, kFmmuActivationOffAddress), kFmmuActivationOffLength,
                       ConstByteSpan(kZeros)).ok());
      }
    }
    probe_count_ = kept;  // the rest are asked for again next cycle
    add_reintegration_datagrams(frame);
    add_recovery_datagrams(frame);
    // ctl diag --reset: the ESC counters of the reset slaves are cleared by writing them (ET1100
    // datasheet: a write to any of 0x0300-0x030B clears those twelve, to 0x0310-0x0313 the lost-link
    // counters, to 0x030C / 0x030D that counter), ahead of the round robin's read in the same frame.
    diag_clear_pending_ |= diag_clear_in_flight_;  // the last frame's writes were not all answered
    diag_clear_in_flight_ = 0;
    if (count_bits(diag_clear_pending_) > kMaxClearWritesPerFrame) {
      if (fits(kDiagnosticsBytes)) {
        note(Role::diagnostics_clear, kMaxSlaves,
             frame.add(Command::BWR, index, make_address(0, reg::kRxErrorCounter), LinkDiagnostics::kReadLength,
                       ConstByteSpan(kCounterClear)).ok());
        diag_clear_in_flight_ = diag_clear_pending_;
        diag_clear_pending_ = 0;
      }
    } else {
      for (std::size_t p = 0; p < kMaxSlaves && diag_clear_pending_ != 0; ++p) {
        if ((diag_clear_pending_ & slave_bit(p)) == 0 || !fits(kDiagnosticsBytes)) continue;
        note(Role::diagnostics_clear, p,
             frame.add(Command::FPWR, index, make_address(plan_[p].station_address, reg::kRxErrorCounter),
                       LinkDiagnostics::kReadLength, ConstByteSpan(kCounterClear)).ok());
        diag_clear_in_flight_ |= slave_bit(p);
        diag_clear_pending_ &= ~slave_bit(p);
      }
    }
    if (options_.diag_interval_cycles != 0 && cycle_ % options_.diag_interval_cycles == 0 && fits(kDiagnosticsBytes)) {
      const std::size_t p = diagnostics_.next(monitor_.in_exchange());
      if (p < kMaxSlaves) {
        note(Role::diagnostics, p,
             frame.add(Command::FPRW, index, make_address(plan_[p].station_address, reg::kRxErrorCounter),
                       LinkDiagnostics::kReadLength, ConstByteSpan(kCounterClear)).ok());
      }
    }
  } else if (state_ == MasterState::going_op) {
    std::array<std::uint8_t, 2> value{};
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((op_pending_ & slave_bit(p)) == 0 || !fits(kOpStatusBytes)) continue;
      const std::uint16_t station = plan_[p].station_address;
      if (op_step_[p] == OpStep::wait) {
        note(Role::al_status, p, frame.add(Command::FPRD, index, make_address(station, reg::kAlStatus), kAlStatusReadLength).ok());
        continue;
      }
      const auto control = op_step_[p] == OpStep::acknowledge
                               ? static_cast<std::uint16_t>(static_cast<std::uint16_t>(reg::AlState::safe_op) | reg::kAlErrorBit)
                               : static_cast<std::uint16_t>(reg::AlState::op);
      store_le16(value.data(), control);
      note(Role::al_control, p, frame.add(Command::FPWR, index, make_address(station, reg::kAlControl), 2, ConstByteSpan(value)).ok());
    }
  }
  const std::size_t mailbox_datagrams = mailbox_.add_datagrams(frame, index, link_.clock().now(), kCyclicMailboxSlaves);
  for (std::size_t k = 0; k < mailbox_datagrams; ++k) note(Role::mailbox, k, true);
}

void Master::evaluate_cycle_frame(const FrameView& frame, CycleResult& result) noexcept {
  std::size_t i = 0;
  for (const DatagramView d : frame) {
    if (i >= planned_count_) break;
    const Planned what = planned_[i++];
    const std::uint8_t* data = d.data().data();
    switch (what.role) {
      case Role::reference_time:
        if (d.wkc() != 0) result.reference_time = load_le64(data);
        frame_reference_time_ = result.reference_time;
        if (result.reference_time != 0) latest_reference_time_ = result.reference_time;
        break;
      case Role::branch: {
        const BranchLayout& branch = layout_.branches[what.param];
        result.branch_wkc[what.param] = d.wkc();
        // Inputs only: the outputs part comes back as sent. Slaves the frame did not reach
        // leave their bytes as they were, so stale values stay and `valid` says so.
        std::memcpy(image_.data() + branch.logical_start + branch.output_length, data + branch.output_length,
                    static_cast<std::size_t>(branch.length - branch.output_length));
        break;
      }
      case Role::probe_status: {
        ProbeResult& r = probe_results_[what.param];
        r.status_wkc = d.wkc();
        r.al_status = load_le16(data);
        r.al_status_code = load_le16(data + 4);
        if (d.wkc() == 1) note_al_status(r.position, data);
        break;
      }
      case Role::probe_clear:
        probe_results_[what.param].clear_wkc = d.wkc();
        break;
      case Role::al_control:
        if (d.wkc() == 1) {
          const std::size_t p = what.param;
          op_step_[p] = op_step_[p] == OpStep::acknowledge ? OpStep::request : OpStep::wait;
        }
        break;
      case Role::al_status: {
        const std::size_t p = what.param;
        const std::uint16_t status = load_le16(data);
        if (d.wkc() != 1) break;
        op_al_status_[p] = status;
        op_al_code_[p] = load_le16(data + 4);
        note_al_status(p, data);
        if ((status & reg::kAlErrorBit) == 0 && (status & reg::kAlStateMask) == static_cast<std::uint16_t>(reg::AlState::op)) {
          op_pending_ &= ~slave_bit(p);
        } else if ((status & reg::kAlErrorBit) != 0) {
          report_.al_failure = AlFailure{static_cast<std::uint8_t>(p), reg::AlState::op, status, load_le16(data + 4), false, false};
          if (++op_refusals_[p] <= options_.al.retries) op_step_[p] = OpStep::acknowledge;
        }
        break;
      }
      case Role::mailbox:
        mailbox_.on_datagram(what.param, d);
        break;
      case Role::reintegration:
        on_reintegration_datagram(what.param, d);
        break;
      case Role::recovery:
        on_recovery_datagram(what.param, d);
        break;
      case Role::search:
        on_search_datagram(what.param, d);
        break;
      case Role::diagnostics:
        // A slave reset but not yet cleared in its ESC: its answer holds errors from before the reset.
        if (d.wkc() == kReadWriteWkc && (diag_clear_pending_ & slave_bit(what.param)) == 0) {
          diagnostics_.observe(what.param, data, cycle_, link_.clock().now());
        }
        break;
      case Role::diagnostics_clear:
        // Written: done. Not answered (a lost slave, a cut): written again next frame, unless the
        // slave is out of the exchange (it is cleared when it is read again after its recovery).
        if (what.param >= kMaxSlaves) {
          if (d.wkc() != 0) diag_clear_in_flight_ = 0;
        } else if (d.wkc() != 0 || (monitor_.in_exchange() & slave_bit(what.param)) == 0) {
          diag_clear_in_flight_ &= ~slave_bit(what.param);
        }
        break;
    }
  }
}

void Master::step_op_transition(CycleResult& result) noexcept {
  const hal::Nanoseconds now = link_.clock().now();
  if (op_pending_ == 0) {
    state_ = MasterState::op;
    report_.op_at = now;
    monitor_.start(operated());
  } else if (now > op_deadline_) {
    // Stay in SAFE-OP, exchanging inputs; the report names the slave that did not follow.
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((op_pending_ & slave_bit(p)) == 0) continue;
      if (report_.al_failure.position != p) report_.al_failure = AlFailure{static_cast<std::uint8_t>(p), reg::AlState::op, 0, 0, true, false};
      break;
    }
    report_.failed_step = "OP";
    report_.error = make_error(Errc::timeout, "network did not reach OP", report_.al_failure.position);
    // Keep trying (a bring-up is never given up here: the owner has the limit): every slave not in
    // OP is acknowledged and asked again, with a new deadline.
    for (std::size_t p = 0; p < kMaxSlaves; ++p) {
      if ((op_pending_ & slave_bit(p)) == 0) continue;
      op_step_[p] = OpStep::acknowledge;
      op_refusals_[p] = 0;
    }
    op_deadline_ = now + options_.op_timeout;
  }
  result.state = state_;
}

void Master::note_al_status(std::size_t p, const std::uint8_t* data) noexcept {
  if (p >= kMaxSlaves) return;
  al_status_[p] = load_le16(data);
  al_code_[p] = load_le16(data + 4);
  al_read_ |= slave_bit(p);
}

void Master::reset_diagnostics(SlaveMask slaves) noexcept {
  SlaveMask planned = 0;
  for (std::size_t p = 0; p < plan_.size() && p < kMaxSlaves; ++p) planned |= slave_bit(p);
  slaves &= planned;
  diagnostics_.reset_slaves(slaves);
  diag_clear_pending_ |= slaves;
}

const FoundSlave* Master::identity(std::size_t position) const noexcept {
  if (position >= kMaxSlaves || (report_.match.present & slave_bit(position)) == 0) return nullptr;
  const std::uint8_t found = report_.match.found_of_slot[position];
  return found < report_.found.size() ? &report_.found[found] : nullptr;
}

void Master::realign_schedule() noexcept {
  const hal::Nanoseconds now = link_.clock().now();
  if (next_wakeup_ > now || options_.cycle_time <= 0) return;
  next_wakeup_ += ((now - next_wakeup_) / options_.cycle_time + 1) * options_.cycle_time;
}

hal::Nanoseconds Master::cycle_receive_deadline(hal::Nanoseconds sent_at) const noexcept {
  // next_wakeup_ is still this period's start: the next period's send is one cycle_time later.
  hal::Nanoseconds deadline = next_wakeup_ + options_.cycle_time - options_.cycle_receive_guard;
  deadline = std::min(deadline, sent_at + options_.cycle_time);
  return std::max(deadline, sent_at + options_.cycle_receive_timeout);
}

CycleResult Master::cycle() noexcept {
  CycleResult result;
  result.cycle = ++cycle_;
  result.state = state_;
  if (state_ != MasterState::going_op && state_ != MasterState::op && state_ != MasterState::safe_op) return result;

  silence_outputs_of_out_slaves();
  frame_reference_time_ = 0;
  FrameBuilder& frame = link_.begin();
  build_cycle_frame(frame);
  if (state_ == MasterState::op) {  // so that a frame back late can be told whole (LinkStats)
    std::uint32_t expected = 0;
    for (std::size_t b = 0; b < kMaxBranches; ++b) expected += layout_.branches[b].length != 0 ? monitor_.expected_wkc(b) : 0U;
    link_.expect_process_data_wkc(static_cast<std::uint16_t>(std::min<std::uint32_t>(expected, 0xFFFF)));
  }
  result.sent_at = link_.clock().now();
  const Result<FrameView> back = link_.exchange(cycle_receive_deadline(result.sent_at));
  result.frame_received = back.ok();
  if (back.ok()) {
    result.received_at = link_.clock().now();
    evaluate_cycle_frame(back.value(), result);
  }
  mailbox_.end_exchange(link_.clock().now());

  if (state_ == MasterState::op) {
    monitor_.observe(cycle_, result.sent_at, result.frame_received, result.branch_wkc,
                     Span<const ProbeResult>(probe_results_.data(), probe_count_));
    result.valid = monitor_.valid();
    finish_reintegration_step();
    step_recovery();
    PortErrorWarning warning;
    while (diagnostics_.pop_warning(warning)) {
      monitor_.recovery_event(LinkEventKind::port_errors, slave_bit(warning.slave), cycle_, warning.time,
                              {warning.port, warning.peer, warning.errors, 0});
    }
  } else if (state_ == MasterState::going_op) {
    step_op_transition(result);
  }
  result.out = monitor_.out_of_exchange() | (operated() ^ kAllSlaves);
  for (std::size_t b = 0; b < kMaxBranches; ++b) result.expected_wkc[b] = monitor_.expected_wkc(b);

  // Keep the cycle in step with the DC reference time.
  hal::Nanoseconds shift = 0;
  if (result.reference_time != 0) {
    shift = dc_sync_.update(result.reference_time);
    result.dc_phase_error = dc_sync_.last_error();
  }
  next_wakeup_ += options_.cycle_time + shift;
  const hal::Nanoseconds now = link_.clock().now();
  while (next_wakeup_ <= now) {  // overran: skip whole periods, keep the phase
    next_wakeup_ += options_.cycle_time;
    ++overruns_;
  }
  result.next_wakeup = next_wakeup_;
  return result;
}

}  // namespace rescue::ecat
