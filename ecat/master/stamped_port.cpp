#include "ecat/master/stamped_port.hpp"

#include <cstring>

#include "ecat/master/ring_dc_service.hpp"

namespace rescue::ecat {

Status StampedPort::send(ConstByteSpan frame) noexcept {
  const hal::Nanoseconds now = inner_->clock().now();
  last_sent_at_ = now;
  if (ring_dc_ == nullptr || !ring_dc_->patches_ring_copies() || frame.size() > buffer_.size()) return inner_->send(frame);
  std::memcpy(buffer_.data(), frame.data(), frame.size());
  const ByteSpan patched(buffer_.data(), frame.size());
  ring_dc_->before_ring_send(patched, now);
  return inner_->send(ConstByteSpan(patched.data(), patched.size()));
}

}  // namespace rescue::ecat
