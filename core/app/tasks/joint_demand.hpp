// What the joint manager publishes for the EtherCAT handler after each step: per joint, whether
// its drive is to be powered, in which mode, and the reference it holds.
#pragma once

#include "core/app/tasks/joint_manager.hpp"
#include "core/app/links/task_links.hpp"

namespace rescue::app {

RobotDemand demand_of(const JointManager& manager) noexcept;

}  // namespace rescue::app
