// Issue 24, `ctl diag --reset [SLAVE]` (docs/operator.md "ctl diag"): against a real `rescue-motion run
// --scenario flaky-cable` (5 frames damaged on the cable into l_elbow 1 s after OP and again every 2
// s), the counters are non-zero, `diag --reset` zeroes every slave's counters and warnings (the reply
// comes once the EtherCAT handler applied it, so the next `ctl diag` shows zeros), the damage then
// counts again, and `diag --reset SLAVE` zeroes that slave only; the run allocates nothing after init
// meanwhile. Every answer through --json, parsed.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "tests/support/json_query.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using testing::CommandResult;
using testing::OperatorRun;

class DiagReset : public ::testing::Test {
 protected:
  std::string query(const std::string& json, const std::string& expr) const {
    return testing::json_query(run.dir.path, json, expr);
  }
  std::string diag() const {
    const CommandResult d = run.ctl({"--json", "diag"});
    EXPECT_EQ(d.status, 0) << d.out;
    return d.out;
  }
  // l_elbow (position 19): its port 0 is the damaged cable; l_wrist_yaw (20) sees forwarded errors.
  int elbow_invalid_frames(const std::string& json) const {
    const std::string v = query(json, "d['slaves'][19]['ports'][0]['invalid_frames']");
    return v.empty() || v[0] < '0' || v[0] > '9' ? -1 : std::stoi(v);
  }
  // Waits (up to 20 s) until l_elbow's port 0 shows more than `than` invalid frames; the diag answer.
  std::string wait_for_damage(int than) const {
    std::string json;
    for (int i = 0; i < 200; ++i) {
      json = diag();
      if (elbow_invalid_frames(json) > than) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return json;
  }
  // Waits until the damage of the flaky cable was just counted (the counter rose), so that the next
  // damage is most of a 2 s period away: what a test then reads is not racing it.
  void wait_for_fresh_damage() const {
    const int now = elbow_invalid_frames(diag());
    (void)wait_for_damage(now);
  }
  OperatorRun run{"60", "flaky-cable"};
};

TEST_F(DiagReset, ZeroesEveryCounterThenTheDamageCountsAgainAndOneSlaveIsResetAlone) {
  ASSERT_EQ(run.keygen.status, 0) << run.keygen.out;
  ASSERT_TRUE(run.wait_for("check the cable between l_shoulder_yaw and l_elbow")) << run.output();
  std::string before = wait_for_damage(0);
  ASSERT_GE(elbow_invalid_frames(before), 5) << before;
  EXPECT_EQ(query(before, "d['slaves'][20]['ports'][0]['forwarded_rx_errors'] > 0"), "true") << before;
  EXPECT_EQ(query(before, "d['slaves'][19]['ports'][0]['warning'] != 'none'"), "true") << before;

  // Every slave: zero, right after the command (the reply waits for the handler). The cable is
  // damaged again every 2 s of the robot's time; on a loaded machine the reset and the next diag
  // may take longer than that (issue 35 item 16: 55 counts, a burst between them). So: a reset
  // right after a burst, until one diag has no burst between (at most 5 tries). A reset that left
  // counts behind never shows all zeros, so one such diag proves it.
  std::string zero;
  for (int attempt = 0; attempt < 5; ++attempt) {
    wait_for_fresh_damage();
    const CommandResult reset = run.ctl({"--json", "diag", "--reset"});
    ASSERT_EQ(reset.status, 0) << reset.out;
    EXPECT_EQ(query(reset.out, "[d['command'], d['accepted'], d['slaves']]"), R"(["diag --reset", true, "all"])")
        << reset.out;
    const std::string snapshot = diag();
    const std::string total = query(snapshot, "sum(p[k] for s in d['slaves'] for p in s['ports'] for k in "
                                              "('invalid_frames', 'rx_errors', 'forwarded_rx_errors', 'lost_links'))");
    if (total == "0") {
      zero = snapshot;
      break;
    }
  }
  ASSERT_FALSE(zero.empty()) << "no diag after a reset came before the next burst in 5 tries";
  EXPECT_EQ(query(zero, "len(d['slaves'])"), "23") << zero;
  EXPECT_EQ(query(zero, "sum(s['processing_unit_errors'] + s['pdi_errors'] for s in d['slaves'])"), "0") << zero;
  EXPECT_EQ(query(zero, "sorted(set(p['warning'] for s in d['slaves'] for p in s['ports']))"), R"(["none"])") << zero;

  // The cable is still bad: the counters rise again, on the same port.
  const std::string again = wait_for_damage(0);
  EXPECT_GE(elbow_invalid_frames(again), 5) << again;
  EXPECT_EQ(query(again, "d['slaves'][20]['ports'][0]['forwarded_rx_errors'] > 0"), "true") << again;

  // One slave, by name: l_wrist_yaw only; l_elbow keeps its count (tried as above: a burst between
  // the reset and the diag counts on l_wrist_yaw again).
  std::string after_one;
  for (int attempt = 0; attempt < 5; ++attempt) {
    wait_for_fresh_damage();
    const int elbow_before = elbow_invalid_frames(diag());
    const CommandResult one = run.ctl({"diag", "--reset", "l_wrist_yaw"});
    ASSERT_EQ(one.status, 0) << one.out;
    EXPECT_EQ(one.out, "diag --reset: l_wrist_yaw: link error counters zeroed\n");
    const std::string snapshot = diag();
    EXPECT_GE(elbow_invalid_frames(snapshot), 5) << snapshot;
    if (elbow_invalid_frames(snapshot) == elbow_before) {  // no burst between: the reset alone shows
      after_one = snapshot;
      break;
    }
  }
  ASSERT_FALSE(after_one.empty()) << "no diag after a reset came before the next burst in 5 tries";
  EXPECT_EQ(query(after_one, "sum(p['forwarded_rx_errors'] + p['invalid_frames'] for p in d['slaves'][20]['ports'])"), "0")
      << after_one;
  // By position, and the refusals of a slave the robot does not have.
  EXPECT_EQ(run.ctl({"diag", "--reset", "19"}).status, 0);
  const CommandResult unknown = run.ctl({"diag", "--reset", "tail"});
  EXPECT_EQ(unknown.status, 2) << "usage: " << unknown.out;
  EXPECT_NE(unknown.out.find("a slave's name (ctl slaves) or its position 0..22"), std::string::npos) << unknown.out;
  EXPECT_EQ(run.ctl({"diag", "--reset", "23"}).status, 2);
  EXPECT_EQ(run.ctl({"status", "--reset"}).status, 2) << "--reset goes with diag only";

  EXPECT_EQ(run.stop(), 0) << run.output();
  // The resets went through the real-time handler without a heap allocation (the run's heap guard).
  EXPECT_NE(run.output().find("rescue-motion run: heap allocations after init: 0\n"), std::string::npos) << run.output();
}

}  // namespace
}  // namespace rescue::app
