#include <gtest/gtest.h>

#include "core/containers/ring_buffer.hpp"

namespace rescue {
namespace {

TEST(RingBuffer, PopsInPushOrder) {
  RingBuffer<int, 4> ring;
  EXPECT_TRUE(ring.empty());
  ASSERT_TRUE(ring.push(1));
  ASSERT_TRUE(ring.push(2));
  ASSERT_TRUE(ring.push(3));
  int out = 0;
  ASSERT_TRUE(ring.pop(out));
  EXPECT_EQ(out, 1);
  ASSERT_TRUE(ring.pop(out));
  EXPECT_EQ(out, 2);
  EXPECT_EQ(ring.size(), 1u);
  EXPECT_EQ(ring.front(), 3);
}

TEST(RingBuffer, RefusesPushWhenFullAndChangesNothing) {
  RingBuffer<int, 3> ring;
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(ring.push(i));
  EXPECT_TRUE(ring.full());
  EXPECT_FALSE(ring.push(99));
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_EQ(ring.front(), 0);
  EXPECT_EQ(ring.back(), 2);
}

TEST(RingBuffer, PopOnEmptyFailsAndLeavesOutput) {
  RingBuffer<int, 2> ring;
  int out = 42;
  EXPECT_FALSE(ring.pop(out));
  EXPECT_EQ(out, 42);
}

TEST(RingBuffer, OverwriteDropsOldestAndSaysSo) {
  RingBuffer<int, 3> ring;
  EXPECT_FALSE(ring.push_overwrite(1));
  EXPECT_FALSE(ring.push_overwrite(2));
  EXPECT_FALSE(ring.push_overwrite(3));
  EXPECT_TRUE(ring.push_overwrite(4));  // drops 1
  EXPECT_TRUE(ring.push_overwrite(5));  // drops 2
  ASSERT_EQ(ring.size(), 3u);
  EXPECT_EQ(ring[0], 3);
  EXPECT_EQ(ring[1], 4);
  EXPECT_EQ(ring[2], 5);
}

TEST(RingBuffer, KeepsOrderAcrossManyWrapArounds) {
  RingBuffer<int, 5> ring;
  int next_in = 0;
  int next_out = 0;
  // Uneven push/pop rhythm so the head visits every slot many times.
  for (int round = 0; round < 1000; ++round) {
    for (int k = 0; k < round % 4 + 1 && !ring.full(); ++k) ASSERT_TRUE(ring.push(next_in++));
    for (int k = 0; k < round % 3 + 1 && !ring.empty(); ++k) {
      int out = -1;
      ASSERT_TRUE(ring.pop(out));
      ASSERT_EQ(out, next_out++);
    }
    for (std::size_t i = 0; i < ring.size(); ++i) ASSERT_EQ(ring[i], next_out + static_cast<int>(i));
  }
  EXPECT_GT(next_out, 1000);
}

TEST(RingBuffer, ClearEmpties) {
  RingBuffer<int, 2> ring;
  ASSERT_TRUE(ring.push(1));
  ring.clear();
  EXPECT_TRUE(ring.empty());
  ASSERT_TRUE(ring.push(7));
  EXPECT_EQ(ring.front(), 7);
}

}  // namespace
}  // namespace rescue
