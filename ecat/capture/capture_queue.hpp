// CaptureQueue: takes capture writes off the EtherCAT handler's thread. The handler's tap copies
// each frame into a fixed single-producer/single-consumer queue (no syscall, no heap, bounded
// time); a low-priority thread drains it into a CaptureWriter, whose write() may block on the disk.
//
//   handler thread (tap)     record(frame, time, direction)   copy into a slot, or count a drop
//   logger thread            drain(writer, max)               oldest first, into the pcapng file
//
// A full queue (the disk stalled for longer than the queue holds) drops the newest frame and counts
// it; the cycle never waits. 1024 frames hold half a second of the robot's two frames per cycle.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "ecat/link/datagram_link.hpp"

namespace rescue::ecat {

// One frame in flight to the writer: at most the writer's snap length is kept.
struct QueuedCaptureFrame {
  hal::Nanoseconds time{0};
  std::uint16_t length{0};
  FrameDirection direction{FrameDirection::unknown};
  std::array<std::uint8_t, CaptureWriter::kSnapLength> bytes{};
};

struct CaptureQueueStats {
  std::uint64_t frames_queued{0};
  std::uint64_t frames_dropped{0};    // the queue was full
  std::uint64_t frames_truncated{0};  // longer than the snap length: queued cut to it
};

class CaptureQueue {
 public:
  static constexpr std::size_t kCapacity = 1024;

  CaptureQueue() = default;

  // Producer side (one thread). Never blocks.
  void record(ConstByteSpan frame, hal::Nanoseconds time, FrameDirection direction) noexcept;

  // Consumer side (one thread): hands up to `max_frames` frames, oldest first, to `writer`.
  // Returns how many it handed over.
  std::size_t drain(CaptureWriter& writer, std::size_t max_frames) noexcept;

  // Either side; counters are updated by the producer.
  CaptureQueueStats stats() const noexcept;

 private:
  SpscQueue<QueuedCaptureFrame, kCapacity> queue_;
  std::atomic<std::uint64_t> queued_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> truncated_{0};
};

// A FrameTapFn: `queue` is the CaptureQueue given to set_tap().
inline void capture_queue_tap(void* queue, ConstByteSpan frame, hal::Nanoseconds time, TapDirection direction) noexcept {
  static_cast<CaptureQueue*>(queue)->record(
      frame, time, direction == TapDirection::outbound ? FrameDirection::outbound : FrameDirection::inbound);
}

}  // namespace rescue::ecat
