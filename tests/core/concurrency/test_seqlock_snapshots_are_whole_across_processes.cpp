// The seqlock in POSIX shared memory between two processes: a forked child writes snapshots
// through its own mapping of the segment (another address), the parent reads them concurrently and
// must only ever see whole snapshots, never older than one it already saw.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <new>

#include "core/base/sanitizers.hpp"
#include "core/concurrency/seqlock.hpp"
#include "tests/support/forked_child.hpp"
#include "tests/support/shared_memory_segment.hpp"

namespace rescue {
namespace {

struct Snapshot {
  std::array<std::uint64_t, 6> words;
};
using Lock = Seqlock<Snapshot>;

constexpr std::uint64_t kWrites = kSanitizerInterceptsMalloc ? 50'000 : 500'000;

Snapshot snapshot_of(std::uint64_t counter) {
  Snapshot s{};
  for (std::size_t i = 0; i < s.words.size(); ++i) s.words[i] = counter + i * 1000;
  return s;
}

bool is_whole(const Snapshot& s) {
  for (std::size_t i = 1; i < s.words.size(); ++i) {
    if (s.words[i] != s.words[0] + i * 1000) return false;
  }
  return true;
}

TEST(SeqlockAcrossProcesses, ReaderSeesOnlyWholeSnapshotsFromAnotherProcess) {
  test::SharedMemorySegment segment("seqlock", sizeof(Lock));
  ASSERT_TRUE(segment.ok()) << "shm_open/mmap failed for " << segment.name();
  Lock* lock = new (segment.address()) Lock();
  lock->write(snapshot_of(0));  // before the fork: the child is the only writer afterwards

  std::uint64_t reads = 0;
  std::uint64_t torn = 0;
  std::uint64_t backwards = 0;
  std::uint64_t last = 0;
  const int child_exit = test::run_with_child(
      [&] {
        void* mine = segment.map_again();
        if (mine == nullptr || mine == segment.address()) return 2;
        auto* writer = static_cast<Lock*>(mine);
        for (std::uint64_t counter = 1; counter <= kWrites; ++counter) writer->write(snapshot_of(counter));
        return 0;
      },
      [&](pid_t child) {
        bool child_done = false;
        while (last < kWrites) {
          const bool final_read = child_done;  // the child has exited: its last write is visible
          Snapshot s{};
          bool fresh = false;
          if (lock->try_read(s, final_read ? UINT32_MAX : Lock::kDefaultReadAttempts)) {
            ++reads;
            if (!is_whole(s)) ++torn;
            if (s.words[0] < last) ++backwards;
            fresh = s.words[0] != last;
            last = s.words[0];
          }
          if (final_read) break;
          if (!fresh) child_done = test::child_has_exited(child);
        }
      });
  EXPECT_EQ(child_exit, 0) << "2: the child could not map the segment at a new address";
  EXPECT_GT(reads, 0u);
  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(backwards, 0u);
  EXPECT_EQ(last, kWrites);
}

}  // namespace
}  // namespace rescue
