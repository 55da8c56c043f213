#include "drivers/sim/segment/simulated_segment.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers {
namespace {

// Ports after port 0, in the order an ESC sends a frame out of them.
constexpr std::array<std::uint8_t, 3> kPortOrder{3, 1, 2};
// The port a frame goes on to after port n (ETG: 0 -> 3 -> 1 -> 2 -> 0).
constexpr std::array<std::uint8_t, kMaxEscPorts> kNextPort{3, 2, 0, 1};
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
    timing_[p] = Timing{slaves[p].link_delay_ns, slaves[p].return_skew_ns, slaves[p].esc.processing_delay_ns,
                        slaves[p].esc.forwarding_delay_ns};
    cut_[p] = false;
    arrival_[p] = -1;
    escs_[p].power_up(slaves_[p].esc, *slaves_[p].device, now);
  }
  counters_ = SegmentCounters{};
  now_ = now;  // a segment built again starts at its new time, not at the instant the old build reached
  has_ring_ = false;
  ring_cut_ = false;
  drop_pending_ = 0;
  delay_pending_ = 0;
  port_corrupt_pending_ = {};
  corrupt_pending_ = 0;
  update_links();
  return Status::success();
}

namespace {

// Whether a cable may end at `position`'s `port` (not port 0, a port the ESC has, no slave cabled there).
Status check_spare_port(Span<const SegmentSlave> slaves, std::size_t position, unsigned port, const char* cable) noexcept {
  if (position >= slaves.size()) return make_error(Errc::invalid_argument, cable, static_cast<std::uint32_t>(position));
  if (port == 0 || port >= slaves[position].esc.port_count) {
    return make_error(Errc::invalid_argument, "ring cable onto port 0 or a port the ESC lacks", port);
  }
  for (std::size_t p = 1; p < slaves.size(); ++p) {
    if (slaves[p].upstream == position && slaves[p].upstream_port == port) {
      return make_error(Errc::invalid_argument, "ring cable onto a port already cabled", static_cast<std::uint32_t>(position), port);
    }
  }
  return Status::success();
}

}  // namespace

Status SimulatedSegment::build_ring(Span<const SegmentSlave> slaves, const RingCable& ring, hal::Nanoseconds now,
                                    Span<const LoopCable> loops) noexcept {
  count_ = 0;
  has_ring_ = false;
  loop_count_ = 0;
  RESCUE_TRY(check_spare_port(slaves, ring.position, ring.port, "ring cable onto no slave"));
  if (loops.size() > kMaxLoopCables) return make_error(Errc::capacity_exceeded, "loop cables", static_cast<std::uint32_t>(loops.size()));
  // Every cable end once: the ring cable's and both ends of each loop cable.
  std::array<std::uint8_t, 1 + 2 * kMaxLoopCables> end_position{};
  std::array<std::uint8_t, 1 + 2 * kMaxLoopCables> end_port{};
  std::size_t ends = 0;
  end_position[ends] = ring.position;
  end_port[ends++] = ring.port;
  for (const LoopCable& loop : loops) {
    RESCUE_TRY(check_spare_port(slaves, loop.a, loop.a_port, "loop cable onto no slave"));
    RESCUE_TRY(check_spare_port(slaves, loop.b, loop.b_port, "loop cable onto no slave"));
    for (const auto& [position, port] : {std::pair<std::uint8_t, std::uint8_t>{loop.a, loop.a_port}, {loop.b, loop.b_port}}) {
      for (std::size_t e = 0; e < ends; ++e) {
        if (end_position[e] == position && end_port[e] == port) return make_error(Errc::invalid_argument, "ring cable onto a port already cabled", position, port);
      }
      end_position[ends] = position;
      end_port[ends++] = port;
    }
  }
  Status built = build(slaves, now);
  if (!built.ok()) return built;
  ring_ = ring;
  has_ring_ = true;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    loops_[i] = loops[i];
    loop_cut_[i] = false;
  }
  loop_count_ = loops.size();
  update_links();
  return Status::success();
}

std::size_t SimulatedSegment::loop_at(std::size_t position, unsigned port) const noexcept {
  for (std::size_t i = 0; i < loop_count_; ++i) {
    if ((loops_[i].a == position && loops_[i].a_port == port) || (loops_[i].b == position && loops_[i].b_port == port)) return i;
  }
  return loop_count_;
}

bool SimulatedSegment::loop_up(std::size_t index) const noexcept {
  return index < loop_count_ && !loop_cut_[index] && escs_[loops_[index].a].powered() && escs_[loops_[index].b].powered();
}

Status SimulatedSegment::set_loop_cable_cut(std::size_t index, bool cut) noexcept {
  if (index >= loop_count_) return make_error(Errc::out_of_range, "loop cable", static_cast<std::uint32_t>(index));
  loop_cut_[index] = cut;
  update_links();
  return Status::success();
}

bool SimulatedSegment::ring_up() const noexcept { return has_ring_ && !ring_cut_ && escs_[ring_.position].powered(); }

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
      const bool ring = has_ring_ && p == ring_.position && port == ring_.port;
      const std::size_t loop = loop_at(p, port);
      bool up = c != kUpstreamIsMaster && cable_up(c);
      if (ring) {
        up = ring_up();
      } else if (loop < loop_count_) {
        up = loop_up(loop);
      }
      escs_[p].set_link(port, up);
    }
  }
}

void SimulatedSegment::advance_to(hal::Nanoseconds now) noexcept {
  now_ = std::max(now_, now);
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

Result<FrameOutcome> SimulatedSegment::process(ByteSpan frame, hal::Nanoseconds sent, MasterPort from) noexcept {
  if (frame.empty() || count_ == 0) return make_error(Errc::invalid_argument, "empty frame or segment");
  if (from == MasterPort::ring && !has_ring_) return make_error(Errc::invalid_argument, "ring port used on a segment without a ring cable");
  ++counters_.frames;
  // In the segment's past, every ESC's clock would read its last advance: each slave's time the
  // same instant, so a compare of 0x0910 would see its whole propagation delay as a clock error
  // (over veth on a loaded host: 1-4 us of 0x092C in one frame, the clocks steered by 1/16 of it).
  if (sent < now_) ++counters_.taken_late;
  const hal::Nanoseconds sent_at = std::max(sent, now_);
  advance_to(sent_at);
  arrival_.fill(-1);
  FrameOutcome outcome{};
  outcome.port = from;
  // The ESC and port the frame enters by.
  const bool from_ring = from == MasterPort::ring;
  const std::size_t entry = from_ring ? ring_.position : 0;
  const unsigned entry_port = from_ring ? ring_.port : 0;
  if (from_ring ? !ring_up() : !cable_up(0)) {
    ++counters_.lost_no_link;
    return outcome;
  }
  auto parsed = ecat::MutableFrameView::parse(frame);
  if (!parsed.ok()) {
    const Error& e = parsed.error();
    const bool ethercat = std::strcmp(e.what, "not EtherCAT") != 0;
    if (!ethercat && (escs_[entry].register_u32(ecat::reg::kDlControl) & kForwardingRuleDestroy) != 0) {
      ++counters_.lost_not_ethercat;
      return outcome;
    }
    if (e.code != Errc::unsupported) {
      // A datagram runs past the frame: the first ESC counts an invalid frame on its receiving port
      // and forwards it with a broken FCS, which the master's NIC discards.
      escs_[entry].count_invalid_frame(entry_port);
      ++counters_.lost_malformed;
      return outcome;
    }
    // Other EtherCAT frame types, or non-EtherCAT frames when forwarding is allowed: forwarded
    // unprocessed. Timing as for a frame with no datagrams.
  }
  ecat::MutableFrameView* view = parsed.ok() ? &parsed.value() : nullptr;  // nullptr: forwarded unprocessed
  const bool came_back = has_ring_ ? walk_ring(view, from, sent_at, outcome) : walk_tree(view, sent_at, outcome);
  if (!came_back) return outcome;
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

bool SimulatedSegment::walk_tree(ecat::MutableFrameView* view, hal::Nanoseconds sent_at, FrameOutcome& outcome) noexcept {
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
      outcome.first_bit_back = t_out + timing_[0].link_delay_ns + timing_[0].return_skew_ns;
      break;
    }
    Visit& parent = stack[depth - 1];
    const hal::Nanoseconds t_rx = t_out + timing_[position].link_delay_ns + timing_[position].return_skew_ns;
    receive(parent.position, via);
    escs_[parent.position].arrived_at_port(via, t_rx);
    parent.t = t_rx + timing_[parent.position].forwarding_delay_ns;
  }
  if (lost) {
    for (std::size_t i = 0; i < depth; ++i) escs_[stack[i].position].frame_left();
    ++counters_.lost_open_port;
    return false;
  }
  return true;
}

SimulatedSegment::CableEnd SimulatedSegment::far_end(std::size_t position, unsigned port) const noexcept {
  CableEnd end;
  if (port == 0) {
    end.delay = timing_[position].link_delay_ns + timing_[position].return_skew_ns;  // towards the master's side
    const std::uint8_t up = slaves_[position].upstream;
    end.master = up == kUpstreamIsMaster;
    end.position = up;
    end.port = slaves_[position].upstream_port;
    return end;
  }
  if (has_ring_ && position == ring_.position && port == ring_.port) {
    end.master = true;
    end.master_port = MasterPort::ring;
    end.delay = ring_.link_delay_ns + ring_.return_skew_ns;
    return end;
  }
  const std::size_t loop = loop_at(position, port);
  if (loop < loop_count_) {
    const LoopCable& l = loops_[loop];
    const bool from_a = l.a == position && l.a_port == port;
    end.position = from_a ? l.b : l.a;
    end.port = from_a ? l.b_port : l.a_port;
    end.delay = l.link_delay_ns;
    return end;
  }
  const std::uint8_t c = children_[position][port];
  end.position = c;
  end.port = 0;
  end.delay = timing_[c].link_delay_ns;
  return end;
}

void SimulatedSegment::pass_processing_unit(std::size_t position, ecat::MutableFrameView* view, hal::Nanoseconds t) noexcept {
  Passage& passage = passage_[position];
  if (passage.processed) return;  // the walk passes port 0's receive side at most once; kept safe anyway
  enter(position, view, t);
  // begin_frame starts the ESC's record of the frame: the ports it reached earlier are given again.
  for (unsigned port = 1; port < kMaxEscPorts; ++port) {
    if (passage.arrived[port]) escs_[position].arrived_at_port(port, passage.at[port]);
  }
  passage.processed = true;
  processed_order_[processed_count_++] = static_cast<std::uint8_t>(position);
}

bool SimulatedSegment::walk_ring(ecat::MutableFrameView* view, MasterPort from, hal::Nanoseconds sent_at, FrameOutcome& outcome) noexcept {
  for (std::size_t p = 0; p < count_; ++p) passage_[p] = Passage{};
  processed_count_ = 0;
  frame_damaged_ = false;
  std::size_t position = from == MasterPort::ring ? ring_.position : 0;
  unsigned port_in = from == MasterPort::ring ? ring_.port : 0;
  hal::Nanoseconds t = sent_at + (from == MasterPort::ring ? ring_.link_delay_ns : timing_[0].link_delay_ns);
  // Every cable is passed at most once each way: a longer walk is a fault of the model.
  constexpr std::size_t kMaxSteps = 2 * kMaxSegmentSlaves * kMaxEscPorts + 2;
  bool returned = false;
  bool lost_open = false;
  for (std::size_t step = 0; step < kMaxSteps && !returned && !lost_open; ++step) {
    // The frame's start arrives at `position`'s `port_in` at `t`.
    receive(position, port_in);
    Esc& e = escs_[position];
    bool processed_here = false;
    if (port_in == 0) {
      pass_processing_unit(position, view, t);
      processed_here = true;
    } else if (passage_[position].processed) {
      e.arrived_at_port(port_in, t);
    } else {
      passage_[position].arrived[port_in] = true;
      passage_[position].at[port_in] = t;
    }
    // Round the ports after the one it came in by; a closed port 0 is passed through the processing unit.
    unsigned port = kNextPort[port_in];
    unsigned tried = 0;
    for (; tried < kMaxEscPorts && e.loop_closed(port); ++tried) {
      if (port == 0) {
        pass_processing_unit(position, view, t);
        processed_here = true;
      }
      port = kNextPort[port];
    }
    if (tried == kMaxEscPorts) break;  // every port closed: the frame circles inside this ESC
    if (!e.link(port)) {
      lost_open = true;  // sent out of an open port into nothing
      break;
    }
    const hal::Nanoseconds t_out = t + (processed_here ? timing_[position].processing_delay_ns : timing_[position].forwarding_delay_ns);
    const CableEnd end = far_end(position, port);
    if (end.master) {
      outcome.port = end.master_port;
      outcome.first_bit_back = t_out + end.delay;
      returned = true;
      break;
    }
    position = end.position;
    port_in = end.port;
    t = t_out + end.delay;
  }
  for (std::size_t i = 0; i < processed_count_; ++i) escs_[processed_order_[i]].frame_left();
  if (returned) return true;
  if (lost_open) {
    ++counters_.lost_open_port;
  } else {
    ++counters_.lost_circulating;
  }
  return false;
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

Status SimulatedSegment::cut_ring_cable() noexcept {
  if (!has_ring_) return make_error(Errc::invalid_argument, "no ring cable: the segment is a tree");
  ring_cut_ = true;
  update_links();
  return Status::success();
}

Status SimulatedSegment::restore_ring_cable() noexcept {
  if (!has_ring_) return make_error(Errc::invalid_argument, "no ring cable: the segment is a tree");
  ring_cut_ = false;
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

hal::Nanoseconds SimulatedSegment::true_clock_offsets(hal::Nanoseconds now, Span<std::int64_t> out) const noexcept {
  hal::Nanoseconds at = now;
  for (std::size_t p = 0; p < count_; ++p) at = std::max(at, escs_[p].dc().clock().advanced_to());
  const std::uint64_t reference = count_ > 0 ? escs_[0].system_time_at(at) : 0;
  for (std::size_t p = 0; p < count_ && p < out.size(); ++p) {
    out[p] = static_cast<std::int64_t>(escs_[p].system_time_at(at) - reference);
  }
  return at;
}

}  // namespace rescue::drivers
