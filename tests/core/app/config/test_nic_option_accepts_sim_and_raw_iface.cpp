// --nic sim|raw:IFACE: the default and both forms parse; anything else is a clear error. --ring-nic
// (cable redundancy) pairs with it: another raw interface beside a raw one, sim beside sim; the main
// interface itself and a mixed pair are refused with the reason.
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

TEST(RingNicOption, AnotherRawInterfaceBesideARawOne) {
  const Result<NicChoice> main = parse_nic_option("raw:eth1");
  ASSERT_TRUE(main.ok());
  const Result<NicChoice> ring = parse_ring_nic_option("raw:eth2", main.value());
  ASSERT_TRUE(ring.ok());
  EXPECT_EQ(ring.value().kind, NicKind::raw);
  EXPECT_STREQ(ring.value().interface_name.data(), "eth2");
}

TEST(RingNicOption, TheMainInterfaceItselfIsRefusedWithTheReason) {
  const Result<NicChoice> main = parse_nic_option("raw:eth1");
  ASSERT_TRUE(main.ok());
  const Result<NicChoice> ring = parse_ring_nic_option("raw:eth1", main.value());
  ASSERT_FALSE(ring.ok());
  EXPECT_EQ(ring.error().code, Errc::invalid_argument);
  EXPECT_NE(std::strstr(ring.error().what, "is the --nic interface itself"), nullptr) << ring.error().what;
}

TEST(RingNicOption, MixedPairsAndBadTextAreRefused) {
  const Result<NicChoice> sim = parse_nic_option("sim");
  const Result<NicChoice> raw = parse_nic_option("raw:eth1");
  ASSERT_TRUE(sim.ok() && raw.ok());
  EXPECT_TRUE(parse_ring_nic_option("sim", sim.value()).ok());
  const Result<NicChoice> raw_beside_sim = parse_ring_nic_option("raw:eth2", sim.value());
  ASSERT_FALSE(raw_beside_sim.ok());
  EXPECT_NE(std::strstr(raw_beside_sim.error().what, "needs --nic raw:IFACE"), nullptr);
  const Result<NicChoice> sim_beside_raw = parse_ring_nic_option("sim", raw.value());
  ASSERT_FALSE(sim_beside_raw.ok());
  EXPECT_NE(std::strstr(sim_beside_raw.error().what, "needs --nic sim"), nullptr);
  for (const char* bad : {"", "eth2", "raw:", "raw:eth/2"}) {
    EXPECT_FALSE(parse_ring_nic_option(bad, raw.value()).ok()) << bad;
  }
}

}  // namespace
}  // namespace rescue::app
