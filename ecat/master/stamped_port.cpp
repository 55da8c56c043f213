#include "ecat/master/stamped_port.hpp"

#include <cstring>

#include "ecat/master/ring_dc_service.hpp"

namespace rescue::ecat {

Status StampedPort::send(ConstByteSpan frame) noexcept {
  if (!stamping_) return inner_->send(frame);
  if (ring_dc_ == nullptr || !ring_dc_->patches_ring_copies() || frame.size() > buffer_.size()) {
    last_sent_at_ = inner_->clock().now();
    const Status sent = inner_->send(frame);
    count_send(last_sent_at_);
    return sent;
  }
  std::memcpy(buffer_.data(), frame.data(), frame.size());
  const ByteSpan patched(buffer_.data(), frame.size());
  last_sent_at_ = inner_->clock().now();
  ring_dc_->before_ring_send(patched, last_sent_at_);
  const hal::Nanoseconds patched_at = inner_->clock().now();
  const Status sent = inner_->send(ConstByteSpan(patched.data(), patched.size()));
  count_send(patched_at);
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
