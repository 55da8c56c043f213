#include "ecat/capture_queue.hpp"

#include <cstring>

namespace rescue::ecat {

void CaptureQueue::record(ConstByteSpan frame, hal::Nanoseconds time, FrameDirection direction) noexcept {
  std::size_t length = frame.size();
  if (length > staging_.bytes.size()) {
    length = staging_.bytes.size();
    truncated_.fetch_add(1, std::memory_order_relaxed);
  }
  staging_.time = time;
  staging_.length = static_cast<std::uint16_t>(length);
  staging_.direction = direction;
  if (length != 0) std::memcpy(staging_.bytes.data(), frame.data(), length);
  if (queue_.try_push(staging_)) {
    queued_.fetch_add(1, std::memory_order_relaxed);
  } else {
    dropped_.fetch_add(1, std::memory_order_relaxed);
  }
}

std::size_t CaptureQueue::drain(CaptureWriter& writer, std::size_t max_frames) noexcept {
  std::size_t handed = 0;
  while (handed < max_frames && queue_.try_pop(drained_)) {
    writer.record(ConstByteSpan(drained_.bytes.data(), drained_.length), drained_.time, drained_.direction);
    ++handed;
  }
  return handed;
}

CaptureQueueStats CaptureQueue::stats() const noexcept {
  CaptureQueueStats s;
  s.frames_queued = queued_.load(std::memory_order_relaxed);
  s.frames_dropped = dropped_.load(std::memory_order_relaxed);
  s.frames_truncated = truncated_.load(std::memory_order_relaxed);
  return s;
}

}  // namespace rescue::ecat
