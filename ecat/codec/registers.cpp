#include "ecat/codec/registers.hpp"

namespace rescue::ecat::reg {

const char* to_string(AlState state) noexcept {
  switch (state) {
    case AlState::none: return "NONE";
    case AlState::init: return "INIT";
    case AlState::pre_op: return "PRE-OP";
    case AlState::boot: return "BOOT";
    case AlState::safe_op: return "SAFE-OP";
    case AlState::op: return "OP";
  }
  return "INVALID";
}

const char* explain_al_status_code(std::uint16_t code) noexcept {
  switch (code) {
    case al_code::kNoError: return "no error";
    case al_code::kUnspecified: return "unspecified error";
    case al_code::kInvalidStateChange: return "invalid requested state change";
    case al_code::kUnknownState: return "unknown requested state";
    case al_code::kBootstrapNotSupported: return "bootstrap not supported";
    case al_code::kInvalidMailboxConfig: return "invalid mailbox configuration";
    case al_code::kInvalidSyncManagerConfig: return "invalid sync manager configuration";
    case al_code::kNoValidInputs: return "no valid inputs available";
    case al_code::kNoValidOutputs: return "no valid outputs";
    case al_code::kSynchronizationError: return "synchronization error";
    case al_code::kSyncManagerWatchdog: return "sync manager watchdog";
    case al_code::kInvalidSyncManagerTypes: return "invalid sync manager types";
    case al_code::kInvalidOutputConfig: return "invalid output configuration";
    case al_code::kInvalidInputConfig: return "invalid input configuration";
    case al_code::kInvalidWatchdogConfig: return "invalid watchdog configuration";
    case al_code::kInvalidInputMapping: return "invalid input mapping";
    case al_code::kInvalidOutputMapping: return "invalid output mapping";
    case al_code::kInconsistentSettings: return "inconsistent settings";
    case al_code::kFreeRunNotSupported: return "free run not supported";
    case al_code::kSyncNotSupported: return "synchronization not supported";
    case al_code::kInvalidDcSyncConfig: return "invalid DC SYNC configuration";
    case al_code::kDcPllError: return "DC PLL error";
    case al_code::kDcSyncIoError: return "DC sync IO error";
    case al_code::kDcSyncTimeout: return "DC sync timeout";
    case al_code::kDcInvalidSyncCycleTime: return "DC invalid sync cycle time";
    case al_code::kMailboxCoe: return "mailbox CoE error";
    case al_code::kEepromNoAccess: return "EEPROM no access";
    case al_code::kEepromError: return "EEPROM error";
    default:
      // ETG.1000.6 leaves 0x8000..0xFFFF to the device's vendor: its manual, not the standard, says
      // what it means; below that a code this list lacks is one the standard may define.
      return code >= al_code::kVendorSpecificFirst ? "vendor-specific AL status code (see the device's manual)"
                                                    : "AL status code not in this program's list (see ETG.1000.6)";
  }
}

}  // namespace rescue::ecat::reg
