// hal/rt/privileges.hpp: the capabilities and limits are read from the kernel; each missing one is
// named with what it costs; a process that has them all gets one line saying so.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "hal/rt/privileges.hpp"
#include "tests/support/forked_child.hpp"

namespace rescue::hal {
namespace {

std::string describe(const Privileges& have, const PrivilegeNeeds& needs, std::size_t& missing) {
  std::FILE* out = std::tmpfile();
  missing = describe_privileges(have, needs, "p: ", out);
  std::rewind(out);
  std::string text;
  char buf[512];
  while (std::fgets(buf, sizeof buf, out) != nullptr) text += buf;
  (void)std::fclose(out);
  return text;
}

TEST(Privileges, QueryReadsThisProcess) {
  const Result<Privileges> p = query_privileges();
  ASSERT_TRUE(p.ok());
  EXPECT_EQ(p.value().root, geteuid() == 0);
  rlimit memlock{};
  ASSERT_EQ(getrlimit(RLIMIT_MEMLOCK, &memlock), 0);
  EXPECT_EQ(p.value().memlock_limit,
            memlock.rlim_cur == RLIM_INFINITY ? Privileges::kUnlimited : static_cast<std::uint64_t>(memlock.rlim_cur));
}

// A real non-root process (user nobody, limits at 0, in a forked child): the kernel's answer has none
// of the three capabilities and both limits at 0.
TEST(Privileges, QueryOfANonRootProcessSeesNothingHeld) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to become user nobody";
  const int status = test::run_in_child([] {
    const rlimit zero{0, 0};
    if (setrlimit(RLIMIT_RTPRIO, &zero) != 0 || setrlimit(RLIMIT_MEMLOCK, &zero) != 0) return 2;
    if (setresgid(65534, 65534, 65534) != 0 || setresuid(65534, 65534, 65534) != 0) return 3;
    const Result<Privileges> p = query_privileges();
    if (!p.ok()) return 4;
    const Privileges& h = p.value();
    if (h.root || h.net_raw || h.sys_nice || h.ipc_lock) return 5;
    if (h.rtprio_limit != 0 || h.memlock_limit != 0) return 6;
    PrivilegeNeeds needs;
    needs.max_priority = 80;
    needs.raw_socket = true;
    std::FILE* out = std::fopen("/dev/null", "w");
    const std::size_t missing = describe_privileges(h, needs, "", out);
    (void)std::fclose(out);
    return missing == 3 ? 0 : 7;
  });
  EXPECT_EQ(status, 0) << "1: fork; 2: setrlimit; 3: setresuid; 4: query; 5: a capability seen; 6: a limit; 7: count";
}

TEST(Privileges, UnprivilegedUserIsToldEachMissingItemAndItsCost) {
  Privileges none;
  none.rtprio_limit = 0;
  none.memlock_limit = 8U * 1024U * 1024U;
  PrivilegeNeeds needs;
  needs.max_priority = 80;
  needs.raw_socket = true;
  std::size_t missing = 0;
  const std::string text = describe(none, needs, missing);
  EXPECT_EQ(missing, 3U);
  EXPECT_NE(text.find("p: CAP_NET_RAW missing: the raw EtherCAT socket cannot be opened"), std::string::npos) << text;
  EXPECT_NE(text.find("p: CAP_SYS_NICE missing and RLIMIT_RTPRIO 0 below priority 80: the real-time tasks run at normal priority"),
            std::string::npos) << text;
  EXPECT_NE(text.find("p: CAP_IPC_LOCK missing and RLIMIT_MEMLOCK 8388608 bytes: memory may not be locked"),
            std::string::npos) << text;
}

TEST(Privileges, LimitsStandInForCapabilities) {
  Privileges limits;
  limits.net_raw = true;
  limits.rtprio_limit = 99;
  limits.memlock_limit = Privileges::kUnlimited;
  PrivilegeNeeds needs;
  needs.max_priority = 80;
  std::size_t missing = 1;
  const std::string text = describe(limits, needs, missing);
  EXPECT_EQ(missing, 0U);
  EXPECT_NE(text.find("RLIMIT_RTPRIO 99, RLIMIT_MEMLOCK unlimited: every real-time setting can be applied"),
            std::string::npos) << text;
}

TEST(Privileges, TheServiceSetIsEnough) {
  Privileges service;  // AmbientCapabilities=CAP_NET_RAW CAP_SYS_NICE CAP_IPC_LOCK, default limits
  service.net_raw = service.sys_nice = service.ipc_lock = true;
  service.memlock_limit = 65536;
  PrivilegeNeeds needs;
  needs.max_priority = 80;
  needs.raw_socket = true;
  std::size_t missing = 1;
  (void)describe(service, needs, missing);
  EXPECT_EQ(missing, 0U);
}

TEST(Privileges, SimulatedRobotStillNamesAMissingNetRaw) {
  Privileges p;
  p.sys_nice = p.ipc_lock = true;
  std::size_t missing = 0;
  const std::string text = describe(p, PrivilegeNeeds{}, missing);
  EXPECT_EQ(missing, 1U);
  EXPECT_NE(text.find("CAP_NET_RAW missing: no raw:IFACE NIC (the simulated robot needs none)"), std::string::npos) << text;
}

}  // namespace
}  // namespace rescue::hal
