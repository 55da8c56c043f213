#include "core/app/tasks/sdo_relay.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "drivers/joint/joint_drive_pdo.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/mailbox/coe.hpp"
#include "ecat/mailbox/mailbox_client.hpp"

namespace rescue::app {
namespace {

using protocol::SdoStatus;

constexpr auto kAlSafeOp = static_cast<std::uint8_t>(ecat::reg::AlState::safe_op);
constexpr auto kAlOp = static_cast<std::uint8_t>(ecat::reg::AlState::op);
static_assert(protocol::kSdoDataSize == ecat::kMaxSdoData, "the wire carries every value the mailbox moves");

template <std::size_t N>
bool mapped(const std::array<drivers::PdoMappingEntry, N>& mapping, std::uint16_t index, std::uint8_t subindex) noexcept {
  return std::any_of(mapping.begin(), mapping.end(),
                     [&](const drivers::PdoMappingEntry& e) { return e.index == index && e.subindex == subindex; });
}

SdoStatus status_of(ecat::SdoOutcome outcome) noexcept {
  switch (outcome) {
    case ecat::SdoOutcome::ok: return SdoStatus::ok;
    case ecat::SdoOutcome::aborted: return SdoStatus::aborted;
    case ecat::SdoOutcome::mailbox_error: return SdoStatus::mailbox_error;
    case ecat::SdoOutcome::timeout: return SdoStatus::timeout;
    case ecat::SdoOutcome::no_mailbox: return SdoStatus::no_mailbox;
    case ecat::SdoOutcome::bad_response: return SdoStatus::bad_response;
    case ecat::SdoOutcome::too_long: return SdoStatus::too_long;
  }
  return SdoStatus::bad_response;
}

// An SDO Information response's whole length (the window of it is in r.data): longer than the
// wire's 16 bits is too long, its window dropped.
void take_information_total(const ecat::SdoCompletion& done, protocol::SdoResultPayload& r) noexcept {
  if (done.info_total <= 0xFFFFU) {
    r.info_total = static_cast<std::uint16_t>(done.info_total);
    return;
  }
  r.status = SdoStatus::too_long;
  r.size = 0;
  r.data.fill(0);
}

// The socket handler's request is a record of the shared segment: a field it never writes is damage
// (a stray write, a bit flip), refused whole. It writes a download flag of 0 or 1, a target of its two
// kinds, an information opcode of the three (0 for a transfer) never with a download, and a size of
// 1..256 bytes for a download and 0 otherwise (ctl's decoder refuses every other value).
bool sdo_request_whole(const SdoLinkRequest& request) noexcept {
  unsigned char download = 0;
  std::memcpy(&download, &request.download, 1);
  const auto op = static_cast<std::uint8_t>(request.info_op);
  const bool op_known = op == 0 || op == static_cast<std::uint8_t>(protocol::SdoInfoOp::od_list) ||
                        op == static_cast<std::uint8_t>(protocol::SdoInfoOp::object_description) ||
                        op == static_cast<std::uint8_t>(protocol::SdoInfoOp::entry_description);
  const bool size_known = download == 1 ? request.sdo.size >= 1 && request.sdo.size <= protocol::kSdoDataSize
                                        : request.sdo.size == 0;
  return download <= 1 && static_cast<std::uint8_t>(request.sdo.target) <= protocol::kSdoTargetLast && op_known &&
         (op == 0 || download == 0) && size_known;
}

}  // namespace

SdoStatus judge_sdo_download(std::uint16_t index, std::uint8_t subindex, bool op_or_safe_op) noexcept {
  if (mapped(drivers::kJointRxMapping, index, subindex) || mapped(drivers::kJointTxMapping, index, subindex)) {
    return SdoStatus::mapped_object;
  }
  const bool pdo_mapping = (index >= 0x1600 && index <= 0x17FF) || (index >= 0x1A00 && index <= 0x1BFF);
  const bool pdo_assignment = index == 0x1C12 || index == 0x1C13;
  if ((pdo_mapping || pdo_assignment) && op_or_safe_op) return SdoStatus::pdo_configuration;
  return SdoStatus::ok;
}

void SdoRelay::answer(const SdoLinkResult& result) noexcept {
  // step() answers only with no answer waiting, so one slot is enough.
  if (!results_->try_send(result)) {
    waiting_ = result;  // the socket handler has not taken the earlier answers yet
    has_waiting_ = true;
  }
}

void SdoRelay::step(JointMask unreachable, bool op) noexcept {
  if (requests_ == nullptr || results_ == nullptr) return;
  if (has_waiting_) {
    if (!results_->try_send(waiting_)) return;  // nothing new taken while an answer waits: none lost
    has_waiting_ = false;
  }

  ecat::MailboxClient& mailbox = bus_.master().mailbox();
  ecat::SdoCompletion done;
  while (mailbox.pop_operator_completion(done)) {
    if (!in_flight_ || done.request.tag != tag_) continue;  // not the transfer in flight (never, but harmless)
    protocol::SdoResultPayload& r = current_.result;
    r.status = status_of(done.outcome);
    r.abort_code = done.abort_code;
    r.mailbox_error = done.mailbox_error;
    r.exchanges = done.exchanges;
    r.flags = done.segmented ? protocol::kSdoSegmented : 0;
    if (r.request_type != protocol::MessageType::sdo_download && done.outcome == ecat::SdoOutcome::ok) {
      r.size = done.size <= protocol::kSdoDataSize ? done.size : static_cast<std::uint16_t>(protocol::kSdoDataSize);
      std::memcpy(r.data.data(), done.data.data(), r.size);
    }
    if (r.request_type == protocol::MessageType::sdo_info) take_information_total(done, r);
    in_flight_ = false;
    answer(current_);
    if (has_waiting_) return;
  }

  SdoLinkRequest request;
  if (!requests_->try_receive(request)) return;
  if (!sdo_request_whole(request)) {
    ++damaged_requests_;  // nothing sent, no answer (its id is not trusted): the socket handler's limit answers
    return;
  }
  SdoLinkResult result;
  result.id = request.id;
  protocol::SdoResultPayload& r = result.result;
  const bool information = request.info_op != protocol::SdoInfoOp{};
  r.request_type = information        ? protocol::MessageType::sdo_info
                   : request.download ? protocol::MessageType::sdo_download
                                      : protocol::MessageType::sdo_upload;
  r.joint = request.sdo.joint;
  r.target = request.sdo.target;
  r.slave = request.sdo.slave;
  r.index = request.sdo.index;
  r.subindex = request.sdo.subindex;
  r.al_state = op ? kAlOp : kAlSafeOp;
  const bool by_slave = request.sdo.target == protocol::SdoTarget::slave;
  const std::size_t position = by_slave ? request.sdo.slave : slave_position_of_joint(request.sdo.joint);
  if (position >= kSlaveCount || (!by_slave && request.sdo.joint >= kJointCount)) {
    r.status = SdoStatus::unreachable;
    return answer(result);
  }
  // A drive is judged by its joint (out of service or lost: unreachable), a junction by the master.
  const std::uint8_t joint = kSlaves[position].joint;
  const bool lost = joint < kJointCount ? (unreachable & joint_bit(joint)) != 0
                                        : (bus_.master().monitor().lost() & ecat::slave_bit(position)) != 0;
  if (lost) {
    r.status = SdoStatus::unreachable;
    r.al_state = 0;
    return answer(result);
  }
  if (request.download && !information && joint < kJointCount) {
    r.status = judge_sdo_download(request.sdo.index, request.sdo.subindex, true);
    if (r.status != SdoStatus::ok) return answer(result);
  }
  if (in_flight_ || mailbox.free_slots() == 0) {
    r.status = SdoStatus::busy;
    return answer(result);
  }
  tag_ = ecat::MailboxClient::kOperatorTagBit | (++transfers_started_ & 0x3FFFFFFFU);
  const auto slave = static_cast<std::uint8_t>(position);
  const ecat::SdoRequest sdo =
      information ? ecat::sdo_information(slave, static_cast<std::uint8_t>(request.info_op), request.sdo.index,
                                          request.sdo.subindex, request.info_offset, tag_)
      : request.download
          ? ecat::sdo_download_bytes(slave, request.sdo.index, request.sdo.subindex,
                                     ConstByteSpan(request.sdo.data.data(), request.sdo.size), tag_)
          : ecat::sdo_upload(slave, request.sdo.index, request.sdo.subindex, tag_);
  if (!mailbox.submit(sdo)) {
    r.status = SdoStatus::busy;
    return answer(result);
  }
  current_ = result;
  in_flight_ = true;
}

void describe_sdo_result(protocol::SdoResultPayload& r) noexcept {
  char text[protocol::kSdoTextSize] = {};
  switch (r.status) {
    case SdoStatus::ok: (void)std::snprintf(text, sizeof text, "%s", r.flags != 0 ? "done (segmented)" : "done"); break;
    case SdoStatus::aborted: (void)std::snprintf(text, sizeof text, "%s", ecat::coe::explain_abort_code(r.abort_code)); break;
    case SdoStatus::timeout: (void)std::snprintf(text, sizeof text, "the drive did not answer in time"); break;
    case SdoStatus::busy:
      (void)std::snprintf(text, sizeof text, "another SDO transfer is in flight; try again");
      break;
    case SdoStatus::mapped_object:
      (void)std::snprintf(text, sizeof text, "0x%04X:%02X is in the %s: the cyclic image writes it", r.index,
                          r.subindex, mapped(drivers::kJointRxMapping, r.index, r.subindex) ? "RxPDO" : "TxPDO");
      break;
    case SdoStatus::pdo_configuration:
      (void)std::snprintf(text, sizeof text, "PDO %s is fixed while the slave is in %s",
                          (r.index == 0x1C12 || r.index == 0x1C13) ? "assignment" : "mapping",
                          r.al_state == kAlOp ? "OP" : "SAFE-OP");
      break;
    case SdoStatus::unreachable: (void)std::snprintf(text, sizeof text, "%s is lost or out of the exchange",
                                                     r.target == protocol::SdoTarget::slave ? "the slave" : "the joint"); break;
    case SdoStatus::mailbox_error: (void)std::snprintf(text, sizeof text, "mailbox error reply 0x%04X", r.mailbox_error); break;
    case SdoStatus::bad_response: (void)std::snprintf(text, sizeof text, "the drive's answer could not be used"); break;
    case SdoStatus::too_long:
      (void)std::snprintf(text, sizeof text, "%s", r.request_type == protocol::MessageType::sdo_info
                                                       ? "the SDO Information response is longer than 65535 bytes"
                                                       : "the value is longer than 256 bytes");
      break;
    case SdoStatus::no_answer: (void)std::snprintf(text, sizeof text, "the EtherCAT handler did not answer"); break;
    case SdoStatus::no_mailbox: (void)std::snprintf(text, sizeof text, "the slave has no CoE mailbox"); break;
  }
  r.text.fill('\0');
  std::memcpy(r.text.data(), text, std::strlen(text) < r.text.size() ? std::strlen(text) : r.text.size() - 1);
}

}  // namespace rescue::app
