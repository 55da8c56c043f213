// The socket handler task (design brief section 3, docs/protocol.md): the operator's UDP control port
// and the sensor port of the two other robot computers. Per wake-up it handles at most kBudget
// (config::kSocketDatagramsPerWakeup) datagrams (recvmmsg batches), whatever arrives: a flood costs it bounded work per period, and the
// real-time tasks never touch a socket. Every datagram is checked in this order, and the first check
// that fails is counted under its Rejection and the datagram dropped (no reply: an unauthenticated
// peer learns nothing):
//   size -> structure (parse_frame) -> tag (crypto_auth) -> robot id -> sender -> epoch -> type for
//   this port -> payload and ranges (decode_payload) -> replay window (sender table)
// so a malformed request takes no sender slot.
// get_epoch (any robot id, epoch 0) is answered right after the sender check, with the epoch and the
// robot id in the answer's header and the request's sequence echoed; it takes no sender slot.
// A sender the full sender table has no room for is counted (sender_table_full) and, on the
// control port, told so in a refusal reply: never a silent lockout. So is a sequence too far ahead
// of the robot's clock (counted out_of_range; protocol::kMaxSequenceLeadNs).
// Accepted queries (status, slaves, master, tasks) are answered here from what the tasks publish;
// SDO transfers (sdo_upload, sdo_download, and sdo_info, answered sdo_info_result) go to the
// EtherCAT handler's SDO queue, one in flight at
// a time (a second one is answered `busy` at once), and its result is sent back as sdo_result
// (no_answer when the handler says nothing within kSdoAnswerLimit);
// accepted commands go to the message parser's bounded queue, and its replies are sent back,
// authenticated, to the address the command came from. Sensor records are published in a seqlock.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

#include "core/app/config/firmware_config.hpp"
#include "core/app/links/control_messages.hpp"
#include "core/app/links/joint_messages.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/links/sdo_messages.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/operator_protocol/replay_window.hpp"
#include "core/app/tasks/relayed_request.hpp"
#include "core/concurrency/message_port.hpp"
#include "core/concurrency/seqlock.hpp"
#include "hal/net/udp_socket.hpp"
#include "hal/time/clock.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {

constexpr std::uint16_t kDefaultControlPort = 47010;
constexpr std::uint16_t kDefaultSensorPort = 47011;
constexpr std::uint32_t kRobotSenderId = 0;  // the robot signs its replies as sender 0; requests from 0 are refused

struct SocketHandlerOptions {
  const char* listen{"0.0.0.0"};
  std::uint16_t control_port{kDefaultControlPort};
  std::uint16_t sensor_port{kDefaultSensorPort};
};

struct SocketHandlerPorts {
  MessageSink<ControlRequest>* requests{nullptr};     // to the message parser
  MessageSource<ControlReply>* replies{nullptr};      // from the message parser
  Seqlock<SensorData>* sensors{nullptr};
  Seqlock<SocketCounters>* counters{nullptr};
  const Seqlock<RobotSample>* samples{nullptr};
  const Seqlock<RobotJointStatus>* joint_status{nullptr};
  const Seqlock<MasterStatus>* master{nullptr};
  const Seqlock<protocol::DiagPayload>* diag{nullptr};  // ctl diag: link-quality counters
  const std::array<Seqlock<TaskStat>, kTaskStatSlots>* tasks{nullptr};
  const std::array<std::atomic<std::uint64_t>, kDropCounters>* drops{nullptr};  // the queues' drop counters (ctl tasks)
  const std::array<TaskHealth, kRunHealthSlots>* health{nullptr};  // ctl tasks: each task's thread id, start, restarts
  const MotionLinks* motion{nullptr};                 // ctl status: which RC task drives which joint
  // The EtherCAT handler's heartbeat (TaskLinks::task_heartbeat_ns, the clock of step()'s `now`):
  // status, slaves and master answers say how old its figures are, stale past `stale_after`.
  const std::atomic<std::int64_t>* handler_heartbeat{nullptr};
  hal::Nanoseconds stale_after{config::kTaskSilentAfterNs};
  // ctl owner: the RC tasks' heartbeats (monotonic ns, 0: never), and how many tasks the run has.
  const std::array<std::atomic<std::int64_t>, protocol::kMaxRcTasks>* rc_heartbeat_ns{nullptr};
  std::size_t rc_tasks{0};
  const protocol::VersionPayload* version{nullptr};   // ctl version: what the robot runs
  MessageSink<SdoLinkRequest>* sdo_requests{nullptr};  // ctl upload/download, to the EtherCAT handler
  MessageSource<SdoLinkResult>* sdo_results{nullptr};  // and their results
  MessageSink<RegReadLinkRequest>* reg_requests{nullptr};  // ctl reg_read, to the EtherCAT handler
  MessageSource<RegReadLinkResult>* reg_results{nullptr};  // and its result
  MessageSink<StatesLinkRequest>* states_requests{nullptr};  // ctl states, to the EtherCAT handler
  MessageSource<StatesLinkResult>* states_results{nullptr};  // and its result
  MessageSink<RescanLinkRequest>* rescan_requests{nullptr};   // ctl rescan, to the EtherCAT handler
  MessageSource<RescanLinkResult>* rescan_results{nullptr};   // and its result
  const Seqlock<protocol::SlaveInfoTable>* slave_info{nullptr};  // ctl slaves -v: SII identity, AL status code
  const std::array<Seqlock<SiiImageRecord>, protocol::kMaxSlaves>* sii_images{nullptr};  // ctl sii_read
  DiagResetLink* diag_reset{nullptr};                 // ctl diag --reset: posted here, taken by the EtherCAT handler
};

// A slave's record of a slaves answer (its state now: in the exchange, lost, out of service, AL
// state, recovery) from the handler's and the joint manager's publications (nullptr: none read).
protocol::SlaveRecord slave_record_of(std::size_t position, const MasterStatus* master,
                                      const RobotJointStatus* status) noexcept;

class SocketHandler {
 public:
  static constexpr std::size_t kBatch = config::kSocketRecvBatch;            // datagrams per recvmmsg call
  static constexpr std::size_t kBudget = config::kSocketDatagramsPerWakeup;  // per wake-up, both ports together
  static constexpr std::size_t kRepliesPerStep = config::kSocketRepliesPerWakeup;
  static_assert(kBatch > 0 && kBudget > 0, "a wake-up handles at least one datagram");
  // How long an SDO transfer may take before it is answered no_answer (the mailbox's own response
  // timeout is 100 ms per step; a 256-byte value takes at most 4 steps).
  static constexpr hal::Nanoseconds kSdoAnswerLimit = 2 * hal::kNsPerSec;
  // How long a register read may take (the master tries its FPRD in at most 10 frames).
  static constexpr hal::Nanoseconds kRegAnswerLimit = 500 * hal::kNsPerMs;
  // How long a states request may take (the master gives up at 1.5 s: SlaveStateService::kDeadline).
  static constexpr hal::Nanoseconds kStatesAnswerLimit = 1800 * hal::kNsPerMs;
  // How long a rescan may take (the master ends one within 1000 frames: RescanService).
  static constexpr hal::Nanoseconds kRescanAnswerLimit = 1800 * hal::kNsPerMs;

  // `robot_id`: this robot's identity (run's robot_id): datagrams naming another are refused.
  SocketHandler(const SocketHandlerPorts& ports, const protocol::Key& key, protocol::ReplayWindow& window,
                hal::WallClock& wall, std::uint32_t robot_id = protocol::kDefaultRobotId) noexcept
      : ports_(ports), key_(key), window_(&window), wall_(&wall), robot_id_(robot_id) {}
  std::uint32_t robot_id() const noexcept { return robot_id_; }

  Status open(const SocketHandlerOptions& options) noexcept;
  std::uint16_t control_port() const noexcept { return control_.local_port(); }
  std::uint16_t sensor_port() const noexcept { return sensor_.local_port(); }

  // Waits at most `timeout_ms` for a datagram on either port.
  void wait(int timeout_ms) const noexcept;
  // One wake-up: at most kBudget datagrams, then the parser's replies.
  void step(hal::Nanoseconds now) noexcept;

  const SocketCounters& counters() const noexcept { return counters_; }
  // A restarted socket handler (a new process, docs/tasks.md) counts on from its predecessor's
  // counters, read from its port `counters`, instead of from zero (none published: from zero).
  void resume_counters() noexcept {
    SocketCounters published{};
    if (ports_.counters != nullptr && ports_.counters->try_read(published)) counters_ = published;
  }
  // The most datagrams handled in one wake-up so far (never above kBudget).
  std::size_t max_per_wakeup() const noexcept { return max_per_wakeup_; }
  // Records of the segment refused as damaged: SDO results with a status, target, request type or
  // size the EtherCAT handler never writes (the transfer is answered no_answer at its deadline), and
  // any answer built from the segment that ctl's decoder would refuse (not sent).
  std::uint64_t damaged_records() const noexcept { return damaged_records_; }

 private:
  void handle(const hal::UdpDatagram& d, bool control_port, hal::Nanoseconds now) noexcept;
  void reject(protocol::Rejection reason) noexcept;
  void answer_query(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  // socket_network_answers.cpp: ctl graph, ctl slaves -v, ctl diag --reset.
  void answer_graph(const hal::UdpDatagram& from) noexcept;
  void answer_slave_info(const hal::UdpDatagram& from) noexcept;
  void answer_sii(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  // Posts a diag_reset to the EtherCAT handler (TaskLinks::diag_reset); the reply follows when the
  // handler has applied it (finish_diag_resets, each wake-up), or a refusal after kDiagResetTimeout.
  void post_diag_reset(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  void finish_diag_resets() noexcept;
  void reply_to(const protocol::Header& request, protocol::Outcome outcome, protocol::RefusalReason reason,
                const char* text, std::uint32_t address, std::uint16_t port) noexcept;
  void refuse(const protocol::Header& request, protocol::RefusalReason reason, const char* text,
              const hal::UdpDatagram& from) noexcept;
  // Counts (and on the control port answers) a request the replay window did not accept (`code`).
  void refuse_by_window(Errc code, const protocol::Header& h, bool control_port, const hal::UdpDatagram& d) noexcept;
  void send(protocol::Message& message, std::uint32_t address, std::uint16_t port) noexcept;
  std::uint64_t next_sequence() noexcept;
  void forward_sdo(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  // An sdo_result, or for an sdo_info (result.request_type) its sdo_info_result echoing `info`.
  void answer_sdo(protocol::SdoResultPayload result, const protocol::SdoInfoPayload& info, std::uint64_t request_sequence,
                  std::uint32_t address, std::uint16_t port) noexcept;
  void collect_sdo_result() noexcept;
  // socket_register_reads.cpp: ctl reg_read, one in flight (a second is answered busy at once),
  // answered reg_result (no_answer when the EtherCAT handler says nothing within kRegAnswerLimit).
  void forward_register_read(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  void answer_register_read(protocol::RegResultPayload result, std::uint64_t request_sequence, std::uint32_t address,
                            std::uint16_t port) noexcept;
  void collect_register_read() noexcept;
  // socket_slave_states.cpp: ctl states, one in flight (a second is answered busy at once),
  // answered states_result (no_answer when the EtherCAT handler says nothing within kStatesAnswerLimit).
  void forward_states(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  void answer_states(protocol::StatesResultPayload result, std::uint64_t request_sequence, std::uint32_t address,
                     std::uint16_t port) noexcept;
  void collect_states() noexcept;
  // socket_rescans.cpp: ctl rescan, the same way (no_answer past kRescanAnswerLimit).
  void forward_rescan(const protocol::Message& request, const hal::UdpDatagram& from) noexcept;
  void answer_rescan(const protocol::RescanResultPayload& result, protocol::RescanStatus status,
                     std::uint64_t request_sequence, std::uint32_t address, std::uint16_t port) noexcept;
  void collect_rescan() noexcept;
  protocol::FiguresAge handler_figures_age() const noexcept;

  SocketHandlerPorts ports_;
  protocol::Key key_;
  protocol::ReplayWindow* window_;
  hal::WallClock* wall_;
  std::uint32_t robot_id_;
  hal::UdpSocket control_;
  hal::UdpSocket sensor_;
  std::array<hal::UdpDatagram, kBatch> batch_{};
  SocketCounters counters_{};
  SiiImageRecord sii_scratch_{};  // ctl sii_read: the slave's published image (1 KiB: not on the stack)
  SensorData sensor_data_{};
  std::uint64_t last_sequence_{0};
  std::uint64_t damaged_records_{0};
  std::size_t max_per_wakeup_{0};
  hal::Nanoseconds now_{0};  // the current wake-up's
  // The SDO transfer in flight (one at a time).
  struct SdoInFlight {
    bool active{false};
    std::uint32_t id{0};
    std::uint64_t request_sequence{0};
    protocol::MessageType type{protocol::MessageType::sdo_upload};
    protocol::SdoPayload sdo{};
    protocol::SdoInfoPayload info{};  // sdo_info: the request, echoed in its answer
    std::uint32_t address{0};
    std::uint16_t port{0};
    hal::Nanoseconds deadline{0};
  };
  SdoInFlight sdo_{};
  std::uint32_t sdo_ids_{0};
  // The register read in flight (one at a time).
  struct RegInFlight {
    bool active{false};
    std::uint32_t id{0};
    std::uint64_t request_sequence{0};
    protocol::RegReadPayload read{};
    std::uint32_t address{0};
    std::uint16_t port{0};
    hal::Nanoseconds deadline{0};
  };
  RegInFlight reg_{};
  std::uint32_t reg_ids_{0};
  // The states request and the rescan in flight (one of each at a time), and the results' buffers
  // (a rescan's is 0.9 KiB: a member, not on the stack of every step).
  RelayedRequest<StatesLinkRequest, StatesLinkResult> states_{};
  protocol::StatesPayload states_request_{};
  StatesLinkResult states_result_{};
  RelayedRequest<RescanLinkRequest, RescanLinkResult> rescan_{};
  RescanLinkResult rescan_result_{};
  // diag_reset requests waiting for the EtherCAT handler (a few operators at once; more: busy).
  struct PendingReset {
    bool active{false};
    std::uint64_t generation{0};
    protocol::Header request{};
    std::uint32_t address{0};
    std::uint16_t port{0};
    hal::Nanoseconds posted{0};
  };
  static constexpr std::size_t kPendingResets = 4;
  static constexpr hal::Nanoseconds kDiagResetTimeout = 500 * hal::kNsPerMs;
  std::array<PendingReset, kPendingResets> pending_resets_{};
};

}  // namespace rescue::app
