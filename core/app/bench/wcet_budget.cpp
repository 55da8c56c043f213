#include "core/app/bench/wcet_budget.hpp"

#include <algorithm>
#include <cmath>

namespace rescue::app {
namespace {

const TaskSpec* spec_of(Span<const TaskSpec> table, TaskId id) noexcept {
  const TaskSpec* found = std::find_if(table.begin(), table.end(), [id](const TaskSpec& spec) { return spec.id == id; });
  return found != table.end() ? found : nullptr;
}

const WcetBound* bound_of(Span<const WcetBound> bounds, TaskId id) noexcept {
  const WcetBound* found = std::find_if(bounds.begin(), bounds.end(), [id](const WcetBound& bound) { return bound.task == id; });
  return found != bounds.end() ? found : nullptr;
}

// The task's own pWCET plus the interference of every other task of higher or equal priority on its
// CPU; false when one of them has no pWCET (a real-time task on that CPU that was not measured
// counts as missing: the bound cannot leave it out).
bool response_bound(Span<const WcetBound> bounds, Span<const TaskSpec> table, const TaskSpec& own, double own_ns,
                    double& response) noexcept {
  response = own_ns;
  for (const TaskSpec& other : table) {
    if (other.id == own.id || other.cpu != own.cpu || other.priority < own.priority || other.priority == 0) continue;
    const WcetBound* bound = bound_of(bounds, other.id);
    if (bound == nullptr || !bound->given) return false;
    // An event-driven task above has no release rate to bound its interference.
    if (other.period_ns <= 0) return false;
    const double releases = std::ceil(static_cast<double>(own.period_ns) / static_cast<double>(other.period_ns));
    response += releases * bound->pwcet_ns;
  }
  return true;
}

}  // namespace

void judge_budget(Span<const WcetBound> bounds, Span<const TaskSpec> table, Span<BudgetLine> out) noexcept {
  std::size_t i = 0;
  for (const WcetBound& bound : bounds) {
    if (i >= out.size()) return;
    BudgetLine& line = out[i++];
    line = BudgetLine{};
    line.task = bound.task;
    const TaskSpec* spec = spec_of(table, bound.task);
    if (spec == nullptr) continue;  // not_measured: not a task of the table
    line.cpu = spec->cpu;
    line.period_ns = spec->period_ns;
    if (spec->period_ns <= 0) {
      line.verdict = BudgetVerdict::no_period;
      continue;
    }
    if (!bound.given) continue;
    double response = 0.0;
    if (!response_bound(bounds, table, *spec, bound.pwcet_ns, response)) continue;
    line.share = bound.pwcet_ns / static_cast<double>(spec->period_ns);
    line.response_ns = response;
    line.verdict = response <= static_cast<double>(spec->period_ns) ? BudgetVerdict::within : BudgetVerdict::over;
  }
}

const char* to_string(BudgetVerdict verdict) noexcept {
  switch (verdict) {
    case BudgetVerdict::within: return "within";
    case BudgetVerdict::over: return "over";
    case BudgetVerdict::no_period: return "n/a (event driven: no period)";
    case BudgetVerdict::not_measured: return "n/a (no pWCET for it or a task above it on its CPU)";
  }
  return "?";
}

}  // namespace rescue::app
