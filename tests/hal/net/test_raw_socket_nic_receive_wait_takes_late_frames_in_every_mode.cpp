// Every receive wait of the raw-socket NIC (RawSocketSettings::ReceiveWait: spin, adaptive, sleep)
// still receives a frame that comes back long after its spin or its learnt round trip, and counts
// where it found it (ReceiveWaitStats); the adaptive wait learns the round trip from the frames; a
// frame that never comes is a timeout. Over a veth pair in namespaces, an echo responder on the
// other end. No duration is asserted: the late frame's delay only has to exceed the spin. The
// exchange (send, the wait in each mode, the adaptive learning) allocates nothing after init.
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "core/memory/heap_guard.hpp"
#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/netns_veth.hpp"
#include "tests/support/test_frames.hpp"

namespace rescue::hal {
namespace {

using rescue::testing::InNamespace;
using rescue::testing::VethPair;
using Wait = RawSocketSettings::ReceiveWait;

constexpr Nanoseconds kGenerous = 2 * kNsPerSec;  // only bounds a broken test
constexpr Nanoseconds kSpin = 30'000;             // the master's spin in this test
constexpr auto kLate = std::chrono::milliseconds(20);  // far beyond the spin and any learnt round trip

Status open_in(const std::string& ns, RawSocketNic& nic, const char* iface, const RawSocketSettings& settings) {
  InNamespace inside(ns);
  if (!inside.entered()) return make_error(Errc::io_error, "setns");
  return nic.open(iface, settings);
}

class ReceiveWaitOverVeth : public rescue::testing::NetnsTest, public ::testing::WithParamInterface<Wait> {
 protected:
  void SetUp() override {
    NetnsTest::SetUp();
    if (IsSkipped() || HasFatalFailure()) return;
    RawSocketSettings settings;
    settings.receive_spin = kSpin;
    settings.receive_wait = GetParam();
    ASSERT_TRUE(open_in(veth_->master_ns(), master_, VethPair::kMasterInterface, settings).ok());
    ASSERT_TRUE(open_in(veth_->slave_ns(), slaves_, VethPair::kSlaveInterface, RawSocketSettings{}).ok());
  }

  // Sends frame `index`; the responder returns it after `delay` (or never when `answer` is false);
  // the master's receive result.
  Result<std::size_t> exchange(std::uint8_t index, std::chrono::microseconds delay, bool answer = true) {
    const auto sent = rescue::testing::make_brd_frame(master_.features().hardware_address, index);
    std::thread responder([this, delay, answer] {
      std::array<std::uint8_t, 1514> buffer{};
      const Result<std::size_t> got = slaves_.receive(ByteSpan(buffer), slaves_.clock().now() + kGenerous);
      if (!got.ok() || !answer) return;
      std::this_thread::sleep_for(delay);
      (void)slaves_.send(ConstByteSpan(buffer.data(), got.value()));
    });
    EXPECT_TRUE(master_.send(ConstByteSpan(sent.data(), sent.size())).ok());
    std::array<std::uint8_t, 1514> back{};
    const Nanoseconds deadline = master_.clock().now() + (answer ? kGenerous : 50 * kNsPerMs);
    Result<std::size_t> got = master_.receive(ByteSpan(back), deadline);
    responder.join();
    return got;
  }

  RawSocketNic master_;
  RawSocketNic slaves_;
};

TEST_P(ReceiveWaitOverVeth, ALateFrameIsReceivedAndCountedAfterTheSpin) {
  // Frames answered at once: the adaptive wait learns their round trip from these.
  for (std::uint8_t i = 0; i < kAdaptiveLearnFrames + 2; ++i) ASSERT_TRUE(exchange(i, std::chrono::microseconds(0)).ok());
  if (GetParam() == Wait::adaptive) {
    EXPECT_GT(master_.expected_round_trip(), 0) << "learnt from the answered frames";
  } else {
    EXPECT_EQ(master_.expected_round_trip(), 0) << "only the adaptive wait learns";
  }
  const ReceiveWaitStats before = master_.wait_stats();
  const Result<std::size_t> late = exchange(100, kLate);
  ASSERT_TRUE(late.ok()) << late.error().what;
  EXPECT_EQ(master_.wait_stats().after_spin, before.after_spin + 1) << "found in the wait after the spin";
  EXPECT_EQ(master_.stats().receive_timeouts, 0U);
  const ReceiveWaitStats& w = master_.wait_stats();
  EXPECT_EQ(w.at_once + w.while_asleep + w.while_spinning + w.after_spin, master_.stats().frames_received)
      << "every frame counted once";
}

TEST_P(ReceiveWaitOverVeth, AFrameThatNeverComesIsATimeout) {
  for (std::uint8_t i = 0; i < kAdaptiveLearnFrames; ++i) ASSERT_TRUE(exchange(i, std::chrono::microseconds(0)).ok());
  const Result<std::size_t> lost = exchange(200, std::chrono::microseconds(0), false);
  ASSERT_FALSE(lost.ok());
  EXPECT_EQ(lost.error().code, Errc::timeout);
  EXPECT_EQ(master_.stats().receive_timeouts, 1U);
}

TEST_P(ReceiveWaitOverVeth, TheExchangeAllocatesNothingAfterInit) {
  // One thread plays both ends (the responder answers before the master waits), so nothing but the
  // exchange runs while the heap guard counts.
  const auto sent = rescue::testing::make_brd_frame(master_.features().hardware_address, 7);
  std::array<std::uint8_t, 1514> buffer{};
  declare_init_complete(HeapGuardMode::count);
  const std::uint64_t before = heap_guard_counters().allocations;
  for (unsigned i = 0; i < kAdaptiveLearnFrames + 4; ++i) {
    ASSERT_TRUE(master_.send(ConstByteSpan(sent.data(), sent.size())).ok());
    const Result<std::size_t> at_slaves = slaves_.receive(ByteSpan(buffer), slaves_.clock().now() + kGenerous);
    ASSERT_TRUE(at_slaves.ok());
    ASSERT_TRUE(slaves_.send(ConstByteSpan(buffer.data(), at_slaves.value())).ok());
    ASSERT_TRUE(master_.receive(ByteSpan(buffer), master_.clock().now() + kGenerous).ok());
  }
  EXPECT_EQ(heap_guard_counters().allocations - before, 0U);
}

INSTANTIATE_TEST_SUITE_P(EveryWait, ReceiveWaitOverVeth, ::testing::Values(Wait::spin, Wait::adaptive, Wait::sleep),
                         [](const ::testing::TestParamInfo<Wait>& param_info) { return std::string(to_string(param_info.param)); });

}  // namespace
}  // namespace rescue::hal
