#include "ecat/master/stamped_port.hpp"

namespace rescue::ecat {

Status StampedPort::send(ConstByteSpan frame) noexcept {
  if (!stamping_) return inner_->send(frame);
  last_sent_at_ = inner_->clock().now();
  const Status sent = inner_->send(frame);
  count_send(last_sent_at_);
  return sent;
}

void StampedPort::count_send(hal::Nanoseconds began) noexcept {
  const hal::Nanoseconds took = inner_->clock().now() - began;
  ++durations_.sends;
  if (took > 5 * hal::kNsPerUs) ++durations_.over_5us;
  if (took > 20 * hal::kNsPerUs) ++durations_.over_20us;
  if (took > durations_.max) durations_.max = took;
}

}  // namespace rescue::ecat
