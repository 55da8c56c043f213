#include "drivers/sim/devices/joint_drive_objects.hpp"
#include "drivers/joint/joint_units.hpp"

#include <limits>

#include "core/base/endian.hpp"
#include "drivers/joint/device_identity.hpp"
#include "ecat/mailbox/coe.hpp"

namespace rescue::drivers {
namespace {

namespace dt = data_type;
namespace abort_code = ecat::coe::abort_code;

constexpr Access ro = Access::ro;
constexpr Access rw = Access::rw;
constexpr Access pre = Access::rw_preop;

// clang-format off
constexpr std::array<ObjectEntry, kJointDriveObjectCount> kTable = [] {
  std::array<ObjectEntry, kJointDriveObjectCount> t{{
    {0x1000, 0, dt::kUnsigned32, 4, ro, 0, "Device type"},
    {0x1001, 0, dt::kUnsigned8, 1, ro, 0, "Error register"},
    {0x1008, 0, dt::kVisibleString, kDeviceNameCapacity, ro, 0, "Manufacturer device name"},
    {0x100A, 0, dt::kVisibleString, kFirmwareVersionCapacity, ro, 0, "Manufacturer software version"},
    {0x1018, 0, dt::kUnsigned8, 1, ro, 0, "Identity: highest subindex"},
    {0x1018, 1, dt::kUnsigned32, 4, ro, 0, "Vendor ID"},
    {0x1018, 2, dt::kUnsigned32, 4, ro, 0, "Product code"},
    {0x1018, 3, dt::kUnsigned32, 4, ro, 0, "Revision number"},
    {0x1018, 4, dt::kUnsigned32, 4, ro, 0, "Serial number"},
    {0x1600, 0, dt::kUnsigned8, 1, pre, 0, "RxPDO mapping: entries"},
    {0x1600, 1, dt::kUnsigned32, 4, pre, 0, "RxPDO entry 1"},
    {0x1600, 2, dt::kUnsigned32, 4, pre, 0, "RxPDO entry 2"},
    {0x1600, 3, dt::kUnsigned32, 4, pre, 0, "RxPDO entry 3"},
    {0x1600, 4, dt::kUnsigned32, 4, pre, 0, "RxPDO entry 4"},
    {0x1600, 5, dt::kUnsigned32, 4, pre, 0, "RxPDO entry 5"},
    {0x1A00, 0, dt::kUnsigned8, 1, pre, 0, "TxPDO mapping: entries"},
    {0x1A00, 1, dt::kUnsigned32, 4, pre, 0, "TxPDO entry 1"},
    {0x1A00, 2, dt::kUnsigned32, 4, pre, 0, "TxPDO entry 2"},
    {0x1A00, 3, dt::kUnsigned32, 4, pre, 0, "TxPDO entry 3"},
    {0x1A00, 4, dt::kUnsigned32, 4, pre, 0, "TxPDO entry 4"},
    {0x1A00, 5, dt::kUnsigned32, 4, pre, 0, "TxPDO entry 5"},
    {0x1A00, 6, dt::kUnsigned32, 4, pre, 0, "TxPDO entry 6"},
    {0x1C00, 0, dt::kUnsigned8, 1, ro, 0, "SyncManager types: count"},
    {0x1C00, 1, dt::kUnsigned8, 1, ro, 0, "SM0 type"},
    {0x1C00, 2, dt::kUnsigned8, 1, ro, 0, "SM1 type"},
    {0x1C00, 3, dt::kUnsigned8, 1, ro, 0, "SM2 type"},
    {0x1C00, 4, dt::kUnsigned8, 1, ro, 0, "SM3 type"},
    {0x1C12, 0, dt::kUnsigned8, 1, pre, 0, "RxPDO assignment: count"},
    {0x1C12, 1, dt::kUnsigned16, 2, pre, 0, "RxPDO assigned"},
    {0x1C13, 0, dt::kUnsigned8, 1, pre, 0, "TxPDO assignment: count"},
    {0x1C13, 1, dt::kUnsigned16, 2, pre, 0, "TxPDO assigned"},
    {0x2002, 0, dt::kInteger16, 2, ro, 0, "Drive temperature"},
    {0x2010, 0, dt::kVisibleString, kApplicationLabelCapacity, rw, 0, "Application label"},
    {0x603F, 0, dt::kUnsigned16, 2, ro, 0, "Error code"},
    {0x6040, 0, dt::kUnsigned16, 2, rw, 0, "Controlword"},
    {0x6041, 0, dt::kUnsigned16, 2, ro, 0, "Statusword"},
    {0x6060, 0, dt::kInteger8, 1, rw, 0, "Modes of operation"},
    {0x6061, 0, dt::kInteger8, 1, ro, 0, "Modes of operation display"},
    {0x6064, 0, dt::kInteger32, 4, ro, 0, "Position actual value"},
    {0x6065, 0, dt::kUnsigned32, 4, rw, 0, "Following error window"},
    {0x6066, 0, dt::kUnsigned16, 2, rw, 0, "Following error time out"},
    {0x606C, 0, dt::kInteger32, 4, ro, 0, "Velocity actual value"},
    {0x6071, 0, dt::kInteger16, 2, rw, 0, "Target torque"},
    {0x6072, 0, dt::kUnsigned16, 2, rw, 0, "Max torque"},
    {0x6076, 0, dt::kUnsigned32, 4, ro, 0, "Motor rated torque"},
    {0x6077, 0, dt::kInteger16, 2, ro, 0, "Torque actual value"},
    {0x607A, 0, dt::kInteger32, 4, rw, 0, "Target position"},
    {0x607D, 0, dt::kUnsigned8, 1, ro, 0, "Software position limit: count"},
    {0x607D, 1, dt::kInteger32, 4, rw, 0, "Min position limit"},
    {0x607D, 2, dt::kInteger32, 4, rw, 0, "Max position limit"},
    {0x607F, 0, dt::kUnsigned32, 4, rw, 0, "Max profile velocity"},
    {0x6080, 0, dt::kUnsigned32, 4, ro, 0, "Max motor speed"},
    {0x60FF, 0, dt::kInteger32, 4, rw, 0, "Target velocity"},
    {0x6502, 0, dt::kUnsigned32, 4, ro, 0, "Supported drive modes"},
  }};
  (void)assign_offsets(t);
  return t;
}();
// clang-format on

constexpr std::size_t storage_bytes() noexcept {
  std::size_t n = 0;
  // cppcheck-suppress useStlAlgorithm ; std::accumulate is not constexpr in C++17
  for (const ObjectEntry& e : kTable) n += e.size;
  return n;
}
static_assert(storage_bytes() <= kJointDriveObjectBytes, "object dictionary storage too small");
static_assert(entries_are_sorted(kTable), "object table must be sorted by index and subindex");

// The objects the drive reads or writes on every cycle, resolved here once (see
// drivers/sim/coe/object_dictionary.hpp, "Speed").
constexpr const ObjectEntry& kErrorRegister = object_entry(kTable, 0x1001, 0);
constexpr const ObjectEntry& kErrorCode = object_entry(kTable, 0x603F, 0);
constexpr const ObjectEntry& kTemperature = object_entry(kTable, 0x2002, 0);
constexpr const ObjectEntry& kControlword = object_entry(kTable, 0x6040, 0);
constexpr const ObjectEntry& kStatusword = object_entry(kTable, 0x6041, 0);
constexpr const ObjectEntry& kModesOfOperation = object_entry(kTable, 0x6060, 0);
constexpr const ObjectEntry& kModesDisplay = object_entry(kTable, 0x6061, 0);
constexpr const ObjectEntry& kPositionActual = object_entry(kTable, 0x6064, 0);
constexpr const ObjectEntry& kFollowingErrorWindow = object_entry(kTable, 0x6065, 0);
constexpr const ObjectEntry& kFollowingErrorTimeout = object_entry(kTable, 0x6066, 0);
constexpr const ObjectEntry& kVelocityActual = object_entry(kTable, 0x606C, 0);
constexpr const ObjectEntry& kTargetTorque = object_entry(kTable, 0x6071, 0);
constexpr const ObjectEntry& kMaxTorque = object_entry(kTable, 0x6072, 0);
constexpr const ObjectEntry& kTorqueActual = object_entry(kTable, 0x6077, 0);
constexpr const ObjectEntry& kTargetPosition = object_entry(kTable, 0x607A, 0);
constexpr const ObjectEntry& kPositionMin = object_entry(kTable, 0x607D, 1);
constexpr const ObjectEntry& kPositionMax = object_entry(kTable, 0x607D, 2);
constexpr const ObjectEntry& kMaxProfileVelocity = object_entry(kTable, 0x607F, 0);
constexpr const ObjectEntry& kTargetVelocity = object_entry(kTable, 0x60FF, 0);

std::uint32_t value_of(ConstByteSpan v) noexcept {
  std::uint32_t x = 0;
  for (std::size_t i = 0; i < v.size() && i < 4; ++i) x |= static_cast<std::uint32_t>(v[i]) << (8U * i);
  return x;
}

template <std::size_t N>
std::uint32_t check_mapping(const ObjectDictionary& od, const ObjectEntry& e, std::uint32_t value,
                            const std::array<PdoMappingEntry, N>& mapping) noexcept {
  if (e.subindex == 0) {
    if (value > N) return abort_code::kPdoLengthExceeded;
    // Only the whole fixed layout or none (while it is rewritten) fits the drive's process image.
    if (value != 0 && value != N) return abort_code::kParameterIncompatible;
    return 0;
  }
  if (od.get_u32(e.index, 0) != 0) return abort_code::kSubindex0MustBeZero;
  if (value != mapping[e.subindex - 1U].mapping_word()) return abort_code::kCannotBeMapped;
  return 0;
}

std::uint32_t check_assignment(const ObjectDictionary& od, const ObjectEntry& e, std::uint32_t value,
                               std::uint16_t pdo) noexcept {
  if (e.subindex == 0) return value > 1 ? abort_code::kValueTooHigh : 0;
  if (od.get_u32(e.index, 0) != 0) return abort_code::kSubindex0MustBeZero;
  return value == pdo ? 0 : abort_code::kValueRange;
}

// The drive's own value checks (after existence, access, state and length).
std::uint32_t validate(const ObjectDictionary& od, const ObjectEntry& e, ConstByteSpan v) noexcept {
  const std::uint32_t value = value_of(v);
  switch (e.index) {
    case kJointRxPdoIndex: return check_mapping(od, e, value, kJointRxMapping);
    case kJointTxPdoIndex: return check_mapping(od, e, value, kJointTxMapping);
    case 0x1C12: return check_assignment(od, e, value, kJointRxPdoIndex);
    case 0x1C13: return check_assignment(od, e, value, kJointTxPdoIndex);
    case 0x6060: {
      const auto mode = static_cast<std::int8_t>(value);
      const bool ok = mode == 0 || mode == static_cast<std::int8_t>(ControlMode::cyclic_position) ||
                      mode == static_cast<std::int8_t>(ControlMode::cyclic_velocity) ||
                      mode == static_cast<std::int8_t>(ControlMode::cyclic_torque);
      return ok ? 0 : abort_code::kValueRange;
    }
    case 0x6072: return value > 1000 ? abort_code::kValueTooHigh : 0;
    case 0x607F: return value > od.get_u32(0x6080, 0) ? abort_code::kValueTooHigh : 0;
    case 0x607D: {
      const auto limit = static_cast<std::int32_t>(value);
      if (e.subindex == 1 && limit > od.get_i32(0x607D, 2)) return abort_code::kMaxBelowMin;
      if (e.subindex == 2 && limit < od.get_i32(0x607D, 1)) return abort_code::kMaxBelowMin;
      return 0;
    }
    default: return 0;
  }
}

std::uint32_t u32_of(std::int32_t v) noexcept { return static_cast<std::uint32_t>(v); }

}  // namespace

Span<const ObjectEntry> joint_drive_object_table() noexcept { return {kTable.data(), kTable.size()}; }

JointDriveObjects::JointDriveObjects(std::size_t joint, std::size_t position) noexcept
    : od_(Span<const ObjectEntry>(kTable.data(), kTable.size()), ByteSpan(storage_), &validate) {
  const JointInfo& info = kJoints[joint];
  od_.set(0x1000, 0, kDeviceTypeServoDrive);
  od_.set_string(0x1008, 0, kJointDriveIdentity.name);
  od_.set_string(0x100A, 0, kJointDriveFirmwareVersion);
  od_.set(0x1018, 0, 4);
  od_.set(0x1018, 1, kJointDriveIdentity.vendor_id);
  od_.set(0x1018, 2, kJointDriveIdentity.product_code);
  od_.set(0x1018, 3, kJointDriveIdentity.revision);
  od_.set(0x1018, 4, serial_number_of(position));
  od_.set(kJointRxPdoIndex, 0, kJointRxMapping.size());
  for (std::size_t i = 0; i < kJointRxMapping.size(); ++i) {
    od_.set(kJointRxPdoIndex, static_cast<std::uint8_t>(i + 1), kJointRxMapping[i].mapping_word());
  }
  od_.set(kJointTxPdoIndex, 0, kJointTxMapping.size());
  for (std::size_t i = 0; i < kJointTxMapping.size(); ++i) {
    od_.set(kJointTxPdoIndex, static_cast<std::uint8_t>(i + 1), kJointTxMapping[i].mapping_word());
  }
  od_.set(0x1C00, 0, 4);
  for (std::uint8_t sm = 0; sm < 4; ++sm) od_.set(0x1C00, static_cast<std::uint8_t>(sm + 1), sm + 1U);  // mbx out/in, outputs, inputs
  od_.set(0x1C12, 0, 1);
  od_.set(0x1C12, 1, kJointRxPdoIndex);
  od_.set(0x1C13, 0, 1);
  od_.set(0x1C13, 1, kJointTxPdoIndex);
  od_.set(0x6060, 0, static_cast<std::uint8_t>(info.default_mode));
  od_.set(0x6065, 0, static_cast<std::uint32_t>(drivers::rad_to_counts(0.5)));
  od_.set(0x6066, 0, 100);
  od_.set(0x6072, 0, 1000);
  od_.set(0x6076, 0, static_cast<std::uint32_t>(info.rated_torque_nm * 1000.0));
  od_.set(0x607D, 0, 2);
  if (info.continuous) {
    od_.set(0x607D, 1, u32_of(std::numeric_limits<std::int32_t>::min()));
    od_.set(0x607D, 2, u32_of(std::numeric_limits<std::int32_t>::max()));
  } else {
    od_.set(0x607D, 1, u32_of(drivers::rad_to_counts(info.limits.position_min_rad)));
    od_.set(0x607D, 2, u32_of(drivers::rad_to_counts(info.limits.position_max_rad)));
  }
  const auto max_speed = static_cast<std::uint32_t>(drivers::rad_to_counts(info.limits.velocity_max_rad_s));
  od_.set(0x607F, 0, max_speed);
  od_.set(0x6080, 0, max_speed);
  od_.set(0x6502, 0, kSupportedModesCsxBits);
}

void JointDriveObjects::store_outputs(const JointOutputs& o) noexcept {
  od_.set(kControlword, o.controlword);
  od_.set(kModesOfOperation, static_cast<std::uint8_t>(o.mode_of_operation));
  od_.set(kTargetPosition, u32_of(o.target_position));
  od_.set(kTargetVelocity, u32_of(o.target_velocity));
  od_.set(kTargetTorque, static_cast<std::uint16_t>(o.target_torque));
}

void JointDriveObjects::store_inputs(const JointInputs& i) noexcept {
  od_.set(kStatusword, i.statusword);
  od_.set(kModesDisplay, static_cast<std::uint8_t>(i.mode_display));
  od_.set(kPositionActual, u32_of(i.position_actual));
  od_.set(kVelocityActual, u32_of(i.velocity_actual));
  od_.set(kTorqueActual, static_cast<std::uint16_t>(i.torque_actual));
  od_.set(kErrorCode, i.error_code);
  // Error register (CiA 301): bit 0 generic error while a fault is present.
  od_.set(kErrorRegister, i.error_code != 0 ? 1U : 0U);
  // The power stage warms with the torque it gives: +0.1 degC per 2 per mille of rated torque.
  const bool over_temperature = i.error_code == 0x4210 || i.error_code == 0x4310;
  const int torque = i.torque_actual < 0 ? -static_cast<int>(i.torque_actual) : static_cast<int>(i.torque_actual);
  const int deci_c = over_temperature ? kDriveTemperatureFaultDeciC : kDriveTemperatureIdleDeciC + torque / 2;
  od_.set(kTemperature, static_cast<std::uint16_t>(deci_c));
}

JointOutputs JointDriveObjects::outputs() const noexcept {
  JointOutputs o;
  o.controlword = static_cast<std::uint16_t>(od_.get_u32(kControlword));
  o.mode_of_operation = static_cast<std::int8_t>(od_.get_i32(kModesOfOperation));
  o.target_position = od_.get_i32(kTargetPosition);
  o.target_velocity = od_.get_i32(kTargetVelocity);
  o.target_torque = static_cast<std::int16_t>(od_.get_i32(kTargetTorque));
  return o;
}

DriveSettings JointDriveObjects::settings() const noexcept {
  DriveSettings s;
  s.position_min_counts = od_.get_i32(kPositionMin);
  s.position_max_counts = od_.get_i32(kPositionMax);
  s.max_velocity_counts_s = od_.get_u32(kMaxProfileVelocity);
  s.max_torque_per_mille = static_cast<std::uint16_t>(od_.get_u32(kMaxTorque));
  s.following_error_window_counts = od_.get_u32(kFollowingErrorWindow);
  s.following_error_timeout_ms = static_cast<std::uint16_t>(od_.get_u32(kFollowingErrorTimeout));
  return s;
}

bool JointDriveObjects::mapping_is_complete() const noexcept {
  return od_.get_u32(0x1C12, 0) == 1 && od_.get_u32(0x1C12, 1) == kJointRxPdoIndex && od_.get_u32(0x1C13, 0) == 1 &&
         od_.get_u32(0x1C13, 1) == kJointTxPdoIndex && od_.get_u32(kJointRxPdoIndex, 0) == kJointRxMapping.size() &&
         od_.get_u32(kJointTxPdoIndex, 0) == kJointTxMapping.size();
}

void JointDriveObjects::corrupt_mapping(PdoMappingFault fault) noexcept {
  if (fault == PdoMappingFault::half_written) {
    // Every RxPDO entry written, the entry count never: SAFE-OP is refused with 0x0025.
    for (std::size_t i = 0; i < kJointRxMapping.size(); ++i) {
      od_.set(kJointRxPdoIndex, static_cast<std::uint8_t>(i + 1), kJointRxMapping[i].mapping_word());
    }
    od_.set(kJointRxPdoIndex, 0, 0);
    return;
  }
  // A factory default of another drive: controlword and target position in, statusword and
  // position actual out (a CSP-only mapping), the other entries cleared.
  constexpr std::array<std::uint32_t, 2> kForeignRx{0x60400010U, 0x607A0020U};
  constexpr std::array<std::uint32_t, 2> kForeignTx{0x60410010U, 0x60640020U};
  for (std::size_t i = 0; i < kJointRxMapping.size(); ++i) {
    od_.set(kJointRxPdoIndex, static_cast<std::uint8_t>(i + 1), i < kForeignRx.size() ? kForeignRx[i] : 0U);
  }
  for (std::size_t i = 0; i < kJointTxMapping.size(); ++i) {
    od_.set(kJointTxPdoIndex, static_cast<std::uint8_t>(i + 1), i < kForeignTx.size() ? kForeignTx[i] : 0U);
  }
  od_.set(kJointRxPdoIndex, 0, kForeignRx.size());
  od_.set(kJointTxPdoIndex, 0, kForeignTx.size());
}

}  // namespace rescue::drivers
