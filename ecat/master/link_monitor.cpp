#include "ecat/master/link_monitor.hpp"

#include "ecat/codec/registers.hpp"

namespace rescue::ecat {
namespace {

constexpr std::size_t kMaxOutProbesPerCycle = 2;

// The branch all `slaves` belong to, or kNoBranch.
std::uint8_t common_branch(const NetworkPlan& plan, SlaveMask slaves) noexcept {
  std::uint8_t branch = kNoBranch;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) == 0) continue;
    if (branch == kNoBranch) {
      branch = plan[p].branch;
    } else if (plan[p].branch != branch) {
      return kNoBranch;
    }
  }
  return branch;
}

}  // namespace

const char* to_string(LinkEventKind kind) noexcept {
  switch (kind) {
    case LinkEventKind::lost: return "lost";
    case LinkEventKind::not_operational: return "not operational";
    case LinkEventKind::restored: return "restored";
    case LinkEventKind::reintegrated: return "reintegrated";
    case LinkEventKind::reintegration_failed: return "reintegration failed";
    case LinkEventKind::silent: return "silent (no frame came back)";
    case LinkEventKind::heard_again: return "heard again";
    case LinkEventKind::recovered: return "recovered";
    case LinkEventKind::recovery_refused: return "recovery refused";
    case LinkEventKind::recovery_failed: return "recovery failed";
    case LinkEventKind::port_errors: return "port errors";
    case LinkEventKind::watchdog_expired: return "watchdog expired while the master was silent (not a link fault), re-arming";
    case LinkEventKind::rearmed: return "re-armed, back in OP";
  }
  return "?";
}

LinkMonitor::LinkMonitor(const NetworkPlan& plan, const ProcessImageLayout& layout) noexcept
    : plan_(plan), layout_(layout) {}

void LinkMonitor::start(SlaveMask in_exchange) noexcept {
  present_ = in_exchange;
  counted_ = 0;
  for (std::size_t b = 0; b < kMaxBranches; ++b) counted_ |= branch_slaves(layout_, b);
  out_ = lost_ = restored_ = fmmus_cleared_ = suspect_ = valid_ = recovering_ = 0;
  pending_lost_ = pending_restored_ = 0;
  watchdog_check_ = rearm_requests_ = rearming_ = pending_expired_ = pending_rearmed_ = 0;
  last_returned_ = -1;
  silent_frames_.fill(0);
  frames_missing_in_row_ = 0;
  silence_reported_ = false;
}

std::uint16_t LinkMonitor::expected_wkc(std::size_t branch) const noexcept {
  return static_cast<std::uint16_t>(kLrwWkcPerSlave * popcount(present_ & branch_slaves(layout_, branch)));
}

std::size_t LinkMonitor::plan_probes(ProbeRequest* out, std::size_t capacity) noexcept {
  // Walks set bits only (most cycles every mask is empty): a scan of all kMaxSlaves positions in each
  // of the four loops cost the cycle about 1300 instructions (callgrind, bench master).
  std::size_t n = 0;
  for (SlaveMask m = suspect_; m != 0 && n < capacity; m &= m - 1) {
    out[n++] = ProbeRequest{static_cast<std::uint8_t>(lowest_slave(m)), false};
  }
  const SlaveMask to_check = watchdog_check_ & present_ & ~suspect_;
  for (SlaveMask m = to_check; m != 0 && n < capacity; m &= m - 1) {
    out[n++] = ProbeRequest{static_cast<std::uint8_t>(lowest_slave(m)), false};
  }
  // The AL state watch (item 6): the next few slaves in the exchange not probed otherwise.
  const SlaveMask to_watch = present_ & ~suspect_ & ~watchdog_check_ & ~rearming_;
  const auto watched = static_cast<std::size_t>(popcount(present_));
  std::size_t watch_budget = (watched + kAlWatchPeriods - 1) / kAlWatchPeriods;
  if (to_watch != 0) {
    for_each_slave_from(present_, watch_rotate_, [&](std::size_t p) {
      if (n >= capacity || watch_budget == 0) return false;
      --watch_budget;  // a slave the others already probe this frame uses its turn
      watch_rotate_ = p + 1;
      if ((to_watch & slave_bit(p)) != 0) out[n++] = ProbeRequest{static_cast<std::uint8_t>(p), false, true};
      return true;
    });
  }
  const SlaveMask to_clear = out_ & ~fmmus_cleared_ & ~recovering_;
  std::size_t budget = kMaxOutProbesPerCycle;
  // (rotate_ moves inside the walk: it starts from its value before, so no slave is probed twice)
  for_each_slave_from(to_clear, rotate_, [&](std::size_t p) {
    if (n >= capacity || budget == 0) return false;
    out[n++] = ProbeRequest{static_cast<std::uint8_t>(p), true};
    --budget;
    rotate_ = p + 1;
    return true;
  });
  return n;
}

void LinkMonitor::observe(std::uint64_t cycle, hal::Nanoseconds time, bool frame_received,
                          const std::array<std::uint16_t, kMaxBranches>& branch_wkc,
                          Span<const ProbeResult> probes) noexcept {
  cycle_ = cycle;
  time_ = time;
  valid_ = 0;
  probed_silent_ = probed_in_op_ = 0;
  pending_lost_ = pending_restored_ = 0;
  pending_detected_ = cycle;
  if (pending_rearmed_ != 0) {
    report(LinkEventKind::rearmed, pending_rearmed_, cycle);
    pending_rearmed_ = 0;
  }
  if (!frame_received) {
    // Late or missing: no evidence. Suspects stay suspects and are probed again next frame.
    ++frames_missing_;
    if (frames_missing_in_row_++ == 0) {
      silent_since_ = time;
      silent_since_cycle_ = cycle;
    }
    if (!silence_reported_ && time - silent_since_ >= kSilenceAlarm) {
      silence_reported_ = true;
      ++silences_;
      report(LinkEventKind::silent, present_, silent_since_cycle_);
    }
    return;
  }
  frames_missing_in_row_ = 0;
  if (silence_reported_) {
    silence_reported_ = false;
    report(LinkEventKind::heard_again, present_, cycle);
  }
  // Before this frame's probes: they may already show what the silence did (item 5).
  if (last_returned_ >= 0 && time - last_returned_ >= kWatchdogCheckGap) {
    watchdog_check_ = present_;
    silence_gap_ = time - last_returned_;
    ++watchdog_check_rounds_;
  }
  last_returned_ = time;
  pending_expired_ = 0;
  const SlaveMask out_before = out_;
  const bool probed_suspects = (suspect_ & present_) != 0;
  bool silent_seen = false;
  for (const ProbeResult& probe : probes) silent_seen = observe_probe(probe) || silent_seen;  // first: they change the expectation
  if (probed_suspects && out_ == out_before && !silent_seen) ++glitches_;  // a shortfall nobody explains
  observe_branches(branch_wkc);
  if (pending_expired_ != 0) {
    report(LinkEventKind::watchdog_expired, pending_expired_, cycle, 0, reg::al_code::kSyncManagerWatchdog,
           {static_cast<std::uint32_t>(silence_gap_ / hal::kNsPerMs), 0, 0, 0});
  }
  if (pending_lost_ != 0) report(LinkEventKind::lost, pending_lost_, pending_detected_);
  if (pending_restored_ != 0) report(LinkEventKind::restored, pending_restored_, cycle);
}

bool LinkMonitor::observe_probe(const ProbeResult& probe) noexcept {
  if (probe.position >= kMaxSlaves) return false;
  const SlaveMask bit = slave_bit(probe.position);
  // Its answer lost with a ring copy: a suspect stays one, probed again next frame (its shortfall
  // is explained: the copy was lost); nothing else changes.
  if (probe.no_evidence) return (present_ & suspect_ & bit) != 0;
  if ((present_ & bit) != 0) {
    if ((suspect_ & bit) == 0 && (watchdog_check_ & bit) == 0) {
      if (probe.watch) observe_watch(probe, bit);
      return false;
    }
    std::uint8_t& silent = silent_frames_[probe.position];
    if (probe.status_wkc == 0) {
      probed_silent_ |= bit;
      // A check that did not reach a slave the counters do not doubt: checked again next frame.
      if ((suspect_ & bit) == 0) return false;
      // Silent once more. The counter that raised the suspicion was the first such frame.
      if (silent == 0) silent = 1;
      if (++silent < kLossConfirmFrames) return true;  // stays a suspect: probed again next frame
      silent = 0;
      suspect_ &= ~bit;
      watchdog_check_ &= ~bit;
      rearming_ &= ~bit;
      rearm_requests_ &= ~bit;
      present_ &= ~bit;
      out_ |= bit;
      lost_ |= bit;
      pending_lost_ |= bit;
      if (suspect_since_[probe.position] < pending_detected_) pending_detected_ = suspect_since_[probe.position];
      return true;
    }
    // It answered: whatever the counter said, the link to it is there.
    silent = 0;
    suspect_ &= ~bit;
    const bool expired = expired_by_watchdog(probe, bit);
    watchdog_check_ &= ~bit;
    if (expired) {
      // Out of OP because nothing reached it while the master was silent: the master re-arms it.
      if ((rearming_ & bit) == 0) {
        rearming_ |= bit;
        rearm_requests_ |= bit;
        pending_expired_ |= bit;
        ++watchdog_expiries_;
      }
      return false;
    }
    if ((probe.al_status & reg::kAlStateMask) == static_cast<std::uint16_t>(reg::AlState::op)) probed_in_op_ |= bit;
    if ((probe.al_status & reg::kAlStateMask) != static_cast<std::uint16_t>(reg::AlState::op)) {
      rearming_ &= ~bit;
      rearm_requests_ &= ~bit;
      present_ &= ~bit;
      out_ |= bit;
      report(LinkEventKind::not_operational, bit, suspect_since_[probe.position], probe.al_status,
             probe.al_status_code);
    }
    return false;  // reachable and in OP: the shortfall was elsewhere on the branch, or transient
  }
  if ((out_ & bit) == 0) return false;
  if (probe.had_clear && probe.clear_wkc != 0) fmmus_cleared_ |= bit;
  if (probe.status_wkc != 0 && (lost_ & bit) != 0) {
    lost_ &= ~bit;
    restored_ |= bit;
    pending_restored_ |= bit;
  } else if (probe.status_wkc == 0 && (lost_ & bit) == 0) {
    // Out but reachable before (restored or not operational), now silent: lost again, quietly,
    // as it is already out of the exchange. Its FMMUs may come back reset with it: clear again.
    restored_ &= ~bit;
    lost_ |= bit;
    fmmus_cleared_ &= ~bit;
  }
  return false;
}

void LinkMonitor::observe_watch(const ProbeResult& probe, SlaveMask bit) noexcept {
  if (probe.status_wkc == 0) {
    // Not reached. The counters judge the reachability of the slaves they count: no evidence. A slave
    // without process data (a junction) is in no counter: the read is the only evidence there is, so
    // it becomes a suspect, probed until kLossConfirmFrames returned frames in a row found it silent
    // (a power cycle took its station address) or one finds it.
    if ((counted_ & bit) == 0 && (suspect_ & bit) == 0) {
      suspect_ |= bit;
      suspect_since_[probe.position] = cycle_;
      silent_frames_[probe.position] = 1;
    }
    return;
  }
  ++watch_reads_;
  const bool op = (probe.al_status & reg::kAlStateMask) == static_cast<std::uint16_t>(reg::AlState::op);
  if (op && (probe.al_status & reg::kAlErrorBit) == 0) return;
  // Out of OP on its own (or flagging an error): out of the exchange, reported with its code.
  rearming_ &= ~bit;
  rearm_requests_ &= ~bit;
  present_ &= ~bit;
  out_ |= bit;
  report(LinkEventKind::not_operational, bit, cycle_, probe.al_status, probe.al_status_code);
}

bool LinkMonitor::expired_by_watchdog(const ProbeResult& probe, SlaveMask bit) const noexcept {
  // Found by the watchdog check, or a suspect the master is already re-arming (a device whose
  // counter in SAFE-OP falls short raises suspicion until it is back in OP).
  if ((watchdog_check_ & bit) == 0 && (rearming_ & bit) == 0) return false;
  if ((probe.al_status & reg::kAlStateMask) != static_cast<std::uint16_t>(reg::AlState::safe_op)) return false;
  return (rearming_ & bit) != 0 || probe.al_status_code == reg::al_code::kSyncManagerWatchdog;
}

void LinkMonitor::rearmed(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time) noexcept {
  slaves &= rearming_;
  if (slaves == 0) return;
  rearming_ &= ~slaves;
  pending_rearmed_ |= slaves;  // one report for the frame's answers, by observe()
  cycle_ = cycle;
  time_ = time;
}

void LinkMonitor::rearm_failed(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time, std::uint16_t al_status,
                               std::uint16_t al_code) noexcept {
  slaves &= rearming_;
  if (slaves == 0) return;
  rearming_ &= ~slaves;
  rearm_requests_ &= ~slaves;
  cycle_ = cycle;
  time_ = time;
  const SlaveMask taken_out = slaves & present_;
  present_ &= ~taken_out;
  out_ |= taken_out;
  if (taken_out != 0) report(LinkEventKind::not_operational, taken_out, cycle, al_status, al_code);
}

void LinkMonitor::observe_branches(const std::array<std::uint16_t, kMaxBranches>& branch_wkc) noexcept {
  for (std::size_t b = 0; b < kMaxBranches; ++b) {
    const BranchLayout& branch = layout_.branches[b];
    const SlaveMask present = present_ & branch_slaves(layout_, b);
    const std::uint16_t wkc = branch_wkc[b];
    if (wkc >= expected_wkc(b)) {
      // A counter above the expectation is a slave out of the exchange still mapped for a cycle.
      // A full counter is evidence against a cut: the silent count of the branch starts again.
      valid_ |= present;
      for (std::size_t i = 0; i < branch.slave_count; ++i) silent_frames_[branch.slaves[i]] = 0;
      continue;
    }
    // Short: probe every present slave of the branch. Only whole multiples of 3 say how many
    // slaves from the start of the branch were reached in OP (a link cut); any other shortfall
    // (a slave out of OP adds 1) cannot be placed, so nothing on the branch is trusted this cycle.
    // When this frame's probes reached every present slave of the branch, they place the shortfall:
    // the slaves found in OP are the ones counted, if the counter says exactly that many (a single
    // slave out mid-branch, e.g. its drive power-cycled, leaves the slaves behind it in the exchange).
    const SlaveMask in_op = present & probed_in_op_;
    const bool placed = ((probed_silent_ | probed_in_op_) & present) == present &&
                        wkc == kLrwWkcPerSlave * popcount(in_op);
    if (placed) valid_ |= in_op;
    std::uint16_t fine =
        !placed && !redundant_ && wkc % kLrwWkcPerSlave == 0 ? static_cast<std::uint16_t>(wkc / kLrwWkcPerSlave) : 0;
    for (std::size_t i = 0; i < branch.slave_count; ++i) {
      const std::size_t p = branch.slaves[i];
      if ((present & slave_bit(p)) == 0) continue;
      if (fine > 0) {
        --fine;
        valid_ |= slave_bit(p);
      }
      if ((suspect_ & slave_bit(p)) == 0) {
        suspect_ |= slave_bit(p);
        suspect_since_[p] = cycle_;
      }
    }
  }
}

void LinkMonitor::reintegrated(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time) noexcept {
  slaves &= restored_;
  if (slaves == 0) return;
  present_ |= slaves;
  out_ &= ~slaves;
  restored_ &= ~slaves;
  fmmus_cleared_ &= ~slaves;
  cycle_ = cycle;
  time_ = time;
  report(LinkEventKind::reintegrated, slaves, cycle);
}

void LinkMonitor::recovered(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time, std::uint32_t cause,
                            std::uint32_t pdo_writes) noexcept {
  slaves &= out_;
  if (slaves == 0) return;
  present_ |= slaves;
  out_ &= ~slaves;
  lost_ &= ~slaves;
  restored_ &= ~slaves;
  fmmus_cleared_ &= ~slaves;
  suspect_ &= ~slaves;
  recovering_ &= ~slaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((slaves & slave_bit(p)) != 0) silent_frames_[p] = 0;
  }
  cycle_ = cycle;
  time_ = time;
  report(LinkEventKind::recovered, slaves, cycle, 0, 0, {cause, pdo_writes, 0, 0});
}

void LinkMonitor::recovery_event(LinkEventKind kind, SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time,
                                 const std::array<std::uint32_t, 4>& found) noexcept {
  cycle_ = cycle;
  time_ = time;
  report(kind, slaves, cycle, 0, 0, found);
}

void LinkMonitor::reintegration_failed(SlaveMask slaves, std::uint64_t cycle, hal::Nanoseconds time,
                                       std::uint16_t al_status, std::uint16_t al_code) noexcept {
  if (slaves == 0) return;
  cycle_ = cycle;
  time_ = time;
  fmmus_cleared_ &= ~slaves;  // clear them again: they must add nothing to the counters
  report(LinkEventKind::reintegration_failed, slaves, cycle, al_status, al_code);
}

void LinkMonitor::report(LinkEventKind kind, SlaveMask slaves, std::uint64_t detected_cycle, std::uint16_t al_status,
                         std::uint16_t al_code, const std::array<std::uint32_t, 4>& found) noexcept {
  LinkReport r;
  r.kind = kind;
  r.branch = common_branch(plan_, slaves);
  r.al_status = al_status;
  r.al_status_code = al_code;
  r.slaves = slaves;
  r.cycle = cycle_;
  r.detected_cycle = detected_cycle;
  r.time = time_;
  r.found = found;
  if (!reports_.push(r)) ++reports_dropped_;  // nobody collects them: keep the oldest, count the rest
}

bool LinkMonitor::pop_report(LinkReport& out) noexcept { return reports_.pop(out); }

}  // namespace rescue::ecat
