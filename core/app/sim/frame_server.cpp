#include "core/app/sim/frame_server.hpp"

#include <algorithm>

namespace rescue::app {
namespace {

constexpr std::size_t kSourceMacOffset = 6;
constexpr std::uint8_t kLocallyAdministeredBit = 0x02;

}  // namespace

void mark_processed_by_esc(ByteSpan frame) noexcept {
  if (frame.size() < ecat::kEthernetHeaderSize) return;
  frame[kSourceMacOffset] = static_cast<std::uint8_t>(frame[kSourceMacOffset] | kLocallyAdministeredBit);
}

void FrameServer::release_held() noexcept {
  for (std::size_t i = 0; i < held_count_; ++i) {
    if (nic_.send(ConstByteSpan(held_[i].data(), held_length_[i])).ok()) {
      ++counters_.frames_returned;
    } else {
      ++counters_.send_errors;
    }
  }
  held_count_ = 0;
}

hal::Nanoseconds FrameServer::arrival_of_last_frame() noexcept {
  const hal::Nanoseconds now = nic_.clock().now();
  const Result<hal::Nanoseconds> stamped = nic_.last_receive_time();
  last_arrival_ = now;
  if (stamped.ok()) {
    ++counters_.frames_timestamped;
    if (stamped.value() < now) last_arrival_ = stamped.value();
  }
  last_read_delay_ = now - last_arrival_;
  return last_arrival_;
}

Status FrameServer::serve_one(hal::Nanoseconds deadline) noexcept {
  const hal::Nanoseconds start = nic_.clock().now();
  if (held_count_ > 0 && start >= stall_until_) release_held();
  if (held_count_ > 0 && stall_until_ < deadline) deadline = stall_until_;
  const Result<std::size_t> got = nic_.receive(ByteSpan(buffer_), deadline);
  if (!got.ok()) {
    if (got.error().code == Errc::timeout) {
      processor_.idle(nic_.clock().now());
      ++counters_.idle_steps;
    }
    return got.error();
  }
  ++counters_.frames_received;
  const hal::Nanoseconds arrival = arrival_of_last_frame();

  const Result<std::size_t> processed = processor_.process(ByteSpan(buffer_.data(), got.value()), arrival);
  if (!processed.ok() || processed.value() > buffer_.size()) {
    ++counters_.frames_not_returned;
    return Status::success();
  }
  const ByteSpan reply(buffer_.data(), processed.value());
  mark_processed_by_esc(reply);
  if (arrival < stall_until_) {
    if (held_count_ == held_.size()) {
      ++counters_.frames_held_dropped;
      return Status::success();
    }
    std::copy(reply.begin(), reply.end(), held_[held_count_].begin());
    held_length_[held_count_++] = reply.size();
    ++counters_.frames_held;
    return Status::success();
  }
  if (!nic_.send(reply).ok()) {
    ++counters_.send_errors;
    return Status::success();
  }
  ++counters_.frames_returned;
  return Status::success();
}

}  // namespace rescue::app
