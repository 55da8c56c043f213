// hal::FileSnapshot is how `decode` reads a capture. It copies the file into private memory, so a
// file truncated by someone else after open (or while it is read) can no longer kill the reader
// with SIGBUS, as a mapping of the file did; and it opens non-blocking and refuses anything that
// is not a regular file, so a FIFO with no writer returns at once instead of hanging open().
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "hal/files/file_snapshot.hpp"

namespace rescue::hal {
namespace {

std::string temp_path(const char* name) {
  return std::string(::testing::TempDir()) + "/" + name + "-" + std::to_string(::getpid());
}

std::uint8_t pattern(std::size_t i) { return static_cast<std::uint8_t>((i * 131U + 7U) & 0xFFU); }

void write_pattern(const std::string& path, std::size_t size) {
  std::vector<std::uint8_t> bytes(size);
  for (std::size_t i = 0; i < size; ++i) bytes[i] = pattern(i);
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::write(fd, bytes.data(), size), static_cast<ssize_t>(size));
  ASSERT_EQ(::close(fd), 0);
}

TEST(FileSnapshot, ReadsTheWholeFile) {
  const std::string path = temp_path("snapshot-whole");
  write_pattern(path, 100'000);
  const auto s = FileSnapshot::open(path.c_str());
  ASSERT_TRUE(s.ok()) << s.error().what;
  ASSERT_EQ(s.value().bytes().size(), 100'000U);
  for (std::size_t i = 0; i < 100'000; ++i) ASSERT_EQ(s.value().bytes()[i], pattern(i)) << i;
  EXPECT_FALSE(s.value().shrank());
  ::unlink(path.c_str());
}

TEST(FileSnapshot, EmptyFileGivesNoBytes) {
  const std::string path = temp_path("snapshot-empty");
  write_pattern(path, 0);
  const auto s = FileSnapshot::open(path.c_str());
  ASSERT_TRUE(s.ok());
  EXPECT_TRUE(s.value().bytes().empty());
  ::unlink(path.c_str());
}

// With the former mmap of the file, touching the bytes after this truncation raised SIGBUS.
TEST(FileSnapshot, BytesSurviveATruncationAfterOpen) {
  const std::string path = temp_path("snapshot-truncated");
  write_pattern(path, 1 << 20);
  const auto s = FileSnapshot::open(path.c_str());
  ASSERT_TRUE(s.ok());
  ASSERT_EQ(::truncate(path.c_str(), 0), 0);
  unsigned long sum = 0;
  unsigned long expected = 0;
  for (std::size_t i = 0; i < s.value().bytes().size(); ++i) {
    sum += s.value().bytes()[i];
    expected += pattern(i);
  }
  EXPECT_EQ(s.value().bytes().size(), std::size_t{1} << 20);
  EXPECT_EQ(sum, expected);
  ::unlink(path.c_str());
}

// Truncations racing the read itself: the reader never crashes, never returns more than was there,
// and every byte it returns is the file's (or a zero a re-extension wrote). Bounded: 60 reads.
TEST(FileSnapshot, TruncationsDuringTheReadNeverCrash) {
  const std::string path = temp_path("snapshot-racing");
  constexpr std::size_t kSize = 4 << 20;
  write_pattern(path, kSize);
  std::atomic<bool> stop{false};
  std::thread truncator([&] {
    std::size_t n = 0;
    while (!stop.load()) {
      (void)::truncate(path.c_str(), static_cast<off_t>((n++ % 2 == 0) ? kSize / 3 : kSize));
    }
  });
  int shrank = 0;
  for (int i = 0; i < 60; ++i) {
    const auto s = FileSnapshot::open(path.c_str());
    ASSERT_TRUE(s.ok());
    const ConstByteSpan b = s.value().bytes();
    ASSERT_LE(b.size(), kSize);
    for (std::size_t j = 0; j < b.size(); j += 4093) ASSERT_TRUE(b[j] == pattern(j) || b[j] == 0) << j;
    shrank += s.value().shrank() ? 1 : 0;
  }
  stop = true;
  truncator.join();
  RecordProperty("reads_that_saw_the_file_shrink", shrank);
  ::unlink(path.c_str());
}

// In a child with an alarm: before the fix open() of a FIFO without a writer never returned.
TEST(FileSnapshot, FifoWithoutAWriterIsRefusedAtOnce) {
  const std::string path = temp_path("snapshot-fifo");
  ::unlink(path.c_str());
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::alarm(5);
    const auto s = FileSnapshot::open(path.c_str());
    const bool refused = !s.ok() && s.error().code == Errc::invalid_argument;
    ::_exit(refused ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status)) << "the child hung in open() and the alarm killed it (signal "
                                 << (WIFSIGNALED(status) ? WTERMSIG(status) : 0) << ")";
  if (WIFEXITED(status)) {
    EXPECT_EQ(WEXITSTATUS(status), 0) << "not refused as 'not a regular file'";
  }
  ::unlink(path.c_str());
}

TEST(FileSnapshot, DirectoriesAndDevicesAreRefused) {
  for (const char* path : {"/", "/dev/null", "/dev/zero"}) {
    const auto s = FileSnapshot::open(path);
    ASSERT_FALSE(s.ok()) << path;
    EXPECT_EQ(s.error().code, Errc::invalid_argument) << path;
    EXPECT_STREQ(s.error().what, "not a regular file");
  }
}

TEST(FileSnapshot, MissingFileIsAnIoErrorWithErrno) {
  const auto s = FileSnapshot::open("/nonexistent/capture.pcapng");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().code, Errc::io_error);
  EXPECT_STREQ(s.error().what, "open file");
  EXPECT_EQ(s.error().detail0, static_cast<std::uint32_t>(ENOENT));
}

}  // namespace
}  // namespace rescue::hal
