#include <gtest/gtest.h>

#include <cstdint>

#include "core/concurrency/seqlock.hpp"

namespace rescue {
namespace {

struct JointState {
  std::int32_t position;
  std::int32_t velocity;
  std::int16_t torque;
  std::uint16_t status;
  std::uint8_t mode;  // odd size: the last word is partly padding
};

TEST(Seqlock, StartsWithAZeroSnapshotAtVersionZero) {
  Seqlock<JointState> lock;
  JointState out{1, 1, 1, 1, 1};
  ASSERT_TRUE(lock.try_read(out));
  EXPECT_EQ(out.position, 0);
  EXPECT_EQ(out.mode, 0);
  EXPECT_EQ(lock.version(), 0u);
}

TEST(Seqlock, ABegunWriteHidesEverySnapshotUntilWriteCompletesIt) {
  Seqlock<JointState> lock;
  lock.write(JointState{10, -2, 3, 0x0237, 8});
  lock.begin_write();  // a writer building its next snapshot (or one that died doing so)
  JointState out{};
  EXPECT_FALSE(lock.try_read(out, 4));
  EXPECT_EQ(out.position, 0) << "left alone";
  lock.write(JointState{11, -3, 4, 0x0637, 9});
  ASSERT_TRUE(lock.try_read(out));
  EXPECT_EQ(out.position, 11);
  EXPECT_EQ(lock.version(), 2u);
}

TEST(Seqlock, ReadReturnsTheLatestWrite) {
  Seqlock<JointState> lock;
  lock.write(JointState{10, -2, 3, 0x0237, 8});
  lock.write(JointState{11, -3, 4, 0x0637, 9});
  JointState out{};
  ASSERT_TRUE(lock.try_read(out));
  EXPECT_EQ(out.position, 11);
  EXPECT_EQ(out.velocity, -3);
  EXPECT_EQ(out.torque, 4);
  EXPECT_EQ(out.status, 0x0637);
  EXPECT_EQ(out.mode, 9);
  EXPECT_EQ(lock.version(), 2u);
}

TEST(Seqlock, ZeroAttemptsNeverReads) {
  Seqlock<JointState> lock;
  JointState out{5, 5, 5, 5, 5};
  EXPECT_FALSE(lock.try_read(out, 0));
  EXPECT_EQ(out.position, 5);
}

}  // namespace
}  // namespace rescue
