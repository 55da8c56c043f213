// Stress: one producer thread and one consumer thread push and pop hundreds of thousands of
// messages through a small queue (constantly full and empty). Every message must arrive once, in
// order, intact. Labelled `concurrency`: ThreadSanitizer runs it too.
#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

#include "core/base/sanitizers.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue {
namespace {

struct Message {
  std::uint64_t sequence;
  std::uint64_t check;  // derived from sequence: a torn or stale slot would not match
  std::uint64_t pad[2];
};

constexpr std::uint64_t check_of(std::uint64_t sequence) { return sequence * 0x9E3779B97F4A7C15ULL ^ 0xA5A5A5A5ULL; }

constexpr std::uint64_t kMessages = kSanitizerInterceptsMalloc ? 100'000 : 1'000'000;

TEST(SpscQueueStress, EveryMessageArrivesOnceInOrderIntact) {
  static SpscQueue<Message, 64> queue;
  std::uint64_t received = 0;
  std::uint64_t out_of_order = 0;
  std::uint64_t corrupted = 0;

  std::thread consumer([&] {
    std::uint64_t expected = 0;
    while (expected < kMessages) {
      Message m{};
      if (!queue.try_pop(m)) {
        std::this_thread::yield();
        continue;
      }
      if (m.sequence != expected) ++out_of_order;
      if (m.check != check_of(m.sequence) || m.pad[0] != m.sequence || m.pad[1] != ~m.sequence) ++corrupted;
      expected = m.sequence + 1;
      ++received;
    }
  });

  for (std::uint64_t i = 0; i < kMessages; ++i) {
    const Message m{i, check_of(i), {i, ~i}};
    while (!queue.try_push(m)) std::this_thread::yield();
  }
  consumer.join();

  EXPECT_EQ(received, kMessages);
  EXPECT_EQ(out_of_order, 0u);
  EXPECT_EQ(corrupted, 0u);
  EXPECT_TRUE(queue.empty_approx());
}

}  // namespace
}  // namespace rescue
