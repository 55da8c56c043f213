// --nic sim|raw:IFACE: the default and both forms parse; anything else is a clear error.
#include <cstring>

#include <gtest/gtest.h>

#include "core/app/config/nic_option.hpp"

namespace rescue::app {
namespace {

TEST(NicOption, AbsentMeansTheSimulatedRobot) {
  auto choice = parse_nic_option(nullptr);
  ASSERT_TRUE(choice.ok());
  EXPECT_EQ(choice.value().kind, NicKind::sim);
}

TEST(NicOption, SimIsTheSimulatedRobot) {
  auto choice = parse_nic_option("sim");
  ASSERT_TRUE(choice.ok());
  EXPECT_EQ(choice.value().kind, NicKind::sim);
}

TEST(NicOption, RawNamesTheInterface) {
  auto choice = parse_nic_option("raw:enp3s0");
  ASSERT_TRUE(choice.ok());
  EXPECT_EQ(choice.value().kind, NicKind::raw);
  EXPECT_STREQ(choice.value().interface_name.data(), "enp3s0");

  auto longest = parse_nic_option("raw:abcdefghijklmno");  // 15 characters, the kernel's limit
  ASSERT_TRUE(longest.ok());
  EXPECT_STREQ(longest.value().interface_name.data(), "abcdefghijklmno");
}

TEST(NicOption, BadTextIsAnErrorThatSaysWhatIsExpected) {
  for (const char* bad : {"", "raw", "Sim", "simulator", "eth0", "pcap:eth0", "raw :eth0"}) {
    auto choice = parse_nic_option(bad);
    ASSERT_FALSE(choice.ok()) << bad;
    EXPECT_EQ(choice.error().code, Errc::invalid_argument);
    EXPECT_NE(std::strstr(choice.error().what, "'sim' or 'raw:IFACE'"), nullptr) << bad;
  }
}

TEST(NicOption, BadInterfaceNamesAreRefused) {
  auto empty = parse_nic_option("raw:");
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(std::strstr(empty.error().what, "needs an interface name"), nullptr);

  auto too_long = parse_nic_option("raw:abcdefghijklmnop");  // 16 characters
  ASSERT_FALSE(too_long.ok());
  EXPECT_NE(std::strstr(too_long.error().what, "15 characters"), nullptr);

  for (const char* bad : {"raw:eth/0", "raw:eth:0", "raw:eth 0", "raw:.", "raw:.."}) {
    auto choice = parse_nic_option(bad);
    ASSERT_FALSE(choice.ok()) << bad;
    EXPECT_EQ(choice.error().code, Errc::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace rescue::app
