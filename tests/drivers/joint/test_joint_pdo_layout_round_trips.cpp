// The joint drive's process data: 13 output and 15 input bytes, little-endian, packed in the
// order of the 0x1600/0x1A00 mapping. Byte positions are pinned, and values round-trip
// (extremes and signs included).
#include <gtest/gtest.h>

#include <limits>

#include "drivers/joint/joint_drive_pdo.hpp"

namespace rescue::drivers {
namespace {

TEST(JointPdoLayout, SizesAreTheDesignBriefsFields) {
  EXPECT_EQ(kJointOutputBytes, 2u + 1u + 4u + 4u + 2u);
  EXPECT_EQ(kJointInputBytes, 2u + 1u + 4u + 4u + 2u + 2u);
  EXPECT_EQ(kJointRxMapping[0].mapping_word(), 0x60400010u);
  EXPECT_EQ(kJointTxMapping[5].mapping_word(), 0x603F0010u);
}

TEST(JointPdoLayout, OutputBytesSitWhereTheDocsSay) {
  JointOutputs o;
  o.controlword = 0x010F;
  o.mode_of_operation = 8;
  o.target_position = 0x11223344;
  o.target_velocity = -2;  // 0xFFFFFFFE
  o.target_torque = 0x5566;
  JointOutputImage img{};
  encode_outputs(o, ByteSpan(img));
  const JointOutputImage expected{0x0F, 0x01, 0x08, 0x44, 0x33, 0x22, 0x11, 0xFE, 0xFF, 0xFF, 0xFF, 0x66, 0x55};
  EXPECT_EQ(img, expected);
  EXPECT_EQ(decode_outputs(ConstByteSpan(img)), o);
}

TEST(JointPdoLayout, InputBytesSitWhereTheDocsSay) {
  JointInputs i;
  i.statusword = 0x1637;
  i.mode_display = 9;
  i.position_actual = -1;
  i.velocity_actual = 0x01020304;
  i.torque_actual = -300;  // 0xFED4
  i.error_code = 0x4210;
  JointInputImage img{};
  encode_inputs(i, ByteSpan(img));
  const JointInputImage expected{0x37, 0x16, 0x09, 0xFF, 0xFF, 0xFF, 0xFF, 0x04, 0x03, 0x02, 0x01, 0xD4, 0xFE, 0x10, 0x42};
  EXPECT_EQ(img, expected);
  EXPECT_EQ(decode_inputs(ConstByteSpan(img)), i);
}

TEST(JointPdoLayout, ExtremeValuesRoundTrip) {
  JointOutputs o;
  o.controlword = 0xFFFF;
  o.mode_of_operation = std::numeric_limits<std::int8_t>::min();
  o.target_position = std::numeric_limits<std::int32_t>::min();
  o.target_velocity = std::numeric_limits<std::int32_t>::max();
  o.target_torque = std::numeric_limits<std::int16_t>::min();
  JointOutputImage out{};
  encode_outputs(o, ByteSpan(out));
  EXPECT_EQ(decode_outputs(ConstByteSpan(out)), o);

  JointInputs i;
  i.statusword = 0;
  i.mode_display = -1;
  i.position_actual = std::numeric_limits<std::int32_t>::max();
  i.velocity_actual = std::numeric_limits<std::int32_t>::min();
  i.torque_actual = std::numeric_limits<std::int16_t>::max();
  i.error_code = 0xFFFF;
  JointInputImage in{};
  encode_inputs(i, ByteSpan(in));
  EXPECT_EQ(decode_inputs(ConstByteSpan(in)), i);
}

TEST(JointPdoLayout, CodecsTouchOnlyTheirBytes) {
  std::array<std::uint8_t, kJointOutputBytes + 2> wide{};
  wide.fill(0xAA);
  encode_outputs(JointOutputs{}, ByteSpan(wide.data(), kJointOutputBytes));
  EXPECT_EQ(wide[kJointOutputBytes], 0xAA);
  EXPECT_EQ(wide[kJointOutputBytes + 1], 0xAA);
}

}  // namespace
}  // namespace rescue::drivers
