// Issue 12, "Done means": SIGKILL the RC task process that owns the motion while the robot moves, on
// the simulator in processes mode (the default of `rescue-motion run`, every task its own process
// under the supervisor), driven as an operator would with `rescue-motion ctl` (docs/motion-owner.md,
// docs/tasks.md "When a task dies"). Proven:
//   - the EtherCAT handler goes on: its cycle counter advances across the kill, no frame is lost, no
//     joint is lost, disabled or faulted, and it never waits for the dead owner: the periods its
//     motion intake held the dead owner's joints (owner misses) are at most kOwnerDeadAfterPeriods
//     + 1 and stop growing once the owner word is released;
//   - the robot holds: the joints the owner drove stay where they are (sampled twice, 200 ms apart);
//   - the owner word is released within kOwnerDeadAfterPeriods + 1 handler periods (the intake's own
//     count), the log says `motion: no owner`, `ctl status` shows OWNER `-` on every joint;
//   - the supervisor restarts the task (its log line, a new pid in `ctl --json tasks`);
//   - the same task, restarted, takes the motion back with `ctl owner 0` and the joints move again;
//     or (second test) the other RC task takes it with `ctl owner 1` and drives the joints.
// The figures that depend on the host's scheduling (late periods, per-task MISSED) are printed; the
// handler's late periods are asserted 0 only when the handler process got every real-time setting.
// The counters are read from the run's shared-memory segment (attached by name like a task process,
// read only), the operator's view from `ctl`. Labelled `serial`: a whole wall-clock run.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/kinematics/kinematic_model.hpp"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/app/bench/bench_header.hpp"
#include "core/app/config/firmware_config.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/shm/shared_segment.hpp"
#include "hal/files/state_dir.hpp"
#include "hal/time/clock.hpp"
#include "tests/support/background_run.hpp"
#include "tests/support/operator_run.hpp"

namespace rescue::app {
namespace {

using std::chrono::milliseconds;
using testing::CommandResult;
using testing::json_field;
using testing::OperatorRun;

constexpr double kHoldToleranceRad = 1e-3;  // a held joint moves less than this over 200 ms
constexpr double kMovedRad = 1e-3;          // a driven joint moves more than this over 200 ms
constexpr double kFastRad = 0.1;            // the owner is killed once a joint moves this much in 200 ms
constexpr std::uint64_t kReleaseBoundPeriods = config::kOwnerDeadAfterPeriods + 1;  // docs/motion-owner.md

bool has(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

// One joint of `ctl --json status`.
struct JointView {
  std::string name;
  std::string state;
  std::string fault;
  bool lost{true};
  double position{NAN};
  int owner{-1};  // -1: null (no owner drove it)
};

std::vector<JointView> joints_of(const std::string& json) {
  std::vector<JointView> joints;
  for (std::size_t at = json.find("{\"name\":"); at != std::string::npos; at = json.find("{\"name\":", at + 1)) {
    const std::string object = json.substr(at, json.find('}', at) - at + 1);
    JointView j;
    j.name = json_field(object, "name");
    j.state = json_field(object, "state");
    j.fault = json_field(object, "fault");
    j.lost = json_field(object, "lost") != "false";
    j.position = std::strtod(json_field(object, "position_rad").c_str(), nullptr);
    const std::string owner = json_field(object, "owner");
    j.owner = owner == "null" ? -1 : std::atoi(owner.c_str());
    joints.push_back(j);
  }
  return joints;
}

// The handler's figures and the motion intake's, read from the segment.
struct Figures {
  std::uint64_t cycles{0};
  std::uint64_t frames_lost{0};
  std::uint64_t late_periods{0};
  std::uint64_t lost_slaves{0};
  std::uint64_t owner_word{MotionOwner::kNobody};
  std::uint64_t owner_misses{0};
  std::uint64_t owner_releases{0};
};

class KilledOwner : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(run_.keygen.status, 0) << run_.keygen.out;
    ASSERT_TRUE(run_.wait_for("network in OP")) << run_.output();
    const Result<hal::StateDir> dir = hal::resolve_state_dir(run_.dir.path.c_str());
    ASSERT_TRUE(dir.ok());
    hal::MonotonicClock clock;
    Result<shm::SegmentAttachment> attached =
        shm::SegmentAttachment::attach(shm::default_segment_name(dir.value().path.c_str()), clock, 5 * hal::kNsPerSec);
    ASSERT_TRUE(attached.ok()) << attached.error().what;
    segment_.emplace(std::move(attached.value()));
    // Repeated if refused: once on this loaded host `init` right after OP was refused "no selected
    // joint is reachable" (the parser's sample of that moment had no joint reachable).
    const CommandResult init = ctl_until_accepted({"init"});
    ASSERT_EQ(init.status, 0) << init.out;
    // Every real-time setting applied to the handler's process (SCHED_FIFO, CPU, memory lock)? On
    // a kernel without PREEMPT_RT even a SCHED_FIFO handler is delayed by the host (seen here: 10
    // late periods in a 5 s run on the loaded 2-vCPU VM), so its late periods are a fault only on
    // a real-time kernel.
    sched_fifo_ = run_.handler_got_sched_fifo();
    preempt_rt_ = kernel_is_preempt_rt();
    late_at_start_ = figures().late_periods;
  }

  TaskLinks& links() const { return segment_->links(); }

  Figures figures() const {
    Figures f;
    MasterStatus master{};
    while (!links().master_status.try_read(master)) {
    }
    f.cycles = master.cycles;
    f.frames_lost = master.frames_lost;
    f.late_periods = master.late_periods;
    f.lost_slaves = master.lost;
    f.owner_word = links().motion.owner.word();
    f.owner_misses = links().motion.owner_misses.load();
    f.owner_releases = links().motion.owner_releases.load();
    return f;
  }

  RobotSample sample() const {
    RobotSample s{};
    while (!links().samples.try_read(s)) {
    }
    return s;
  }

  // Waits (up to 3 s) until every joint of `joints` is within kHoldToleranceRad of the reference
  // the handler sends, at rest.
  void settle(const std::vector<std::size_t>& joints) const {
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      const RobotSample s = sample();
      bool settled = true;
      for (const std::size_t j : joints) {
        settled = settled && std::fabs(s[j].position_rad - s[j].position_ref_rad) < kHoldToleranceRad / 2 &&
                  std::fabs(s[j].velocity_rad_s) < kHoldToleranceRad;
      }
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      if (settled || ms > 3000.0) return;
      std::this_thread::sleep_for(milliseconds(5));
    }
  }

  // `ctl --json status`, asked again (up to 3 times) when no answer came: under load the host held
  // the socket handler (SCHED_OTHER) off its CPU longer than ctl's 2 s once.
  std::vector<JointView> status() const {
    CommandResult r;
    for (int i = 0; i < 3; ++i) {
      r = run_.ctl({"--json", "status"});
      if (r.status == 0) break;
      std::printf("no status, asked again: %s", r.out.c_str());
    }
    EXPECT_EQ(r.status, 0) << r.out;
    std::vector<JointView> joints = joints_of(r.out);
    EXPECT_EQ(joints.size(), kJointCount) << r.out;
    return joints;
  }

  // Repeats `ctl ARGS` until accepted (a restarted RC task's heartbeat may not beat yet: "no RC task
  // running"), up to 5 s; prints each refusal.
  CommandResult ctl_until_accepted(const std::vector<std::string>& args) const {
    CommandResult r;
    for (int i = 0; i < 50; ++i) {
      r = run_.ctl(args);
      if (r.status == 0) break;
      std::printf("refused, repeated in 100 ms: %s", r.out.c_str());
      std::this_thread::sleep_for(milliseconds(100));
    }
    return r;
  }

  // Takes two `ctl --json status` 200 ms apart.
  std::pair<std::vector<JointView>, std::vector<JointView>> two_samples() const {
    std::vector<JointView> first = status();
    std::this_thread::sleep_for(milliseconds(200));
    return {first, status()};
  }

  static double largest_move(const std::vector<JointView>& a, const std::vector<JointView>& b, const std::vector<std::size_t>& joints) {
    double most = 0.0;
    for (const std::size_t j : joints) most = std::max(most, std::fabs(b[j].position - a[j].position));
    return most;
  }

  // Every joint Enabled, not lost, no fault (the joint manager noticed nothing).
  static void expect_every_joint_healthy(const std::vector<JointView>& joints) {
    for (const JointView& j : joints) {
      EXPECT_EQ(j.state, "Enabled") << j.name;
      EXPECT_FALSE(j.lost) << j.name;
      EXPECT_EQ(j.fault, "none") << j.name;
    }
  }

  // The joints RC task `task` drives (OWNER in two `ctl --json status` 200 ms apart), once they
  // move and `also` holds for the two samples; retried up to 8 s (other processes at real-time
  // priority on this shared host can hold the RC tasks off their CPU for seconds).
  template <typename Also>
  std::vector<std::size_t> joints_moving_under(int task, double min_move, Also also) const {
    std::vector<std::size_t> driven;
    double moved = 0.0;
    bool also_held = false;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(8);
    while (std::chrono::steady_clock::now() < until) {
      const auto [a, b] = two_samples();
      driven.clear();
      for (std::size_t j = 0; j < b.size(); ++j) {
        if (a[j].owner == task && b[j].owner == task) driven.push_back(j);
      }
      moved = largest_move(a, b, driven);
      also_held = also(a, b);
      if (!driven.empty() && moved > min_move && also_held) break;
    }
    EXPECT_FALSE(driven.empty()) << "RC task " << task << " drives no joint\n" << run_.ctl({"status"}).out << run_.output();
    EXPECT_GT(moved, min_move) << "RC task " << task << "'s joints did not move\n" << run_.ctl({"status"}).out;
    EXPECT_TRUE(also_held) << run_.ctl({"status"}).out;
    std::printf("RC task %d drives %zu joints; largest move over 200 ms: %.4f rad\n", task, driven.size(), moved);
    return driven;
  }

  // `ctl owner 0`: the rescue task starts its motion (the approach to the ready posture, 1.6 s,
  // then the rescue motion's phases). Returns the joints it drives, once one moved more than
  // `min_move` in 200 ms.
  std::vector<std::size_t> rescue_task_drives_the_joints(double min_move) const {
    const CommandResult owner = ctl_until_accepted({"owner", "0"});
    EXPECT_EQ(owner.status, 0) << owner.out;
    return joints_moving_under(0, min_move, [](const std::vector<JointView>&, const std::vector<JointView>&) { return true; });
  }

  // SIGKILL the rescue task while it owns the motion and its joints move; then the handler's
  // intake releases the owner word, the robot holds and the supervisor restarts the task.
  void kill_the_owner_and_see_the_robot_hold(const std::vector<std::size_t>& driven) {
    ASSERT_TRUE(run_.wait_for("supervisor: started rc-rescue")) << run_.output();  // printed after the fork: may trail the task
    const pid_t victim = test::pid_on_line(run_.output(), "supervisor: started rc-rescue");
    ASSERT_GT(victim, 0) << run_.output();
    // The baseline: the rescue task owns the motion and its references drove the joints in the
    // handler's last period.
    Figures before = figures();
    for (int i = 0; i < 5000 && (MotionOwner::task_of(before.owner_word) != 0 || links().motion.owner_joints.load() == 0); ++i) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      before = figures();
    }
    ASSERT_EQ(MotionOwner::task_of(before.owner_word), 0) << "the rescue task does not own the motion";
    const auto killed_at = std::chrono::steady_clock::now();
    ASSERT_EQ(::kill(victim, SIGKILL), 0);

    // The owner word freed by the handler's intake (polled every 0.2 ms, up to 5 s).
    Figures released = figures();
    while (MotionOwner::task_of(released.owner_word) != kNoOwnerTask &&
           std::chrono::steady_clock::now() - killed_at < std::chrono::seconds(5)) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      released = figures();
    }
    const auto released_at = std::chrono::steady_clock::now();
    const double wall_ms = std::chrono::duration<double, std::milli>(released_at - killed_at).count();
    ASSERT_EQ(MotionOwner::task_of(released.owner_word), kNoOwnerTask) << "the dead owner was never released";
    const std::uint64_t held_periods = released.owner_misses - before.owner_misses;
    std::printf("owner released: handler periods held on the dead owner (owner misses) %llu (bound %llu); "
                "handler cycles kill->observed release %llu; %.1f ms wall (host-dependent)\n",
                static_cast<unsigned long long>(held_periods), static_cast<unsigned long long>(kReleaseBoundPeriods),
                static_cast<unsigned long long>(released.cycles - before.cycles), wall_ms);
    EXPECT_GE(held_periods, 1U);
    EXPECT_LE(held_periods, kReleaseBoundPeriods);
    // Released by the handler's intake; or, had the handler been held off its CPU past the
    // supervisor's back-off, by the restarted process (docs/motion-owner.md): never twice.
    releases_seen_ = released.owner_releases;
    EXPECT_LE(released.owner_releases, before.owner_releases + 1);
    EXPECT_GT(released.cycles, before.cycles) << "the handler's cycles stopped";

    // The robot holds. What the handler sends (the firmware's part): the dead owner's joints came to
    // rest within their deceleration limit (at most kStopFromVelocityLimitS after the owner's last
    // period, docs/motion-owner.md) and then keep the same reference, to the bit, 200 ms apart.
    // (The intake brings a joint to rest at the smaller of its deceleration and acceleration limits:
    // wait for the slowest joint's stop from its velocity limit.)
    double longest_stop_s = kStopFromVelocityLimitS;
    for (std::size_t j = 0; j < kJointCount; ++j) {
      const double rest = std::min(deceleration_limit_rad_s2(kJoints[j].limits), kin::kJointAcceleration[j]);
      longest_stop_s = std::max(longest_stop_s, kJoints[j].limits.velocity_max_rad_s / rest);
    }
    std::this_thread::sleep_for(milliseconds(static_cast<int>(longest_stop_s * 1000.0) + 50));
    const RobotSample sent_first = sample();
    std::this_thread::sleep_for(milliseconds(200));
    const RobotSample sent_second = sample();
    for (const std::size_t j : driven) {
      EXPECT_EQ(sent_second[j].position_ref_rad, sent_first[j].position_ref_rad) << kJoints[j].name;
    }
    // The joints (the simulated drives' part): a joint brought to rest follows its reference and
    // settles on it; once settled,
    // two `ctl status` 200 ms apart show them still. Nothing is disabled, lost or faulted, and no
    // joint is driven by an owner.
    settle(driven);
    const double settle_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - released_at).count();
    const auto [a, b] = two_samples();
    const double drift = largest_move(a, b, driven);
    std::printf("held joints: settled on their held references %.0f ms after the release (host-dependent); "
                "largest move over 200 ms after that: %.6f rad (tolerance %.4f)\n",
                settle_ms, drift, kHoldToleranceRad);
    EXPECT_LE(drift, kHoldToleranceRad);
    expect_every_joint_healthy(b);
    for (const JointView& j : b) {
      EXPECT_EQ(j.owner, -1) << j.name << " still driven by RC task " << j.owner;
    }
    const Figures after = figures();
    EXPECT_EQ(after.owner_misses, released.owner_misses) << "the handler still counts misses of a released owner";
    EXPECT_GT(after.cycles, released.cycles) << "the handler's cycles stopped";
    if (sched_fifo_ && preempt_rt_) {  // else host jitter: printed at the end
      EXPECT_EQ(after.frames_lost, before.frames_lost);
    }
    EXPECT_EQ(after.lost_slaves, 0U);
    late_in_kill_window_ = after.late_periods - before.late_periods;
    EXPECT_TRUE(run_.wait_for("motion: no owner")) << run_.output();

    // The supervisor restarts it, with a new pid in `ctl --json tasks`.
    EXPECT_TRUE(run_.wait_for("supervisor: rc-rescue (pid " + std::to_string(victim) + ") killed by signal 9 (SIGKILL); restart 1 in"))
        << run_.output();
    ASSERT_TRUE(run_.wait_for("supervisor: rc-rescue restarted (pid ")) << run_.output();
    const pid_t restarted = test::pid_on_line(run_.output(), "supervisor: rc-rescue restarted");
    EXPECT_GT(restarted, 0);
    EXPECT_NE(restarted, victim);
    const std::string listed = "{\"name\":\"rc-rescue\",\"pid\":" + std::to_string(restarted) + ",";
    CommandResult tasks;
    for (int i = 0; i < 50 && !has(tasks.out, listed); ++i) {
      if (i > 0) std::this_thread::sleep_for(milliseconds(100));
      tasks = run_.ctl({"--json", "tasks"});
    }
    EXPECT_TRUE(has(tasks.out, listed)) << tasks.out;
  }

  // Stops the run and checks its summary: the handler missed no cycle, the releases, one restart.
  void stop_and_check_the_summary(const char* restarted_task_line) {
    const Figures last = figures();
    const CommandResult tasks = run_.ctl({"tasks"});
    const std::uint64_t late = last.late_periods - late_at_start_;
    std::printf("handler late periods: %llu from the kill until the hold was checked, %llu in the whole test "
                "(SCHED_FIFO %s, PREEMPT_RT kernel %s: %s)\n%s",
                static_cast<unsigned long long>(late_in_kill_window_), static_cast<unsigned long long>(late),
                sched_fifo_ ? "applied" : "refused", preempt_rt_ ? "yes" : "no",
                sched_fifo_ && preempt_rt_ ? "asserted 0" : "host jitter, not asserted", tasks.out.c_str());
    std::printf("frames lost: %llu (%s)\n", static_cast<unsigned long long>(last.frames_lost),
                sched_fifo_ && preempt_rt_ ? "asserted 0" : "a frame back after its deadline is host jitter here, not asserted");
    if (sched_fifo_ && preempt_rt_) {
      EXPECT_EQ(late, 0U) << "a SCHED_FIFO handler on a PREEMPT_RT kernel was late";
      EXPECT_EQ(last.frames_lost, 0U) << "a SCHED_FIFO handler on a PREEMPT_RT kernel lost a frame";
    }
    EXPECT_EQ(run_.stop(), 0) << run_.output();
    const std::string out = run_.output();
    EXPECT_TRUE(has(out, "healthy joints missed 0 cycles")) << out;
    EXPECT_TRUE(has(out, restarted_task_line)) << out;
    EXPECT_TRUE(has(out, "ethercat-handler restarts: 0\n")) << out;
    EXPECT_TRUE(has(out, "joint-manager restarts: 0\n")) << out;
    // The summary counts the kill's release, plus any stall of a live owner the host caused
    // (released and taken back, docs/motion-owner.md).
    const std::size_t releases = out.find("\nowner_releases: ");
    ASSERT_NE(releases, std::string::npos) << out;
    EXPECT_GE(std::strtoull(out.c_str() + releases + 17, nullptr, 10), releases_seen_) << out;
    EXPECT_TRUE(has(out, "joints_lost: 0\n")) << out;
  }

  OperatorRun run_;
  std::optional<shm::SegmentAttachment> segment_;
  bool sched_fifo_{false};
  bool preempt_rt_{false};
  std::uint64_t late_at_start_{0};
  std::uint64_t late_in_kill_window_{0};
  std::uint64_t releases_seen_{0};
};

TEST_F(KilledOwner, IsReleasedTheRobotHoldsAndTheRestartedTaskTakesTheMotionBack) {
  const std::vector<std::size_t> driven = rescue_task_drives_the_joints(kFastRad);
  ASSERT_FALSE(driven.empty());
  kill_the_owner_and_see_the_robot_hold(driven);

  // The restarted task re-takes the motion (its approach starts again from where the joints held).
  const std::vector<std::size_t> again = rescue_task_drives_the_joints(kMovedRad);
  EXPECT_EQ(again, driven);
  stop_and_check_the_summary("rc-rescue restarts: 1\n");
}

TEST_F(KilledOwner, IsReleasedTheRobotHoldsAndTheOtherTaskTakesTheMotion) {
  const std::vector<std::size_t> driven = rescue_task_drives_the_joints(kFastRad);
  ASSERT_FALSE(driven.empty());
  kill_the_owner_and_see_the_robot_hold(driven);

  // The teleop task takes the motion: it continues from the held references (the dead owner's
  // joints do not move) and closes the left hand.
  const CommandResult owner = ctl_until_accepted({"owner", "1"});
  EXPECT_EQ(owner.status, 0) << owner.out;
  const CommandResult hand = ctl_until_accepted({"hand", "left", "close", "--task", "1"});
  EXPECT_EQ(hand.status, 0) << hand.out;
  const std::size_t l_hand = joint_index_by_name("l_hand");
  std::vector<JointView> last;
  const std::vector<std::size_t> teleop = joints_moving_under(1, kMovedRad, [&](const std::vector<JointView>& a, const std::vector<JointView>& b) {
    last = b;
    return std::fabs(b[l_hand].position - a[l_hand].position) > kMovedRad && largest_move(a, b, driven) <= kHoldToleranceRad;
  });
  EXPECT_NE(std::find(teleop.begin(), teleop.end(), l_hand), teleop.end()) << "l_hand not driven by RC task 1";
  for (const std::size_t j : driven) {
    EXPECT_NE(std::find(teleop.begin(), teleop.end(), j), teleop.end()) << kJoints[j].name << " not driven by RC task 1";
  }
  ASSERT_EQ(last.size(), kJointCount);
  expect_every_joint_healthy(last);
  EXPECT_TRUE(run_.wait_for("motion: owned by rc-teleop (RC task 1")) << run_.output();
  stop_and_check_the_summary("rc-rescue restarts: 1\n");
}

}  // namespace
}  // namespace rescue::app
