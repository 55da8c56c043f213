// The two ways the tasks run (docs/tasks.md), on the same task loops (task_loops.hpp) and logger passes
// (run_log.hpp, operator_side.hpp): as processes under the supervisor (task_processes.cpp, the default)
// or as threads of this process (task_threads.cpp, --threads). Each returns once the tasks stopped.
#pragma once

#include "core/app/runtime/operator_side.hpp"

namespace rescue::app::runner {

// --threads: the tasks as threads of this process, the logger in the main thread.
int run_task_threads(OperatorSide& side) noexcept;
// A damaged shared segment (docs/shared-memory.md "A damaged segment"): every task killed, nothing
// read from the segment or recorded after it.
constexpr int kExitSegmentDamaged = 6;

// The supervisor's loop; returns 0 after an ordered stop, kExitTaskDied after a critical task died,
// kExitSegmentDamaged when it found the segment damaged.
int run_task_processes(OperatorSide& side) noexcept;

}  // namespace rescue::app::runner
