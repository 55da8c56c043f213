// Stress: one writer publishes snapshots whose eight words all derive from one counter, as fast as
// it can; two readers copy them concurrently. A reader must never return a mix of two writes, and
// must never see the counter go backwards. Labelled `concurrency`: ThreadSanitizer runs it too.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <thread>

#include "core/base/sanitizers.hpp"
#include "core/concurrency/seqlock.hpp"

namespace rescue {
namespace {

struct Snapshot {
  std::array<std::uint64_t, 8> words;
};

Snapshot snapshot_of(std::uint64_t counter) {
  Snapshot s{};
  for (std::size_t i = 0; i < s.words.size(); ++i) s.words[i] = counter * (i + 1) + i;
  return s;
}

bool is_whole(const Snapshot& s) {
  const std::uint64_t counter = s.words[0];
  for (std::size_t i = 0; i < s.words.size(); ++i) {
    if (s.words[i] != counter * (i + 1) + i) return false;
  }
  return true;
}

constexpr std::uint64_t kWrites = kSanitizerInterceptsMalloc ? 100'000 : 1'000'000;

struct ReaderResult {
  std::uint64_t reads{0};
  std::uint64_t torn{0};
  std::uint64_t backwards{0};
  std::uint64_t last{0};
};

TEST(SeqlockStress, ReadersNeverSeeATornOrOlderSnapshot) {
  static Seqlock<Snapshot> lock;
  lock.write(snapshot_of(0));  // the zero-initialised state is not a snapshot_of() anything
  std::atomic<bool> writer_done{false};
  std::array<ReaderResult, 2> results{};

  auto reader = [&](ReaderResult& result) {
    std::uint64_t last = 0;
    bool final_read = false;
    while (!final_read) {
      final_read = writer_done.load(std::memory_order_acquire);  // one more read after the writer ends
      Snapshot s{};
      if (!lock.try_read(s, final_read ? UINT32_MAX : Seqlock<Snapshot>::kDefaultReadAttempts)) continue;
      ++result.reads;
      if (!is_whole(s)) ++result.torn;
      if (s.words[0] < last) ++result.backwards;
      last = s.words[0];
    }
    result.last = last;
  };
  std::thread reader_a(reader, std::ref(results[0]));
  std::thread reader_b(reader, std::ref(results[1]));

  for (std::uint64_t counter = 1; counter <= kWrites; ++counter) lock.write(snapshot_of(counter));
  writer_done.store(true, std::memory_order_release);
  reader_a.join();
  reader_b.join();

  for (const ReaderResult& r : results) {
    EXPECT_GT(r.reads, 0u);
    EXPECT_EQ(r.torn, 0u);
    EXPECT_EQ(r.backwards, 0u);
    EXPECT_EQ(r.last, kWrites) << "the read after the writer finished sees the last write";
  }
  EXPECT_EQ(lock.version(), kWrites + 1);  // with the initial snapshot_of(0)
}

}  // namespace
}  // namespace rescue
