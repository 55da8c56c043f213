// What start-up says before the tasks run (docs/firmware.md): the lost joints restored from the
// error-joints file, what it did with a damaged file or an interrupted write, the operator's
// --clear-joint, and a bring-up that failed or that a signal stopped.
#pragma once

#include "core/app/runtime/firmware.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/repaired_joints.hpp"
#include "drivers/joint/joint_bus.hpp"

namespace rescue::app::runner {

int report_bring_up_failure(drivers::JointBus& bus) noexcept;
void print_restored(JointMask restored) noexcept;
// What start-up did with a damaged error-joints file or an interrupted write: exactly what was salvaged,
// dropped and added, where the original is kept, and what the operator can do.
void print_restore_problems(const RestoreReport& r, const char* dir) noexcept;
// A signal stopped the bring-up: nothing reached OP, no drive was enabled; exit 0.
int stopped_in_bring_up(drivers::JointBus& bus, const FirmwareOptions& options) noexcept;
// Prints what the operator's --clear-joint request will do; false when it is refused.
bool announce_repaired_joints(const RepairedJointsPlan& plan) noexcept;

}  // namespace rescue::app::runner
