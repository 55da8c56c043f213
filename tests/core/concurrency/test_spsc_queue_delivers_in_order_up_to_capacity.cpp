#include <gtest/gtest.h>

#include <cstdint>

#include "core/concurrency/spsc_queue.hpp"

namespace rescue {
namespace {

struct Message {
  std::uint64_t sequence;
  std::int32_t value;
};

TEST(SpscQueue, DeliversInOrderUpToCapacity) {
  SpscQueue<Message, 8> queue;
  for (std::uint64_t i = 0; i < 8; ++i) ASSERT_TRUE(queue.try_push(Message{i, static_cast<std::int32_t>(i) * 3}));
  EXPECT_FALSE(queue.try_push(Message{99, 0}));
  EXPECT_EQ(queue.size_approx(), 8u);
  for (std::uint64_t i = 0; i < 8; ++i) {
    Message out{};
    ASSERT_TRUE(queue.try_pop(out));
    EXPECT_EQ(out.sequence, i);
    EXPECT_EQ(out.value, static_cast<std::int32_t>(i) * 3);
  }
  Message out{77, 77};
  EXPECT_FALSE(queue.try_pop(out));
  EXPECT_EQ(out.sequence, 77u);
  EXPECT_TRUE(queue.empty_approx());
}

TEST(SpscQueue, InPlacePushAndPopSeeTheSlotAndAreNotCalledWhenFullOrEmpty) {
  SpscQueue<Message, 4> queue;
  int fills = 0;
  for (std::uint64_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(queue.try_push_in_place([&](Message& slot) noexcept {
      ++fills;
      slot.sequence = i;
      slot.value = -static_cast<std::int32_t>(i);
    }));
  }
  EXPECT_FALSE(queue.try_push_in_place([&](Message&) noexcept { ++fills; }));
  EXPECT_EQ(fills, 4);  // full: the slot of an unread message is never handed out
  int uses = 0;
  for (std::uint64_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(queue.try_pop_in_place([&](const Message& slot) noexcept {
      ++uses;
      EXPECT_EQ(slot.sequence, i);
      EXPECT_EQ(slot.value, -static_cast<std::int32_t>(i));
    }));
  }
  EXPECT_FALSE(queue.try_pop_in_place([&](const Message&) noexcept { ++uses; }));
  EXPECT_EQ(uses, 4);
  // Mixed with the copying calls, order holds across the wrap.
  ASSERT_TRUE(queue.try_push(Message{10, 1}));
  Message out{};
  ASSERT_TRUE(queue.try_pop(out));
  EXPECT_EQ(out.sequence, 10u);
}

TEST(SpscQueue, WrapsAroundItsSlots) {
  SpscQueue<Message, 4> queue;
  std::uint64_t next_in = 0;
  std::uint64_t next_out = 0;
  for (int round = 0; round < 500; ++round) {
    while (queue.try_push(Message{next_in, 0})) ++next_in;
    for (int k = 0; k < round % 4 + 1; ++k) {
      Message out{};
      if (!queue.try_pop(out)) break;
      ASSERT_EQ(out.sequence, next_out++);
    }
  }
  EXPECT_GT(next_out, 500u);
}

TEST(SpscQueue, CreatedInRawMemoryAndAttachedAgain) {
  using Queue = SpscQueue<Message, 16>;
  alignas(Queue) static unsigned char memory[sizeof(Queue)];
  auto created = Queue::create_at(memory);
  ASSERT_TRUE(created.ok());
  ASSERT_TRUE(created.value()->try_push(Message{5, 6}));
  auto attached = Queue::attach(memory);
  ASSERT_TRUE(attached.ok());
  Message out{};
  ASSERT_TRUE(attached.value()->try_pop(out));
  EXPECT_EQ(out.sequence, 5u);
}

TEST(SpscQueue, AttachRefusesADifferentLayout) {
  using Small = SpscQueue<Message, 16>;
  using Large = SpscQueue<Message, 32>;
  alignas(Large) static unsigned char memory[sizeof(Large)];
  ASSERT_TRUE(Small::create_at(memory).ok());
  auto attached = Large::attach(memory);
  ASSERT_FALSE(attached.ok());
  EXPECT_EQ(attached.error().code, Errc::mismatch);
}

TEST(SpscQueue, RefusesMisalignedOrNullMemory) {
  using Queue = SpscQueue<Message, 4>;
  alignas(Queue) static unsigned char memory[sizeof(Queue) + 8];
  auto misaligned = Queue::create_at(memory + 8);
  ASSERT_FALSE(misaligned.ok());
  EXPECT_EQ(misaligned.error().code, Errc::invalid_argument);
  EXPECT_FALSE(Queue::attach(nullptr).ok());
}

}  // namespace
}  // namespace rescue
