#include "core/robot/error_joints_file.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>

#include "core/base/crc32.hpp"
#include "core/base/endian.hpp"

namespace rescue {
namespace {

constexpr std::uint8_t kMagic[4] = {'R', 'M', 'E', 'J'};

// Header field offsets.
constexpr std::size_t kOffVersion = 4;
constexpr std::size_t kOffHeaderSize = 6;
constexpr std::size_t kOffRecordSize = 8;
constexpr std::size_t kOffCount = 10;
constexpr std::size_t kOffFingerprint = 12;
constexpr std::size_t kOffSequence = 16;
constexpr std::size_t kOffHeaderReserved = 24;
constexpr std::size_t kOffHeaderCrc = 28;

// Record field offsets.
constexpr std::size_t kOffJoint = 0;
constexpr std::size_t kOffReason = 1;
constexpr std::size_t kOffRecordReserved = 2;
constexpr std::size_t kOffPosition = 4;
constexpr std::size_t kOffTime = 8;
constexpr std::size_t kOffCycle = 16;
constexpr std::size_t kOffName = 24;
constexpr std::size_t kOffRecordCrc = kOffName + kErrorJointsNameSize;
static_assert(kOffRecordCrc + 4 == kErrorJointsRecordSize, "record layout");
static_assert(kOffHeaderCrc + 4 == kErrorJointsHeaderSize, "header layout");

constexpr bool names_fit() {
  for (const JointInfo& j : kJoints) {
    std::size_t n = 0;
    while (j.name[n] != '\0') ++n;
    if (n >= kErrorJointsNameSize) return false;  // room for at least one NUL
  }
  return true;
}
static_assert(names_fit(), "a joint name does not fit the record's name field");

constexpr std::uint32_t compute_fingerprint() {
  Crc32 c;
  for (const JointInfo& j : kJoints) {
    for (const char* p = j.name; *p != '\0'; ++p) c.update(static_cast<std::uint8_t>(*p));
    c.update(0);
  }
  return c.value();
}
constexpr std::uint32_t kFingerprint = compute_fingerprint();

std::uint32_t crc_of(const std::uint8_t* p, std::size_t n) noexcept { return crc32(ConstByteSpan(p, n)); }

void encode_record(const LostJointRecord& r, std::uint8_t* out) noexcept {
  std::memset(out, 0, kErrorJointsRecordSize);
  out[kOffJoint] = r.joint;
  out[kOffReason] = static_cast<std::uint8_t>(r.reason);
  store_le32(out + kOffPosition, static_cast<std::uint32_t>(r.last_position_counts));
  store_le64(out + kOffTime, static_cast<std::uint64_t>(r.time_unix_ns));
  store_le64(out + kOffCycle, r.cycle);
  // The name without its NUL: the field's padding (zeroed above) terminates it.
  const char* name = kJoints[r.joint].name;
  for (std::size_t i = 0; name[i] != '\0'; ++i) out[kOffName + i] = static_cast<std::uint8_t>(name[i]);
  store_le32(out + kOffRecordCrc, crc_of(out, kOffRecordCrc));
}

// The name field must hold exactly the table's name for `joint`, then NULs only.
bool name_matches(const std::uint8_t* field, std::size_t joint) noexcept {
  const char* expected = kJoints[joint].name;
  const std::size_t n = std::strlen(expected);
  if (std::memcmp(field, expected, n) != 0) return false;
  for (std::size_t i = n; i < kErrorJointsNameSize; ++i) {
    if (field[i] != 0) return false;
  }
  return true;
}

Result<LostJointRecord> decode_record(const std::uint8_t* in, std::uint32_t index) noexcept {
  if (load_le32(in + kOffRecordCrc) != crc_of(in, kOffRecordCrc)) {
    return make_error(Errc::checksum, "record checksum mismatch", index);
  }
  LostJointRecord r;
  r.joint = in[kOffJoint];
  if (r.joint >= kJointCount) return make_error(Errc::out_of_range, "record joint index out of range", index, r.joint);
  if (!is_valid_fault_reason(in[kOffReason]) || in[kOffReason] == 0) {
    return make_error(Errc::malformed, "record reason unknown", index, in[kOffReason]);
  }
  r.reason = static_cast<FaultReason>(in[kOffReason]);
  if (load_le16(in + kOffRecordReserved) != 0) return make_error(Errc::malformed, "record reserved bytes not zero", index);
  if (!name_matches(in + kOffName, r.joint)) {
    return make_error(Errc::mismatch, "record joint name does not match the robot's table", index, r.joint);
  }
  r.last_position_counts = load_le32s(in + kOffPosition);
  r.time_unix_ns = load_le64s(in + kOffTime);
  r.cycle = load_le64(in + kOffCycle);
  return r;
}

// Remembers the first problem; later ones are only counted by the caller.
void note(ErrorJointsDecoded& d, const Error& e) noexcept {
  if (d.status.ok()) d.status = e;
}

}  // namespace

JointMask ErrorJointsContents::joints() const noexcept {
  return std::accumulate(records.begin(), records.end(), JointMask{0}, [](JointMask mask, const LostJointRecord& r) {
    return r.joint < kJointCount ? mask | joint_bit(r.joint) : mask;
  });
}

const LostJointRecord* ErrorJointsContents::find(std::size_t joint) const noexcept {
  const LostJointRecord* it =
      std::find_if(records.begin(), records.end(), [joint](const LostJointRecord& r) { return r.joint == joint; });
  return it != records.end() ? it : nullptr;
}

std::uint32_t robot_fingerprint() noexcept { return kFingerprint; }

Result<std::size_t> encode_error_joints(const ErrorJointsContents& contents, ByteSpan out) noexcept {
  const std::size_t size = kErrorJointsHeaderSize + contents.records.size() * kErrorJointsRecordSize;
  if (out.size() < size) return make_error(Errc::capacity_exceeded, "output buffer too small", static_cast<std::uint32_t>(size));
  JointMask seen = 0;
  for (const LostJointRecord& r : contents.records) {
    if (r.joint >= kJointCount) return make_error(Errc::invalid_argument, "joint index out of range", r.joint);
    const auto reason = static_cast<std::uint8_t>(r.reason);
    if (!is_valid_fault_reason(reason) || reason == 0) return make_error(Errc::invalid_argument, "reason unknown", reason);
    if ((seen & joint_bit(r.joint)) != 0) return make_error(Errc::invalid_argument, "joint listed twice", r.joint);
    seen |= joint_bit(r.joint);
  }
  std::uint8_t* h = out.data();
  std::memset(h, 0, kErrorJointsHeaderSize);
  std::memcpy(h, kMagic, sizeof kMagic);
  store_le16(h + kOffVersion, kErrorJointsVersion);
  store_le16(h + kOffHeaderSize, static_cast<std::uint16_t>(kErrorJointsHeaderSize));
  store_le16(h + kOffRecordSize, static_cast<std::uint16_t>(kErrorJointsRecordSize));
  store_le16(h + kOffCount, static_cast<std::uint16_t>(contents.records.size()));
  store_le32(h + kOffFingerprint, kFingerprint);
  store_le64(h + kOffSequence, contents.sequence);
  store_le32(h + kOffHeaderCrc, crc_of(h, kOffHeaderCrc));
  for (std::size_t i = 0; i < contents.records.size(); ++i) {
    encode_record(contents.records[i], h + kErrorJointsHeaderSize + i * kErrorJointsRecordSize);
  }
  return size;
}

ErrorJointsDecoded decode_error_joints(ConstByteSpan bytes) noexcept {
  ErrorJointsDecoded d;
  const std::size_t size = bytes.size();
  const auto size32 = static_cast<std::uint32_t>(size > 0xFFFFFFFFU ? 0xFFFFFFFFU : size);
  if (size == 0) {
    d.status = make_error(Errc::truncated, "file is empty");
    return d;
  }
  if (size > kErrorJointsMaxFileSize) {
    d.status = make_error(Errc::capacity_exceeded, "file larger than 21 records", size32,
                          static_cast<std::uint32_t>(kErrorJointsMaxFileSize));
    return d;
  }
  const std::uint8_t* h = bytes.data();
  const std::size_t magic_bytes = size < sizeof kMagic ? size : sizeof kMagic;
  if (std::memcmp(h, kMagic, magic_bytes) != 0) {
    d.status = make_error(Errc::malformed, "not an error-joints file (bad magic)", size32);
    return d;
  }
  if (size < kErrorJointsHeaderSize) {
    d.status = make_error(Errc::truncated, "file shorter than its header", size32);
    return d;
  }
  const std::uint16_t version = load_le16(h + kOffVersion);
  if (version != kErrorJointsVersion) {
    d.status = make_error(Errc::version, "unsupported error-joints file version", version, kErrorJointsVersion);
    return d;
  }

  // Which records to read. A trusted header gives the count; an untrusted one leaves the records to
  // prove themselves by their own checksums and names, at the fixed version-1 layout.
  std::size_t count = 0;
  const std::size_t complete = (size - kErrorJointsHeaderSize) / kErrorJointsRecordSize;
  if (load_le32(h + kOffHeaderCrc) != crc_of(h, kOffHeaderCrc)) {
    note(d, make_error(Errc::checksum, "header checksum mismatch"));
    d.salvaged = true;
  } else if (load_le16(h + kOffHeaderSize) != kErrorJointsHeaderSize ||
             load_le16(h + kOffRecordSize) != kErrorJointsRecordSize || load_le32(h + kOffHeaderReserved) != 0) {
    note(d, make_error(Errc::malformed, "header sizes or reserved field differ from version 1",
                       load_le16(h + kOffHeaderSize), load_le16(h + kOffRecordSize)));
    d.salvaged = true;
  } else if (load_le32(h + kOffFingerprint) != kFingerprint) {
    d.status = make_error(Errc::mismatch, "file written for another robot (joint table fingerprint differs)",
                          load_le32(h + kOffFingerprint), kFingerprint);
    return d;
  } else if (load_le16(h + kOffCount) > kJointCount) {
    note(d, make_error(Errc::malformed, "record count above the joint count", load_le16(h + kOffCount)));
    d.salvaged = true;
  } else {
    count = load_le16(h + kOffCount);
    d.contents.sequence = load_le64(h + kOffSequence);
    const std::size_t expected = kErrorJointsHeaderSize + count * kErrorJointsRecordSize;
    if (size < expected) {
      note(d, make_error(Errc::truncated, "file shorter than its record count", size32, static_cast<std::uint32_t>(expected)));
      d.records_rejected += static_cast<std::uint32_t>(count - complete);
      count = complete;
    } else if (size > expected) {
      note(d, make_error(Errc::malformed, "bytes after the last record", size32, static_cast<std::uint32_t>(expected)));
    }
  }
  if (d.salvaged) count = complete < kJointCount ? complete : kJointCount;

  JointMask seen = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const auto index = static_cast<std::uint32_t>(i);
    auto record = decode_record(h + kErrorJointsHeaderSize + i * kErrorJointsRecordSize, index);
    if (record.ok() && (seen & joint_bit(record.value().joint)) != 0) {
      record = make_error(Errc::malformed, "record joint listed twice", index, record.value().joint);
    }
    if (!record.ok()) {
      note(d, record.error());
      ++d.records_rejected;
      continue;
    }
    seen |= joint_bit(record.value().joint);
    (void)d.contents.records.push_back(record.value());  // cannot fail: count <= kJointCount
  }
  return d;
}

}  // namespace rescue
