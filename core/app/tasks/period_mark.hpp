// The end of one measured period of a task, marked for valgrind's callgrind (bench wcet's tasks, and
// run's EtherCAT handler): toolchain/wcet/instructions.sh and run-instructions.sh run the program
// under callgrind with collection on only inside the period functions, and this mark dumps the
// counters there, so each dump is one period's instructions of one task (with --dump-after and
// --toggle-collect both naming the same functions, valgrind 3.19 applied only one of the two to each
// function). Outside valgrind the client request is a few no-op instructions; without valgrind's
// header it is nothing.
#pragma once

#if defined(__has_include)
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define RESCUE_HAVE_CALLGRIND_H 1
#endif
#endif

namespace rescue::app {

// `task`: the samples file's name of the task (ethercat_handler, ...), the dump's trigger text.
inline void mark_period_end(const char* task) noexcept {
#ifdef RESCUE_HAVE_CALLGRIND_H
  CALLGRIND_DUMP_STATS_AT(task);
#else
  (void)task;
#endif
}

}  // namespace rescue::app
