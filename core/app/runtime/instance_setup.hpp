// The instance's resources, taken before anything else starts (docs/firmware.md, step 1): the locks
// that keep a second rescue-motion off the same state directory and raw NIC, and the shared-memory
// segment the tasks share (docs/shared-memory.md). Each returns 0 when done, else the exit status.
#pragma once

#include "core/app/runtime/firmware.hpp"

namespace rescue::app::runner {

// One instance per state directory and per raw NIC; 0 when taken, else the exit status. A read-only
// state directory is warned about (a loss could not be recorded) and takes no lock.
int take_instance_locks(const FirmwareOptions& options, const char* dir) noexcept;

// Step 1b: the shared-memory segment (docs/shared-memory.md): named by --segment or after the state
// directory; a stale one from a crashed run is replaced with a log line. 0 when ready, else the exit
// status.
int create_segment(const FirmwareOptions& options, const char* state_dir) noexcept;

}  // namespace rescue::app::runner
