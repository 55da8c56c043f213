// Issue 21 item 5, end to end (`serial`: a real `rescue-motion run`, tasks as processes): the
// EtherCAT handler's process is stopped (SIGSTOP) for 1 s while the robot is in OP. The supervisor's
// liveness watch reports it (the run's figures: task_silences_reported, and the handler's heartbeat
// age when it did, within the documented time: the limit, 30 ms, plus the supervisor's own delay,
// docs/tasks.md "Liveness"); meanwhile `ctl --json status`, `slaves`, `master`, `tasks`, `diag` and
// `owner` mark the handler's figures stale with their age (`ctl tasks` in text says so on its first
// line); once it runs again they are fresh, the run goes on and stops cleanly.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>

#include "tests/support/background_run.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using std::chrono::milliseconds;
using testing::OperatorRun;
using testing::json_field;

// The documented bound (docs/tasks.md "Liveness"): the limit (30 ms) plus one supervisor pass (5 ms)
// plus the supervisor's own wake-up delay at normal priority on a loaded host, allowed 215 ms.
constexpr double kReportedWithinMs = 250.0;

// The value of a `key: value` line ("" when absent).
std::string value_of(const std::string& out, const std::string& key) {
  const std::size_t at = out.find("\n" + key + ": ");
  if (at == std::string::npos) return "";
  const std::size_t begin = at + key.size() + 3;
  return out.substr(begin, out.find('\n', begin) - begin);
}

TEST(Liveness, ASilentHandlerIsReportedAndCtlMarksItsFiguresStale) {
  OperatorRun run("30");
  ASSERT_TRUE(run.wait_for("network in OP")) << run.output();
  // The supervisor prints this after it gave back the handler's real-time scheduling: on a loaded
  // host it may come after the handler (SCHED_FIFO) already reached OP (seen in CI's load stage).
  ASSERT_TRUE(run.wait_for("supervisor: started ethercat-handler")) << run.output();
  const pid_t handler = test::pid_on_line(run.output(), "supervisor: started ethercat-handler");
  ASSERT_GT(handler, 0) << run.output();
  const testing::CommandResult fresh = run.ctl({"--json", "status"});
  ASSERT_EQ(fresh.status, 0) << fresh.out;
  EXPECT_EQ(json_field(fresh.out, "stale"), "false") << fresh.out;

  ASSERT_EQ(::kill(handler, SIGSTOP), 0);
  std::this_thread::sleep_for(milliseconds(500));
  const testing::CommandResult status = run.ctl({"--json", "status"});
  const testing::CommandResult master = run.ctl({"--json", "master"});
  const testing::CommandResult slaves = run.ctl({"--json", "slaves"});
  const testing::CommandResult tasks = run.ctl({"--json", "tasks"});
  const testing::CommandResult diag = run.ctl({"--json", "diag"});
  const testing::CommandResult owner = run.ctl({"--json", "owner"});
  const testing::CommandResult tasks_text = run.ctl({"tasks"});
  std::this_thread::sleep_for(milliseconds(500));
  ASSERT_EQ(::kill(handler, SIGCONT), 0);

  for (const testing::CommandResult* r : {&status, &master, &slaves, &tasks, &diag, &owner}) {
    EXPECT_EQ(r->status, 0) << r->out;
    EXPECT_EQ(json_field(r->out, "stale"), "true") << r->out;
    EXPECT_GE(std::atoi(json_field(r->out, "age_ms").c_str()), 400) << r->out;
  }
  EXPECT_EQ(tasks_text.out.rfind("STALE: the EtherCAT handler has completed no period for ", 0), 0U) << tasks_text.out;
  // Running again: fresh figures (asked until they are, up to 5 s: the handler first re-arms the
  // drives its silence let the watchdog stop).
  bool fresh_again = false;
  for (int i = 0; i < 50 && !fresh_again; ++i) {
    std::this_thread::sleep_for(milliseconds(100));
    fresh_again = json_field(run.ctl({"--json", "status"}).out, "stale") == "false" &&
                  json_field(run.ctl({"--json", "tasks"}).out, "stale") == "false";
  }
  EXPECT_TRUE(fresh_again) << run.output();

  ASSERT_EQ(run.stop(), 0) << run.output();
  const std::string out = run.output();
  EXPECT_GE(std::atoi(value_of(out, "task_silences_reported").c_str()), 1) << out;
  const double reported_at = std::atof(value_of(out, "task_silence_report_age_max_ms").c_str());
  // The watch reports an age strictly above the limit in ns (test_liveness_watch proves the strict
  // edge); the summary prints it rounded to 1 us, so here "at least the limit": printed to 0.1 ms, a
  // report 20 us past the limit read "30.0" and a strict check failed CI under load.
  EXPECT_GE(reported_at, 30.0) << out;
  EXPECT_LE(reported_at, kReportedWithinMs) << out;
  std::printf("liveness: handler stopped 1 s; reported silent at a heartbeat age of %.1f ms (limit 30 ms, bound %.0f ms); "
              "ctl status age while stopped %s ms\n",
              reported_at, kReportedWithinMs, json_field(status.out, "age_ms").c_str());
}

}  // namespace
}  // namespace rescue::app
