// The NIC's user-space filter: EtherType 0x88A4, directly or behind one 802.1Q tag; anything else,
// or a frame too short to carry an EtherType, is not EtherCAT.
#include <cstdint>

#include <gtest/gtest.h>

#include "hal/net/raw_socket_nic.hpp"

namespace rescue::hal {
namespace {

TEST(EthercatFrameFilter, AcceptsPlainAndVlanTaggedEthercat) {
  std::uint8_t plain[16] = {0};
  plain[12] = 0x88;
  plain[13] = 0xA4;
  EXPECT_TRUE(is_ethercat_frame(ConstByteSpan(plain)));

  std::uint8_t tagged[20] = {0};
  tagged[12] = 0x81;
  tagged[13] = 0x00;
  tagged[16] = 0x88;
  tagged[17] = 0xA4;
  EXPECT_TRUE(is_ethercat_frame(ConstByteSpan(tagged)));
}

TEST(EthercatFrameFilter, RejectsOtherTypesAndShortFrames) {
  std::uint8_t ipv4[16] = {0};
  ipv4[12] = 0x08;
  EXPECT_FALSE(is_ethercat_frame(ConstByteSpan(ipv4)));

  std::uint8_t tagged_ipv4[20] = {0};
  tagged_ipv4[12] = 0x81;
  tagged_ipv4[16] = 0x08;
  EXPECT_FALSE(is_ethercat_frame(ConstByteSpan(tagged_ipv4)));

  std::uint8_t short_tagged[16] = {0};
  short_tagged[12] = 0x81;
  EXPECT_FALSE(is_ethercat_frame(ConstByteSpan(short_tagged)));

  std::uint8_t runt[13] = {0};
  EXPECT_FALSE(is_ethercat_frame(ConstByteSpan(runt)));
  EXPECT_FALSE(is_ethercat_frame(ConstByteSpan()));
}

}  // namespace
}  // namespace rescue::hal
