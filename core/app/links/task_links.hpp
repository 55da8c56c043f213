// What the tasks of the firmware share (design brief section 3): the EtherCAT handler's published
// joint values, the joint manager's published drive demand, and the bounded queues between them.
// Every member is a lock-free, pointer-free, standard-layout object (Seqlock, SpscQueue), so this
// record can live in static storage when the tasks are threads of one process (`run`) or in a
// POSIX shared-memory segment when they are processes.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/app/links/joint_messages.hpp"
#include "core/robot/joint_limits.hpp"
#include "core/robot/robot.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue::app {

// What the joint manager wants of one drive, as the EtherCAT handler reads it every cycle.
// Trivial (no member initialisers): published through a seqlock as bytes; value-initialise it.
struct JointDemand {
  bool enable;                    // DFA state Enabled: power the drive and follow the reference
  std::int8_t mode;               // CiA 402 mode of operation (ControlMode)
  std::int32_t position_counts;   // reference held while no RC task owns the motion
};
static_assert(std::is_trivial_v<JointDemand>, "published through the seqlock as bytes");
using RobotDemand = std::array<JointDemand, kJointCount>;

struct TaskLinks {
  static constexpr std::uint32_t kLayoutVersion = 1;
  static constexpr std::size_t kReportQueueDepth = 16;
  static constexpr std::size_t kNoticeQueueDepth = 16;
  static constexpr std::size_t kCommandQueueDepth = 64;

  std::uint32_t layout_version{kLayoutVersion};
  Seqlock<RobotSample> samples;                                   // handler -> joint manager, RC tasks
  Seqlock<RobotDemand> demand;                                    // joint manager -> handler
  SpscQueue<LostJointsReport, kReportQueueDepth> lost_reports;    // handler -> joint manager (step 1)
  SpscQueue<JointManagerNotice, kNoticeQueueDepth> notices;       // joint manager -> handler (step 4)
  SpscQueue<JointCommand, kCommandQueueDepth> joint_commands;     // message parser -> joint manager
};
static_assert(std::is_standard_layout_v<TaskLinks>, "shared between processes: standard layout only");

}  // namespace rescue::app
