#include "ecat/capture/capture_queue.hpp"

#include <cstring>

namespace rescue::ecat {

void CaptureQueue::record(ConstByteSpan frame, hal::Nanoseconds time, FrameDirection direction) noexcept {
  std::size_t length = frame.size();
  if (length > CaptureWriter::kSnapLength) {
    length = CaptureWriter::kSnapLength;
    truncated_.fetch_add(1, std::memory_order_relaxed);
  }
  // One copy of the frame's own bytes, straight into the slot.
  const bool queued = queue_.try_push_in_place([&](QueuedCaptureFrame& slot) noexcept {
    slot.time = time;
    slot.length = static_cast<std::uint16_t>(length);
    slot.direction = direction;
    if (length != 0) std::memcpy(slot.bytes.data(), frame.data(), length);
  });
  (queued ? queued_ : dropped_).fetch_add(1, std::memory_order_relaxed);
}

std::size_t CaptureQueue::drain(CaptureWriter& writer, std::size_t max_frames) noexcept {
  std::size_t handed = 0;
  while (handed < max_frames && queue_.try_pop_in_place([&writer](const QueuedCaptureFrame& f) noexcept {
           writer.record(ConstByteSpan(f.bytes.data(), f.length), f.time, f.direction);
         })) {
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
