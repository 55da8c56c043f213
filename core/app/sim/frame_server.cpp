#include "core/app/sim/frame_server.hpp"

namespace rescue::app {
namespace {

constexpr std::size_t kSourceMacOffset = 6;
constexpr std::uint8_t kLocallyAdministeredBit = 0x02;

}  // namespace

void mark_processed_by_esc(ByteSpan frame) noexcept {
  if (frame.size() < ecat::kEthernetHeaderSize) return;
  frame[kSourceMacOffset] = static_cast<std::uint8_t>(frame[kSourceMacOffset] | kLocallyAdministeredBit);
}

Status FrameServer::serve_one(hal::Nanoseconds deadline) noexcept {
  const Result<std::size_t> got = nic_.receive(ByteSpan(buffer_), deadline);
  if (!got.ok()) return got.error();
  ++counters_.frames_received;
  const hal::Nanoseconds arrival = nic_.clock().now();

  const Result<std::size_t> processed = processor_.process(ByteSpan(buffer_.data(), got.value()), arrival);
  if (!processed.ok() || processed.value() > buffer_.size()) {
    ++counters_.frames_not_returned;
    return Status::success();
  }
  const ByteSpan reply(buffer_.data(), processed.value());
  mark_processed_by_esc(reply);
  if (!nic_.send(reply).ok()) {
    ++counters_.send_errors;
    return Status::success();
  }
  ++counters_.frames_returned;
  return Status::success();
}

}  // namespace rescue::app
