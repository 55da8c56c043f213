#include "core/app/operator_protocol/replay_window.hpp"

namespace rescue::app::protocol {

void ReplayWindow::begin_epoch(std::uint64_t epoch) noexcept {
  windows_.clear();
  epoch_ = epoch;
}

Status ReplayWindow::accept(std::uint32_t sender, std::uint64_t sequence, std::uint64_t robot_unix_ns) noexcept {
  const std::uint64_t latest = robot_unix_ns > UINT64_MAX - kMaxSequenceLeadNs ? UINT64_MAX : robot_unix_ns + kMaxSequenceLeadNs;
  if (sequence > latest) {
    return make_error(Errc::out_of_range, "sequence more than 10 min ahead of the robot's clock", sender);
  }
  std::size_t index = windows_.size();
  bool operator_present = false;
  for (std::size_t i = 0; i < windows_.size(); ++i) {
    if (windows_[i].sender == sender) index = i;
    if (windows_[i].sender == kOperatorSender) operator_present = true;
  }
  if (index == windows_.size()) {
    // A sender's first datagram of the epoch: any sequence up to `latest`, the window starts at it.
    const std::size_t room = sender == kOperatorSender || operator_present ? kMaxSenders : kMaxSenders - 1;
    if (windows_.size() >= room || !windows_.push_back(Window{sender, sequence, 1U})) {
      return make_error(Errc::capacity_exceeded, "sender table full for this epoch", sender);
    }
    return Status::success();
  }
  Window& w = windows_[index];
  if (sequence <= w.highest) {
    const std::uint64_t behind = w.highest - sequence;
    if (behind >= kWindowSize) return make_error(Errc::refused, "sequence older than the replay window");
    if ((w.seen & (std::uint64_t{1} << behind)) != 0) return make_error(Errc::refused, "sequence already accepted");
    w.seen |= std::uint64_t{1} << behind;
    return Status::success();
  }
  const std::uint64_t shift = sequence - w.highest;
  w.seen = shift >= kWindowSize ? 1U : ((w.seen << shift) | 1U);
  w.highest = sequence;
  return Status::success();
}

}  // namespace rescue::app::protocol
