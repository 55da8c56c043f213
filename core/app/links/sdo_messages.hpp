// ctl upload / ctl download (docs/operator.md, docs/protocol.md "SDO"): the operator's CoE SDO
// transfers to one joint's drive, as they travel on the wire (SdoPayload, SdoResultPayload) and
// between the socket handler and the EtherCAT handler (SdoLinkRequest, SdoLinkResult: one bounded
// queue each way in TaskLinks). The EtherCAT handler runs them on the master's cyclic mailbox
// channel, one step per period (core/app/tasks/sdo_relay.hpp); nothing here allocates.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace rescue::app::protocol {

enum class MessageType : std::uint8_t;

constexpr std::size_t kSdoDataSize = 256;  // the longest value of one transfer (ecat::kMaxSdoData)

// Whom a transfer addresses: a joint's drive (joint), or a slave by its position (slave), which
// reaches the junctions too (ctl upload SLAVE).
enum class SdoTarget : std::uint8_t { joint = 0, slave = 1 };
constexpr std::uint8_t kSdoTargetLast = 1;

// sdo_upload (size 0, data zero) and sdo_download (size 1..kSdoDataSize bytes of data, the value
// little-endian as the object holds it). target joint: `joint` names it, slave 0; target slave:
// `slave` is its position, joint 0.
struct SdoPayload {
  std::uint8_t joint{0};
  std::uint8_t subindex{0};
  std::uint16_t index{0};
  SdoTarget target{SdoTarget::joint};
  std::uint8_t slave{0};
  std::uint16_t size{0};
  std::array<std::uint8_t, kSdoDataSize> data{};
};

// How an SDO transfer ended (sdo_result's status).
enum class SdoStatus : std::uint8_t {
  ok = 0,
  aborted = 1,          // the drive answered with an SDO abort (abort_code, named by ctl)
  timeout = 2,          // the drive did not answer within the mailbox's response time
  busy = 3,             // another transfer is in flight (ctl's or the master's own): nothing was sent; try again
  mapped_object = 4,    // download refused: the object is in the drive's RxPDO/TxPDO (the cyclic image owns it)
  pdo_configuration = 5,// download refused: PDO mapping/assignment while the slave is in SAFE-OP/OP (al_state)
  unreachable = 6,      // the joint's drive is lost or out of the exchange: nothing was sent
  mailbox_error = 7,    // the drive answered with a mailbox error reply (mailbox_error)
  bad_response = 8,     // an answer the master cannot use (toggle, sizes that disagree)
  too_long = 9,         // the value is longer than kSdoDataSize bytes
  no_answer = 10,       // the EtherCAT handler did not answer in time (socket handler's own limit)
  no_mailbox = 11,      // the slave has no CoE mailbox
};
constexpr std::uint8_t kSdoStatusLast = 11;

constexpr const char* to_string(SdoStatus s) noexcept {
  switch (s) {
    case SdoStatus::ok: return "ok";
    case SdoStatus::aborted: return "aborted";
    case SdoStatus::timeout: return "timeout";
    case SdoStatus::busy: return "busy";
    case SdoStatus::mapped_object: return "mapped object";
    case SdoStatus::pdo_configuration: return "PDO configuration";
    case SdoStatus::unreachable: return "unreachable";
    case SdoStatus::mailbox_error: return "mailbox error";
    case SdoStatus::bad_response: return "bad response";
    case SdoStatus::too_long: return "too long";
    case SdoStatus::no_answer: return "no answer";
    case SdoStatus::no_mailbox: return "no mailbox";
  }
  return "?";
}

constexpr std::size_t kSdoTextSize = 64;
constexpr std::uint8_t kSdoSegmented = 0x01;  // flags: the value travelled in segments

struct SdoResultPayload {
  std::uint64_t request_sequence{0};
  MessageType request_type{};          // sdo_upload or sdo_download (sdo_info only between the tasks)
  std::uint8_t joint{0};               // the request's target, echoed (SdoPayload)
  std::uint8_t subindex{0};
  SdoStatus status{SdoStatus::ok};
  std::uint16_t index{0};
  SdoTarget target{SdoTarget::joint};
  std::uint8_t slave{0};
  std::uint16_t size{0};               // upload: bytes of the value in data
  std::uint16_t info_total{0};         // sdo_info between the tasks: the response's data bytes (not on the wire)
  std::uint32_t abort_code{0};         // aborted: the drive's SDO abort code
  std::uint16_t mailbox_error{0};      // mailbox_error: the reply's detail
  std::uint8_t al_state{0};            // the slave's AL state when judged (4 SAFE-OP, 8 OP, 0 unknown)
  std::uint8_t flags{0};               // kSdoSegmented
  std::uint32_t exchanges{0};          // cyclic frames the transfer took
  std::array<char, kSdoTextSize> text{};  // why, in words (NUL-padded)
  std::array<std::uint8_t, kSdoDataSize> data{};
};

// ctl sdos (docs/operator.md "Object dictionary"): one CoE SDO Information request (ETG.1000.6
// 5.6.3, ecat/mailbox/coe_information.hpp) to a slave, addressed as an SDO transfer. `index`: Get OD
// List's list type (1: all objects), or the object; `subindex`: Get Entry Description's entry;
// `offset`: the first byte of the response's data to answer with (a long OD list is read in windows
// of kSdoDataSize bytes).
enum class SdoInfoOp : std::uint8_t { od_list = 1, object_description = 3, entry_description = 5 };
struct SdoInfoPayload {
  SdoTarget target{SdoTarget::joint};
  std::uint8_t joint{0};
  std::uint8_t slave{0};
  SdoInfoOp op{SdoInfoOp::od_list};
  std::uint16_t index{0};
  std::uint8_t subindex{0};
  std::uint16_t offset{0};
};

// sdo_info_result: the request echoed, how it ended (SdoStatus, as an SDO transfer: aborted carries
// the SDO Info Error's abort code; too_long: a response of more than 65535 bytes), `total` bytes of
// the whole response's data and `length` of them from the request's offset in data (the rest zero).
struct SdoInfoResultPayload {
  std::uint64_t request_sequence{0};
  SdoInfoPayload request{};
  SdoStatus status{SdoStatus::ok};
  std::uint32_t abort_code{0};
  std::uint16_t mailbox_error{0};
  std::uint16_t length{0};
  std::uint16_t total{0};
  std::uint32_t exchanges{0};
  std::array<char, kSdoTextSize> text{};
  std::array<std::uint8_t, kSdoDataSize> data{};
};

}  // namespace rescue::app::protocol

namespace rescue::app {

// socket handler -> EtherCAT handler (TaskLinks::sdo_requests). An sdo_info travels as an upload
// with `info_op` set (its target, index and subindex in `sdo`) and `info_offset`.
struct SdoLinkRequest {
  std::uint32_t id{0};      // the socket handler's, echoed in the result
  bool download{false};
  protocol::SdoInfoOp info_op{};  // 0: an upload or download
  protocol::SdoPayload sdo{};
  std::uint16_t info_offset{0};
};

// EtherCAT handler -> socket handler (TaskLinks::sdo_results). result.request_sequence/type and
// text are the socket handler's to fill.
struct SdoLinkResult {
  std::uint32_t id{0};
  protocol::SdoResultPayload result{};
};

}  // namespace rescue::app
