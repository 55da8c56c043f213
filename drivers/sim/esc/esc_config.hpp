// What distinguishes one simulated EtherCAT slave controller (ESC) from another: the silicon it
// models (ESC information registers 0x0000-0x0009, number of FMMUs and SyncManagers, RAM, ports,
// DC), the EEPROM interface's behaviour, its forwarding delays and its crystal.
//
// Defaults model an ET1100-class ESC with MII ports (100BASE-TX PHYs), as both the robot's joint
// drives and its junction slaves carry. Timing figures are of the order of the ET1100 datasheet's
// (section III) and of what masters measure on real chains; docs/simulator.md lists them.
#pragma once

#include <cstdint>

#include "hal/time/clock.hpp"

namespace rescue::drivers {

constexpr unsigned kMaxEscPorts = 4;
constexpr unsigned kMaxFmmus = 16;
constexpr unsigned kMaxSyncManagers = 16;
constexpr std::uint32_t kMaxProcessRamBytes = 8 * 1024;

struct EscConfig {
  // ESC information (0x0000-0x0009), read-only for the master.
  std::uint8_t type{0x11};            // 0x11: ET1100
  std::uint8_t revision{0x00};
  std::uint16_t build{0x0003};
  std::uint8_t fmmu_count{8};         // <= kMaxFmmus
  std::uint8_t sync_manager_count{8}; // <= kMaxSyncManagers
  std::uint8_t ram_kib{8};            // process RAM from 0x1000, <= kMaxProcessRamBytes / 1024
  std::uint8_t port_count{2};         // ports 0..port_count-1 exist (MII); the others are "not implemented"
  // 0x0008: DC (bit 2), 64-bit DC (3), enhanced link detection MII (6), separate FCS error handling (7),
  // enhanced DC SYNC activation (8); LRW and xxRW supported (bits 9/10 clear). 0x01CC is what a real
  // ESC with MII ports reports.
  std::uint16_t features{0x01CC};
  bool dc_supported{true};            // DC registers 0x0900-0x09FF present

  // SII EEPROM interface: 8-byte reads (0x0502 bit 6) or 4-byte reads, and how long a command keeps
  // the busy bit set (a real I2C EEPROM read takes a few hundred microseconds).
  std::uint8_t sii_read_bytes{8};
  hal::Nanoseconds sii_read_busy_ns{500 * hal::kNsPerUs};
  hal::Nanoseconds sii_write_busy_ns{5 * hal::kNsPerMs};

  // Frame timing inside the ESC, start of frame to start of frame.
  hal::Nanoseconds processing_delay_ns{290};  // port 0 in -> EtherCAT processing unit -> next open port out
  hal::Nanoseconds forwarding_delay_ns{280};  // port n in (n != 0) -> next open port out, no processing

  // Local clock: crystal deviation and the local time at segment time 0 (power-up instants differ).
  double drift_ppm{0.0};
  std::uint64_t local_time_at_zero{0};
};

}  // namespace rescue::drivers
