#include "drivers/joint/joint_drive_pdo.hpp"

#include <cassert>

#include "core/base/endian.hpp"

namespace rescue::drivers {

// Offsets come from the mapping tables so the codec cannot drift from 0x1600/0x1A00.
void encode_outputs(const JointOutputs& o, ByteSpan out) noexcept {
  assert(out.size() >= kJointOutputBytes);
  std::uint8_t* p = out.data();
  store_le16(p + kJointRxMapping[0].byte_offset, o.controlword);
  p[kJointRxMapping[1].byte_offset] = static_cast<std::uint8_t>(o.mode_of_operation);
  store_le32(p + kJointRxMapping[2].byte_offset, static_cast<std::uint32_t>(o.target_position));
  store_le32(p + kJointRxMapping[3].byte_offset, static_cast<std::uint32_t>(o.target_velocity));
  store_le16(p + kJointRxMapping[4].byte_offset, static_cast<std::uint16_t>(o.target_torque));
}

JointOutputs decode_outputs(ConstByteSpan in) noexcept {
  assert(in.size() >= kJointOutputBytes);
  const std::uint8_t* p = in.data();
  JointOutputs o;
  o.controlword = load_le16(p + kJointRxMapping[0].byte_offset);
  o.mode_of_operation = static_cast<std::int8_t>(p[kJointRxMapping[1].byte_offset]);
  o.target_position = load_le32s(p + kJointRxMapping[2].byte_offset);
  o.target_velocity = load_le32s(p + kJointRxMapping[3].byte_offset);
  o.target_torque = load_le16s(p + kJointRxMapping[4].byte_offset);
  return o;
}

void encode_inputs(const JointInputs& i, ByteSpan out) noexcept {
  assert(out.size() >= kJointInputBytes);
  std::uint8_t* p = out.data();
  store_le16(p + kJointTxMapping[0].byte_offset, i.statusword);
  p[kJointTxMapping[1].byte_offset] = static_cast<std::uint8_t>(i.mode_display);
  store_le32(p + kJointTxMapping[2].byte_offset, static_cast<std::uint32_t>(i.position_actual));
  store_le32(p + kJointTxMapping[3].byte_offset, static_cast<std::uint32_t>(i.velocity_actual));
  store_le16(p + kJointTxMapping[4].byte_offset, static_cast<std::uint16_t>(i.torque_actual));
  store_le16(p + kJointTxMapping[5].byte_offset, i.error_code);
}

JointInputs decode_inputs(ConstByteSpan in) noexcept {
  assert(in.size() >= kJointInputBytes);
  const std::uint8_t* p = in.data();
  JointInputs i;
  i.statusword = load_le16(p + kJointTxMapping[0].byte_offset);
  i.mode_display = static_cast<std::int8_t>(p[kJointTxMapping[1].byte_offset]);
  i.position_actual = load_le32s(p + kJointTxMapping[2].byte_offset);
  i.velocity_actual = load_le32s(p + kJointTxMapping[3].byte_offset);
  i.torque_actual = load_le16s(p + kJointTxMapping[4].byte_offset);
  i.error_code = load_le16(p + kJointTxMapping[5].byte_offset);
  return i;
}

}  // namespace rescue::drivers
