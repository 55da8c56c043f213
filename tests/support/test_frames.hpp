// Test support: small EtherCAT frames built with the codec, for tests that move frames around.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "ecat/codec/frame.hpp"

namespace rescue::testing {

// A broadcast read of the ESC type register (BRD 0x0000:0x0000, 2 bytes) with datagram index
// `index`, from `source` to the broadcast address: what a master sends first to count slaves.
inline std::vector<std::uint8_t> make_brd_frame(const ecat::MacAddress& source, std::uint8_t index) {
  ecat::FrameBuilder builder;
  builder.reset(source);
  auto slot = builder.add(ecat::Command::BRD, index, 0, 2);
  EXPECT_TRUE(slot.ok());
  const ConstByteSpan bytes = builder.finish();
  return std::vector<std::uint8_t>(bytes.begin(), bytes.end());
}

// A frame of another EtherType (IPv4 number, junk payload) that an EtherCAT NIC must never return.
inline std::vector<std::uint8_t> make_ipv4_typed_frame(const ecat::MacAddress& source) {
  std::vector<std::uint8_t> frame(60, 0xA5);
  for (std::size_t i = 0; i < 6; ++i) frame[i] = 0xFF;
  for (std::size_t i = 0; i < 6; ++i) frame[6 + i] = source[i];
  frame[12] = 0x08;
  frame[13] = 0x00;
  return frame;
}

}  // namespace rescue::testing
