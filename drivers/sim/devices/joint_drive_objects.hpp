// The joint drive's object dictionary: the objects of CiA 301 a master reads at start-up, the PDO
// assignment and mapping, and the CiA 402 objects the process image and the aperiodic joint
// settings use. Table (docs/devices.md lists it with defaults):
//
//   0x1000 device type ro | 0x1001 error register ro | 0x1008 device name ro | 0x100A software
//   (firmware) version ro, a string longer than one 128-byte mailbox (uploaded in segments) |
//   0x1018 identity ro
//   0x1600 RxPDO mapping, 0x1A00 TxPDO mapping, 0x1C12/0x1C13 PDO assignment: rw in PRE-OP only,
//          and only the fixed layout of drivers/joint/joint_drive_pdo.hpp (sub 0 may go to 0 and back,
//          as masters do when they download a mapping) | 0x1C00 SyncManager types ro
//   0x603F error code ro | 0x6040 controlword rw | 0x6041 statusword ro | 0x6060 modes of
//   operation rw | 0x6061 display ro | 0x6064 position actual ro | 0x6065 following error window
//   rw | 0x6066 following error timeout rw | 0x606C velocity actual ro | 0x6071 target torque rw |
//   0x6072 max torque rw | 0x6076 motor rated torque ro | 0x6077 torque actual ro | 0x607A target
//   position rw | 0x607D software position limit rw | 0x607F max profile velocity rw | 0x6080 max
//   motor speed ro | 0x60FF target velocity rw | 0x6502 supported drive modes ro
//   0x2002 drive temperature ro (INTEGER16, 0.1 degC: the power stage, warmed by the torque it
//   gives, 95.0 degC under an over-temperature fault) | 0x2010 application label rw (a visible
//   string of up to 160 bytes the integrator writes at commissioning; segmented downloads)
//
// Units: counts, counts/s, per mille of rated torque (0x6076, mNm), ms.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "drivers/sim/devices/cia402_drive.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"
#include "drivers/sim/coe/object_dictionary.hpp"
#include "drivers/sim/devices/slave_device.hpp"

namespace rescue::drivers {

constexpr std::uint32_t kDeviceTypeServoDrive = 0x00020192;  // CiA 402 profile, servo drive
constexpr std::uint32_t kSupportedModesCsxBits = 0x00000380;  // CSP (bit 7), CSV (8), CST (9)
constexpr std::size_t kDeviceNameCapacity = 24;

constexpr std::size_t kFirmwareVersionCapacity = 160;
constexpr std::size_t kApplicationLabelCapacity = 160;
// 0x100A: the drive's software version, as the simulated drives report it.
constexpr const char* kJointDriveFirmwareVersion =
    "RJD-48 joint drive firmware 3.2.1 (build 2026-02-11, git 5e1c0a9f; bootloader 1.4.0; FPGA 0x2107; "
    "encoder 2.0.3; motor table rev 7; CiA 402 CSP/CSV/CST)";
constexpr std::int16_t kDriveTemperatureIdleDeciC = 350;     // 35.0 degC at rest
constexpr std::int16_t kDriveTemperatureFaultDeciC = 950;    // over-temperature fault (0x4210, 0x4310)

constexpr std::size_t kJointDriveObjectCount = 54;
constexpr std::size_t kJointDriveObjectBytes = 640;
// The table (sorted by index and subindex, offsets assigned), for documentation and tests.
Span<const ObjectEntry> joint_drive_object_table() noexcept;

class JointDriveObjects {
 public:
  // The dictionary of the drive of `joint` built into slot `position` (identity, limits).
  JointDriveObjects(std::size_t joint, std::size_t position) noexcept;
  JointDriveObjects(const JointDriveObjects&) = delete;
  JointDriveObjects& operator=(const JointDriveObjects&) = delete;
  JointDriveObjects(JointDriveObjects&&) = delete;
  JointDriveObjects& operator=(JointDriveObjects&&) = delete;
  ~JointDriveObjects() = default;

  ObjectDictionary& od() noexcept { return od_; }
  const ObjectDictionary& od() const noexcept { return od_; }

  // Process data mirrored into the dictionary, so an SDO upload reads what the PDOs carry.
  void store_outputs(const JointOutputs& outputs) noexcept;
  void store_inputs(const JointInputs& inputs) noexcept;
  JointOutputs outputs() const noexcept;

  DriveSettings settings() const noexcept;
  // The PDO assignment and mapping are the fixed layout (checked on PRE-OP -> SAFE-OP).
  bool mapping_is_complete() const noexcept;
  // Fault injection: the mapping as another tool left it (written directly, past the checks).
  void corrupt_mapping(PdoMappingFault fault) noexcept;

 private:
  std::array<std::uint8_t, kJointDriveObjectBytes> storage_{};
  ObjectDictionary od_;
};

}  // namespace rescue::drivers
