// Process data of one joint drive: the byte layout of its RxPDO 0x1600 (outputs, master -> drive,
// SyncManager 2) and TxPDO 0x1A00 (inputs, drive -> master, SyncManager 3), fixed at compile
// time. Packed without padding, little-endian, in the order of the mapping entries (which is the
// order of the design brief); docs/devices.md draws it byte by byte.
//
//   outputs (13 bytes)                      inputs (15 bytes)
//   0  u16 controlword        0x6040:00     0  u16 statusword           0x6041:00
//   2  i8  modes of operation 0x6060:00     2  i8  modes of op. display 0x6061:00
//   3  i32 target position    0x607A:00     3  i32 position actual      0x6064:00
//   7  i32 target velocity    0x60FF:00     7  i32 velocity actual      0x606C:00
//   11 i16 target torque      0x6071:00     11 i16 torque actual        0x6077:00
//                                           13 u16 error code           0x603F:00
//
// Units: positions in encoder counts (drivers/joint/joint_units.hpp kCountsPerRad), velocities in counts/s,
// torques in per mille of the joint's rated torque (CiA 402).
//
// The master and the simulator both encode and decode through these functions; the tables below
// are what the object dictionary's 0x1600/0x1A00 and the SII PDO categories are built from.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/span.hpp"

namespace rescue::drivers {

constexpr std::size_t kJointOutputBytes = 13;
constexpr std::size_t kJointInputBytes = 15;

// PDO numbers and the SyncManagers they are assigned to.
constexpr std::uint16_t kJointRxPdoIndex = 0x1600;
constexpr std::uint16_t kJointTxPdoIndex = 0x1A00;
constexpr std::uint8_t kJointOutputsSyncManager = 2;
constexpr std::uint8_t kJointInputsSyncManager = 3;

// CoE data type codes (ETG.1000.6 table 64) used by the mapping.
namespace data_type {
constexpr std::uint16_t kBoolean = 0x0001;
constexpr std::uint16_t kInteger8 = 0x0002;
constexpr std::uint16_t kInteger16 = 0x0003;
constexpr std::uint16_t kInteger32 = 0x0004;
constexpr std::uint16_t kUnsigned8 = 0x0005;
constexpr std::uint16_t kUnsigned16 = 0x0006;
constexpr std::uint16_t kUnsigned32 = 0x0007;
constexpr std::uint16_t kVisibleString = 0x0009;
}  // namespace data_type

// One entry of a PDO mapping: the object it maps, its size, its offset in the PDO.
struct PdoMappingEntry {
  std::uint16_t index;
  std::uint8_t subindex;
  std::uint8_t bit_length;
  std::uint16_t data_type;
  std::uint8_t byte_offset;
  const char* name;
  // The value 0x1600/0x1A00 sub n holds for this entry: index << 16 | subindex << 8 | bits.
  constexpr std::uint32_t mapping_word() const noexcept {
    return (static_cast<std::uint32_t>(index) << 16U) | (static_cast<std::uint32_t>(subindex) << 8U) | bit_length;
  }
};

// clang-format off
inline constexpr std::array<PdoMappingEntry, 5> kJointRxMapping{{
  {0x6040, 0, 16, data_type::kUnsigned16, 0,  "Controlword"},
  {0x6060, 0,  8, data_type::kInteger8,   2,  "Modes of operation"},
  {0x607A, 0, 32, data_type::kInteger32,  3,  "Target position"},
  {0x60FF, 0, 32, data_type::kInteger32,  7,  "Target velocity"},
  {0x6071, 0, 16, data_type::kInteger16,  11, "Target torque"},
}};
inline constexpr std::array<PdoMappingEntry, 6> kJointTxMapping{{
  {0x6041, 0, 16, data_type::kUnsigned16, 0,  "Statusword"},
  {0x6061, 0,  8, data_type::kInteger8,   2,  "Modes of operation display"},
  {0x6064, 0, 32, data_type::kInteger32,  3,  "Position actual value"},
  {0x606C, 0, 32, data_type::kInteger32,  7,  "Velocity actual value"},
  {0x6077, 0, 16, data_type::kInteger16,  11, "Torque actual value"},
  {0x603F, 0, 16, data_type::kUnsigned16, 13, "Error code"},
}};
// clang-format on

// The mapping words of a table (what 0x1600/0x1A00 sub 1..n hold), for the master's PDO plan.
template <std::size_t N>
constexpr std::array<std::uint32_t, N> mapping_words(const std::array<PdoMappingEntry, N>& m) noexcept {
  std::array<std::uint32_t, N> words{};
  for (std::size_t i = 0; i < N; ++i) words[i] = m[i].mapping_word();
  return words;
}
inline constexpr std::array<std::uint32_t, kJointRxMapping.size()> kJointRxMappingWords = mapping_words(kJointRxMapping);
inline constexpr std::array<std::uint32_t, kJointTxMapping.size()> kJointTxMappingWords = mapping_words(kJointTxMapping);

// The tables and the byte sizes agree: entries are contiguous, in order, and fill the image.
template <std::size_t N>
constexpr bool mapping_is_packed(const std::array<PdoMappingEntry, N>& m, std::size_t bytes) noexcept {
  std::size_t offset = 0;
  for (const PdoMappingEntry& e : m) {
    if (e.byte_offset != offset || e.bit_length % 8 != 0) return false;
    offset += e.bit_length / 8U;
  }
  return offset == bytes;
}
static_assert(mapping_is_packed(kJointRxMapping, kJointOutputBytes), "RxPDO mapping and output size disagree");
static_assert(mapping_is_packed(kJointTxMapping, kJointInputBytes), "TxPDO mapping and input size disagree");

struct JointOutputs {
  std::uint16_t controlword{0};
  std::int8_t mode_of_operation{0};
  std::int32_t target_position{0};
  std::int32_t target_velocity{0};
  std::int16_t target_torque{0};
  bool operator==(const JointOutputs& o) const noexcept {
    return controlword == o.controlword && mode_of_operation == o.mode_of_operation &&
           target_position == o.target_position && target_velocity == o.target_velocity && target_torque == o.target_torque;
  }
};

struct JointInputs {
  std::uint16_t statusword{0};
  std::int8_t mode_display{0};
  std::int32_t position_actual{0};
  std::int32_t velocity_actual{0};
  std::int16_t torque_actual{0};
  std::uint16_t error_code{0};
  bool operator==(const JointInputs& o) const noexcept {
    return statusword == o.statusword && mode_display == o.mode_display && position_actual == o.position_actual &&
           velocity_actual == o.velocity_actual && torque_actual == o.torque_actual && error_code == o.error_code;
  }
};

using JointOutputImage = std::array<std::uint8_t, kJointOutputBytes>;
using JointInputImage = std::array<std::uint8_t, kJointInputBytes>;

// Encoders write exactly 13/15 bytes at `out`; decoders read exactly that many. The caller owns
// the bounds (the spans must be at least that long; asserted).
void encode_outputs(const JointOutputs& outputs, ByteSpan out) noexcept;
JointOutputs decode_outputs(ConstByteSpan in) noexcept;
void encode_inputs(const JointInputs& inputs, ByteSpan out) noexcept;
JointInputs decode_inputs(ConstByteSpan in) noexcept;

}  // namespace rescue::drivers
