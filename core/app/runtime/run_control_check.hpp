// RunControl (core/app/links/run_control.hpp) is a record of the shared segment that the supervisor
// reads to stop the tasks and to print the run's figures. A value no writer writes is damage (a stray
// write, a bit flip): a flag byte other than 0 or 1, a negative count of tasks started, a joint
// mask naming a joint beyond the robot, a robot condition or ring state that does not exist, a silent
// task beyond the slots, a sent speed, acceleration or jerk that is not a finite number >= 0 (a NaN
// passed the joint-limit verdict as "within"). Counts are any value. No heap.
#pragma once

#include "core/app/links/run_control.hpp"

namespace rescue::app {

// The first damaged field's name ("RunControl::FIELD", static), or nullptr when every field is a
// value its writer writes. Read while the tasks run too: a flag is read as its byte, never as a bool.
const char* run_control_damage(const RunControl& run) noexcept;

}  // namespace rescue::app
