// CaptureReader sees the real captures as Wireshark does, frame by frame: same frame numbers,
// timestamps to the nanosecond, captured and original lengths. tshark missing is a failure;
// the shared captures missing is a skip with the reason.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "ecat/capture/capture_reader.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/shared_captures.hpp"

namespace rescue::ecat {
namespace {

const std::string& kCaptures = test::kSharedCaptureDir;

class ReaderVersusTshark : public testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    ASSERT_TRUE(test::program_available("tshark")) << "tshark is missing: run toolchain/setup.sh (Debian package tshark)";
    path_ = kCaptures + GetParam();
    if (::access(path_.c_str(), R_OK) != 0) {
      GTEST_SKIP() << "no shared captures: " << kCaptures << " is absent (the data is not part of the repository)";
    }
  }
  std::string path_;
};

TEST_P(ReaderVersusTshark, SameFramesTimestampsAndLengths) {
  std::ifstream in(path_, std::ios::binary);
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  auto reader = CaptureReader::open(ConstByteSpan(bytes.data(), bytes.size()));
  ASSERT_TRUE(reader.ok());
  std::vector<std::string> ours;
  CapturedFrame f;
  while (reader.value().next(f).value_or(false)) {
    char line[128];
    std::snprintf(line, sizeof line, "%" PRIu32 "\t%" PRIu64 ".%09" PRIu64 "\t%zu\t%" PRIu32, f.number,
                  f.timestamp_ns / std::uint64_t{1'000'000'000}, f.timestamp_ns % std::uint64_t{1'000'000'000}, f.bytes.size(), f.original_length);
    ours.emplace_back(line);
  }
  const test::CommandOutput out = test::run_command(
      "tshark -r '" + path_ + "' -T fields -E separator=/t -e frame.number -e frame.time_epoch -e frame.cap_len -e frame.len 2>/dev/null");
  ASSERT_EQ(out.exit_status, 0);
  const std::vector<std::string> theirs = test::split_lines(out.out);
  ASSERT_EQ(ours.size(), theirs.size());
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    if (ours[i] != theirs[i] && ++mismatches <= 5) ADD_FAILURE() << "ours:   " << ours[i] << "\ntshark: " << theirs[i];
  }
  EXPECT_EQ(mismatches, 0U);
}

INSTANTIATE_TEST_SUITE_P(Captures, ReaderVersusTshark,
                         testing::ValuesIn(test::kSharedCaptures),
                         test::capture_param_name);

}  // namespace
}  // namespace rescue::ecat
