// Seqlock<T>: one writer publishes snapshots of T (joint state, sensor data); any number of readers
// copy the latest one without blocking the writer. Readers retry when a write overlapped their
// copy, so they never return a torn snapshot. Works between threads and between processes through
// shared memory (no pointers; lock-free 64-bit atomics only; standard-layout, trivially destructible).
//
// Memory ordering. A plain seqlock (data copied with memcpy between a sequence load and a fence) is
// a data race in C++ and invisible to ThreadSanitizer; here every payload word is itself an atomic,
// and the ordering needs no standalone fence (which TSan cannot check):
//   writer:  seq.store(odd, relaxed); word[i].store(release) ...; seq.store(odd + 1, release)
//   reader:  s1 = seq.load(acquire); odd -> retry; word[i].load(acquire) ...; s2 = seq.load(relaxed);
//            s1 != s2 -> retry
// - If the reader saw any word of a later write k, its acquire load synchronises with that word's
//   release store, which comes after write k set seq odd; so s2 sees that odd value (or later) and
//   the reader retries.
// - If s1 is the even value written at the end of write j (acquire/release pair), every word of
//   write j happens-before the reader's loads, so it cannot see anything older.
// So s1 == s2 (even) means every word came from write j alone. On x86-64 release stores and acquire
// loads are plain MOVs: this costs nothing over the fence version. On AArch64 they are STLR/LDAR.
//
// A writer that dies mid-write (another process) leaves seq odd: readers see "no snapshot" through
// try_read's bounded attempts instead of spinning for ever, and the next writer simply continues.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace rescue {

template <typename T>
class Seqlock {
  static_assert(std::is_trivially_copyable_v<T>, "seqlock snapshots are copied as bytes");
  static_assert(std::is_default_constructible_v<T>, "seqlock readers build a T to copy into");
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free,
                "shared-memory seqlocks need lock-free (address-free) 64-bit atomics");

 public:
  using value_type = T;
  static constexpr std::uint32_t kDefaultReadAttempts = 64;

  Seqlock() noexcept {
    static_assert(std::is_standard_layout_v<Seqlock>, "shared-memory objects must be standard-layout");
    static_assert(std::is_trivially_destructible_v<Seqlock>, "processes unmap the seqlock without destroying it");
  }
  Seqlock(const Seqlock&) = delete;
  Seqlock& operator=(const Seqlock&) = delete;
  Seqlock(Seqlock&&) = delete;
  Seqlock& operator=(Seqlock&&) = delete;
  ~Seqlock() = default;

  // Single writer only: marks a write in progress ahead of write(), for a writer that builds its
  // snapshot piece by piece. Readers get no snapshot until write() completes it; a writer that dies
  // in between leaves none (try_read false), never a stale one presented as current.
  void begin_write() noexcept { seq_.store(seq_.load(std::memory_order_relaxed) | 1U, std::memory_order_relaxed); }

  // Single writer only.
  void write(const T& value) noexcept {
    std::array<std::uint64_t, kWords> words{};
    std::memcpy(words.data(), &value, sizeof(T));
    // `| 1` also resumes cleanly after a writer that died with seq odd.
    const std::uint64_t begin = seq_.load(std::memory_order_relaxed) | 1U;
    seq_.store(begin, std::memory_order_relaxed);
    for (std::size_t i = 0; i < kWords; ++i) words_[i].store(words[i], std::memory_order_release);
    seq_.store(begin + 1, std::memory_order_release);
  }

  // Copies the latest complete snapshot into `out`. Returns false, leaving `out` alone, when
  // `max_attempts` copies all overlapped a write (writer busy, or died mid-write).
  [[nodiscard]] bool try_read(T& out, std::uint32_t max_attempts = kDefaultReadAttempts) const noexcept {
    std::array<std::uint64_t, kWords> words{};
    for (std::uint32_t attempt = 0; attempt < max_attempts; ++attempt) {
      const std::uint64_t before = seq_.load(std::memory_order_acquire);
      if ((before & 1U) != 0) continue;  // write in progress
      for (std::size_t i = 0; i < kWords; ++i) words[i] = words_[i].load(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == before) {
        std::memcpy(&out, words.data(), sizeof(T));
        return true;
      }
    }
    return false;
  }

  // Number of completed writes (the sequence counter / 2): lets a reader see whether anything new
  // was published since its last copy without copying.
  std::uint64_t version() const noexcept { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  static constexpr std::size_t kWords = (sizeof(T) + sizeof(std::uint64_t) - 1) / sizeof(std::uint64_t);

  std::atomic<std::uint64_t> seq_{0};  // even: stable; odd: a write is in progress
  std::array<std::atomic<std::uint64_t>, kWords> words_{};
};

}  // namespace rescue
