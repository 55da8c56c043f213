#include "core/app/runtime/run_control_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <iterator>

#include "ecat/master/ring_monitor.hpp"
#include "fsm/machines/joint_status_dfa.hpp"

namespace rescue::app {
namespace {

// A flag's byte as the segment holds it (an atomic<bool> holding another byte cannot be loaded).
bool flag_whole(const std::atomic<bool>& flag) noexcept {
  static_assert(sizeof(std::atomic<bool>) == 1, "a flag is one byte");
  unsigned char byte = 0;
  std::memcpy(&byte, static_cast<const void*>(&flag), 1);
  return byte <= 1;
}

bool figures_whole(const std::array<std::atomic<double>, kJointCount>& figures) noexcept {
  return std::all_of(figures.begin(), figures.end(), [](const std::atomic<double>& f) {
    const double v = f.load(std::memory_order_relaxed);
    return std::isfinite(v) && v >= 0.0;
  });
}

}  // namespace

const char* run_control_damage(const RunControl& run) noexcept {
  struct Flag {
    const std::atomic<bool>& flag;
    const char* name;
  };
  const Flag flags[] = {{run.stop, "RunControl::stop"},
                        {run.operator_stop, "RunControl::operator_stop"},
                        {run.rc_stop, "RunControl::rc_stop"},
                        {run.manager_stop, "RunControl::manager_stop"},
                        {run.op, "RunControl::op"},
                        {run.scenario_acted, "RunControl::scenario_acted"},
                        {run.scenario_ok, "RunControl::scenario_ok"},
                        {run.handler_done, "RunControl::handler_done"},
                        {run.drives_disabled, "RunControl::drives_disabled"},
                        {run.manager_done, "RunControl::manager_done"},
                        {run.file_dirty, "RunControl::file_dirty"}};
  const Flag* const damaged =
      std::find_if(std::begin(flags), std::end(flags), [](const Flag& f) { return !flag_whole(f.flag); });
  if (damaged != std::end(flags)) return damaged->name;
  if (std::any_of(run.health.begin(), run.health.end(), [](const TaskHealth& h) { return !flag_whole(h.reported); })) {
    return "RunControl::health[].reported";
  }
  const std::int32_t started = run.tasks_started.load(std::memory_order_relaxed);
  // Each task's start adds 1, a restarted task process's too: more than the run's tasks is whole.
  if (started < 0) return "RunControl::tasks_started";
  if ((run.lost_joints.load(std::memory_order_relaxed) & ~kAllJoints) != 0) return "RunControl::lost_joints";
  if ((run.lost_since_start.load(std::memory_order_relaxed) & ~kAllJoints) != 0) return "RunControl::lost_since_start";
  if (run.condition.load(std::memory_order_relaxed) > static_cast<std::uint8_t>(fsm::RobotCondition::error)) {
    return "RunControl::condition";
  }
  if (run.ring_state.load(std::memory_order_relaxed) > static_cast<std::uint8_t>(ecat::RingState::lost)) return "RunControl::ring_state";
  if ((run.silent_tasks.load(std::memory_order_relaxed) >> kRunHealthSlots) != 0) return "RunControl::silent_tasks";
  if (!figures_whole(run.sent_max_speed_rad_s)) return "RunControl::sent_max_speed_rad_s";
  if (!figures_whole(run.sent_max_acceleration_rad_s2)) return "RunControl::sent_max_acceleration_rad_s2";
  if (!figures_whole(run.sent_max_jerk_rad_s3)) return "RunControl::sent_max_jerk_rad_s3";
  return nullptr;
}

}  // namespace rescue::app
