// What the tasks of the firmware share (design brief section 3): the EtherCAT handler's published
// joint values, the joint manager's published drive demand, and the bounded queues between them.
// Every member is a lock-free, pointer-free, standard-layout object (Seqlock, SpscQueue), so this
// record can live in static storage when the tasks are threads of one process (`run`) or in a
// POSIX shared-memory segment when they are processes.
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/robot/joint_demand.hpp"
#include "core/robot/joint_sample.hpp"
#include "core/robot/robot.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue::app {

struct TaskLinks {
  static constexpr std::uint32_t kLayoutVersion = 1;
  static constexpr std::size_t kReportQueueDepth = config::kLostReportQueueDepth;
  static constexpr std::size_t kNoticeQueueDepth = config::kNoticeQueueDepth;
  static constexpr std::size_t kCommandQueueDepth = config::kJointCommandQueueDepth;

  std::uint32_t layout_version{kLayoutVersion};
  Seqlock<RobotSample> samples;                                   // handler -> joint manager, RC tasks
  Seqlock<RobotDemand> demand;                                    // joint manager -> handler
  SpscQueue<LostJointsReport, kReportQueueDepth> lost_reports;    // handler -> joint manager (step 1)
  SpscQueue<JointManagerNotice, kNoticeQueueDepth> notices;       // joint manager -> handler (step 4)
  SpscQueue<JointCommand, kCommandQueueDepth> joint_commands;     // message parser -> joint manager
};
static_assert(std::is_standard_layout_v<TaskLinks>, "shared between processes: standard layout only");

}  // namespace rescue::app
