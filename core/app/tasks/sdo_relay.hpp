// ctl upload / ctl download / ctl sdos on the EtherCAT handler's side (docs/operator.md "SDO"): the
// operator's CoE SDO transfers and SDO Information requests (SdoLinkRequest::info_op) run on the master's one cyclic mailbox channel (ecat/mailbox/mailbox_client.hpp,
// the same queue the master's online recovery uses for its start-up SDOs), one mailbox step per
// period inside the cyclic frame, so a transfer never waits inside a period and never costs one.
//
// Per period, step() (called by EthercatHandler::cycle after the exchange):
//   - takes at most one request from the socket handler's queue (TaskLinks::sdo_requests); a
//     damaged record (a field the socket handler never writes) is refused whole, counted and not
//     answered; otherwise it judges it: a joint out of the exchange or recorded lost -> unreachable; a download of an
//     object mapped into the drive's RxPDO/TxPDO -> mapped_object; a download of the PDO mapping
//     (0x1600-0x17FF, 0x1A00-0x1BFF) or assignment (0x1C12, 0x1C13) while the slave is in
//     SAFE-OP/OP -> pdo_configuration; a transfer already in flight, or no room in the mailbox
//     queue -> busy. Otherwise it is submitted with MailboxClient::kOperatorTagBit.
//   - takes the operator's completion when there is one and answers it (TaskLinks::sdo_results);
//     an answer the full result queue cannot take now waits for the next period (never lost).
// No heap, no locks; bounded work (one request and one completion per period).
#pragma once

#include <cstdint>

#include "core/app/links/protocol_messages.hpp"
#include "core/app/links/sdo_messages.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/robot/robot.hpp"
#include "drivers/joint/joint_bus.hpp"

namespace rescue::app {

// Why a download would fight the cyclic image (SdoStatus::ok: it would not). `op_or_safe_op`: the
// slave is in SAFE-OP or OP (the PDO configuration is in use).
protocol::SdoStatus judge_sdo_download(std::uint16_t index, std::uint8_t subindex, bool op_or_safe_op) noexcept;

class SdoRelay {
 public:
  // `requests`, `results`: the ends of TaskLinks::sdo_requests / sdo_results (both null: step() does nothing).
  SdoRelay(drivers::JointBus& bus, MessageSource<SdoLinkRequest>* requests, MessageSink<SdoLinkResult>* results) noexcept
      : bus_(bus), requests_(requests), results_(results) {}

  // One period: `unreachable` the joints out of the exchange or recorded lost; `op` the master
  // is in OP (else the slaves in the exchange are in SAFE-OP).
  void step(JointMask unreachable, bool op) noexcept;

  bool in_flight() const noexcept { return in_flight_; }
  std::uint32_t transfers() const noexcept { return transfers_started_; }  // submitted to the mailbox
  // Requests refused as damaged records of the segment (a field the socket handler never writes: a
  // download flag, target, information opcode or size): nothing sent and nothing answered.
  std::uint32_t damaged_requests() const noexcept { return damaged_requests_; }

 private:
  void answer(const SdoLinkResult& result) noexcept;

  drivers::JointBus& bus_;
  MessageSource<SdoLinkRequest>* requests_;
  MessageSink<SdoLinkResult>* results_;
  SdoLinkResult current_{};   // the request in flight (its address), then its answer
  SdoLinkResult waiting_{};   // an answer the result queue had no room for
  bool in_flight_{false};
  bool has_waiting_{false};
  std::uint32_t tag_{0};
  std::uint32_t transfers_started_{0};
  std::uint32_t damaged_requests_{0};
};

// The reason of a result in words, for its text field (socket handler; not on a real-time path).
void describe_sdo_result(protocol::SdoResultPayload& result) noexcept;

}  // namespace rescue::app
