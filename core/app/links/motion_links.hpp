// The motion's part of the shared record (TaskLinks::motion): one reference space per RC task, the
// Motion owner word, and each RC task's published state. Pointer-free, standard-layout, lock-free
// atomics only, so it lives in static storage (threads) or in the shared-memory segment (processes).
// The RC tasks' heartbeats stay TaskLinks::rc_heartbeat_ns (the message parser reads them too).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

#include "core/app/links/motion_owner.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/links/reference_space.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/robot/robot.hpp"

namespace rescue::app {

// The RC tasks of `run` (index = the task number of `ctl owner TASK`).
enum class RcTaskId : std::uint8_t { rescue = 0, teleop = 1 };
constexpr std::size_t kRcTasksRun = 2;

// What an RC task shows of itself each period (for the log, `ctl status` and tests). Trivial:
// published through a seqlock as bytes; value-initialise it.
struct RcTaskState {
  std::uint8_t mode;            // RcMode (tasks/rc_task_frame.hpp)
  std::uint8_t phase;           // kin::RescuePhase of the rescue motion
  bool owns;                    // it held the Motion owner word this period
  JointMask out_of_service;     // joints it locked (lost, in Error, unreachable)
  std::uint64_t periods;
  std::uint64_t kinematics_errors;
  double position_residual_m[2];  // IK: left, right palm (rescue task)
  double rotation_residual_rad[2];
  // The rescue task's own figures over the motion it drove (approach, rescue motion, targets), for
  // the run's report (`run --scenario rescue`), all from the references it sent (after every limit):
  // per joint the largest speed and acceleration (joints out of service left out from the period
  // they were lost); the largest difference of mirrored arm joints while both arms were whole; the
  // largest |waist| over the whole run; the smallest COM support margin (`margin_measured`: false
  // until a period of the rescue motion measured one). After damage (`loss_seen`: an arm lost a
  // joint during the motion) how far the waist and the damaged arm's palm moved since.
  double max_speed_rad_s[kJointCount];
  double max_acceleration_rad_s2[kJointCount];
  double symmetry_error_rad;
  double max_abs_waist_rad;
  double min_support_margin_m;
  bool margin_measured;
  bool symmetry_measured;              // a period with both arms whole was measured
  bool loss_seen;
  std::uint8_t damaged_arms;           // bit 0 left, bit 1 right (kin::TaskShape)
  double waist_travel_after_loss_rad;  // largest |waist - waist at the loss|
  double palm_travel_after_loss_m[2];  // a damaged arm's palm: largest distance from where it was at the loss
  // Each palm's largest distance from its planned path while its arm was whole (the rescue motion
  // only, FK of the references sent); `path_measured[arm]`: a period was measured.
  double path_deviation_m[2];
  bool path_measured[2];
  double min_time_scale;               // the slowest the rescue motion ran (1 = its own timing)
  // Self-collision (kin::self_collision): the smallest distance of a pair within the activation
  // distance (`close_pair_seen` false: none came that close), and the stop if the clearance could
  // not be kept (the pair, an index of kin::kCollisionPairs, and its distance).
  bool close_pair_seen;
  double min_self_clearance_m;
  bool collision_stop;
  std::int16_t collision_pair;
  double collision_distance_m;
  std::uint64_t clipped_periods;       // periods a joint was limited off the path
};
static_assert(std::is_trivial_v<RcTaskState>, "published through a seqlock");

struct MotionLinks {
  std::array<ReferenceSpace, protocol::kMaxRcTasks> references;  // RC task k writes references[k] only
  MotionOwner owner;                                            // compare-exchange only
  std::array<Seqlock<RcTaskState>, protocol::kMaxRcTasks> task_state;  // RC task k writes task_state[k]
  // The EtherCAT handler's intake counters, for `ctl status` and the run's summary.
  std::atomic<std::uint64_t> owner_misses{0};    // handler periods the owner's references were late or incomplete
  std::atomic<std::uint64_t> owner_releases{0};  // dead owners released
  std::atomic<JointMask> owner_joints{0};        // joints the owner's references drove in the handler's last period
};
static_assert(std::is_standard_layout_v<MotionLinks>, "shared between processes: standard layout only");
static_assert(protocol::kNoOwner == kNoOwnerTask, "the wire's 'no owner' is the owner word's");

}  // namespace rescue::app
