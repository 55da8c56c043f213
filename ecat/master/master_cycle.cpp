// Master cycle: one frame per period, built by the schedule of cyclic services, sent, received with
// a deadline, each answer handed to the service that asked, then every service settles.
// No heap, no system call but the NIC's send and receive, bounded loops only.
#include <algorithm>

#include "ecat/master/master.hpp"

namespace rescue::ecat {

void Master::record_identities() noexcept {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    SlaveRecord& record = slaves_[p];
    const std::uint8_t found = report_.match.found_of_slot[p];
    record.identified = found != kNoPosition && found < report_.found.size();
    record.identity = record.identified ? report_.found[found] : FoundSlave{};
  }
}

const FoundSlave* Master::identity(std::size_t position) const noexcept {
  if (position >= kMaxSlaves || (report_.match.present & slave_bit(position)) == 0) return nullptr;
  return slaves_[position].identified ? &slaves_[position].identity : nullptr;
}

const SiiImage* Master::sii_image(std::size_t position) const noexcept {
  if (identity(position) == nullptr) return nullptr;
  const std::size_t found = report_.match.found_of_slot[position];
  return found < sii_.size() ? &sii_[found] : nullptr;
}

void Master::realign_schedule() noexcept {
  const hal::Nanoseconds now = link_.clock().now();
  if (next_wakeup_ > now || options_.cycle_time <= 0) return;
  next_wakeup_ += ((now - next_wakeup_) / options_.cycle_time + 1) * options_.cycle_time;
}

ExchangeDeadlines Master::cycle_deadlines(hal::Nanoseconds sent_at) const noexcept {
  // next_wakeup_ is still this period's start: the next period's send is one cycle_time later.
  const hal::Nanoseconds next_send = next_wakeup_ + options_.cycle_time;
  hal::Nanoseconds deadline = next_send - options_.cycle_receive_guard;
  deadline = std::min(deadline, sent_at + options_.cycle_time);
  deadline = std::max(deadline, sent_at + options_.cycle_receive_timeout);
  return ExchangeDeadlines{deadline, std::max(deadline, next_send - options_.cycle_repeat_guard), options_.cycle_time};
}

CycleResult Master::cycle() noexcept {
  CycleResult result;
  result.cycle = ++cycle_;
  result.state = state_;
  if (state_ != MasterState::going_op && state_ != MasterState::op && state_ != MasterState::safe_op) return result;

  FrameBuilder& builder = link_.begin();  // before index(): begin() takes the frame's index
  frame_.begin(builder, link_.index());
  ring_dc_.add_before_reference(frame_);  // before the reference's FRMW (ring_dc_service.hpp)
  for_each_service([this](auto& service) { service.add_datagrams(frame_); });
  if (state_ == MasterState::op) {  // so that a frame back late can be told whole (LinkStats)
    std::uint32_t expected = 0;
    for (std::size_t b = 0; b < kMaxBranches; ++b) expected += layout_.branches[b].length != 0 ? monitor_.expected_wkc(b) : 0U;
    link_.expect_process_data_wkc(static_cast<std::uint16_t>(std::min<std::uint32_t>(expected, 0xFFFF)));
  }
  result.sent_at = link_.clock().now();
  const Result<FrameView> back = link_.exchange(cycle_deadlines(result.sent_at));
  result.frame_received = back.ok();
  if (back.ok()) {
    result.received_at = link_.clock().now();
    frame_.dispatch(back.value());
  }
  const hal::Nanoseconds ended = link_.clock().now();
  for_each_service([ended](auto& service) { service.end_exchange(ended); });
  for_each_service([&result](auto& service) { service.settle(result); });
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
