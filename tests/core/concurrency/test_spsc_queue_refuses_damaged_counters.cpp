// A queue whose bytes were overwritten (a stray write or a bit flip in the shared segment,
// docs/shared-memory.md "A damaged segment"): pop never hands out more than the capacity before it
// refuses, push refuses too, and corrupt() says so; damage to a side's cached copy of the other's
// counter alone loses and invents nothing.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <new>
#include <random>

#include "core/concurrency/spsc_queue.hpp"

namespace rescue {
namespace {

struct Record {
  std::uint64_t sequence;
  std::uint32_t value;
};

using Queue = SpscQueue<Record, 16>;

struct Storage {
  alignas(Queue) unsigned char bytes[sizeof(Queue)];
};

// Pops until refused, at most `limit` times; how many it handed out.
std::size_t drain(Queue& q, std::size_t limit) {
  std::size_t n = 0;
  Record r{};
  while (n < limit && q.try_pop(r)) ++n;
  return n;
}

TEST(SpscQueueDamage, CountersFarApartAreRefusedNotDrained) {
  Storage s;
  Queue* q = Queue::create_at(s.bytes).value();
  ASSERT_TRUE(q->try_push(Record{1, 1}));
  // tail 2^63 ahead of head: "2^63 entries".
  std::uint64_t far = std::uint64_t{1} << 63U;
  std::memcpy(s.bytes + 64, &far, sizeof far);  // tail_ is the first word of the second line
  EXPECT_TRUE(q->corrupt());
  EXPECT_EQ(drain(*q, 1000), 0U);
  EXPECT_FALSE(q->try_push(Record{2, 2}));
}

TEST(SpscQueueDamage, RandomBytesOverTheQueueNeverYieldMoreThanItsCapacity) {
  std::mt19937_64 random(35);
  for (int trial = 0; trial < 2000; ++trial) {
    Storage s;
    Queue* q = Queue::create_at(s.bytes).value();
    for (std::uint64_t i = 0; i < 5; ++i) ASSERT_TRUE(q->try_push(Record{i, 0}));
    for (std::size_t i = 0; i < sizeof s.bytes; i += sizeof(std::uint64_t)) {
      const std::uint64_t word = random();
      std::memcpy(s.bytes + i, &word, sizeof word);
    }
    Queue* damaged = std::launder(reinterpret_cast<Queue*>(s.bytes));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
    const bool corrupt = damaged->corrupt();
    const std::size_t popped = drain(*damaged, 10 * Queue::capacity());
    ASSERT_LE(popped, Queue::capacity()) << "trial " << trial;
    if (corrupt) {
      EXPECT_EQ(popped, 0U) << "trial " << trial;
      EXPECT_FALSE(damaged->try_push(Record{9, 9})) << "trial " << trial;
    }
  }
}

TEST(SpscQueueDamage, ADamagedCachedCounterAloneLosesAndInventsNothing) {
  Storage s;
  Queue* q = Queue::create_at(s.bytes).value();
  for (std::uint64_t i = 0; i < 3; ++i) ASSERT_TRUE(q->try_push(Record{i, 0}));
  // The consumer's cached tail (the word after head_) and the producer's cached head (after tail_).
  const std::uint64_t garbage = 0xDEADBEEFDEADBEEFULL;
  std::memcpy(s.bytes + sizeof(std::uint64_t), &garbage, sizeof garbage);
  std::memcpy(s.bytes + 64 + sizeof(std::uint64_t), &garbage, sizeof garbage);
  EXPECT_FALSE(q->corrupt());
  EXPECT_EQ(drain(*q, 100), 3U);
  ASSERT_TRUE(q->try_push(Record{7, 7}));
  Record r{};
  ASSERT_TRUE(q->try_pop(r));
  EXPECT_EQ(r.sequence, 7U);
}

}  // namespace
}  // namespace rescue
