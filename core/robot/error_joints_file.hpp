// The error-joints file (design brief section 6, paper IV-C): the joints the robot lost, why, when,
// and where each one was when it was lost (its worm gear still holds it there). It is versioned and
// little-endian, each field written byte by byte (core/base/endian.hpp). The header and every record carry
// their own CRC-32, so one damaged record never hides the others. docs/joint-manager.md lays it out
// byte by byte.
//
//   header, 32 bytes                         record, 48 bytes (one per lost joint)
//   0  4 magic "RMEJ"                        0  1 joint index (core/robot/robot.hpp order)
//   4  2 format version (1)                  1  1 reason (FaultReason)
//   6  2 header size (32)                    2  2 reserved, 0
//   8  2 record size (48)                    4  4 last position, encoder counts (int32)
//  10  2 record count (0..21)                8  8 time lost, ns since the Unix epoch (int64)
//  12  4 robot fingerprint (CRC-32 of the   16  8 EtherCAT cycle of the detection (uint64)
//        joint names, in table order)       24 20 joint name, ASCII, NUL-padded
//  16  8 sequence number (+1 per write)     44  4 CRC-32 of record bytes 0..43
//  24  4 reserved, 0
//  28  4 CRC-32 of header bytes 0..27
//
// Decoding takes untrusted bytes (the file may be damaged, truncated, foreign or huge): every length,
// count and offset is checked before use, and the result says what was wrong. It never crashes (fuzzed:
// tests/fuzz/fuzz_error_joints_file.cpp).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/containers/fixed_vector.hpp"
#include "core/robot/joint_fault.hpp"
#include "core/base/result.hpp"
#include "core/robot/robot.hpp"
#include "core/base/span.hpp"

namespace rescue {

constexpr std::uint16_t kErrorJointsVersion = 1;
constexpr std::size_t kErrorJointsHeaderSize = 32;
constexpr std::size_t kErrorJointsRecordSize = 48;
constexpr std::size_t kErrorJointsNameSize = 20;
constexpr std::size_t kErrorJointsMaxFileSize = kErrorJointsHeaderSize + kJointCount * kErrorJointsRecordSize;

struct LostJointRecord {
  std::uint8_t joint{0};
  FaultReason reason{FaultReason::comm_lost};
  std::int32_t last_position_counts{0};
  std::int64_t time_unix_ns{0};
  std::uint64_t cycle{0};
};

struct ErrorJointsContents {
  std::uint64_t sequence{0};
  FixedVector<LostJointRecord, kJointCount> records;

  JointMask joints() const noexcept;
  // The record of `joint`, or nullptr.
  const LostJointRecord* find(std::size_t joint) const noexcept;
};

// CRC-32 of the joint names (each followed by a NUL), in table order: a file written for a robot
// whose joint table differs is not applied to this one.
std::uint32_t robot_fingerprint() noexcept;

// Writes the file image into `out` (at least kErrorJointsMaxFileSize bytes); returns its size.
// Refuses (invalid_argument) records with a joint index out of range, an unknown reason or a joint
// listed twice.
Result<std::size_t> encode_error_joints(const ErrorJointsContents& contents, ByteSpan out) noexcept;

struct ErrorJointsDecoded {
  ErrorJointsContents contents;      // every record that passed all its checks (maybe none)
  Status status;                     // success, or the first problem found (what + details)
  std::uint32_t records_rejected{0}; // records present but not usable
  bool salvaged{false};              // header not trusted: records recovered by their own CRCs
};

// Never fails outright: a problem is reported in `status`, and every record that can still be trusted
// is kept. A wrong magic, an unknown version, an oversized file or another robot's fingerprint keep
// nothing, because the records cannot be interpreted.
ErrorJointsDecoded decode_error_joints(ConstByteSpan bytes) noexcept;

}  // namespace rescue
