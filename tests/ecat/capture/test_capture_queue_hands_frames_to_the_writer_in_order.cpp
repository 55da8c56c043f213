// CaptureQueue takes capture writes off the EtherCAT handler's thread: frames recorded by one thread
// reach the pcapng file through drain() on another, byte for byte, in order, with their timestamps
// and directions; a full queue drops (and counts) the newest frames and never blocks the producer;
// recording and draining allocate nothing after init.
#include <gtest/gtest.h>


#include <fstream>
#include <iterator>
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/memory/heap_guard.hpp"
#include "ecat/capture/capture_queue.hpp"
#include "ecat/codec/frame.hpp"
#include "tests/support/read_frames.hpp"
#include "tests/support/temp_directory.hpp"

namespace rescue::ecat {
namespace {

// A frame read back from the file, owning its bytes.
struct FileFrame {
  std::vector<std::uint8_t> bytes;
  std::uint64_t timestamp_ns{0};
  FrameDirection direction{FrameDirection::unknown};
};

std::vector<FileFrame> frames_in(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<FileFrame> frames;
  for (const CapturedFrame& f : test::read_all_frames(file)) {
    frames.push_back(FileFrame{std::vector<std::uint8_t>(f.bytes.begin(), f.bytes.end()), f.timestamp_ns, f.direction});
  }
  return frames;
}

// Frame n: an FPRD whose datagram length and data carry n, so order and content are both checked.
std::vector<std::uint8_t> numbered_frame(std::uint32_t n) {
  FrameBuilder b;
  b.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
  const std::uint16_t length = static_cast<std::uint16_t>(4 + n % 200);
  std::vector<std::uint8_t> data(length, static_cast<std::uint8_t>(n));
  data[0] = static_cast<std::uint8_t>(n);
  data[1] = static_cast<std::uint8_t>(n >> 8U);
  data[2] = static_cast<std::uint8_t>(n >> 16U);
  EXPECT_TRUE(b.add(Command::FPRD, static_cast<std::uint8_t>(n), make_address(0x1000, 0x0130), length,
                    ConstByteSpan(data.data(), data.size()))
                  .ok());
  const ConstByteSpan f = b.finish();
  return std::vector<std::uint8_t>(f.begin(), f.end());
}

// A writer on a file in the test's own temporary directory (removed when the test ends) and an empty
// queue (both too large for the stack).
class CaptureQueueToWriter : public rescue::testing::TempDirectoryTest {
 protected:
  void open(const char* name) {
    file = path((std::string(name) + ".pcapng").c_str());
    ASSERT_TRUE(writer.open(file.c_str()).ok());
  }
  std::string file;
  std::unique_ptr<CaptureWriter> writer_storage = std::make_unique<CaptureWriter>();
  std::unique_ptr<CaptureQueue> queue_storage = std::make_unique<CaptureQueue>();
  CaptureWriter& writer = *writer_storage;
  CaptureQueue& queue = *queue_storage;
};

TEST_F(CaptureQueueToWriter, FramesReachTheFileInOrderWithTimesAndDirections) {
  open("queue-order");
  std::vector<std::vector<std::uint8_t>> sent;
  for (std::uint32_t n = 0; n < 100; ++n) {
    sent.push_back(numbered_frame(n));
    queue.record(ConstByteSpan(sent.back().data(), sent.back().size()), 1000 + n,
                 n % 2 == 0 ? FrameDirection::outbound : FrameDirection::inbound);
  }
  EXPECT_EQ(writer.stats().frames_written, 0U) << "recording must not write: the logger thread does";
  EXPECT_EQ(queue.drain(writer, 30), 30U);  // bounded work per pass
  EXPECT_EQ(queue.drain(writer, 1000), 70U);
  EXPECT_EQ(queue.drain(writer, 1000), 0U);
  ASSERT_TRUE(writer.close().ok());

  const auto frames = frames_in(file);
  ASSERT_EQ(frames.size(), sent.size());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(frames[i].bytes, sent[i]);
    EXPECT_EQ(frames[i].timestamp_ns, 1000 + i);
    EXPECT_EQ(frames[i].direction, i % 2 == 0 ? FrameDirection::outbound : FrameDirection::inbound);
  }
  EXPECT_EQ(queue.stats().frames_queued, 100U);
  EXPECT_EQ(queue.stats().frames_dropped, 0U);
}

TEST_F(CaptureQueueToWriter, AFullQueueDropsTheNewestFramesAndCountsThem) {
  open("queue-full");
  const std::size_t extra = 10;
  for (std::uint32_t n = 0; n < CaptureQueue::kCapacity + extra; ++n) {
    const auto f = numbered_frame(n);
    queue.record(ConstByteSpan(f.data(), f.size()), n, FrameDirection::outbound);
  }
  EXPECT_EQ(queue.stats().frames_queued, CaptureQueue::kCapacity);
  EXPECT_EQ(queue.stats().frames_dropped, extra);
  while (queue.drain(writer, 256) != 0) {
  }
  ASSERT_TRUE(writer.close().ok());
  const auto frames = frames_in(file);
  ASSERT_EQ(frames.size(), CaptureQueue::kCapacity);
  EXPECT_EQ(frames.front().bytes, numbered_frame(0));  // the oldest ones were kept
  EXPECT_EQ(frames.back().bytes, numbered_frame(CaptureQueue::kCapacity - 1));
}

TEST_F(CaptureQueueToWriter, AnOversizedFrameIsQueuedCutToTheSnapLengthAndCounted) {
  open("queue-oversized");
  const std::vector<std::uint8_t> jumbo(CaptureWriter::kSnapLength + 100, 0xAB);
  queue.record(ConstByteSpan(jumbo.data(), jumbo.size()), 5, FrameDirection::inbound);
  EXPECT_EQ(queue.stats().frames_truncated, 1U);
  EXPECT_EQ(queue.drain(writer, 10), 1U);
  ASSERT_TRUE(writer.close().ok());
  const auto frames = frames_in(file);
  ASSERT_EQ(frames.size(), 1U);
  EXPECT_EQ(frames[0].bytes.size(), CaptureWriter::kSnapLength);
}

TEST_F(CaptureQueueToWriter, AProducerThreadAndADrainingThreadLoseNothing) {
  open("queue-threads");
  constexpr std::uint32_t kFrames = 20000;
  std::vector<std::vector<std::uint8_t>> frames;
  for (std::uint32_t n = 0; n < kFrames; ++n) frames.push_back(numbered_frame(n));
  std::atomic<bool> produced{false};
  std::thread producer([&] {
    for (std::uint32_t n = 0; n < kFrames; ++n) {
      // Retried until queued, as a test only: the handler never waits (a full queue is a counted drop).
      for (;;) {
        const std::uint64_t before = queue.stats().frames_queued;
        queue.record(ConstByteSpan(frames[n].data(), frames[n].size()), n, FrameDirection::outbound);
        if (queue.stats().frames_queued != before) break;
        std::this_thread::yield();
      }
    }
    produced.store(true, std::memory_order_release);
  });
  std::size_t drained = 0;
  while (!produced.load(std::memory_order_acquire) || drained < kFrames) drained += queue.drain(writer, 64);
  producer.join();
  ASSERT_TRUE(writer.close().ok());
  const auto read = frames_in(file);
  ASSERT_EQ(read.size(), kFrames);
  for (std::uint32_t n = 0; n < kFrames; ++n) {
    ASSERT_EQ(read[n].bytes, frames[n]) << n;
  }
}

TEST_F(CaptureQueueToWriter, RecordingAndDrainingAllocateNothingAfterInit) {
  open("queue-heap");
  const auto frame = numbered_frame(7);
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);
  for (int cycle = 0; cycle < 5000; ++cycle) {
    queue.record(ConstByteSpan(frame.data(), frame.size()), cycle, FrameDirection::outbound);
    queue.record(ConstByteSpan(frame.data(), frame.size()), cycle, FrameDirection::inbound);
    if (cycle % 5 == 0) (void)queue.drain(writer, 256);
  }
  while (queue.drain(writer, 256) != 0) {
  }
  const HeapGuardCounters counters = heap_guard_counters();
  reopen_init_for_testing();
  EXPECT_EQ(counters.allocations, 0U);
  EXPECT_EQ(writer.stats().frames_written, 10000U);
  ASSERT_TRUE(writer.close().ok());
}

}  // namespace
}  // namespace rescue::ecat
