// Over veth with the wall clock, against `rescue-motion sim --iface`: replies held back 5 ms at a
// time (host jitter) raise nothing; 300 ms without any reply (the simulator's "stall 300", as a
// pulled cable at the master or a dead NIC would look) raise exactly one link-silence alarm about
// 100 ms in, then "heard again" when frames return, and no joint is reported lost for it.
#include <gtest/gtest.h>

#include <signal.h>

#include <string>

#include "tests/support/master_over_veth.hpp"

namespace rescue::app {
namespace {

using LinkSilenceOverVeth = rescue::testing::MasterOverVethTest;

TEST_F(LinkSilenceOverVeth, JitterRaisesNothingAndASilenceRaisesOneAlarm) {
  ecat::MasterOptions options;
  options.drift_compensation_frames = 1000;
  options.frame_timeout = 20 * hal::kNsPerMs;
  bring_up_to_op(options, 3000);
  if (HasFatalFailure()) return;
  for (int i = 0; i < 200; ++i) (void)cycle();

  for (int burst = 0; burst < 4; ++burst) {
    ASSERT_TRUE(sim_.write_input("stall 5\n"));
    for (int i = 0; i < 100; ++i) (void)cycle();
  }
  EXPECT_EQ(reported(ecat::LinkEventKind::silent), 0U) << "5 ms stalls are jitter";
  EXPECT_EQ(bus_->master().monitor().silences(), 0U);

  const hal::Nanoseconds stalled_at = nic_.clock().now();
  ASSERT_TRUE(sim_.write_input("stall 300\n"));
  hal::Nanoseconds alarm_at = 0;
  for (int i = 0; i < 600; ++i) {
    (void)cycle();
    for (const drivers::JointLinkReport& r : reports_) {
      if (r.link.kind == ecat::LinkEventKind::silent && alarm_at == 0) alarm_at = r.link.time;
    }
  }
  ASSERT_NE(alarm_at, 0) << "300 ms without a reply raised no alarm";
  // kSilenceAlarm after the first frame that did not come back, which was sent after the stall
  // began (the simulator reads its console between frames): well inside the 300 ms stall.
  EXPECT_GE(alarm_at - stalled_at, ecat::LinkMonitor::kSilenceAlarm);
  EXPECT_LE(alarm_at - stalled_at, 250 * hal::kNsPerMs);
  int silent = 0;
  int heard = 0;
  for (const drivers::JointLinkReport& r : reports_) {
    silent += r.link.kind == ecat::LinkEventKind::silent ? 1 : 0;
    heard += r.link.kind == ecat::LinkEventKind::heard_again ? 1 : 0;
    EXPECT_NE(r.link.kind, ecat::LinkEventKind::lost) << "silence is no evidence against single joints";
  }
  EXPECT_EQ(silent, 1);
  EXPECT_EQ(heard, 1);
  EXPECT_FALSE(bus_->master().monitor().silence_alarm());
  int all_valid = 0;
  for (int i = 0; i < 100; ++i) all_valid += cycle().valid == kAllJoints ? 1 : 0;
  EXPECT_GE(all_valid, 90) << "every joint valid again once frames came back";
  EXPECT_EQ(sim_.stop(SIGTERM), 0) << sim_.output();
}

}  // namespace
}  // namespace rescue::app
