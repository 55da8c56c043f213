// ctl rescan (docs/operator.md "Rescan", docs/protocol.md "Rescan"): the segment identified again
// and compared with the plan, as it travels on the wire (the rescan request has no fields;
// RescanResultPayload) and between the socket handler and the EtherCAT handler (RescanLinkRequest,
// RescanLinkResult: one bounded queue each way in TaskLinks, rescan_requests / rescan_results). The
// EtherCAT handler hands it to its master (ecat/master/rescan_service.hpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue::app::protocol {

constexpr std::size_t kRescanDevices = 31;                        // ecat::kMaxFoundSlaves (checked in the relay)
constexpr std::size_t kRescanDifferences = 2 * kRescanDevices;    // NetworkMatch::differences' capacity
constexpr std::uint8_t kNoPlace = 0xFF;                           // no planned / found position

// How a rescan ended (rescan_result's status).
enum class RescanStatus : std::uint8_t {
  ok = 0,           // every device identified and compared with the plan
  incomplete = 1,   // a device could not be identified: its identity unknown, no comparison
  recovering = 2,   // the master's online recovery identifies a slave: given up (try again)
  busy = 3,         // another rescan is under way: try again
  not_cycling = 4,  // the master is not cycling in OP
  no_answer = 5,    // the EtherCAT handler did not answer in time (the socket handler's own limit)
};
constexpr std::uint8_t kRescanStatusLast = 5;

constexpr const char* to_string(RescanStatus s) noexcept {
  switch (s) {
    case RescanStatus::ok: return "ok";
    case RescanStatus::incomplete: return "incomplete";
    case RescanStatus::recovering: return "recovering";
    case RescanStatus::busy: return "busy";
    case RescanStatus::not_cycling: return "not cycling";
    case RescanStatus::no_answer: return "no answer";
  }
  return "?";
}

// A difference from the plan (ecat::DifferenceKind, in its order).
enum class RescanDifference : std::uint8_t {
  missing = 0,
  extra = 1,
  wrong_device = 2,
  wrong_position = 3,
  duplicate_alias = 4,
  process_data_size = 5,
  revision = 6,
  known_lost_present = 7,
};
constexpr std::uint8_t kRescanDifferenceLast = 7;

// One device on the wire, by auto-increment position.
struct RescanDeviceRecord {
  std::uint32_t vendor_id{0};
  std::uint32_t product_code{0};
  std::uint32_t revision{0};
  std::uint32_t serial_number{0};
  std::uint16_t station_alias{0};
  std::uint8_t slot{kNoPlace};   // the planned position it answers as (kNoPlace: none)
  std::uint8_t identified{0};    // 1: its SII was read (else the numbers are 0)
};

struct RescanDifferenceRecord {
  RescanDifference kind{RescanDifference::missing};
  std::uint8_t planned{kNoPlace};
  std::uint8_t found{kNoPlace};
};

// rescan_result: the status, the devices the count found (counted: the BRD's working counter) and
// read (devices), their records, and the differences from the plan (status ok only).
struct RescanResultPayload {
  std::uint64_t request_sequence{0};
  RescanStatus status{RescanStatus::ok};
  std::uint8_t counted{0};
  std::uint8_t devices{0};
  std::uint8_t differences{0};
  std::uint16_t frames{0};
  std::array<RescanDeviceRecord, kRescanDevices> records{};
  std::array<RescanDifferenceRecord, kRescanDifferences> found_differences{};
};

// rescan: no fields.
struct RescanPayload {};

}  // namespace rescue::app::protocol

namespace rescue::app {

// socket handler -> EtherCAT handler (TaskLinks::rescan_requests).
struct RescanLinkRequest {
  std::uint32_t id{0};  // the socket handler's, echoed in the result
};

// EtherCAT handler -> socket handler (TaskLinks::rescan_results); request_sequence is the socket handler's.
struct RescanLinkResult {
  std::uint32_t id{0};
  protocol::RescanResultPayload result{};
};

}  // namespace rescue::app
