#include "core/app/tasks/socket_handler.hpp"

#include <poll.h>

#include <algorithm>
#include <limits>

#include "core/app/links/heartbeat.hpp"
#include "core/app/operator_protocol/protocol_auth.hpp"
#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/sdo_relay.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "ecat/master/master.hpp"

static_assert(rescue::app::protocol::kRecoveryStates == rescue::ecat::kRecoveryStateCount,
              "the operator protocol carries every recovery state");

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using protocol::Rejection;


// The answer to an SDO transfer that ends here, without the EtherCAT handler's result.
protocol::SdoResultPayload sdo_refusal(MessageType type, const protocol::SdoPayload& sdo, protocol::SdoStatus status) noexcept {
  protocol::SdoResultPayload r;
  r.request_type = type;
  r.joint = sdo.joint;
  r.target = sdo.target;
  r.slave = sdo.slave;
  r.index = sdo.index;
  r.subindex = sdo.subindex;
  r.status = status;
  return r;
}

// sdo_info travels to the EtherCAT handler as an SDO transfer to the same target.
protocol::SdoPayload sdo_of(const protocol::SdoInfoPayload& info) noexcept {
  protocol::SdoPayload sdo;
  sdo.target = info.target;
  sdo.joint = info.joint;
  sdo.slave = info.slave;
  sdo.index = info.index;
  sdo.subindex = info.subindex;
  return sdo;
}

// The wire's sdo_info_result of the handler's result: the window only when it is done, never past
// the response's end.
protocol::SdoInfoResultPayload info_result_of(const protocol::SdoResultPayload& r,
                                              const protocol::SdoInfoPayload& info) noexcept {
  protocol::SdoInfoResultPayload out;
  out.request = info;
  out.status = r.status;
  out.abort_code = r.abort_code;
  out.mailbox_error = r.mailbox_error;
  out.exchanges = r.exchanges;
  out.text = r.text;
  if (r.status != protocol::SdoStatus::ok) return out;
  out.total = r.info_total;
  const std::size_t total = r.info_total;
  const std::size_t room = total > info.offset ? total - info.offset : 0;
  out.length = static_cast<std::uint16_t>(std::min<std::size_t>({r.size, room, protocol::kSdoDataSize}));
  std::copy_n(r.data.begin(), out.length, out.data.begin());
  return out;
}


// The EtherCAT handler's SDO result is a record of the shared segment: a status, target or request
// type it never writes, or a size beyond the record's data, is damage (a stray write, a bit flip).
bool sdo_result_whole(const protocol::SdoResultPayload& r) noexcept {
  const bool type = r.request_type == MessageType::sdo_upload || r.request_type == MessageType::sdo_download ||
                    r.request_type == MessageType::sdo_info;
  return type && static_cast<std::uint8_t>(r.status) <= protocol::kSdoStatusLast &&
         static_cast<std::uint8_t>(r.target) <= protocol::kSdoTargetLast && r.size <= protocol::kSdoDataSize;
}

}  // namespace

Status SocketHandler::open(const SocketHandlerOptions& options) noexcept {
  RESCUE_TRY(control_.open(options.listen, options.control_port));
  RESCUE_TRY(sensor_.open(options.listen, options.sensor_port));
  return Status::success();
}

void SocketHandler::wait(int timeout_ms) const noexcept {
  std::array<pollfd, 2> fds{{{control_.fd(), POLLIN, 0}, {sensor_.fd(), POLLIN, 0}}};
  (void)::poll(fds.data(), fds.size(), timeout_ms);
}

std::uint64_t SocketHandler::next_sequence() noexcept {
  const std::int64_t wall = wall_->unix_time_ns();
  const std::uint64_t now = wall > 0 ? static_cast<std::uint64_t>(wall) : 0;
  last_sequence_ = now > last_sequence_ ? now : last_sequence_ + 1;
  return last_sequence_;
}

void SocketHandler::reject(Rejection reason) noexcept { ++counters_.rejected[static_cast<std::size_t>(reason)]; }

void SocketHandler::send(Message& message, std::uint32_t address, std::uint16_t port) noexcept {
  message.header.version = protocol::kVersion;
  message.header.sender = kRobotSenderId;
  message.header.robot = robot_id_;
  message.header.epoch = window_->epoch();
  message.header.sequence = next_sequence();
  std::array<std::uint8_t, protocol::kMaxDatagram> out{};
  const Result<std::size_t> size = protocol::seal(message, key_, ByteSpan(out));
  if (!size.ok()) return;
  // Every answer is built from records of the segment (replies, results, published figures): one
  // that ctl's decoder would refuse carries a value no writer writes (a damaged record) and is not
  // sent; the operator's ctl times out and says so.
  const ConstByteSpan sealed(out.data(), size.value());
  const Result<protocol::FrameView> frame = protocol::parse_frame(sealed);
  if (!frame.ok() || !protocol::decode_payload(frame.value().header, frame.value().payload).ok()) {
    ++damaged_records_;
    return;
  }
  if (control_.send_to(address, port, ConstByteSpan(out.data(), size.value())).ok()) ++counters_.replies_sent;
}

protocol::FiguresAge SocketHandler::handler_figures_age() const noexcept {
  protocol::FiguresAge age;
  if (ports_.handler_heartbeat == nullptr) return age;
  const std::int64_t beat = ports_.handler_heartbeat->load(std::memory_order_acquire);
  const HeartbeatAge judged = heartbeat_age(now_, beat);
  if (judged.kind == HeartbeatAge::Kind::never) return age;  // before the handler's first period: no figures to age
  // A damaged beat (links/heartbeat.hpp): the figures' age cannot be told, so it is the largest
  // (saturated, as a very old one) and they are stale.
  const hal::Nanoseconds old =
      judged.kind == HeartbeatAge::Kind::whole ? judged.age : std::numeric_limits<hal::Nanoseconds>::max();
  const hal::Nanoseconds ms = old / hal::kNsPerMs;
  age.age_ms = ms > 0xFFFFFFFF ? 0xFFFFFFFFU : static_cast<std::uint32_t>(ms);
  age.stale = old > ports_.stale_after;
  return age;
}

void SocketHandler::answer_query(const Message& request, const hal::UdpDatagram& from) noexcept {
  Message m;
  RobotSample sample{};
  RobotJointStatus status{};
  MasterStatus master{};
  const bool have_sample = ports_.samples != nullptr && ports_.samples->try_read(sample);
  const bool have_status = ports_.joint_status != nullptr && ports_.joint_status->try_read(status);
  const bool have_master = ports_.master != nullptr && ports_.master->try_read(master);
  const std::uint8_t owner = ports_.motion != nullptr ? ports_.motion->owner.task() : protocol::kNoOwner;
  const JointMask owner_joints = ports_.motion != nullptr ? ports_.motion->owner_joints.load(std::memory_order_relaxed) : 0;
  switch (request.header.type) {
    case MessageType::get_status:
      m.header.type = MessageType::status;
      m.status.cycle = have_master ? master.cycles : 0;
      m.status.age = handler_figures_age();
      for (std::size_t j = 0; j < kJointCount; ++j) {
        // The Motion owner's RC task on the joints its references drove in the handler's last
        // period; kNoOwner on the others (they hold their reference, or are not driven).
        m.status.joints[j] = joint_status_record_of(have_status ? &status[j] : nullptr, have_sample ? &sample[j] : nullptr,
                                                    (owner_joints & joint_bit(j)) != 0 ? owner : protocol::kNoOwner);
      }
      break;
    case MessageType::get_slaves:
      m.header.type = MessageType::slaves;
      m.slaves.count = static_cast<std::uint8_t>(drivers::kRobotNetworkPlan.size());
      m.slaves.age = handler_figures_age();
      static_assert(drivers::kRobotNetworkPlan.size() <= protocol::kMaxSlaves, "every slave fits one slaves message");
      for (std::size_t p = 0; p < drivers::kRobotNetworkPlan.size(); ++p) {
        m.slaves.slaves[p] = slave_record_of(p, have_master ? &master : nullptr, have_status ? &status : nullptr);
      }
      break;
    case MessageType::get_master:
      m.header.type = MessageType::master;
      m.master = master_payload_of(master);
      m.master.age = handler_figures_age();
      m.master.datagrams_accepted = counters_.accepted;
      m.master.rejected = counters_.rejected;
      break;
    case MessageType::get_tasks:
      m.header.type = MessageType::tasks;
      m.tasks.age = handler_figures_age();
      if (ports_.tasks != nullptr) {
        const hal::Nanoseconds mono = hal::MonotonicClock().now();  // the clock of TaskHealth::started_ns
        for (std::size_t k = 0; k < ports_.tasks->size(); ++k) {
          TaskStat t{};
          if (!(*ports_.tasks)[k].try_read(t) || t.name[0] == '\0') continue;
          const TaskHealth* health = ports_.health != nullptr && k < ports_.health->size() ? &(*ports_.health)[k] : nullptr;
          m.tasks.tasks[m.tasks.count++] = task_record_of(t, health, mono);
        }
      }
      if (ports_.drops != nullptr) {
        static_assert(kDropCounters <= protocol::kMaxDropCounters, "every drop counter fits the tasks message");
        m.tasks.drop_count = static_cast<std::uint8_t>(kDropCounters);
        for (std::size_t i = 0; i < kDropCounters; ++i) m.tasks.dropped[i] = (*ports_.drops)[i].load(std::memory_order_relaxed);
      }
      break;
    case MessageType::get_diag:
      m.header.type = MessageType::diag;
      if (ports_.diag != nullptr && !ports_.diag->try_read(m.diag)) m.diag = protocol::DiagPayload{};
      {
        const protocol::FiguresAge age = handler_figures_age();
        m.diag.age_ms = age.age_ms;
        m.diag.stale = age.stale ? 1 : 0;
      }
      break;
    case MessageType::get_version:
      m.header.type = MessageType::version;
      if (ports_.version != nullptr) m.version = *ports_.version;
      break;
    case MessageType::get_graph: return answer_graph(from);
    case MessageType::get_slave_info: return answer_slave_info(from);
    case MessageType::get_sii: return answer_sii(request, from);
    case MessageType::get_owner: {
      m.header.type = MessageType::owner_state;
      m.owner_state.age = handler_figures_age();
      const std::uint64_t word = ports_.motion != nullptr ? ports_.motion->owner.word() : MotionOwner::kNobody;
      m.owner_state.owner = MotionOwner::task_of(word);
      m.owner_state.generation = MotionOwner::generation_of(word);
      const hal::Nanoseconds mono = hal::MonotonicClock().now();
      for (std::size_t k = 0; k < ports_.rc_tasks && k < protocol::kMaxRcTasks; ++k) {
        protocol::RcTaskRecord& t = m.owner_state.tasks[k];
        t.present = 1;
        const std::int64_t beat = ports_.rc_heartbeat_ns != nullptr ? (*ports_.rc_heartbeat_ns)[k].load(std::memory_order_acquire) : 0;
        // A beat after `mono` was read (the task ran meanwhile) is 0 ms old, not "never"; a damaged
        // one (links/heartbeat.hpp) is shown as never, not alive.
        const HeartbeatAge judged = heartbeat_age(mono, beat);
        const std::int64_t age = judged.kind == HeartbeatAge::Kind::whole ? judged.age : -1;
        t.heartbeat_age_ms = age < 0 ? 0xFFFFFFFFU : static_cast<std::uint32_t>(std::min<std::int64_t>(age / hal::kNsPerMs, 0xFFFFFFFE));
        t.alive = age >= 0 && age <= 100 * hal::kNsPerMs ? 1 : 0;  // the message parser's kRcTaskSilence
        RcTaskState state{};
        if (ports_.motion != nullptr && ports_.motion->task_state[k].try_read(state)) {
          t.phase = state.phase;
          t.mode = state.mode;
        }
      }
      break;
    }
    default:
      return;
  }
  send(m, from.address, from.port);
}

void SocketHandler::handle(const hal::UdpDatagram& d, bool control_port, hal::Nanoseconds now) noexcept {
  ++counters_.datagrams;
  if (d.truncated || d.size > protocol::kMaxDatagram) return reject(Rejection::oversized);
  const Result<protocol::FrameView> frame = protocol::parse_frame(ConstByteSpan(d.bytes.data(), d.size));
  if (!frame.ok()) return reject(protocol::rejection_of(frame.error()));
  if (!protocol::verify_frame(frame.value(), key_).ok()) return reject(Rejection::unauthenticated);
  const protocol::Header& h = frame.value().header;
  const bool asks_epoch = h.type == MessageType::get_epoch;
  // For this robot (a get_epoch may ask whichever robot answers).
  if (h.robot != robot_id_ && !(asks_epoch && h.robot == protocol::kAnyRobot)) return reject(Rejection::wrong_robot);
  if (h.sender == kRobotSenderId) return reject(Rejection::out_of_range);  // only the robot signs as 0
  if (asks_epoch) {
    if (!control_port) return reject(Rejection::unknown_type);
    ++counters_.accepted;
    Message answer;
    answer.header.type = MessageType::epoch;
    answer.epoch.request_sequence = h.sequence;
    return send(answer, d.address, d.port);
  }
  // Of this epoch: a datagram of an earlier epoch (recorded before a restart) is a replay.
  if (h.epoch != window_->epoch()) return reject(Rejection::replayed);
  // Well-formed before the window: a malformed request takes no sender slot and moves no window.
  const bool allowed = control_port ? protocol::is_control_request(h.type) : protocol::is_sensor_record(h.type);
  if (!allowed) return reject(Rejection::unknown_type);
  const Result<Message> decoded = protocol::decode_payload(h, frame.value().payload);
  if (!decoded.ok()) return reject(protocol::rejection_of(decoded.error()));
  const std::int64_t wall = wall_->unix_time_ns();
  const Status fresh = window_->accept(h.sender, h.sequence, wall > 0 ? static_cast<std::uint64_t>(wall) : 0);
  if (!fresh.ok()) return refuse_by_window(fresh.error().code, h, control_port, d);
  const Message& m = decoded.value();
  ++counters_.accepted;

  if (!control_port) {
    if (h.type == MessageType::imu) {
      sensor_data_.imu = m.imu;
      sensor_data_.imu_received_ns = now;
      ++sensor_data_.imu_records;
    } else {
      sensor_data_.gps = m.gps;
      sensor_data_.gps_received_ns = now;
      ++sensor_data_.gps_records;
    }
    if (ports_.sensors != nullptr) ports_.sensors->write(sensor_data_);
    return;
  }
  if (protocol::is_query(h.type)) return answer_query(m, d);
  if (h.type == MessageType::sdo_upload || h.type == MessageType::sdo_download) return forward_sdo(m, d);
  if (h.type == MessageType::sdo_info) return forward_sdo(m, d);
  if (h.type == MessageType::reg_read) return forward_register_read(m, d);
  if (h.type == MessageType::states) return forward_states(m, d);
  if (h.type == MessageType::rescan) return forward_rescan(m, d);
  if (h.type == MessageType::diag_reset) return post_diag_reset(m, d);  // for the EtherCAT handler, not the parser

  const ControlRequest r = request_of(m, d.address, d.port);
  if (ports_.requests == nullptr || !ports_.requests->try_send(r)) {
    ++counters_.forwarded_dropped;
    refuse(h, protocol::RefusalReason::busy, "the message parser's queue is full; try again", d);
  }
}

void SocketHandler::answer_sdo(protocol::SdoResultPayload result, const protocol::SdoInfoPayload& info,
                               std::uint64_t request_sequence, std::uint32_t address, std::uint16_t port) noexcept {
  Message m;
  describe_sdo_result(result);
  if (result.request_type == MessageType::sdo_info) {
    m.header.type = MessageType::sdo_info_result;
    m.sdo_info_result = info_result_of(result, info);
    m.sdo_info_result.request_sequence = request_sequence;
  } else {
    m.header.type = MessageType::sdo_result;
    result.request_sequence = request_sequence;
    m.sdo_result = result;
  }
  send(m, address, port);
}

void SocketHandler::forward_sdo(const Message& request, const hal::UdpDatagram& from) noexcept {
  const MessageType type = request.header.type;
  const bool download = type == MessageType::sdo_download;
  const bool information = type == MessageType::sdo_info;
  const protocol::SdoPayload sdo = information ? sdo_of(request.sdo_info) : request.sdo;
  if (sdo_.active || ports_.sdo_requests == nullptr) {
    // One transfer at a time: this one is refused at once, never queued behind and never lost.
    const auto status = ports_.sdo_requests == nullptr ? protocol::SdoStatus::no_answer : protocol::SdoStatus::busy;
    return answer_sdo(sdo_refusal(type, sdo, status), request.sdo_info, request.header.sequence, from.address, from.port);
  }
  SdoLinkRequest r;
  r.id = ++sdo_ids_;
  r.download = download;
  r.info_op = information ? request.sdo_info.op : protocol::SdoInfoOp{};
  r.info_offset = information ? request.sdo_info.offset : std::uint16_t{0};
  r.sdo = sdo;
  if (!download) r.sdo.size = 0;
  if (!ports_.sdo_requests->try_send(r)) {
    ++counters_.forwarded_dropped;  // cannot happen with one in flight and two slots; counted if it does
    return answer_sdo(sdo_refusal(type, sdo, protocol::SdoStatus::busy), request.sdo_info, request.header.sequence,
                      from.address, from.port);
  }
  sdo_.active = true;
  sdo_.id = r.id;
  sdo_.request_sequence = request.header.sequence;
  sdo_.type = type;
  sdo_.sdo = r.sdo;
  sdo_.info = request.sdo_info;
  sdo_.address = from.address;
  sdo_.port = from.port;
  sdo_.deadline = now_ + kSdoAnswerLimit;
}

void SocketHandler::collect_sdo_result() noexcept {
  SdoLinkResult result;
  while (ports_.sdo_results != nullptr && ports_.sdo_results->try_receive(result)) {
    if (!sdo_.active || result.id != sdo_.id) continue;  // the answer to a transfer already answered no_answer
    if (!sdo_result_whole(result.result)) {
      ++damaged_records_;  // not sent: the transfer is answered no_answer at its deadline
      continue;
    }
    sdo_.active = false;
    answer_sdo(result.result, sdo_.info, sdo_.request_sequence, sdo_.address, sdo_.port);
  }
  if (sdo_.active && now_ > sdo_.deadline) {
    sdo_.active = false;
    answer_sdo(sdo_refusal(sdo_.type, sdo_.sdo, protocol::SdoStatus::no_answer), sdo_.info, sdo_.request_sequence,
               sdo_.address, sdo_.port);
  }
}

void SocketHandler::refuse(const protocol::Header& request, protocol::RefusalReason reason, const char* text,
                           const hal::UdpDatagram& from) noexcept {
  reply_to(request, protocol::Outcome::refused, reason, text, from.address, from.port);
}

void SocketHandler::refuse_by_window(Errc code, const protocol::Header& h, bool control_port,
                                     const hal::UdpDatagram& d) noexcept {
  if (code == Errc::refused) return reject(Rejection::replayed);  // silent: a replay learns nothing new
  if (code == Errc::out_of_range) {
    reject(Rejection::out_of_range);
    if (control_port) {
      refuse(h, protocol::RefusalReason::bad_request,
             "sequence >10 min ahead of the robot's clock: check both clocks", d);
    }
    return;
  }
  reject(Rejection::sender_table_full);
  if (control_port) {
    refuse(h, protocol::RefusalReason::sender_table_full, "16 senders this epoch: restart the robot to retire them", d);
  }
}

void SocketHandler::step(hal::Nanoseconds now) noexcept {
  now_ = now;
  ++counters_.wakeups;
  std::size_t handled = 0;
  bool more = true;
  while (more && handled < kBudget) {
    more = false;
    for (hal::UdpSocket* socket : {&control_, &sensor_}) {
      const std::size_t room = kBudget - handled < kBatch ? kBudget - handled : kBatch;
      const std::size_t got = socket->receive_batch(Span<hal::UdpDatagram>(batch_.data(), room));
      for (std::size_t i = 0; i < got; ++i) handle(batch_[i], socket == &control_, now);
      handled += got;
      if (got == room) more = true;
      if (handled >= kBudget) break;
    }
  }
  if (handled >= kBudget) ++counters_.budget_exhausted;
  if (handled > max_per_wakeup_) max_per_wakeup_ = handled;
  finish_diag_resets();
  ControlReply reply;
  for (std::size_t n = 0; n < kRepliesPerStep && ports_.replies != nullptr && ports_.replies->try_receive(reply); ++n) {
    Message m = message_of(reply);
    send(m, reply.reply_address, reply.reply_port);
  }
  collect_sdo_result();
  collect_register_read();
  collect_states();
  collect_rescan();
  if (ports_.counters != nullptr) ports_.counters->write(counters_);
}

}  // namespace rescue::app
