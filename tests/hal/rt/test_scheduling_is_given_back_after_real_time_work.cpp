// A thread that runs real-time work for a while (run's bring-up at the EtherCAT handler's priority
// on its CPU) gets back exactly the scheduling it had: policy, priority and CPUs, so the processes it
// forks afterwards (the tasks, which set their own) and the supervisor it becomes run as before.
#include <pthread.h>
#include <sched.h>

#include <gtest/gtest.h>

#include "hal/rt/rt_setup.hpp"

namespace rescue::hal {
namespace {

TEST(SchedulingState, RestoreGivesBackPolicyPriorityAndCpus) {
  const Result<SchedulingState> before = save_scheduling();
  ASSERT_TRUE(before.ok()) << before.error().what;
  const Status raised = set_fifo_priority(10);
  if (!raised.ok()) GTEST_SKIP() << "SCHED_FIFO not permitted here: " << raised.error().what;
  (void)pin_to_cpu(0);  // may be refused by a cpuset: the policy is still checked
  int policy = 0;
  sched_param param{};
  ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
  EXPECT_EQ(policy, SCHED_FIFO);

  ASSERT_TRUE(restore_scheduling(before.value()).ok());
  ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
  EXPECT_EQ(policy, before.value().policy);
  EXPECT_EQ(param.sched_priority, before.value().priority);
  cpu_set_t now;
  CPU_ZERO(&now);
  ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof now, &now), 0);
  cpu_set_t saved = before.value().cpus;
  EXPECT_TRUE(CPU_EQUAL(&now, &saved)) << CPU_COUNT(&now) << " CPUs now, " << CPU_COUNT(&saved) << " before";
}

}  // namespace
}  // namespace rescue::hal
