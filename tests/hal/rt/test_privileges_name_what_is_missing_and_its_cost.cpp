// hal/rt/privileges.hpp: the capabilities and limits are read from the kernel; each missing one is
// named with what it costs; a process that has them all gets one line saying so.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "hal/rt/privileges.hpp"

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
  // Whatever the test runs as, the limits were read (0 is a valid soft limit).
  EXPECT_TRUE(p.value().root || !p.value().root);
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
