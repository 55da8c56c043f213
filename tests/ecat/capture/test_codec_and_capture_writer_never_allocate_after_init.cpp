// The cyclic path of the codec is heap-free: with the heap guard in strict mode (any allocation
// aborts), a thousand cycles build a frame, parse it, let a "slave" edit it in place, and record
// both directions to a capture file, including cycles where every write fails.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <string>

#include "core/memory/heap_guard.hpp"
#include "ecat/capture/capture_writer.hpp"
#include "ecat/codec/frame.hpp"

namespace rescue::ecat {
namespace {

TEST(CodecHeapFree, ThousandCyclesOfBuildParseEditAndCaptureAllocateNothing) {
  const std::string path = std::string(::testing::TempDir()) + "/heap-free-" + std::to_string(::getpid()) + ".pcapng";
  // Init: everything that may allocate.
  static CaptureWriter writer;
  static FrameBuilder builder;
  ASSERT_TRUE(writer.open(path.c_str()).ok());
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  std::array<std::uint8_t, kMaxFrameSize> returned{};
  hal::VirtualClock clock;
  reopen_init_for_testing();
  declare_init_complete(HeapGuardMode::strict);

  std::uint64_t datagrams = 0;
  for (int cycle = 0; cycle < 1000; ++cycle) {
    if (cycle == 500) {  // from here on the disk is "full": every record fails and is counted
      rlimit full = old_limit;
      full.rlim_cur = static_cast<rlim_t>(writer.stats().bytes_written);
      (void)::setrlimit(RLIMIT_FSIZE, &full);
    }
    builder.reset(MacAddress{0x02, 0, 0, 0, 0, 0x01});
    const auto dc = builder.add(Command::FRMW, 1, make_address(0x1000, 0x0910), 8);
    const auto pd = builder.add(Command::LRW, 2, 0x10000, 200);
    if (!dc.ok() || !pd.ok()) break;
    builder.data(pd.value())[0] = static_cast<std::uint8_t>(cycle);
    const ConstByteSpan sent = builder.finish();
    writer.record(sent, clock.now(), FrameDirection::outbound);

    std::copy(sent.begin(), sent.end(), returned.begin());
    const auto view = MutableFrameView::parse(ByteSpan(returned.data(), sent.size()));
    if (!view.ok()) break;
    for (const MutableDatagramView d : view.value()) {
      d.set_wkc(static_cast<std::uint16_t>(d.wkc() + 21));
      ++datagrams;
    }
    clock.advance(hal::kNsPerMs / 2);
    writer.record(ConstByteSpan(returned.data(), sent.size()), clock.now(), FrameDirection::inbound);
    clock.advance(hal::kNsPerMs / 2);
  }

  const HeapGuardCounters heap = heap_guard_counters();
  reopen_init_for_testing();
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old_limit), 0);
  (void)std::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(heap.allocations, 0U);
  EXPECT_EQ(datagrams, 2000U);
  EXPECT_EQ(writer.stats().frames_written, 1000U);
  EXPECT_EQ(writer.stats().write_errors, 1000U);
  EXPECT_TRUE(writer.close().ok());
  ::unlink(path.c_str());
}

}  // namespace
}  // namespace rescue::ecat
