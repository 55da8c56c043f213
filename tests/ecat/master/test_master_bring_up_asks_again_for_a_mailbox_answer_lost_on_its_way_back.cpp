// Issue 35 (loaded CI, ASan stage): bring-up failed at PRE-OP SDO, "start-up SDO not answered in
// time", with late frames counted. The ESCs carry out a frame's datagrams whether or not it comes
// back: a frame that read SM1 took the slave's answer out of its mailbox, and when that frame was not
// back in time, MailboxClient::run sent it again blind. The copy found SM1 empty, the answer was
// gone, and the step timed out. Here, on the simulated robot in virtual time, the first frames that
// take an answer out of a mailbox (an FPRD of a mailbox buffer, working counter 1) are lost on their
// way back: bring-up still completes, no SDO times out, and the master asked the slaves to put their
// answers back (mailbox repeat request) at least once per lost answer.
#include <gtest/gtest.h>

#include "ecat/codec/frame.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

// The NIC of the rig, except that the first `to_lose` frames that took an answer out of a mailbox
// never come back.
class LosesMailboxAnswers final : public hal::Nic {
 public:
  LosesMailboxAnswers(hal::Nic& inner, int to_lose) noexcept : inner_(inner), to_lose_(to_lose) {}

  Status send(ConstByteSpan frame) noexcept override { return inner_.send(frame); }
  Result<std::size_t> receive(ByteSpan buffer, hal::Nanoseconds deadline) noexcept override {
    const Result<std::size_t> got = inner_.receive(buffer, deadline);
    if (!got.ok() || to_lose_ == 0 || !takes_an_answer(ConstByteSpan(buffer.data(), got.value()))) return got;
    --to_lose_;
    ++lost_;
    inner_.clock().sleep_until(deadline);
    return make_error(Errc::timeout, "lost on its way back");
  }
  hal::Clock& clock() noexcept override { return inner_.clock(); }
  const char* name() const noexcept override { return "loses mailbox answers"; }
  hal::NicStats stats() const noexcept override { return inner_.stats(); }
  int lost() const noexcept { return lost_; }

 private:
  static bool takes_an_answer(ConstByteSpan bytes) noexcept {
    const Result<FrameView> view = FrameView::parse(bytes);
    if (!view.ok()) return false;
    for (const DatagramView d : view.value()) {
      // Mailbox buffers lie above the registers (0x0000-0x0FFF); process data goes by LRW.
      if (d.command() == Command::FPRD && d.ado() >= 0x1000U && d.wkc() == 1) return true;
    }
    return false;
  }

  hal::Nic& inner_;
  int to_lose_;
  int lost_{0};
};

TEST(BringUpMailbox, AnAnswerLostOnItsWayBackIsAskedForAgainAndNoSdoTimesOut) {
  constexpr int kLost = 3;
  auto rig = std::make_unique<testing::SimulatedRobotRig>();
  ASSERT_TRUE(rig->built.ok());
  LosesMailboxAnswers nic(rig->nic, kLost);
  auto bus = std::make_unique<drivers::JointBus>(nic);
  const Status up = bus->bring_up(testing::fast_options());
  EXPECT_TRUE(up.ok()) << testing::describe_master_failure(bus->master());
  EXPECT_EQ(nic.lost(), kLost) << "bring-up read fewer mailbox answers than the test loses";
  const MailboxStats& stats = bus->master().mailbox().stats();
  EXPECT_EQ(stats.timeouts, 0U);
  EXPECT_GE(stats.repeat_requests, static_cast<std::uint64_t>(kLost));
}

}  // namespace
}  // namespace rescue::ecat
