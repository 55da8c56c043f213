#include "drivers/sim/segment/simulated_segment.hpp"

#include <algorithm>
#include <cstring>

#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

// Ports after port 0, in the order an ESC sends a frame out of them.
constexpr std::array<std::uint8_t, 3> kPortOrder{3, 1, 2};
constexpr std::size_t kSourceMacFirstByte = 6;
constexpr std::uint8_t kLocallyAdministered = 0x02;
constexpr std::uint32_t kForwardingRuleDestroy = 0x00000001;  // DL control bit 0

struct Visit {
  std::uint8_t position;
  std::uint8_t via_port;  // port of the upstream ESC the frame came through
  std::uint8_t next;      // index into kPortOrder of the next port to try
  hal::Nanoseconds t;     // when the frame's start leaves towards the next port
};

}  // namespace

Status SimulatedSegment::build(Span<const SegmentSlave> slaves, hal::Nanoseconds now) noexcept {
  count_ = 0;
  if (slaves.empty() || slaves.size() > kMaxSegmentSlaves) {
    return make_error(Errc::invalid_argument, "segment slave count", static_cast<std::uint32_t>(slaves.size()));
  }
  std::array<std::array<std::uint8_t, kMaxEscPorts>, kMaxSegmentSlaves> children{};
  for (auto& row : children) row.fill(kUpstreamIsMaster);
  for (std::size_t p = 0; p < slaves.size(); ++p) {
    const SegmentSlave& s = slaves[p];
    const auto where = static_cast<std::uint32_t>(p);
    if (s.device == nullptr) return make_error(Errc::invalid_argument, "slave without device", where);
    if (s.esc.port_count < 1 || s.esc.port_count > kMaxEscPorts) return make_error(Errc::invalid_argument, "port count", where);
    if (p == 0) {
      if (s.upstream != kUpstreamIsMaster) return make_error(Errc::invalid_argument, "first slave must hang off the master");
      continue;
    }
    if (s.upstream >= p) return make_error(Errc::invalid_argument, "upstream must come earlier", where, s.upstream);
    const unsigned port = s.upstream_port;
    if (port == 0 || port >= slaves[s.upstream].esc.port_count) {
      return make_error(Errc::invalid_argument, "upstream port", where, port);
    }
    if (children[s.upstream][port] != kUpstreamIsMaster) return make_error(Errc::invalid_argument, "port cabled twice", where, port);
    children[s.upstream][port] = static_cast<std::uint8_t>(p);
  }
  // Auto-increment positions must be the frame's processing order (depth first, ports 3, 1, 2).
  std::array<std::uint8_t, kMaxSegmentSlaves> order{};
  std::size_t visited = 0;
  std::array<Visit, kMaxSegmentSlaves> stack{};
  std::size_t depth = 0;
  stack[depth++] = Visit{0, 0, 0, 0};
  order[visited++] = 0;
  while (depth > 0) {
    Visit& v = stack[depth - 1];
    if (v.next >= kPortOrder.size()) {
      --depth;
      continue;
    }
    const std::uint8_t c = children[v.position][kPortOrder[v.next++]];
    if (c == kUpstreamIsMaster) continue;
    order[visited++] = c;
    stack[depth++] = Visit{c, 0, 0, 0};
  }
  for (std::size_t p = 0; p < slaves.size(); ++p) {
    if (order[p] != p) return make_error(Errc::invalid_argument, "positions differ from frame order", static_cast<std::uint32_t>(p));
  }

  count_ = slaves.size();
  children_ = children;
  for (std::size_t p = 0; p < count_; ++p) {
    slaves_[p] = slaves[p];
    timing_[p] = Timing{slaves[p].link_delay_ns, slaves[p].esc.processing_delay_ns, slaves[p].esc.forwarding_delay_ns};
    cut_[p] = false;
    arrival_[p] = -1;
    escs_[p].power_up(slaves_[p].esc, *slaves_[p].device, now);
  }
  counters_ = SegmentCounters{};
  drop_pending_ = 0;
  delay_pending_ = 0;
  port_corrupt_pending_ = {};
  corrupt_pending_ = 0;
  update_links();
  return Status::success();
}

bool SimulatedSegment::cable_up(std::size_t position) const noexcept {
  if (position >= count_ || cut_[position] || !escs_[position].powered()) return false;
  const std::uint8_t up = slaves_[position].upstream;
  return up == kUpstreamIsMaster || escs_[up].powered();
}

void SimulatedSegment::update_links() noexcept {
  for (std::size_t p = 0; p < count_; ++p) {
    if (!escs_[p].powered()) continue;
    escs_[p].set_link(0, cable_up(p));
    for (unsigned port = 1; port < kMaxEscPorts; ++port) {
      const std::uint8_t c = children_[p][port];
      escs_[p].set_link(port, c != kUpstreamIsMaster && cable_up(c));
    }
  }
}

void SimulatedSegment::advance_to(hal::Nanoseconds now) noexcept {
  for (std::size_t p = 0; p < count_; ++p) {
    if (escs_[p].powered()) escs_[p].advance_to(now);
  }
}

void SimulatedSegment::enter(std::size_t position, ecat::MutableFrameView* view, hal::Nanoseconds t) noexcept {
  arrival_[position] = t;
  Esc& e = escs_[position];
  e.advance_to(t);
  e.begin_frame(t);
  if (view != nullptr) {
    for (const ecat::MutableDatagramView d : *view) e.process(d);
  }
  e.end_frame(t);
}

Result<FrameOutcome> SimulatedSegment::process(ByteSpan frame, hal::Nanoseconds sent_at) noexcept {
  if (frame.empty() || count_ == 0) return make_error(Errc::invalid_argument, "empty frame or segment");
  ++counters_.frames;
  advance_to(sent_at);
  arrival_.fill(-1);
  FrameOutcome outcome{};
  if (!cable_up(0)) {
    ++counters_.lost_no_link;
    return outcome;
  }
  auto parsed = ecat::MutableFrameView::parse(frame);
  if (!parsed.ok()) {
    const Error& e = parsed.error();
    const bool ethercat = std::strcmp(e.what, "not EtherCAT") != 0;
    if (!ethercat && (escs_[0].register_u32(ecat::reg::kDlControl) & kForwardingRuleDestroy) != 0) {
      ++counters_.lost_not_ethercat;
      return outcome;
    }
    if (e.code != Errc::unsupported) {
      // A datagram runs past the frame: the first ESC counts an invalid frame on port 0 and
      // forwards it with a broken FCS, which the master's NIC discards.
      escs_[0].count_invalid_frame(0);
      ++counters_.lost_malformed;
      return outcome;
    }
    // Other EtherCAT frame types, or non-EtherCAT frames when forwarding is allowed: forwarded
    // unprocessed. Timing as for a frame with no datagrams.
  }
  ecat::MutableFrameView* view = parsed.ok() ? &parsed.value() : nullptr;  // nullptr: forwarded unprocessed

  std::array<Visit, kMaxSegmentSlaves> stack{};
  std::size_t depth = 0;
  const hal::Nanoseconds t0 = sent_at + timing_[0].link_delay_ns;
  frame_damaged_ = false;
  receive(0, 0);
  enter(0, view, t0);
  stack[depth++] = Visit{0, 0, 0, t0 + timing_[0].processing_delay_ns};
  bool lost = false;
  while (depth > 0) {
    Visit& v = stack[depth - 1];
    Esc& e = escs_[v.position];
    bool descended = false;
    while (v.next < kPortOrder.size()) {
      const std::uint8_t port = kPortOrder[v.next++];
      if (e.loop_closed(port)) continue;
      if (!e.link(port)) {
        lost = true;  // sent out of an open port into nothing
        break;
      }
      const std::uint8_t c = children_[v.position][port];
      const hal::Nanoseconds t_child = v.t + timing_[c].link_delay_ns;
      receive(c, 0);
      enter(c, view, t_child);
      stack[depth++] = Visit{c, port, 0, t_child + timing_[c].processing_delay_ns};
      descended = true;
      break;
    }
    if (lost) break;
    if (descended) continue;
    // Back out of port 0.
    const hal::Nanoseconds t_out = v.t;
    const std::uint8_t position = v.position;
    const std::uint8_t via = v.via_port;
    e.frame_left();
    --depth;
    if (depth == 0) {
      outcome.first_bit_back = t_out + timing_[0].link_delay_ns;
      break;
    }
    Visit& parent = stack[depth - 1];
    const hal::Nanoseconds t_rx = t_out + timing_[position].link_delay_ns;
    receive(parent.position, via);
    escs_[parent.position].arrived_at_port(via, t_rx);
    parent.t = t_rx + timing_[parent.position].forwarding_delay_ns;
  }
  if (lost) {
    for (std::size_t i = 0; i < depth; ++i) escs_[stack[i].position].frame_left();
    ++counters_.lost_open_port;
    return outcome;
  }
  // Every ESC sets the locally administered bit of the source address on the way back.
  if (frame.size() > kSourceMacFirstByte) frame[kSourceMacFirstByte] = static_cast<std::uint8_t>(frame[kSourceMacFirstByte] | kLocallyAdministered);
  if (frame_damaged_) {
    ++counters_.lost_port_corruption;
    return outcome;
  }
  if (drop_pending_ > 0) {
    --drop_pending_;
    ++counters_.dropped_by_fault;
    return outcome;
  }
  if (corrupt_pending_ > 0 && frame.size() > ecat::kEthernetHeaderSize) {
    --corrupt_pending_;
    ++counters_.corrupted_by_fault;
    // A deterministic bit in the EtherCAT part of the frame.
    const std::size_t bits = (frame.size() - ecat::kEthernetHeaderSize) * 8U;
    const auto bit = static_cast<std::size_t>((corrupt_sequence_++ * 7919U + 13U) % bits);
    std::uint8_t& byte = frame[ecat::kEthernetHeaderSize + bit / 8U];
    byte = static_cast<std::uint8_t>(byte ^ (1U << (bit % 8U)));
  }
  const std::size_t wire_bytes = std::max(frame.size(), ecat::kMinFrameSize) + kWireOverheadBytes;
  outcome.returned = true;
  if (delay_pending_ > 0) {
    --delay_pending_;
    ++counters_.delayed_by_fault;
    outcome.first_bit_back += delay_;
  }
  outcome.last_bit_back = outcome.first_bit_back + static_cast<hal::Nanoseconds>(wire_bytes) * kNsPerByte;
  ++counters_.returned;
  return outcome;
}

// --- faults ---------------------------------------------------------------------------------------

Status SimulatedSegment::cut_link(std::size_t position) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  cut_[position] = true;
  update_links();
  return Status::success();
}

Status SimulatedSegment::restore_link(std::size_t position) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  cut_[position] = false;
  update_links();
  return Status::success();
}

Status SimulatedSegment::freeze(std::size_t position, bool frozen) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  escs_[position].set_application_frozen(frozen);
  return Status::success();
}

Status SimulatedSegment::set_power(std::size_t position, bool on, hal::Nanoseconds now) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  if (on && !escs_[position].powered()) {
    escs_[position].power_up(slaves_[position].esc, *slaves_[position].device, now);
  } else if (!on && escs_[position].powered()) {
    // Its neighbours see the links go down.
    const std::uint8_t up = slaves_[position].upstream;
    if (up != kUpstreamIsMaster) escs_[up].set_link(slaves_[position].upstream_port, false);
    escs_[position].power_down();
  }
  update_links();
  return Status::success();
}

Status SimulatedSegment::drop_to_safe_op(std::size_t position, std::uint16_t al_status_code) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  Esc& e = escs_[position];
  if (!e.powered() || e.al_state() != AlState::op) return make_error(Errc::refused, "slave not in OP", static_cast<std::uint32_t>(position));
  if (e.device_emulation()) return make_error(Errc::refused, "no application (device emulation)", static_cast<std::uint32_t>(position));
  e.raise_al_error(AlState::safe_op, al_status_code);
  return Status::success();
}

void SimulatedSegment::receive(std::size_t position, unsigned port) noexcept {
  if (port >= kMaxEscPorts) return;
  std::uint32_t& pending = port_corrupt_pending_[position][port];
  if (pending > 0) {
    --pending;
    frame_damaged_ = true;
    escs_[position].count_invalid_frame(port);
  } else if (frame_damaged_) {
    escs_[position].count_forwarded_error(port);
  }
}

Status SimulatedSegment::power_cycle(std::size_t position, hal::Nanoseconds now) noexcept {
  Status st = set_power(position, false, now);
  if (st.ok()) st = set_power(position, true, now);
  return st;
}

Status SimulatedSegment::plug_device(std::size_t position, bool foreign, hal::Nanoseconds now) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  escs_[position].set_foreign_identity(foreign);
  return power_cycle(position, now);
}

Status SimulatedSegment::replace_cable(std::size_t position) noexcept {
  Status st = cut_link(position);
  if (st.ok()) st = restore_link(position);
  return st;
}

Status SimulatedSegment::corrupt_port(std::size_t position, unsigned port, std::uint32_t count) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  if (port >= kMaxEscPorts) return make_error(Errc::out_of_range, "port", port);
  port_corrupt_pending_[position][port] = count;
  return Status::success();
}

Status SimulatedSegment::inject_device_fault(std::size_t position, std::uint16_t error_code) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  escs_[position].inject_device_fault(error_code);
  return Status::success();
}

Status SimulatedSegment::refuse_state(std::size_t position, AlState state, std::uint16_t al_status_code) noexcept {
  if (position >= count_) return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  escs_[position].refuse_state(state, al_status_code);
  return Status::success();
}

Status SimulatedSegment::power_on_named(const char* name, hal::Nanoseconds now) noexcept {
  for (std::size_t p = 0; p < count_; ++p) {
    if (slaves_[p].name != nullptr && name != nullptr && std::strcmp(slaves_[p].name, name) == 0) return set_power(p, true, now);
  }
  return make_error(Errc::not_found, "no slave of that name in the segment");
}

Status SimulatedSegment::corrupt_pdo_mapping(std::size_t position, PdoMappingFault fault) noexcept {
  if (position >= count_ || slaves_[position].device == nullptr) {
    return make_error(Errc::out_of_range, "slave position", static_cast<std::uint32_t>(position));
  }
  return slaves_[position].device->corrupt_pdo_mapping(fault);
}

}  // namespace rescue::drivers
