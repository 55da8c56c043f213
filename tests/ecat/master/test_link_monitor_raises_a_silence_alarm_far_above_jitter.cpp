// A link that returns no frame at all (the cable at the master pulled, the NIC dead) was never
// reported: every cycle was "late or missing". LinkMonitor now raises one `silent` alarm when no
// frame came back for kSilenceAlarm (100 ms, far above host jitter) and `heard_again` when one
// does; neither marks any slave lost (no evidence against single slaves), and bursts of missing
// frames as long as host jitter makes them (3-7 ms, even 90 ms) never raise it. Virtual time.
#include <gtest/gtest.h>

#include <vector>

#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/link_monitor.hpp"

namespace rescue::ecat {
namespace {

using drivers::kRobotImageLayout;
using drivers::kRobotNetworkPlan;

class SilenceAlarm : public ::testing::Test {
 protected:
  SilenceAlarm() { monitor.start(kAllSlaves); }

  // One 1 ms cycle whose frame did or did not come back (full counters when it did).
  void cycle(bool returned) {
    ++n;
    std::array<std::uint16_t, kMaxBranches> wkc{};
    for (std::size_t b = 0; b < kMaxBranches; ++b) wkc[b] = monitor.expected_wkc(b);
    monitor.observe(n, static_cast<hal::Nanoseconds>(n) * hal::kNsPerMs, returned, wkc, Span<const ProbeResult>());
    LinkReport r;
    while (monitor.pop_report(r)) reports.push_back(r);
  }
  void cycles(int count, bool returned) {
    for (int i = 0; i < count; ++i) cycle(returned);
  }

  LinkMonitor monitor{kRobotNetworkPlan, kRobotImageLayout};
  std::uint64_t n = 0;
  std::vector<LinkReport> reports;
};

TEST_F(SilenceAlarm, JitterBurstsNeverRaiseIt) {
  for (int burst = 0; burst < 200; ++burst) {
    cycles(3 + burst % 5, false);  // 3..7 ms without a frame, as stalls and bunching make them
    cycles(20, true);
  }
  cycles(90, false);  // a 90 ms host stall: still jitter, still below the alarm
  cycles(1, true);
  EXPECT_TRUE(reports.empty());
  EXPECT_EQ(monitor.silences(), 0U);
  EXPECT_FALSE(monitor.silence_alarm());
}

TEST_F(SilenceAlarm, RaisedOnceAfter100MsAndEndedByTheNextFrame) {
  cycles(10, true);
  const std::uint64_t first_missing = n + 1;
  const auto alarm_cycles = static_cast<int>(LinkMonitor::kSilenceAlarm / hal::kNsPerMs);
  cycles(alarm_cycles, false);  // cycles first_missing .. first_missing + 99: 99 ms after the first
  EXPECT_TRUE(reports.empty()) << "raised before " << alarm_cycles << " ms";
  cycle(false);  // 100 ms after the first frame that did not come back
  ASSERT_EQ(reports.size(), 1U);
  EXPECT_EQ(reports[0].kind, LinkEventKind::silent);
  EXPECT_EQ(reports[0].slaves, monitor.in_exchange());
  EXPECT_EQ(reports[0].detected_cycle, first_missing);
  EXPECT_EQ(reports[0].cycle, first_missing + static_cast<std::uint64_t>(alarm_cycles));
  EXPECT_TRUE(monitor.silence_alarm());

  cycles(5000, false);  // five more seconds of silence: one alarm, not one per cycle
  EXPECT_EQ(reports.size(), 1U);

  cycle(true);
  ASSERT_EQ(reports.size(), 2U);
  EXPECT_EQ(reports[1].kind, LinkEventKind::heard_again);
  EXPECT_FALSE(monitor.silence_alarm());
  EXPECT_EQ(monitor.silences(), 1U);
  EXPECT_EQ(monitor.lost(), 0U) << "silence is no evidence against single slaves";
  EXPECT_EQ(monitor.in_exchange(), kAllSlaves);

  cycles(150, false);  // a second silence is a second alarm
  EXPECT_EQ(monitor.silences(), 2U);
}

}  // namespace
}  // namespace rescue::ecat
