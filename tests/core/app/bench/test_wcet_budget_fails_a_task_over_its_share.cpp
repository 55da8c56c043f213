// Issue 38 item 3, bench wcet's budget (core/app/bench/wcet_budget.hpp): a task's response bound is
// its pWCET plus the pWCETs of the tasks above it on its Table I CPU; over its period it is "over"
// (bench wcet fails); a task without a pWCET, or below one without it, is not judged; an event-driven
// task has no budget.
#include <gtest/gtest.h>

#include <cmath>

#include "core/app/bench/wcet_budget.hpp"

namespace rescue::app {
namespace {

constexpr double kUs = 1000.0;

struct Judged {
  BudgetLine handler, manager, parser, rc;
};

Judged judge(WcetBound handler, WcetBound manager, WcetBound parser, WcetBound rc) {
  const WcetBound bounds[] = {handler, manager, parser, rc};
  BudgetLine lines[4];
  judge_budget(Span<const WcetBound>(bounds), task_table(), Span<BudgetLine>(lines));
  return {lines[0], lines[1], lines[2], lines[3]};
}

WcetBound given(TaskId task, double ns) { return {task, true, ns}; }
WcetBound refused(TaskId task) { return {task, false, 0.0}; }

TEST(WcetBudget, TasksWithinTheirPeriodsAreWithinAndTheSharesAddUpOnTheSharedCpu) {
  const Judged j = judge(given(TaskId::ethercat_handler, 120 * kUs), given(TaskId::joint_manager, 50 * kUs),
                         given(TaskId::message_parser, 10 * kUs), given(TaskId::rc_tasks, 300 * kUs));
  EXPECT_EQ(j.handler.verdict, BudgetVerdict::within);
  EXPECT_EQ(j.handler.cpu, 3);
  EXPECT_DOUBLE_EQ(j.handler.share, 0.12);
  EXPECT_DOUBLE_EQ(j.handler.response_ns, 120 * kUs);  // alone on CPU 3
  EXPECT_EQ(j.manager.verdict, BudgetVerdict::within);
  EXPECT_DOUBLE_EQ(j.manager.response_ns, 50 * kUs);  // the highest on CPU 2
  EXPECT_EQ(j.rc.verdict, BudgetVerdict::within);
  EXPECT_DOUBLE_EQ(j.rc.response_ns, 350 * kUs);  // its own and the joint manager's, above it on CPU 2
  EXPECT_DOUBLE_EQ(j.rc.share, 0.3);
  EXPECT_EQ(j.parser.verdict, BudgetVerdict::no_period);
}

TEST(WcetBudget, ATaskOverItsPeriodIsOver) {
  const Judged j = judge(given(TaskId::ethercat_handler, 1001 * kUs), given(TaskId::joint_manager, 50 * kUs),
                         given(TaskId::message_parser, 10 * kUs), given(TaskId::rc_tasks, 300 * kUs));
  EXPECT_EQ(j.handler.verdict, BudgetVerdict::over);
  EXPECT_EQ(j.manager.verdict, BudgetVerdict::within) << "CPU 3's handler does not take CPU 2's time";
}

TEST(WcetBudget, ATaskWithinItsPeriodAloneIsOverWithTheTaskAboveItOnItsCpu) {
  const Judged j = judge(given(TaskId::ethercat_handler, 100 * kUs), given(TaskId::joint_manager, 400 * kUs),
                         given(TaskId::message_parser, 10 * kUs), given(TaskId::rc_tasks, 700 * kUs));
  EXPECT_EQ(j.manager.verdict, BudgetVerdict::within);
  EXPECT_EQ(j.rc.verdict, BudgetVerdict::over);
  EXPECT_DOUBLE_EQ(j.rc.response_ns, 1100 * kUs);
}

TEST(WcetBudget, AnInfiniteBoundIsOver) {
  const Judged j = judge(given(TaskId::ethercat_handler, HUGE_VAL), given(TaskId::joint_manager, 50 * kUs),
                         given(TaskId::message_parser, 10 * kUs), given(TaskId::rc_tasks, 300 * kUs));
  EXPECT_EQ(j.handler.verdict, BudgetVerdict::over);
}

TEST(WcetBudget, NoPwcetIsNotJudgedNorIsATaskBelowOneWithout) {
  const Judged j = judge(refused(TaskId::ethercat_handler), refused(TaskId::joint_manager), given(TaskId::message_parser, 10 * kUs),
                         given(TaskId::rc_tasks, 300 * kUs));
  EXPECT_EQ(j.handler.verdict, BudgetVerdict::not_measured);
  EXPECT_EQ(j.manager.verdict, BudgetVerdict::not_measured);
  EXPECT_EQ(j.rc.verdict, BudgetVerdict::not_measured) << "the joint manager above it on CPU 2 has no bound";
  EXPECT_EQ(j.rc.response_ns, 0.0);
  EXPECT_STREQ(to_string(j.rc.verdict), "n/a (no pWCET for it or a task above it on its CPU)");
}

}  // namespace
}  // namespace rescue::app
