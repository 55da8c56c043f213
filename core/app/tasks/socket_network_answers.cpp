// The socket handler's answers about the network (docs/operator.md, docs/protocol.md): ctl slaves
// (each slave's state now), ctl graph (the tree and each slave's state), ctl slaves -v (SII identity
// and AL status code, as the EtherCAT handler published them), and ctl diag --reset (posted to the
// EtherCAT handler through TaskLinks::diag_reset, answered once the handler applied it).
#include <algorithm>
#include <cstring>

#include "core/app/operator_protocol/protocol_codec.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/robot/robot_ring.hpp"
#include "drivers/joint/robot_network_plan.hpp"
#include "drivers/joint/robot_ring_network_plan.hpp"
#include "ecat/codec/registers.hpp"
#include "ecat/master/master.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

constexpr auto kAlOp = static_cast<std::uint8_t>(ecat::reg::AlState::op);
constexpr auto kAlSafeOp = static_cast<std::uint8_t>(ecat::reg::AlState::safe_op);
constexpr std::size_t kPlanned = drivers::kRobotNetworkPlan.size();
static_assert(kPlanned <= protocol::kMaxSlaves, "every slave fits one answer");
static_assert(protocol::kRingStateClosed == static_cast<std::uint8_t>(ecat::RingState::closed) &&
                  protocol::kRingStateOpen == static_cast<std::uint8_t>(ecat::RingState::open) &&
                  protocol::kRingStateLost == static_cast<std::uint8_t>(ecat::RingState::lost) &&
                  protocol::kRingMainPort == ecat::kMainPort && protocol::kRingRingPort == ecat::kRingPort,
              "the graph's ring codes are the master's");

}  // namespace

protocol::SlaveRecord slave_record_of(std::size_t p, const MasterStatus* master, const RobotJointStatus* status) noexcept {
  protocol::SlaveRecord s;
  const ecat::SlavePlan& plan = drivers::kRobotNetworkPlan[p];
  s.position = static_cast<std::uint16_t>(p);
  s.station = plan.station_address;
  const bool in = master != nullptr && (master->in_exchange & (std::uint64_t{1} << p)) != 0;
  const bool lost = master != nullptr && (master->lost & (std::uint64_t{1} << p)) != 0;
  if (in) s.flags |= protocol::kSlaveInExchange;
  if (lost) s.flags |= protocol::kSlaveLost;
  const std::uint8_t joint = drivers::kJointOfSlave[p];
  if (joint < kJointCount && status != nullptr && (*status)[joint].lost && !lost) s.flags |= protocol::kSlaveOutOfService;
  const bool op = master != nullptr && master->state == static_cast<std::uint8_t>(ecat::MasterState::op);
  s.al_state = in ? (op ? kAlOp : kAlSafeOp) : 0;
  if (master != nullptr) {
    s.recovery = master->recovery[p] < protocol::kRecoveryStates ? master->recovery[p] : 0;
    s.recovery_age_ms = master->recovery_age_ms[p];
  }
  protocol::set_text(s.name, plan.name);
  return s;
}

void SocketHandler::answer_graph(const hal::UdpDatagram& from) noexcept {
  MasterStatus master{};
  RobotJointStatus status{};
  const bool have_master = ports_.master != nullptr && ports_.master->try_read(master);
  const bool have_status = ports_.joint_status != nullptr && ports_.joint_status->try_read(status);
  Message m;
  m.header.type = MessageType::graph;
  m.graph.count = static_cast<std::uint8_t>(kPlanned);
  m.graph.age = handler_figures_age();
  // With a ring NIC the master runs the ring configuration: its cables are the line's.
  const bool ring = have_master && master.ring.state != static_cast<std::uint8_t>(ecat::RingState::none);
  const ecat::NetworkPlan& cabling = ring ? drivers::kRobotRingNetworkPlan : drivers::kRobotNetworkPlan;
  if (ring) {
    protocol::GraphRing& r = m.graph.ring;
    r.state = master.ring.state;
    r.before = master.ring.before;
    r.after = master.ring.after;
    r.return_slave = kRingReturnSlave;
    r.return_port = kRingReturnPort;
    r.transients = master.ring.transients;
    r.breaks = master.ring.breaks;
    r.repairs = master.ring.repairs;
  }
  for (std::size_t p = 0; p < kPlanned; ++p) {
    const ecat::SlavePlan& plan = cabling[p];
    const protocol::SlaveRecord s = slave_record_of(p, have_master ? &master : nullptr, have_status ? &status : nullptr);
    protocol::GraphRecord& g = m.graph.slaves[p];
    g.position = static_cast<std::uint8_t>(p);
    g.upstream = plan.upstream == ecat::kMasterUpstream ? protocol::kGraphNone : plan.upstream;
    g.upstream_port = plan.upstream_port;
    g.kind = kSlaves[p].kind == SlaveKind::joint_drive ? 1 : 0;
    g.station = plan.station_address;
    g.joint = drivers::kJointOfSlave[p] < kJointCount ? drivers::kJointOfSlave[p] : protocol::kGraphNone;
    g.branch = plan.branch == ecat::kNoBranch ? protocol::kGraphNone : plan.branch;
    g.al_state = s.al_state;
    g.flags = s.flags;
    g.recovery = s.recovery;
  }
  send(m, from.address, from.port);
}

void SocketHandler::answer_slave_info(const hal::UdpDatagram& from) noexcept {
  Message m;
  m.header.type = MessageType::slave_info;
  m.slave_info.age = handler_figures_age();
  protocol::SlaveInfoTable table{};
  if (ports_.slave_info != nullptr && ports_.slave_info->try_read(table) && table.cycle != 0) {
    m.slave_info.count = table.count <= protocol::kMaxSlaves ? table.count : static_cast<std::uint8_t>(protocol::kMaxSlaves);
    for (std::size_t i = 0; i < m.slave_info.count; ++i) m.slave_info.slaves[i] = table.slaves[i];
  }
  send(m, from.address, from.port);
}

void SocketHandler::reply_to(const protocol::Header& request, protocol::Outcome outcome, protocol::RefusalReason reason,
                             const char* text, std::uint32_t address, std::uint16_t port) noexcept {
  Message m;
  m.header.type = MessageType::reply;
  m.reply.request_sequence = request.sequence;
  m.reply.request_type = request.type;
  m.reply.outcome = outcome;
  m.reply.reason = reason;
  protocol::set_text(m.reply.text, text);
  send(m, address, port);
}

void SocketHandler::post_diag_reset(const Message& request, const hal::UdpDatagram& from) noexcept {
  const protocol::Header& h = request.header;
  auto* const slot =
      std::find_if(pending_resets_.begin(), pending_resets_.end(), [](const PendingReset& p) { return !p.active; });
  if (ports_.diag_reset == nullptr || slot == pending_resets_.end()) {
    return reply_to(h, protocol::Outcome::refused, protocol::RefusalReason::busy,
                    ports_.diag_reset == nullptr ? "no EtherCAT handler to reset the counters" : "resets waiting; try again",
                    from.address, from.port);
  }
  DiagResetLink& link = *ports_.diag_reset;
  // The only writer: a request the handler has not taken yet is widened, not replaced.
  const std::uint64_t old = link.requested.load(std::memory_order_relaxed);
  const std::uint64_t generation = DiagResetLink::generation_of(old) + 1;
  const bool untaken = DiagResetLink::generation_of(old) != link.done.load(std::memory_order_acquire);
  const std::uint32_t slaves = request.diag_reset.slaves | (untaken ? DiagResetLink::slaves_of(old) : 0U);
  link.requested.store((generation << 32) | slaves, std::memory_order_release);
  *slot = PendingReset{true, generation, h, from.address, from.port, now_};
}

void SocketHandler::finish_diag_resets() noexcept {
  if (ports_.diag_reset == nullptr) return;
  const std::uint64_t done = ports_.diag_reset->done.load(std::memory_order_acquire);
  for (PendingReset& p : pending_resets_) {
    if (!p.active) continue;
    if (done >= p.generation) {
      p.active = false;
      reply_to(p.request, protocol::Outcome::accepted, protocol::RefusalReason::none, "link error counters zeroed",
               p.address, p.port);
    } else if (now_ - p.posted > kDiagResetTimeout) {
      p.active = false;
      reply_to(p.request, protocol::Outcome::refused, protocol::RefusalReason::busy,
               "the EtherCAT handler did not take the reset within 0.5 s", p.address, p.port);
    }
  }
}

// ctl sii_read: a chunk of one slave's SII image from the copy the EtherCAT handler published
// (size 0, flags 0: none yet, or no slave identified there).
void SocketHandler::answer_sii(const Message& request, const hal::UdpDatagram& from) noexcept {
  const std::uint8_t slave = request.sii_request.slave;
  Message m;
  m.header.type = MessageType::sii;
  m.sii.slave = slave;
  if (ports_.sii_images != nullptr && slave < ports_.sii_images->size() &&
      (*ports_.sii_images)[slave].try_read(sii_scratch_) && sii_scratch_.size <= sii_scratch_.bytes.size()) {
    const std::size_t offset = std::min<std::size_t>(request.sii_request.offset, sii_scratch_.size);
    const std::size_t length = std::min(protocol::kSiiChunkBytes, sii_scratch_.size - offset);
    m.sii.flags = static_cast<std::uint8_t>(sii_scratch_.flags & protocol::kSiiFlagsMask);
    m.sii.size = sii_scratch_.size;
    m.sii.offset = static_cast<std::uint16_t>(offset);
    m.sii.length = static_cast<std::uint16_t>(length);
    std::memcpy(m.sii.bytes.data(), sii_scratch_.bytes.data() + offset, length);
  }
  send(m, from.address, from.port);
}

}  // namespace rescue::app
