// The EtherCAT handler's side of the Motion owner (docs/motion-owner.md). Once per handler period,
// never blocking, it decides each position-mode joint's reference:
//   - the owner's references, if its reference space holds a complete period written under the
//     current owner word and completed within kOwnerReferenceDeadlineNs; only the joints they
//     command that the handler drives (enabled, reachable, not excluded) take them, clamped to the
//     joint's position limits and to its velocity limit from the reference sent last period;
//   - otherwise the last safe references (hold position), and the period counts as an owner miss;
//   - an owner whose heartbeat is older than kOwnerDeadAfterPeriods RC periods is released
//     (compare-exchange on the word it saw) in the period the handler notices it;
//   - while nobody owns the motion, each joint holds the reference last sent; a joint the joint
//     manager gives a new reference (set reference, hold, initialize) or does not drive takes the
//     joint manager's.
// A non-owner's reference space is never read. No heap, no locks, bounded work.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "core/app/links/motion_links.hpp"
#include "core/robot/joint_demand.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app {

struct MotionIntakeSettings {
  hal::Nanoseconds reference_deadline_ns{0};  // config::kOwnerReferenceDeadlineNs
  hal::Nanoseconds owner_dead_after_ns{0};    // config::kOwnerDeadAfterPeriods * config::kRcTaskPeriodNs
  hal::Nanoseconds handler_period_ns{0};      // the velocity clamp's step
};
MotionIntakeSettings default_intake_settings() noexcept;

struct MotionIntakeCounters {
  std::uint64_t periods{0};
  std::uint64_t owned_periods{0};   // periods with an owner
  std::uint64_t used_periods{0};    // periods the owner's references were taken
  std::uint64_t misses{0};          // periods with an owner whose references were late, incomplete or not its own
  std::uint64_t incomplete{0};      // of the misses: no complete period (torn, never written, writer died mid-write)
  std::uint64_t stale{0};           // of the misses: completed longer ago than the deadline
  std::uint64_t foreign{0};         // of the misses: written under another owner word
  std::uint64_t releases{0};        // dead owners released
  std::uint64_t clamped{0};         // joint references limited (position or velocity limit)
};

class MotionIntake {
 public:
  using Heartbeats = std::array<std::atomic<std::int64_t>, protocol::kMaxRcTasks>;

  MotionIntake(MotionLinks& links, const Heartbeats& heartbeats, const MotionIntakeSettings& settings) noexcept;

  // One handler period at `now`: `demand` is the joint manager's, `driven` the joints the handler
  // drives this period. Returns every joint's position reference (rad).
  const std::array<double, kJointCount>& period(hal::Nanoseconds now, const RobotDemand& demand, JointMask driven) noexcept;

  const MotionIntakeCounters& counters() const noexcept { return counters_; }
  // The owner task whose references drove the joints last period (kNoOwnerTask: none, or held).
  std::uint8_t driving_task() const noexcept { return driving_; }
  std::uint64_t consecutive_misses() const noexcept { return consecutive_misses_; }
  // The joints the owner's references drove last period (also published: MotionLinks::owner_joints).
  JointMask owner_joints() const noexcept { return driven_by_owner_; }

 private:
  void decide(hal::Nanoseconds now, const RobotDemand& demand, JointMask driven) noexcept;
  bool take_owner_references(hal::Nanoseconds now, std::uint64_t word, JointMask driven) noexcept;

  MotionLinks& links_;
  const Heartbeats& heartbeats_;
  MotionIntakeSettings settings_;
  std::array<double, kJointCount> held_{};          // the references sent last period
  std::array<double, kJointCount> manager_ref_{};   // the joint manager's reference seen last period
  std::array<bool, kJointCount> driven_before_{};
  ReferenceSnapshot snapshot_{};
  MotionIntakeCounters counters_{};
  std::uint64_t consecutive_misses_{0};
  JointMask driven_by_owner_{0};
  std::uint8_t driving_{kNoOwnerTask};
};

}  // namespace rescue::app
