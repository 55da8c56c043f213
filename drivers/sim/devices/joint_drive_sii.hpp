// The joint drive's SII (EEPROM) image and the ESC memory layout it announces, as a real CoE
// servo drive carries it (compare ../shared/vectors/sii/akd.bin):
//
//   header     identity kJointDriveIdentity (drivers/joint/device_identity.hpp) with the slot's serial
//              number and commissioned station alias; standard mailbox 0x1000/0x1080, 128 bytes
//              each; protocols CoE; no bootstrap mailbox; 2 KiB EEPROM
//   Strings    order/name, group, PDO and entry names, DC mode names
//   General    group "Drives", CoE details SDO + PDO assign + PDO config, one DS402 channel,
//              ports 0 and 1 MII
//   FMMU       outputs, inputs, SyncManager status
//   SyncManager SM0 mailbox out, SM1 mailbox in, SM2 outputs (13 bytes), SM3 inputs (15 bytes)
//   TxPDO      0x1A00 on SM3, RxPDO 0x1600 on SM2: the entries of drivers/joint/joint_drive_pdo.hpp
//   DC         "DC-Synchron" (AssignActivate 0x0300: cyclic unit + SYNC0) and "SM-Synchron" (0)
//
// docs/devices.md lists the bytes.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"

namespace rescue::drivers {

constexpr std::size_t kSiiImageBytes = 2048;  // 16 KiBit EEPROM, like the real images
using SiiImage = std::array<std::uint8_t, kSiiImageBytes>;

// ESC memory the drive's SyncManagers use (process RAM starts at 0x1000).
constexpr std::uint16_t kJointMailboxOutStart = 0x1000;  // SM0: master -> drive
constexpr std::uint16_t kJointMailboxInStart = 0x1080;   // SM1: drive -> master
constexpr std::uint16_t kJointMailboxSize = 128;
constexpr std::uint16_t kJointOutputsStart = 0x1100;     // SM2
constexpr std::uint16_t kJointInputsStart = 0x1180;      // SM3

// SyncManager control bytes (register 0x0804): mode [1:0] (0 buffered, 2 mailbox), direction
// [3:2] (0 master reads, 1 master writes), AL event interrupt [5], watchdog trigger [6].
constexpr std::uint8_t kSmControlMailboxOut = 0x26;
constexpr std::uint8_t kSmControlMailboxIn = 0x22;
constexpr std::uint8_t kSmControlOutputs = 0x64;
constexpr std::uint8_t kSmControlInputs = 0x20;

constexpr std::uint16_t kDcAssignActivateSync0 = 0x0300;

// The image of the joint drive built into slot `position` of kSlaves. Fails only if the content
// outgrew the EEPROM (a programming error caught by the tests).
Result<SiiImage> build_joint_drive_sii(std::size_t position) noexcept;

}  // namespace rescue::drivers
