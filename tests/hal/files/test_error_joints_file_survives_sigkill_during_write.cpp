// Crash consistency of the error-joints file: a child process rewrites the file in a loop, alternating
// two versions (the left-arm cut, 4 records, and the torso cut, 3 records; the sequence number says
// which one), and is killed with SIGKILL at a random instant. After every kill the file must read back
// as one complete version: header and every record valid, the records those of its sequence number,
// and never older than the version seen after the previous kill. Hundreds of kills.
//
// SIGKILL tests a crash of the process. A power cut also loses the page cache; docs/joint-manager.md
// explains why the fsync of the file before the rename, and of the directory after it, cover that case.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

#include "core/robot/error_joints_file.hpp"
#include "hal/files/durable_file.hpp"

namespace rescue {
namespace {

constexpr int kKills = 300;
constexpr const char* kName = "error-joints.bin";

ErrorJointsContents version_for(std::uint64_t sequence) {
  ErrorJointsContents c;
  c.sequence = sequence;
  const JointMask lost = sequence % 2 == 0 ? joints_lost_by_link_failure_at(joint_index_by_name("l_elbow"))
                                           : joints_of_branch(Branch::torso);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((lost & joint_bit(j)) == 0) continue;
    LostJointRecord r;
    r.joint = static_cast<std::uint8_t>(j);
    r.reason = FaultReason::comm_lost;
    r.last_position_counts = static_cast<std::int32_t>(j * 1000 + sequence % 2);
    r.time_unix_ns = static_cast<std::int64_t>(sequence % 2);
    r.cycle = 4242 + sequence % 2;
    (void)c.records.push_back(r);
  }
  return c;
}

// Shared with the child: it counts its completed writes here.
struct Progress {
  std::atomic<std::uint64_t> started{0};
  std::atomic<std::uint64_t> completed{0};
};

[[noreturn]] void writer_child(const std::string& dir, std::uint64_t first_sequence, Progress* progress) {
  std::array<std::uint8_t, kErrorJointsMaxFileSize> buf{};
  progress->started.store(1);
  for (std::uint64_t seq = first_sequence;; ++seq) {
    auto size = encode_error_joints(version_for(seq), ByteSpan(buf));
    if (!size.ok()) _exit(2);
    if (!hal::write_file_atomically(dir.c_str(), kName, ConstByteSpan(buf.data(), size.value())).ok()) _exit(3);
    progress->completed.fetch_add(1);
  }
}

struct Readback {
  bool ok{false};
  std::uint64_t sequence{0};
  std::string why;
};

Readback read_back(const std::string& dir) {
  Readback out;
  std::array<std::uint8_t, 4096> buf{};
  auto n = hal::read_file_capped((dir + "/" + kName).c_str(), ByteSpan(buf));
  if (!n.ok()) {
    out.why = std::string("read: ") + n.error().what;
    return out;
  }
  const ErrorJointsDecoded d = decode_error_joints(ConstByteSpan(buf.data(), n.value()));
  if (!d.status.ok() || d.records_rejected != 0) {
    out.why = std::string("decode: ") + (d.status.ok() ? "rejected records" : d.status.error().what);
    return out;
  }
  const ErrorJointsContents expected = version_for(d.contents.sequence);
  if (d.contents.records.size() != expected.records.size()) {
    out.why = "record count differs from its version";
    return out;
  }
  for (std::size_t i = 0; i < expected.records.size(); ++i) {
    const LostJointRecord& a = d.contents.records[i];
    const LostJointRecord& b = expected.records[i];
    if (a.joint != b.joint || a.last_position_counts != b.last_position_counts || a.cycle != b.cycle ||
        a.time_unix_ns != b.time_unix_ns) {
      out.why = "record differs from its version";
      return out;
    }
  }
  out.ok = true;
  out.sequence = d.contents.sequence;
  return out;
}

TEST(ErrorJointsCrash, FileIsAlwaysACompleteOldOrNewVersionAfterSigkill) {
  std::string dir = ::testing::TempDir() + "crash-XXXXXX";
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  {
    std::array<std::uint8_t, kErrorJointsMaxFileSize> buf{};
    auto size = encode_error_joints(version_for(0), ByteSpan(buf));
    ASSERT_TRUE(size.ok());
    ASSERT_TRUE(hal::write_file_atomically(dir.c_str(), kName, ConstByteSpan(buf.data(), size.value())).ok());
  }
  void* shared = mmap(nullptr, sizeof(Progress), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(shared, MAP_FAILED);

  std::mt19937_64 rng(20240601);
  std::uint64_t last_sequence = 0;
  int mid_write_kills = 0;      // a temporary file was left behind: killed between create and rename
  std::uint64_t writes_completed = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int kill_no = 0; kill_no < kKills; ++kill_no) {
    auto* progress = new (shared) Progress{};
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) writer_child(dir, last_sequence + 1, progress);

    while (progress->started.load() == 0) {
    }
    // A random instant: let it complete 0..2 writes, then spin a random while (one write takes a few
    // hundred microseconds to milliseconds, mostly in fsync).
    const std::uint64_t wait_writes = rng() % 3;
    while (progress->completed.load() < wait_writes) {
    }
    const std::uint64_t spins = rng() % 3'000'000;
    for (volatile std::uint64_t i = 0; i < spins; i = i + 1) {
    }
    ASSERT_EQ(kill(child, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the writer exited by itself with status " << WEXITSTATUS(status);
    writes_completed += progress->completed.load();

    mid_write_kills += access((dir + "/" + kName + ".tmp").c_str(), F_OK) == 0 ? 1 : 0;
    const Readback r = read_back(dir);
    ASSERT_TRUE(r.ok) << "after kill " << kill_no << ": " << r.why;
    ASSERT_GE(r.sequence, last_sequence) << "after kill " << kill_no << " the file went back to an older version";
    last_sequence = r.sequence;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  munmap(shared, sizeof(Progress));
  (void)std::system(("rm -rf '" + dir + "'").c_str());

  // Figures for the report (not assertions on time): how many kills, how many landed mid-write.
  std::printf("crash-test: kills: %d\ncrash-test: kills with a temporary file left (mid-write): %d\n"
              "crash-test: completed writes: %llu\ncrash-test: final sequence: %llu\ncrash-test: duration: %.2f s\n",
              kKills, mid_write_kills, static_cast<unsigned long long>(writes_completed),
              static_cast<unsigned long long>(last_sequence), seconds);
  RecordProperty("kills", kKills);
  RecordProperty("mid_write_kills", mid_write_kills);
  EXPECT_GT(mid_write_kills, 0) << "no kill landed inside a write: the test did not exercise the window";
}

}  // namespace
}  // namespace rescue
