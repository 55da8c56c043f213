// for_each_slave_from (ecat/link/network_plan.hpp) walks only the set bits of a slave mask, in the
// order a scan of every position from `start` round to start - 1 visits them: the link monitor's
// probe plan relies on it to give the same probes in the same order as the scan it replaced.
#include <gtest/gtest.h>

#include <cstddef>
#include <random>
#include <vector>

#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {
namespace {

std::vector<std::size_t> scan(SlaveMask mask, std::size_t start, std::size_t stop_after) {
  std::vector<std::size_t> visited;
  for (std::size_t i = 0; i < kMaxSlaves && visited.size() < stop_after; ++i) {
    const std::size_t p = (start + i) % kMaxSlaves;
    if ((mask & slave_bit(p)) != 0) visited.push_back(p);
  }
  return visited;
}

std::vector<std::size_t> walk(SlaveMask mask, std::size_t start, std::size_t stop_after) {
  std::vector<std::size_t> visited;
  for_each_slave_from(mask, start, [&](std::size_t p) {
    if (visited.size() >= stop_after) return false;
    visited.push_back(p);
    return true;
  });
  return visited;
}

TEST(SlaveMaskWalk, VisitsTheSetBitsInTheOrderOfAScanFromEveryStartAndStopsWhenAsked) {
  std::mt19937 random(7);
  const SlaveMask all = (SlaveMask{1} << kMaxSlaves) - 1;
  std::vector<SlaveMask> masks = {0, all, slave_bit(0), slave_bit(kMaxSlaves - 1), slave_bit(0) | slave_bit(kMaxSlaves - 1)};
  for (int i = 0; i < 2000; ++i) masks.push_back(static_cast<SlaveMask>(random()) & all);
  for (const SlaveMask mask : masks) {
    for (std::size_t start = 0; start <= kMaxSlaves; ++start) {  // kMaxSlaves: a rotation past the last slave
      for (const std::size_t stop_after : {std::size_t{0}, std::size_t{1}, std::size_t{3}, kMaxSlaves}) {
        ASSERT_EQ(walk(mask, start, stop_after), scan(mask, start, stop_after))
            << "mask " << mask << " start " << start << " stop after " << stop_after;
      }
    }
  }
}

TEST(SlaveMaskWalk, LowestSlaveIsThePositionOfTheLowestSetBit) {
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    EXPECT_EQ(lowest_slave(slave_bit(p)), p);
    EXPECT_EQ(lowest_slave(slave_bit(p) | slave_bit(kMaxSlaves - 1)), p);
  }
}

}  // namespace
}  // namespace rescue::ecat
