#include <gtest/gtest.h>

#include "core/containers/fixed_vector.hpp"

namespace rescue {
namespace {

struct Counted {
  static inline int alive = 0;
  int v;
  explicit Counted(int x) : v(x) { ++alive; }
  Counted(const Counted& o) : v(o.v) { ++alive; }
  Counted& operator=(const Counted&) = default;
  ~Counted() { --alive; }
};

TEST(FixedVector, RefusesPushBeyondCapacity) {
  FixedVector<int, 3> v;
  EXPECT_TRUE(v.push_back(1));
  EXPECT_TRUE(v.push_back(2));
  EXPECT_TRUE(v.push_back(3));
  EXPECT_FALSE(v.push_back(4));
  EXPECT_EQ(v.size(), 3u);
  EXPECT_EQ(v[2], 3);
  EXPECT_EQ(v.emplace_back(5), nullptr);
}

TEST(FixedVector, EraseKeepsOrder) {
  FixedVector<int, 5> v;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(v.push_back(i));
  v.erase_at(1);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[0], 0);
  EXPECT_EQ(v[1], 2);
  EXPECT_EQ(v[3], 4);
}

TEST(FixedVector, DestroysElements) {
  {
    FixedVector<Counted, 4> v;
    ASSERT_NE(v.emplace_back(1), nullptr);
    ASSERT_TRUE(v.push_back(Counted(2)));
    FixedVector<Counted, 4> copy = v;
    EXPECT_EQ(Counted::alive, 4);
    v.pop_back();
    EXPECT_EQ(Counted::alive, 3);
    EXPECT_EQ(copy[1].v, 2);
  }
  EXPECT_EQ(Counted::alive, 0);
}

}  // namespace
}  // namespace rescue
