// Comparing the network the master found with the one it expects (ecat/link/network_plan.hpp), and
// naming every difference: missing, extra, wrong device, wrong position, plus the softer ones
// (other revision, process data of another size, a slave held out of service that answers).
//
// Which found device is which planned slave:
//  - by its commissioned station alias (SII word 4) when both sides have one: robust against the
//    shift of auto-increment positions that every missing slave causes;
//  - otherwise by order: the n-th found device is the n-th planned slave; when fewer devices answer
//    than are planned, the slaves that may be absent (held out, and what is behind them) are skipped.
// A device whose vendor/product differ from its slot's is a wrong device. Devices matched by alias
// whose planned positions do not increase along the frame are in the wrong position (the longest
// increasing run is taken as right, the rest is reported).
//
// Degraded start: slaves held out of service (the owner's choice: e.g. their joints are recorded lost)
// and the slaves behind them may be absent: their absence is not a difference. Whether a slave answers
// and whether it is operated are two things: a held-out slave that answers is `present` (addressed,
// part of the topology and of the distributed clocks, so the slaves behind it are reachable) and
// reported as a warning, but never `operated` (no process data, stays in INIT). Bring-up never fails
// because of it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "core/containers/fixed_vector.hpp"
#include "ecat/link/network_plan.hpp"

namespace rescue::ecat {

constexpr std::size_t kMaxFoundSlaves = kMaxSlaves + 8;  // room to name a few extra devices
constexpr std::uint8_t kNoPosition = 0xFF;
// An SII string's length is one byte: 255 characters is the longest device name the SII reader keeps,
// and FoundSlave holds it whole (a real EK1100 calls itself in 34).
constexpr std::size_t kMaxDeviceNameLength = 255;
// One line of describe(): room for the longest device name whole and the words around it.
constexpr std::size_t kDifferenceLineCapacity = kMaxDeviceNameLength + 256;

struct FoundSlave {
  std::uint32_t vendor_id{0};
  std::uint32_t product_code{0};
  std::uint32_t revision{0};
  std::uint32_t serial_number{0};
  std::uint16_t station_alias{0};
  std::uint32_t output_bits{0};  // default RxPDO bits of SM2 from SII (0 when unknown)
  std::uint32_t input_bits{0};   // default TxPDO bits of SM3
  bool pdo_sizes_known{false};
  std::array<char, kMaxDeviceNameLength + 1> name{};  // SII device name whole, NUL terminated
};

enum class DifferenceKind : std::uint8_t {
  missing,            // planned, not found (and not known lost)
  extra,              // found, no planned slot for it
  wrong_device,       // found in a slot planned for another device type
  wrong_position,     // the right device, at another place in the frame
  duplicate_alias,    // two devices claim the same slot
  process_data_size,  // SII PDOs differ from the plan's sizes
  revision,           // another revision than planned (warning)
  known_lost_present, // held out of service, answers: in the topology, kept out of operation (warning)
};
const char* to_string(DifferenceKind kind) noexcept;
// Whether a difference refuses operation (warnings do not).
constexpr bool is_fatal(DifferenceKind kind) noexcept {
  return kind != DifferenceKind::revision && kind != DifferenceKind::known_lost_present;
}

struct NetworkDifference {
  DifferenceKind kind{DifferenceKind::missing};
  std::uint8_t planned{kNoPosition};  // planned position concerned, kNoPosition for none
  std::uint8_t found{kNoPosition};    // found position concerned, kNoPosition for none
};

struct NetworkMatch {
  // found position -> planned position it answers as (kNoPosition: not placed: extra, wrong device...).
  std::array<std::uint8_t, kMaxFoundSlaves> slot_of_found{};
  // planned position -> found position (kNoPosition: absent or not placed).
  std::array<std::uint8_t, kMaxSlaves> found_of_slot{};
  SlaveMask present{0};      // planned slaves found, right device, right place (held-out ones included)
  SlaveMask operated{0};     // present and not held out: will be run
  SlaveMask held_out{0};     // slaves the owner keeps out of service
  SlaveMask may_be_absent{0};  // held out and every slave behind them: absence is not a difference
  FixedVector<NetworkDifference, 2 * kMaxFoundSlaves> differences{};
  bool fatal{false};         // some difference refuses operation

  std::size_t count(DifferenceKind kind) const noexcept;
};

// `found` in frame order (auto-increment position 0 first). `held_out`: slaves kept out of service.
NetworkMatch match_network(const NetworkPlan& plan, Span<const FoundSlave> found, SlaveMask held_out) noexcept;

// One line describing `difference` ("missing: r_elbow (position 5, expected RM-JD402 0x00000a5c:0x4a443432)").
// Returns the number of characters written (truncated to `size` - 1).
std::size_t describe(const NetworkDifference& difference, const NetworkPlan& plan, Span<const FoundSlave> found,
                     char* out, std::size_t size) noexcept;

// Every difference, one per line, to `stream` (start-up report).
void print_differences(std::FILE* stream, const NetworkMatch& match, const NetworkPlan& plan,
                       Span<const FoundSlave> found) noexcept;

}  // namespace rescue::ecat
