#include "drivers/sim/esc/esc_memory.hpp"

#include <algorithm>

#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

constexpr std::uint8_t kR = esc_attr::kReadable;
constexpr std::uint8_t kRW = esc_attr::kReadable | esc_attr::kWritable;
constexpr std::uint8_t kRT = esc_attr::kReadable | esc_attr::kWritable | esc_attr::kWriteTrigger;

}  // namespace

void EscMemory::mark(std::uint32_t first, std::uint32_t count, std::uint8_t attributes) noexcept {
  for (std::uint32_t a = first; a < first + count && a < kEscRegisterSpace; ++a) attributes_[a] = attributes;
}

void EscMemory::reset(const EscConfig& config) noexcept {
  bytes_.fill(0);
  attributes_.fill(0);
  namespace reg = ecat::reg;
  // Register blocks of an ET1100-class ESC (datasheet section II). Reserved bytes inside a block
  // read as 0 and count; bytes of blocks the ESC lacks do not count at all.
  mark(0x0000, 0x000A, kR);                       // ESC information
  mark(reg::kStationAddress, 2, kRW);
  mark(reg::kStationAlias, 2, kR);                // loaded from SII word 4; the PDI may change it
  mark(0x0020, 2, kRW);                           // register write enable/protection (not enforced)
  mark(0x0030, 2, kRW);                           // ESC write enable/protection (not enforced)
  mark(0x0040, 2, kRW);                           // ESC reset ECAT (reset sequence not modelled)
  mark(reg::kDlControl, 4, kRT);
  mark(0x0108, 2, kRW);                           // physical read/write offset
  mark(reg::kDlStatus, 2, kR);
  mark(reg::kAlControl, 2, kRT);
  mark(reg::kAlStatus, 6, kR);                    // AL status, reserved, AL status code
  mark(0x0138, 2, kRW);                           // RUN/ERR LED override
  mark(0x0140, 2, kR);                            // PDI control, ESC configuration (from SII word 0)
  mark(0x014E, 6, kR);                            // PDI information, PDI configuration (from SII)
  mark(reg::kEcatEventMask, 2, kRW);
  mark(reg::kAlEventMask, 4, kR);
  mark(reg::kEcatEventRequest, 2, kR);
  mark(reg::kAlEventRequest, 4, kR);
  mark(reg::kRxErrorCounter, 0x14, kRT);          // RX, forwarded RX, EPU, PDI error counters, lost link counters: a write clears them
  mark(0x030E, 2, kR);                            // PDI error code
  mark(reg::kWatchdogDivider, 2, kRW);
  mark(reg::kWatchdogTimePdi, 2, kRW);
  mark(reg::kWatchdogTimeProcessData, 2, kRW);
  mark(reg::kWatchdogStatusProcessData, 2, kR);
  mark(0x0442, 2, kRT);                           // watchdog counters: a write clears them
  mark(reg::kSiiConfig, 1, kRW);
  mark(reg::kSiiPdiAccess, 1, kR);
  mark(reg::kSiiControl, 14, kRT);                // control/status, address, data: the SII logic decides
  for (unsigned n = 0; n < config.fmmu_count && n < kMaxFmmus; ++n) {
    mark(reg::fmmu(n), 13, kRW);
    mark(reg::fmmu(n) + 13U, 3, kR);
  }
  for (unsigned n = 0; n < config.sync_manager_count && n < kMaxSyncManagers; ++n) {
    const std::uint32_t sm = reg::sync_manager(n);
    mark(sm, 5, kRT);                             // start, length, control: write-protected while enabled
    mark(sm + reg::kSmStatus, 1, kR);
    mark(sm + reg::kSmActivate, 1, kRT);
    mark(sm + reg::kSmPdiControl, 1, kR);
  }
  if (config.dc_supported) {
    mark(reg::kDcReceiveTimePort0, 4, kRT);       // a write latches the receive times of all ports
    mark(reg::kDcReceiveTimePort0 + 4U, 12, kR);
    mark(reg::kDcSystemTime, 8, kRT);             // a write feeds the drift control loop
    mark(reg::kDcReceiveTimeEpu, 8, kR);
    mark(reg::kDcSystemTimeOffset, 8, kRW);
    mark(reg::kDcSystemTimeDelay, 4, kRW);
    mark(reg::kDcSystemTimeDifference, 4, kR);
    mark(reg::kDcSpeedCounterStart, 2, kRT);      // a write resets the control loop
    mark(reg::kDcSpeedCounterDiff, 2, kR);
    mark(reg::kDcTimeDiffFilterDepth, 2, kRW);
    mark(reg::kDcCyclicUnitControl, 1, kRW);
    mark(reg::kDcActivation, 1, kRT);
    mark(reg::kDcSyncPulseLength, 2, kR);
    mark(reg::kDcActivationStatus, 1, kR);
    mark(reg::kDcSync0Status, 2, kR);
    mark(reg::kDcStartTime, 8, kRT);
    mark(reg::kDcNextSync1, 8, kR);
    mark(reg::kDcSync0CycleTime, 8, kRW);
    mark(0x09A8, 2, kRW);                         // latch control
    mark(0x09AE, 2, kR);                          // latch status
    mark(0x09B0, 32, kR);                         // latch times
  }
  mark(0x0E00, 2, kR);                            // power-on values
  mark(0x0F80, 0x80, kRW);                        // user RAM
  ram_end_ = kEscRegisterSpace + std::min<std::uint32_t>(std::uint32_t{config.ram_kib} * 1024U, kMaxProcessRamBytes);
}

}  // namespace rescue::drivers
