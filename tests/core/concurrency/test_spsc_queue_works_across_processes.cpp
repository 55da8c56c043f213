// Two processes, as the firmware's tasks run: the parent creates two queues in a POSIX shared-memory
// segment, the forked child opens the segment by name and maps it at a different address (the
// queues hold no pointers), then echoes every message back. Both sides check order and contents.
#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

#include "core/base/sanitizers.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "tests/support/forked_child.hpp"
#include "tests/support/shared_memory_segment.hpp"

namespace rescue {
namespace {

struct Message {
  std::uint64_t sequence;
  std::uint64_t check;
};
using Queue = SpscQueue<Message, 128>;

constexpr std::uint64_t kMessages = kSanitizerInterceptsMalloc ? 50'000 : 500'000;
constexpr std::uint64_t request_check(std::uint64_t s) { return s * 0x9E3779B97F4A7C15ULL; }
constexpr std::uint64_t reply_check(std::uint64_t s) { return ~s * 0xC2B2AE3D27D4EB4FULL; }

enum ChildExit : int { kChildOk = 0, kMapFailed = 2, kAttachFailed, kSameAddress, kOutOfOrder, kCorrupted };

// The child: consumer of `to_child`, producer of `to_parent`.
int echo_child(const test::SharedMemorySegment& segment) {
  void* base = segment.map_again();
  if (base == nullptr) return kMapFailed;
  if (base == segment.address()) return kSameAddress;
  auto to_child = Queue::attach(base);
  auto to_parent = Queue::attach(static_cast<unsigned char*>(base) + sizeof(Queue));
  if (!to_child.ok() || !to_parent.ok()) return kAttachFailed;
  for (std::uint64_t expected = 0; expected < kMessages; ++expected) {
    Message m{};
    while (!to_child.value()->try_pop(m)) std::this_thread::yield();
    if (m.sequence != expected) return kOutOfOrder;
    if (m.check != request_check(m.sequence)) return kCorrupted;
    while (!to_parent.value()->try_push(Message{m.sequence, reply_check(m.sequence)})) std::this_thread::yield();
  }
  return kChildOk;
}

TEST(SpscQueueAcrossProcesses, ChildEchoesEveryMessageInOrder) {
  test::SharedMemorySegment segment("spsc", 2 * sizeof(Queue));
  ASSERT_TRUE(segment.ok()) << "shm_open/mmap failed for " << segment.name();
  auto to_child = Queue::create_at(segment.address());
  auto to_parent = Queue::create_at(static_cast<unsigned char*>(segment.address()) + sizeof(Queue));
  ASSERT_TRUE(to_child.ok() && to_parent.ok());

  std::uint64_t sent = 0;
  std::uint64_t replies = 0;
  std::uint64_t bad_replies = 0;
  const int child_exit = test::run_with_child([&] { return echo_child(segment); },
                                              [&](pid_t child) {
                                                while (replies < kMessages) {
                                                  bool progress = false;
                                                  while (sent < kMessages && to_child.value()->try_push(Message{sent, request_check(sent)})) {
                                                    ++sent;
                                                    progress = true;
                                                  }
                                                  Message reply{};
                                                  while (to_parent.value()->try_pop(reply)) {
                                                    if (reply.sequence != replies || reply.check != reply_check(replies)) ++bad_replies;
                                                    ++replies;
                                                    progress = true;
                                                  }
                                                  if (!progress) {
                                                    if (test::child_has_exited(child)) break;  // it failed: see its exit code
                                                    std::this_thread::yield();
                                                  }
                                                }
                                              });
  EXPECT_EQ(child_exit, kChildOk) << "2 map failed, 3 attach failed, 4 same address, 5 out of order, 6 corrupted";
  EXPECT_EQ(sent, kMessages);
  EXPECT_EQ(replies, kMessages);
  EXPECT_EQ(bad_replies, 0u);
}

}  // namespace
}  // namespace rescue
