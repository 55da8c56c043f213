// When the OS refuses the raw socket, open() says why and how to fix it: a missing interface, a
// bad name, missing CAP_NET_RAW, an interface that is down. No socket is left open.
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "hal/net/raw_socket_nic.hpp"
#include "tests/support/netns_veth.hpp"

namespace rescue::hal {
namespace {

TEST(RawSocketNicRefusals, MissingInterfaceIsNotFound) {
  RawSocketNic nic;
  const Status status = nic.open("rm-no-such0");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, Errc::not_found);
  EXPECT_NE(std::strstr(status.error().what, "no such network interface"), nullptr);
  EXPECT_FALSE(nic.is_open());
}

TEST(RawSocketNicRefusals, BadNamesAreInvalidArguments) {
  RawSocketNic nic;
  EXPECT_EQ(nic.open("").error().code, Errc::invalid_argument);
  EXPECT_EQ(nic.open(nullptr).error().code, Errc::invalid_argument);
  EXPECT_EQ(nic.open("a-name-of-16-chr").error().code, Errc::invalid_argument);
  EXPECT_FALSE(nic.is_open());
}

TEST(RawSocketNicRefusals, UsingAClosedNicIsAnErrorNotACrash) {
  RawSocketNic nic;
  std::uint8_t frame[60] = {};
  EXPECT_EQ(nic.send(ConstByteSpan(frame)).error().code, Errc::invalid_argument);
  EXPECT_EQ(nic.receive(ByteSpan(frame), 0).error().code, Errc::invalid_argument);
}

// Opens a raw socket on "lo" without CAP_NET_RAW: as root, in a child that becomes `nobody`.
TEST(RawSocketNicRefusals, NoCapNetRawIsPermissionDeniedWithTheFix) {
  const auto check = [] {
    RawSocketNic nic;
    const Status status = nic.open("lo");
    if (status.ok()) return 2;
    if (status.error().code != Errc::permission_denied) return 3;
    if (std::strstr(status.error().what, "CAP_NET_RAW") == nullptr) return 4;
    if (std::strstr(status.error().what, "setcap cap_net_raw") == nullptr) return 5;
    return 0;
  };
  if (::geteuid() != 0) {
    RawSocketNic probe;
    if (probe.open("lo").ok()) GTEST_SKIP() << "this unprivileged process has CAP_NET_RAW: cannot test the refusal";
    EXPECT_EQ(check(), 0);
    return;
  }
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    constexpr uid_t kNobody = 65534;
    if (::setresgid(kNobody, kNobody, kNobody) != 0 || ::setresuid(kNobody, kNobody, kNobody) != 0) ::_exit(9);
    ::_exit(check());
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "2: opened without privilege, 3: wrong code, 4/5: message lacks the fix";
}

class RawSocketNicOnDownInterface : public rescue::testing::NetnsTest {};

TEST_F(RawSocketNicOnDownInterface, DownInterfaceIsRefusedWithTheFix) {
  std::string output;
  ASSERT_TRUE(rescue::testing::VethPair::ip(veth_->master_ns(), "link set ecm0 down", output)) << output;
  rescue::testing::InNamespace inside(veth_->master_ns());
  ASSERT_TRUE(inside.entered());
  RawSocketNic nic;
  const Status status = nic.open(rescue::testing::VethPair::kMasterInterface);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().code, Errc::refused);
  EXPECT_NE(std::strstr(status.error().what, "ip link set"), nullptr);
  EXPECT_FALSE(nic.is_open());
}

}  // namespace
}  // namespace rescue::hal
