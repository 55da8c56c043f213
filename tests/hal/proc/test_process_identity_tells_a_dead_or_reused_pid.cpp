// hal/proc/process_identity.hpp: a process is its pid AND its start time; a dead process, a zombie
// and a pid with another start time are not alive.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include "hal/proc/process_identity.hpp"

namespace rescue::hal {
namespace {

TEST(ProcessIdentity, OwnProcessIsAliveAndAnotherStartTimeIsNot) {
  const Result<ProcessIdentity> self = own_process_identity();
  ASSERT_TRUE(self.ok());
  EXPECT_EQ(self.value().pid, static_cast<std::int32_t>(::getpid()));
  EXPECT_GT(self.value().start_time, 0U);
  EXPECT_TRUE(process_alive(self.value()));
  ProcessIdentity reused = self.value();
  reused.start_time += 1;
  EXPECT_FALSE(process_alive(reused));
}

TEST(ProcessIdentity, ExitedChildIsDeadAsZombieAndAfterReaping) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  const Result<std::uint64_t> start = process_start_time(child);
  // Read before or after its exit: a zombie still has its /proc entry.
  ASSERT_TRUE(start.ok());
  int status = 0;
  siginfo_t info{};
  ASSERT_EQ(::waitid(P_PID, static_cast<id_t>(child), &info, WEXITED | WNOWAIT), 0);  // exited, not reaped
  EXPECT_FALSE(process_alive(ProcessIdentity{static_cast<std::int32_t>(child), start.value()}));
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_FALSE(process_alive(ProcessIdentity{static_cast<std::int32_t>(child), start.value()}));
  EXPECT_EQ(process_start_time(child).error().code, Errc::not_found);
  EXPECT_FALSE(process_alive(ProcessIdentity{0, 0}));
}

}  // namespace
}  // namespace rescue::hal
