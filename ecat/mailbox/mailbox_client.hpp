// CoE SDO client over the slaves' standard mailboxes (SM0 master -> slave, SM1 slave -> master),
// as a non-blocking state machine: each exchange (a cyclic frame, or a frame of its own during
// bring-up) carries at most one step of one transfer, so the cycle never waits for a slave.
//
//   send   FPWR SM0 (the whole SM0 buffer: writing its last byte hands it to the slave);
//          working counter 0 = the slave has not read the previous message yet: again next time
//   wait   FPRD SM1 status (0x080D) + FPRD SM1 buffer; the buffer counts only when the status
//          said "full" and the read's working counter is 1 (reading empties the mailbox)
//   lost   a frame that did not come back was carried out by the ESCs all the same: after a lost
//          SM1 read the repeat request (SM1's repeat bit toggled once SM1 reads back enabled, the
//          slave's ack awaited: it puts its last message back), after a lost SM0 write the same
//          message again (same mailbox counter); an answer repeating the last one's counter is dropped
//   done   SDO response for the same index/subindex, an SDO abort (code), a mailbox error
//          reply, or the response timeout. Emergencies that arrive meanwhile are counted.
// Values of 1..4 bytes travel expedited; longer ones (up to kMaxSdoData) as a normal transfer,
// continued in segments when they do not fit one mailbox: an upload whose initiate response
// announces more than it carries asks for upload segments (toggle bit alternating) until the
// last; a download sends what fits SM0 with the initiate request and the rest in download
// segments, each step one send/wait pair like the initiate. The response timeout runs per step.
// One transfer per slave is in flight at a time (each slave's mailbox holds one message), the
// slaves side by side: an exchange carries a step of every busy slave that fits the frame (of at
// most `max_slaves` of them: the cyclic frame takes a few, bring-up's own frames all). Requests wait
// in one queue; each slave's are started in the order they were submitted.
// An SDO Information request (direction `information`, ctl sdos; ecat/mailbox/coe_information.hpp)
// is one send and then waits: a response of several fragments is collected fragment by fragment,
// each fragment one wait step (the slave posts the next when SM1 was read), the response timeout
// again per fragment; of the response's data the kMaxSdoData bytes from `info_skip` are kept.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/containers/ring_buffer.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/link/datagram_link.hpp"
#include "ecat/link/network_plan.hpp"
#include "ecat/mailbox/coe.hpp"

namespace rescue::ecat {

enum class SdoDirection : std::uint8_t { download, upload, information };

// The longest value one transfer carries (a visible string such as 0x100A firmware version).
constexpr std::size_t kMaxSdoData = 256;
enum class SdoOutcome : std::uint8_t {
  ok,
  aborted,       // the slave answered with an SDO abort (abort_code)
  mailbox_error, // the slave answered with a mailbox error reply (mailbox_error)
  timeout,       // no answer within the response timeout
  no_mailbox,    // the slave has no configured mailbox
  bad_response,  // an answer this client cannot use (wrong toggle, sizes that disagree)
  too_long,      // the value is longer than kMaxSdoData (the transfer is aborted towards the slave)
};
const char* to_string(SdoOutcome outcome) noexcept;

struct SdoRequest {
  std::uint8_t position{0};  // planned position of the slave
  SdoDirection direction{SdoDirection::upload};
  std::uint16_t index{0};
  std::uint8_t subindex{0};
  std::uint16_t size{0};     // download: bytes of `data` (1..kMaxSdoData)
  std::array<std::uint8_t, kMaxSdoData> data{};
  std::uint32_t tag{0};      // the caller's, returned with the completion
  // Upload of the whole object from `subindex` (0 or 1) in one transfer (SDO complete access,
  // ETG.1000.6 5.6.2): only to slaves whose SII announces it (sii::kCoeDetailSdoCompleteAccess).
  bool complete_access{false};
  // direction information: the SDO Information request (coe::info::kGet*Request), its `index` (Get
  // OD List: the list type) and `subindex`; the response's data bytes before `info_skip` are not
  // kept (a long OD list read in windows of kMaxSdoData bytes).
  std::uint8_t info_opcode{0};
  std::uint16_t info_skip{0};
};

struct SdoCompletion {
  SdoRequest request{};
  SdoOutcome outcome{SdoOutcome::ok};
  std::uint32_t abort_code{0};
  std::uint16_t mailbox_error{0};
  std::uint16_t size{0};                          // upload: bytes received
  std::array<std::uint8_t, kMaxSdoData> data{};   // upload: the value, little-endian
  bool segmented{false};                          // the value travelled in segments
  std::uint32_t exchanges{0};           // frames the transfer took
  std::uint32_t info_total{0};          // information: bytes of the whole response's data (size: those kept)
};

// Helpers building requests.
SdoRequest sdo_download(std::uint8_t position, std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                        std::uint8_t size, std::uint32_t tag = 0) noexcept;
// A download of any length (1..kMaxSdoData bytes; longer is cut to kMaxSdoData: check first).
SdoRequest sdo_download_bytes(std::uint8_t position, std::uint16_t index, std::uint8_t subindex, ConstByteSpan bytes,
                              std::uint32_t tag = 0) noexcept;
SdoRequest sdo_upload(std::uint8_t position, std::uint16_t index, std::uint8_t subindex, std::uint32_t tag = 0) noexcept;
SdoRequest sdo_information(std::uint8_t position, std::uint8_t opcode, std::uint16_t index, std::uint8_t subindex,
                           std::uint16_t skip, std::uint32_t tag = 0) noexcept;
std::uint32_t sdo_value(const SdoCompletion& completion) noexcept;  // upload data as a number

// What the client met on the wire (master figures; bench wcet, ctl).
struct MailboxStats {
  std::uint64_t timeouts{0};            // transfer steps that got no answer in time
  // A frame with this slave's SM1 read came not back (the read may have emptied the mailbox): the
  // master toggled SM1's repeat bit and the slave put its last message back (ETG.1000.4 mailbox
  // repeat request).
  std::uint64_t repeat_requests{0};
  // A frame with this slave's SM0 write came not back (the slave may have taken it): written again
  // with the same mailbox counter, which tells the slave it is a repeat.
  std::uint64_t rewrites{0};
  // Answers carrying the mailbox counter of the answer taken before: a repeat (of a rewritten
  // request, or put back on a repeat request that found nothing lost), dropped.
  std::uint64_t duplicates_dropped{0};
};

class MailboxClient {
 public:
  static constexpr std::size_t kQueueCapacity = 32;
  static constexpr std::size_t kMaxMailboxSize = 512;
  static constexpr std::size_t kMaxDatagrams = 2;  // per slave and exchange

  explicit MailboxClient(const NetworkPlan& plan) noexcept : plan_(plan) {}

  // The slave's standard mailbox (from SII); called by the bring-up.
  void configure(std::size_t position, std::uint16_t out_start, std::uint16_t out_size, std::uint16_t in_start,
                 std::uint16_t in_size) noexcept;
  bool has_mailbox(std::size_t position) const noexcept { return position < kMaxSlaves && boxes_[position].present; }

  // Queues a transfer; false when the queue is full. Requests to slaves without a mailbox
  // complete at once with no_mailbox.
  [[nodiscard]] bool submit(const SdoRequest& request) noexcept;
  [[nodiscard]] bool pop_completion(SdoCompletion& out) noexcept;
  // Transfers whose tag has kMasterTagBit set are the master's own (its recovery's start-up SDOs):
  // their completions go to a queue of their own, never to the owner's.
  static constexpr std::uint32_t kMasterTagBit = 0x80000000U;
  // Transfers whose tag has kOperatorTagBit set are the operator's (ctl upload/download through
  // the EtherCAT handler): their completions go to a third queue, popped by the handler alone.
  static constexpr std::uint32_t kOperatorTagBit = 0x40000000U;
  [[nodiscard]] bool pop_operator_completion(SdoCompletion& out) noexcept { return operator_done_.pop(out); }
  [[nodiscard]] bool pop_master_completion(SdoCompletion& out) noexcept { return master_done_.pop(out); }
  bool idle() const noexcept { return busy_ == 0 && queue_.empty(); }
  std::size_t free_slots() const noexcept { return kQueueCapacity - queue_.size(); }

  // One step: adds this exchange's datagrams (0 to kMaxDatagrams per slave, of at most `max_slaves`
  // busy slaves, taken in turn) to `frame` as far as they fit.
  std::size_t add_datagrams(FrameBuilder& frame, std::uint8_t index, hal::Nanoseconds now,
                            std::size_t max_slaves = kMaxSlaves) noexcept;
  // The k-th datagram added by add_datagrams() came back (call for each, in order) ...
  void on_datagram(std::size_t k, const DatagramView& datagram) noexcept;
  // ... then this, once per exchange (also when the frame did not come back).
  void end_exchange(hal::Nanoseconds now) noexcept;

  // Runs queued transfers to completion with frames of their own (bring-up, outside the cycle).
  Status run(DatagramLink& link, hal::Nanoseconds frame_timeout, hal::Nanoseconds overall_timeout) noexcept;

  void set_response_timeout(hal::Nanoseconds timeout) noexcept { response_timeout_ = timeout; }
  std::uint64_t emergencies() const noexcept { return emergencies_; }
  const MailboxStats& stats() const noexcept { return stats_; }

 private:
  // repeat: the frame with the SM1 read came not back; the master toggled SM1's repeat bit and
  // waits for the slave's acknowledgement before it polls SM1 again.
  enum class Phase : std::uint8_t { none, send, wait, repeat };
  enum class Step : std::uint8_t { initiate, upload_segment, download_segment, abort };
  struct Box {
    std::uint16_t out_start{0};
    std::uint16_t out_size{0};
    std::uint16_t in_start{0};
    std::uint16_t in_size{0};
    std::uint8_t counter{0};     // of the last message written to SM0
    std::uint8_t in_counter{0};  // of the last message taken from SM1 (0: none since configure)
    std::uint8_t repeat{0};      // the repeat bit the master last wrote to SM1's activate register
    bool present{false};
  };

  // One slave's transfer in flight.
  struct Channel {
    Phase phase{Phase::none};
    Step step{Step::initiate};
    SdoCompletion current{};
    hal::Nanoseconds deadline{0};
    std::size_t offset{0};      // bytes of the value moved so far (segmented transfers)
    std::uint32_t expected{0};  // upload: the complete size the slave announced; information: fragments left
    std::size_t chunk{0};       // download: bytes of the step in flight
    bool toggle{false};         // the next segment's toggle bit
    SdoOutcome abort_outcome{SdoOutcome::bad_response};  // what an abort step completes with
    std::uint32_t abort_code_out{0};                     // the code it sends
    std::uint8_t added{0};      // datagrams of this exchange
    // Exchanges with this slave's datagrams sent after the deadline that reached the slave and found
    // no answer: a transfer times out only after kLatePolls of them, so time the master itself was
    // not running (a loaded machine) never passes for a slave's silence. Polls whose frame was lost
    // or late count only a further response timeout after the deadline.
    std::uint8_t late_polls{0};
    bool sent_this_exchange{false};
    bool in_full{false};
    bool answered{false};        // this exchange's datagrams came back (the frame was not lost)
    bool repeat_acked{false};    // this exchange read the slave's acknowledgement of the repeat
    bool repeat_write{false};    // the next repeat step writes the repeat bit (else it reads SM1's registers)
    std::array<std::uint8_t, kMaxMailboxSize> message{};  // encoded request, SM0-sized
  };

  void start_transfers(hal::Nanoseconds now) noexcept;
  void start(Channel& c, hal::Nanoseconds now) noexcept;
  void complete(Channel& c, SdoOutcome outcome) noexcept;
  void deliver(const SdoCompletion& done) noexcept;  // to the owner's, the master's or the operator's queue
  void take_reply(Channel& c, ConstByteSpan bytes) noexcept;
  // What a frame lost with this slave's datagrams means for its step (end_exchange).
  void on_lost_exchange(Channel& c) noexcept;
  void on_repeat_answer(Channel& c, const DatagramView& datagram) noexcept;
  void take_segment(Channel& c, const coe::Sdo& sdo) noexcept;
  void take_information(Channel& c, ConstByteSpan coe_payload) noexcept;
  void abort_transfer(Channel& c, SdoOutcome outcome, std::uint32_t code) noexcept;
  // Encodes the next message of c's transfer into its buffer and arms its send.
  bool encode_step(Channel& c, Step step, hal::Nanoseconds now) noexcept;
  std::size_t download_room(const Channel& c, bool initiate) const noexcept;
  std::size_t add_channel_datagrams(Channel& c, FrameBuilder& frame, std::uint8_t index) noexcept;

  const NetworkPlan& plan_;
  // run(): the pause before polling again when an exchange found no answer and took no message.
  static constexpr hal::Nanoseconds kEmptyPollPause = 50 * hal::kNsPerUs;
  // Polls after the deadline before a transfer times out: the first may be the one a simulated
  // slave, which runs only when a frame passes, takes the request in.
  static constexpr std::uint8_t kLatePolls = 2;
  bool moved_{false};  // this exchange: a message taken by a slave or an answer found
  std::array<Box, kMaxSlaves> boxes_{};
  std::array<Channel, kMaxSlaves> channels_{};
  RingBuffer<SdoRequest, kQueueCapacity> queue_{};
  RingBuffer<SdoCompletion, kQueueCapacity> done_{};  // the oldest uncollected one goes when full
  RingBuffer<SdoCompletion, kQueueCapacity> master_done_{};
  RingBuffer<SdoCompletion, 4> operator_done_{};

  SlaveMask busy_{0};          // slaves with a transfer in flight
  // A request was queued or a slave became free since start_transfers() last looked: only then can
  // a queued request start (it does not pop and push the whole queue back every exchange).
  bool may_start_{false};
  std::size_t next_turn_{0};   // the slave whose step goes first in the next exchange
  // The datagrams of this exchange, in order: the slave each belongs to.
  std::array<std::uint8_t, kMaxSlaves * kMaxDatagrams> exchange_slave_{};
  std::size_t added_{0};
  hal::Nanoseconds now_{0};    // of the current exchange
  hal::Nanoseconds response_timeout_{100 * hal::kNsPerMs};
  std::uint64_t emergencies_{0};
  MailboxStats stats_{};
};

}  // namespace rescue::ecat
