#include "ecat/master/ring_monitor.hpp"

#include <cstdio>

namespace rescue::ecat {

const char* to_string(RingState state) noexcept {
  switch (state) {
    case RingState::none: return "none";
    case RingState::closed: return "closed";
    case RingState::open: return "open";
    case RingState::lost: return "lost";
  }
  return "?";
}

const char* to_string(RingEventKind kind) noexcept {
  switch (kind) {
    case RingEventKind::opened: return "opened";
    case RingEventKind::split: return "split";
    case RingEventKind::closed: return "closed";
  }
  return "?";
}

void RingMonitor::start(const std::array<std::uint8_t, kMaxSlaves>& planned_of_segment, std::size_t slaves) noexcept {
  planned_of_segment_ = planned_of_segment;
  slaves_ = slaves < kMaxSlaves ? slaves : kMaxSlaves;
  status_ = RingStatus{};
  status_.state = RingState::closed;
  status_.reached_main = static_cast<std::uint16_t>(slaves_);
  pending_lost_ = false;
  RingReport dropped;
  while (reports_.pop(dropped)) {
  }
}

std::uint8_t RingMonitor::planned(std::size_t segment_position) const noexcept {
  return segment_position < slaves_ ? planned_of_segment_[segment_position] : kNoSlavePosition;
}

void RingMonitor::observe(std::uint64_t cycle, hal::Nanoseconds time, const CopyReturns& returns,
                          std::uint16_t main_brd_wkc, std::uint16_t ring_brd_wkc) noexcept {
  if (status_.state == RingState::none) return;
  if (!returns.main_back && !returns.ring_back) return;  // no evidence
  // The ring copy went all the way round (a ring closed again) but the main copy, the one that
  // counts then, was not waited for: no evidence this cycle either.
  if (!returns.main_back && returns.ring_on == Port::main) return;
  // Copies that no still ring returns: a cable changed while the frame was in flight (docs/redundancy.md,
  // "A cable changing while a frame is in flight"). The ring copy went round a closed ring but the
  // main copy turned at a break (a repair), or the main copy went round but the ring copy turned (a
  // cut): no evidence, the next frame tells.
  const bool main_round = returns.main_back && returns.main_on == Port::ring;
  const bool ring_round = returns.ring_back && returns.ring_on == Port::main;
  if ((ring_round && returns.main_back && !main_round) || (main_round && returns.ring_back && !ring_round)) {
    ++status_.transients;
    drop_pending_lost();
    return;
  }
  const std::size_t m = returns.main_back ? (main_brd_wkc < slaves_ ? main_brd_wkc : slaves_) : 0;
  const std::size_t r0 = returns.ring_back ? ring_brd_wkc : 0;
  const std::size_t r = r0 < slaves_ - m ? r0 : slaves_ - m;
  status_.reached_main = static_cast<std::uint16_t>(m);
  status_.reached_ring = static_cast<std::uint16_t>(r);

  RingState state = RingState::open;
  std::uint8_t before = m == 0 ? kMainPort : planned(m - 1);
  std::uint8_t after = r == 0 ? kRingPort : planned(slaves_ - r);
  SlaveMask unreachable = 0;
  if (returns.main_back && returns.main_on == Port::ring && m == slaves_) {
    state = RingState::closed;
    before = kMainPort;
    after = kRingPort;
  } else if (m + r < slaves_) {
    state = RingState::lost;
    for (std::size_t i = m; i < slaves_ - r; ++i) {
      const std::uint8_t p = planned(i);
      if (p < kMaxSlaves) unreachable |= slave_bit(p);
    }
  }
  const bool changed = state != status_.state || before != status_.before || after != status_.after;
  if (!changed) {
    drop_pending_lost();
    return;
  }
  // Slaves reachable from neither port are reported when two frames in a row show them: one copy lost
  // or held back in flight (a cable cut while the frame crossed it, a host that held it past the
  // deadline) shows fewer slaves than its port reaches, for that frame only.
  if (state == RingState::lost) {
    if (!pending_lost_ || pending_before_ != before || pending_after_ != after) {
      drop_pending_lost();
      pending_lost_ = true;
      pending_before_ = before;
      pending_after_ = after;
      pending_cycle_ = cycle;
      pending_time_ = time;
      return;
    }
    cycle = pending_cycle_;  // confirmed: it began with the first frame that showed it
    time = pending_time_;
    pending_lost_ = false;
  }
  drop_pending_lost();
  cycle_ = cycle;
  time_ = time;
  if (state == RingState::closed) {
    ++status_.repairs;
    report(RingEventKind::closed, status_.before, status_.after, 0);
  } else {
    if (status_.state == RingState::closed) ++status_.breaks;
    report(state == RingState::open ? RingEventKind::opened : RingEventKind::split, before, after, unreachable);
  }
  status_.state = state;
  status_.before = before;
  status_.after = after;
  status_.unreachable = unreachable;
  status_.since_cycle = cycle;
  status_.before_dl_read = false;
  status_.after_dl_read = false;
}

void RingMonitor::drop_pending_lost() noexcept {
  if (pending_lost_) ++status_.transients;
  pending_lost_ = false;
}

void RingMonitor::observe_dl_status(std::uint8_t position, std::uint16_t wkc, std::uint16_t dl_status) noexcept {
  if (wkc != 1) return;
  if (position == status_.before) {
    status_.before_dl_read = true;
    status_.before_dl_status = dl_status;
  }
  if (position == status_.after) {
    status_.after_dl_read = true;
    status_.after_dl_status = dl_status;
  }
}

void RingMonitor::report(RingEventKind kind, std::uint8_t before, std::uint8_t after, SlaveMask unreachable) noexcept {
  if (!reports_.push(RingReport{kind, before, after, unreachable, cycle_, time_})) ++reports_dropped_;
}

namespace {

// "l_hip (position 7)", "the master's main port".
int place(char* out, std::size_t size, const NetworkPlan& plan, std::uint8_t where) noexcept {
  if (where == kMainPort) return std::snprintf(out, size, "the master's main port");
  if (where == kRingPort) return std::snprintf(out, size, "the master's ring port");
  if (where >= kMaxSlaves) return std::snprintf(out, size, "an unplanned slave");
  const char* name = plan[where].name != nullptr ? plan[where].name : "?";
  return std::snprintf(out, size, "%s (position %u)", name, static_cast<unsigned>(where));
}

}  // namespace

std::size_t describe(const RingReport& report, const NetworkPlan& plan, char* out, std::size_t size) noexcept {
  if (size == 0) return 0;
  std::array<char, 64> a{};
  std::array<char, 64> b{};
  (void)place(a.data(), a.size(), plan, report.before);
  (void)place(b.data(), b.size(), plan, report.after);
  int n = 0;
  switch (report.kind) {
    case RingEventKind::opened:
      n = std::snprintf(out, size, "ring open between %s and %s (cycle %llu)", a.data(), b.data(),
                        static_cast<unsigned long long>(report.cycle));
      break;
    case RingEventKind::closed:
      n = std::snprintf(out, size, "ring closed again: the break between %s and %s is repaired (cycle %llu)", a.data(),
                        b.data(), static_cast<unsigned long long>(report.cycle));
      break;
    case RingEventKind::split: {
      unsigned count = 0;
      for (SlaveMask m = report.unreachable; m != 0; m &= m - 1) ++count;
      n = std::snprintf(out, size, "ring broken twice: %u slaves reachable from neither port, after %s and before %s (cycle %llu)",
                        count, a.data(), b.data(), static_cast<unsigned long long>(report.cycle));
      break;
    }
  }
  if (n < 0) return 0;
  return static_cast<std::size_t>(n) < size ? static_cast<std::size_t>(n) : size - 1;
}

}  // namespace rescue::ecat
