// Registers and bit fields of the EtherCAT slave controller (ESC) that the master and the
// simulator use, in one place (ETG.1000.4 / Beckhoff ESC datasheet section II). Addresses are
// byte offsets in the ESC's physical memory; multi-byte registers are little-endian.
#pragma once

#include <cstdint>

namespace rescue::ecat::reg {

// --- ESC information (read-only) -------------------------------------------------------------
constexpr std::uint16_t kType = 0x0000;            // u8
constexpr std::uint16_t kRevision = 0x0001;        // u8
constexpr std::uint16_t kBuild = 0x0002;           // u16
constexpr std::uint16_t kFmmusSupported = 0x0004;  // u8
constexpr std::uint16_t kSyncManagersSupported = 0x0005;  // u8
constexpr std::uint16_t kRamSize = 0x0006;         // u8, KiB of process RAM
constexpr std::uint16_t kPortDescriptor = 0x0007;  // u8, 2 bits per port: 00 n/a, 01 n/c, 10 EBUS, 11 MII
constexpr std::uint16_t kEscFeatures = 0x0008;     // u16

// --- Station address --------------------------------------------------------------------------
constexpr std::uint16_t kStationAddress = 0x0010;  // u16, configured station address (written by master)
constexpr std::uint16_t kStationAlias = 0x0012;    // u16, from SII word 4

// --- Data link layer -------------------------------------------------------------------------
constexpr std::uint16_t kDlControl = 0x0100;  // u32
constexpr std::uint16_t kDlStatus = 0x0110;   // u16
// DL control: loop setting of port n in bits [8+2n, 9+2n]: 0 auto, 1 auto-close, 2 open, 3 closed.
constexpr std::uint32_t dl_control_loop_shift(unsigned port) noexcept { return 8U + 2U * port; }
// DL status bits.
constexpr std::uint16_t kDlStatusPdiOperational = 0x0001;
constexpr std::uint16_t kDlStatusPdiWatchdog = 0x0002;
constexpr std::uint16_t dl_status_link(unsigned port) noexcept { return static_cast<std::uint16_t>(0x0010U << port); }
constexpr std::uint16_t dl_status_loop_closed(unsigned port) noexcept { return static_cast<std::uint16_t>(0x0100U << (2U * port)); }
constexpr std::uint16_t dl_status_communication(unsigned port) noexcept { return static_cast<std::uint16_t>(0x0200U << (2U * port)); }

// --- Application layer -----------------------------------------------------------------------
constexpr std::uint16_t kAlControl = 0x0120;     // u16: requested state [3:0], error acknowledge [4]
constexpr std::uint16_t kAlStatus = 0x0130;      // u16: current state [3:0], error indication [4]
constexpr std::uint16_t kAlStatusCode = 0x0134;  // u16
constexpr std::uint16_t kAlStateMask = 0x000F;
constexpr std::uint16_t kAlErrorBit = 0x0010;    // AL status: error; AL control: acknowledge

enum class AlState : std::uint8_t { none = 0, init = 1, pre_op = 2, boot = 3, safe_op = 4, op = 8 };
const char* to_string(AlState state) noexcept;

// AL status codes (ETG.1000.6 table 11), the ones this product raises or explains.
namespace al_code {
constexpr std::uint16_t kNoError = 0x0000;
constexpr std::uint16_t kUnspecified = 0x0001;
constexpr std::uint16_t kInvalidStateChange = 0x0011;
constexpr std::uint16_t kUnknownState = 0x0012;
constexpr std::uint16_t kBootstrapNotSupported = 0x0013;
constexpr std::uint16_t kInvalidMailboxConfig = 0x0016;
constexpr std::uint16_t kInvalidSyncManagerConfig = 0x0017;
constexpr std::uint16_t kNoValidInputs = 0x0018;
constexpr std::uint16_t kNoValidOutputs = 0x0019;
constexpr std::uint16_t kSynchronizationError = 0x001A;
constexpr std::uint16_t kSyncManagerWatchdog = 0x001B;
constexpr std::uint16_t kInvalidSyncManagerTypes = 0x001C;
constexpr std::uint16_t kInvalidOutputConfig = 0x001D;
constexpr std::uint16_t kInvalidInputConfig = 0x001E;
constexpr std::uint16_t kInvalidWatchdogConfig = 0x001F;
constexpr std::uint16_t kInvalidInputMapping = 0x0024;
constexpr std::uint16_t kInvalidOutputMapping = 0x0025;
constexpr std::uint16_t kInconsistentSettings = 0x0026;
constexpr std::uint16_t kFreeRunNotSupported = 0x0027;
constexpr std::uint16_t kSyncNotSupported = 0x0028;
constexpr std::uint16_t kInvalidDcSyncConfig = 0x0030;
constexpr std::uint16_t kDcPllError = 0x0032;
constexpr std::uint16_t kDcSyncIoError = 0x0033;
constexpr std::uint16_t kDcSyncTimeout = 0x0034;
constexpr std::uint16_t kDcInvalidSyncCycleTime = 0x0035;
constexpr std::uint16_t kMailboxCoe = 0x0043;
constexpr std::uint16_t kEepromNoAccess = 0x0050;
constexpr std::uint16_t kEepromError = 0x0051;
constexpr std::uint16_t kVendorSpecificFirst = 0x8000;  // 0x8000..0xFFFF: the vendor's own codes
}  // namespace al_code
// Human explanation of an AL status code ("invalid requested state change"); a code of the vendor
// range (0x8000 and up) is called vendor-specific, never unknown.
const char* explain_al_status_code(std::uint16_t code) noexcept;

// --- Event registers ---------------------------------------------------------------------------
constexpr std::uint16_t kEcatEventMask = 0x0200;     // u16
constexpr std::uint16_t kAlEventMask = 0x0204;       // u32
constexpr std::uint16_t kEcatEventRequest = 0x0210;  // u16
constexpr std::uint16_t kAlEventRequest = 0x0220;    // u32

// --- Error counters ------------------------------------------------------------------------------
constexpr std::uint16_t kRxErrorCounter = 0x0300;     // 4 x (u8 invalid frame, u8 RX error)
constexpr std::uint16_t kForwardedRxErrorCounter = 0x0308;  // 4 x u8
constexpr std::uint16_t kEpuErrorCounter = 0x030C;    // u8: ECAT processing unit error
constexpr std::uint16_t kPdiErrorCounter = 0x030D;    // u8
constexpr std::uint16_t kLostLinkCounter = 0x0310;    // 4 x u8
constexpr std::uint16_t kErrorCountersLength = 0x14;  // 0x0300..0x0313

// --- Watchdogs ------------------------------------------------------------------------------------
constexpr std::uint16_t kWatchdogDivider = 0x0400;       // u16
constexpr std::uint16_t kWatchdogTimePdi = 0x0410;       // u16
constexpr std::uint16_t kWatchdogTimeProcessData = 0x0420;  // u16
constexpr std::uint16_t kWatchdogStatusProcessData = 0x0440;  // u16

// --- SII EEPROM interface (0x0500-0x050F) ----------------------------------------------------
constexpr std::uint16_t kSiiConfig = 0x0500;    // u8: EEPROM access assigned to PDI [0]
constexpr std::uint16_t kSiiPdiAccess = 0x0501; // u8
constexpr std::uint16_t kSiiControl = 0x0502;   // u16 control/status
constexpr std::uint16_t kSiiAddress = 0x0504;   // u32 word address
constexpr std::uint16_t kSiiData = 0x0508;      // 4 or 8 bytes
constexpr std::uint16_t kSiiWriteEnable = 0x0001;
constexpr std::uint16_t kSiiRead8Bytes = 0x0040;      // status: reads return 8 bytes (else 4)
constexpr std::uint16_t kSiiTwoAddressBytes = 0x0080; // status: EEPROM > 16 kbit
constexpr std::uint16_t kSiiCommandMask = 0x0700;
constexpr std::uint16_t kSiiCommandRead = 0x0100;
constexpr std::uint16_t kSiiCommandWrite = 0x0200;
constexpr std::uint16_t kSiiCommandReload = 0x0400;
constexpr std::uint16_t kSiiChecksumError = 0x0800;
constexpr std::uint16_t kSiiDeviceInfoError = 0x1000;
constexpr std::uint16_t kSiiCommandError = 0x2000;
constexpr std::uint16_t kSiiWriteError = 0x4000;
constexpr std::uint16_t kSiiBusy = 0x8000;

// --- FMMUs (16 bytes each from 0x0600) ---------------------------------------------------------
constexpr std::uint16_t kFmmuBase = 0x0600;
constexpr std::uint16_t kFmmuSize = 16;
constexpr std::uint16_t fmmu(unsigned n) noexcept { return static_cast<std::uint16_t>(kFmmuBase + kFmmuSize * n); }
// Offsets inside one FMMU entry.
constexpr std::uint16_t kFmmuLogicalStart = 0;    // u32
constexpr std::uint16_t kFmmuLength = 4;          // u16 bytes
constexpr std::uint16_t kFmmuLogicalStartBit = 6; // u8
constexpr std::uint16_t kFmmuLogicalStopBit = 7;  // u8
constexpr std::uint16_t kFmmuPhysicalStart = 8;   // u16
constexpr std::uint16_t kFmmuPhysicalStartBit = 10;  // u8
constexpr std::uint16_t kFmmuType = 11;           // u8: 1 read (slave->master), 2 write (master->slave)
constexpr std::uint16_t kFmmuActivate = 12;       // u8: bit 0
constexpr std::uint8_t kFmmuTypeRead = 0x01;
constexpr std::uint8_t kFmmuTypeWrite = 0x02;

// --- SyncManagers (8 bytes each from 0x0800) ---------------------------------------------------
constexpr std::uint16_t kSyncManagerBase = 0x0800;
constexpr std::uint16_t kSyncManagerSize = 8;
constexpr std::uint16_t sync_manager(unsigned n) noexcept {
  return static_cast<std::uint16_t>(kSyncManagerBase + kSyncManagerSize * n);
}
constexpr std::uint16_t kSmPhysicalStart = 0;  // u16
constexpr std::uint16_t kSmLength = 2;         // u16
constexpr std::uint16_t kSmControl = 4;        // u8: mode [1:0] (0 buffered, 2 mailbox), direction [3:2] (0 read by master, 1 written by master)
constexpr std::uint16_t kSmStatus = 5;         // u8: mailbox full [3]
constexpr std::uint16_t kSmActivate = 6;       // u8: enable [0], repeat [1]
constexpr std::uint16_t kSmPdiControl = 7;     // u8: deactivate [0], repeat ack [1]
constexpr std::uint8_t kSmModeBuffered = 0x00;
constexpr std::uint8_t kSmModeMailbox = 0x02;
constexpr std::uint8_t kSmDirectionMasterReads = 0x00;
constexpr std::uint8_t kSmDirectionMasterWrites = 0x04;
constexpr std::uint8_t kSmStatusMailboxFull = 0x08;
constexpr std::uint8_t kSmEnable = 0x01;
constexpr std::uint8_t kSmRepeat = 0x02;

// --- Distributed clocks --------------------------------------------------------------------------
constexpr std::uint16_t kDcReceiveTimePort0 = 0x0900;  // u32 each, port n at 0x0900 + 4n; write latches
constexpr std::uint16_t dc_receive_time_port(unsigned port) noexcept {
  return static_cast<std::uint16_t>(kDcReceiveTimePort0 + 4U * port);
}
constexpr std::uint16_t kDcSystemTime = 0x0910;           // u64 (u32 access allowed); ARMW/FRMW target
constexpr std::uint16_t kDcReceiveTimeEpu = 0x0918;       // u64, local time of the port 0 latch
constexpr std::uint16_t kDcSystemTimeOffset = 0x0920;     // u64
constexpr std::uint16_t kDcSystemTimeDelay = 0x0928;      // u32
constexpr std::uint16_t kDcSystemTimeDifference = 0x092C; // u32: [30:0] |diff|, [31] 1 = local < received
constexpr std::uint16_t kDcSpeedCounterStart = 0x0930;    // u16
constexpr std::uint16_t kDcSpeedCounterDiff = 0x0932;     // u16
constexpr std::uint16_t kDcTimeDiffFilterDepth = 0x0934;  // u8
constexpr std::uint16_t kDcSpeedCounterFilterDepth = 0x0935;  // u8
constexpr std::uint16_t kDcCyclicUnitControl = 0x0980;    // u8
constexpr std::uint16_t kDcActivation = 0x0981;           // u8: cyclic operation [0], SYNC0 [1], SYNC1 [2]
constexpr std::uint16_t kDcSyncPulseLength = 0x0982;      // u16, units of 10 ns
constexpr std::uint16_t kDcActivationStatus = 0x0984;     // u8
constexpr std::uint16_t kDcSync0Status = 0x098E;          // u8
constexpr std::uint16_t kDcSync1Status = 0x098F;          // u8
constexpr std::uint16_t kDcStartTime = 0x0990;            // u64: start time of cyclic operation / next SYNC0
constexpr std::uint16_t kDcNextSync1 = 0x0998;            // u64
constexpr std::uint16_t kDcSync0CycleTime = 0x09A0;       // u32 ns
constexpr std::uint16_t kDcSync1CycleTime = 0x09A4;       // u32 ns
constexpr std::uint8_t kDcActivateCyclic = 0x01;
constexpr std::uint8_t kDcActivateSync0 = 0x02;
constexpr std::uint8_t kDcActivateSync1 = 0x04;
// SystemTimeDifference sign bit: local copy of system time smaller than received system time.
constexpr std::uint32_t kDcDiffLocalSmaller = 0x80000000U;

// --- Process data RAM ---------------------------------------------------------------------------
constexpr std::uint16_t kProcessRamStart = 0x1000;

}  // namespace rescue::ecat::reg

namespace rescue::ecat::sii {
// SII (EEPROM) word addresses (ETG.1000.6 table 16 / ETG.2010).
constexpr std::uint16_t kPdiControl = 0x0000;
constexpr std::uint16_t kPdiConfig = 0x0001;
constexpr std::uint16_t kSyncImpulseLength = 0x0002;
constexpr std::uint16_t kPdiConfig2 = 0x0003;
constexpr std::uint16_t kStationAlias = 0x0004;
constexpr std::uint16_t kConfigChecksum = 0x0007;  // CRC-8 over words 0..6 (poly 0x07, init 0xFF)
constexpr std::uint16_t kVendorId = 0x0008;        // u32
constexpr std::uint16_t kProductCode = 0x000A;     // u32
constexpr std::uint16_t kRevision = 0x000C;        // u32
constexpr std::uint16_t kSerial = 0x000E;          // u32
// Words 0x0010..0x0013 are reserved (delays); the mailboxes follow. Checked against real images
// (tests/ecat/sii/test_sii_word_map_matches_real_images.cpp).
constexpr std::uint16_t kBootRxMailboxOffset = 0x0014;
constexpr std::uint16_t kBootRxMailboxSize = 0x0015;
constexpr std::uint16_t kBootTxMailboxOffset = 0x0016;
constexpr std::uint16_t kBootTxMailboxSize = 0x0017;
constexpr std::uint16_t kStdRxMailboxOffset = 0x0018;
constexpr std::uint16_t kStdRxMailboxSize = 0x0019;
constexpr std::uint16_t kStdTxMailboxOffset = 0x001A;
constexpr std::uint16_t kStdTxMailboxSize = 0x001B;
constexpr std::uint16_t kMailboxProtocols = 0x001C;
constexpr std::uint16_t kEepromSize = 0x003E;  // (size in kbit) - 1
constexpr std::uint16_t kVersion = 0x003F;
constexpr std::uint16_t kFirstCategory = 0x0040;

constexpr std::uint16_t kMailboxAoE = 0x0001;
constexpr std::uint16_t kMailboxEoE = 0x0002;
constexpr std::uint16_t kMailboxCoE = 0x0004;
constexpr std::uint16_t kMailboxFoE = 0x0008;
constexpr std::uint16_t kMailboxSoE = 0x0010;
constexpr std::uint16_t kMailboxVoE = 0x0020;

// Category types.
constexpr std::uint16_t kCategoryNop = 0;
constexpr std::uint16_t kCategoryStrings = 10;
constexpr std::uint16_t kCategoryDataTypes = 20;
constexpr std::uint16_t kCategoryGeneral = 30;
constexpr std::uint16_t kCategoryFmmu = 40;
constexpr std::uint16_t kCategorySyncManager = 41;
constexpr std::uint16_t kCategoryTxPdo = 50;
constexpr std::uint16_t kCategoryRxPdo = 51;
constexpr std::uint16_t kCategoryDc = 60;
constexpr std::uint16_t kCategoryEnd = 0xFFFF;
}  // namespace rescue::ecat::sii
