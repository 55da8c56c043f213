// bench wcet's budget (docs/timing.md "The budget"): each task's pWCET against its period and the
// share of its CPU that Table I leaves it (core/app/config/task_table.hpp: several tasks share a CPU).
// The check is fixed-priority response-time analysis, first step: a task's response bound is its
// own pWCET plus, for every task of higher or equal priority on the same CPU, that task's pWCET
// times the releases it can have within the period (ceil of period over its period). The task is
// within budget when that bound is at most its period; an event-driven task (period 0) has no
// budget (n/a). Pure: no clock, no I/O, so a test can feed it any figures.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/app/config/task_table.hpp"
#include "core/base/span.hpp"

namespace rescue::app {

// One measured task's bound: its pWCET at 1e-9 per period (the upper end of its interval, the safe
// side), or none when the statistics refused the samples.
struct WcetBound {
  TaskId task{TaskId::ethercat_handler};
  bool given{false};
  double pwcet_ns{0.0};
};

enum class BudgetVerdict : std::uint8_t {
  within,          // response bound <= period
  over,            // response bound > period: bench wcet fails
  no_period,       // event driven: no budget (n/a)
  not_measured,    // this task or one sharing its CPU above it has no pWCET: the bound is n/a
};

struct BudgetLine {
  std::int64_t period_ns{0};    // 0: event driven
  double share{0.0};            // pWCET / period (0 when n/a)
  double response_ns{0.0};      // own pWCET + the interference above (0 when n/a)
  int cpu{0};                   // Table I's CPU
  TaskId task{TaskId::ethercat_handler};
  BudgetVerdict verdict{BudgetVerdict::not_measured};
};

// One line per bound, in the order given (`out` must have room for bounds.size()). `table`: the task
// table in force (task_table()).
void judge_budget(Span<const WcetBound> bounds, Span<const TaskSpec> table, Span<BudgetLine> out) noexcept;

const char* to_string(BudgetVerdict verdict) noexcept;

}  // namespace rescue::app
