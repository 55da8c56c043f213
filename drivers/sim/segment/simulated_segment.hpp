// A simulated EtherCAT segment: ESCs (drivers/sim/esc/esc.hpp) cabled as a tree, each with its device
// application, and the timing of a frame travelling through it.
//
// A frame from the master enters the first ESC's port 0. Every ESC processes it in its EtherCAT
// processing unit on the way out of port 0 and then sends it out of its ports in the order
// 0 -> 3 -> 1 -> 2: a port whose loop is open sends the frame down its branch and receives it back,
// a closed port passes it on internally; from the last port the frame goes back out of port 0.
// Returning frames are only forwarded. So the processing order (auto-increment positions) is the
// depth-first order with ports 3, 1, 2 visited in that order, and a closed port (no link, or closed
// by the master) cuts off everything behind it. A port forced open without a link loses the frame.
//
// Times (start of frame, segment time = true time): an ESC forwards after `processing_delay_ns`
// (port 0 in, through the processing unit) or `forwarding_delay_ns` (other ports); a cable adds
// its PHY and propagation delay, per direction (SegmentSlave::return_skew_ns). The frame's end
// follows its start by its length at 100 Mbit/s.
//
// Ring (build_ring, docs/redundancy.md): a second cable from the master's ring port to a free port
// of one ESC. A frame is then sent from either master port (MasterPort) and walked by the ETG rule
// in general: entering an ESC on port N it leaves by the next open port in the order
// 0 -> 3 -> 1 -> 2 -> 0; the processing unit sits behind port 0's receive side, so the ESC processes
// the frame only when it comes in on port 0 or passes a closed port 0 internally (at most once per
// frame); a closed port is passed internally. The frame comes back on whichever master port its walk
// ends at (FrameOutcome::port): with the ring closed, a frame from main comes back on the ring port
// and one from the ring port, unprocessed, on main; with the ring cut once, each comes back on its
// own port, having been processed by the slaves on its side of the cut. A tree segment (build) keeps
// the tree walk below, unchanged; frames on the ring port of a tree are refused.
//
// Not thread-safe: one thread drives the segment (frames, time and fault injection).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "drivers/sim/esc/esc.hpp"
#include "drivers/sim/esc/esc_config.hpp"
#include "drivers/sim/devices/slave_device.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

constexpr std::size_t kMaxSegmentSlaves = 32;
constexpr std::uint8_t kUpstreamIsMaster = 0xFF;

// 100BASE-TX: 80 ns per byte; a frame also carries preamble + SFD (8) and FCS (4) on the wire.
constexpr hal::Nanoseconds kNsPerByte = 80;
constexpr std::size_t kWireOverheadBytes = 12;
constexpr std::size_t kInterFrameGapBytes = 12;

// One slave: where it is cabled, what silicon it is, and its device.
struct SegmentSlave {
  const char* name{""};
  std::uint8_t upstream{kUpstreamIsMaster};  // position of the ESC whose port it hangs off
  std::uint8_t upstream_port{0};
  EscConfig esc{};
  // The cable into port 0 (from the upstream ESC or the master): propagation plus both PHYs, in
  // the direction away from the master; the direction back takes `link_delay_ns + return_skew_ns`.
  hal::Nanoseconds link_delay_ns{0};
  hal::Nanoseconds return_skew_ns{0};
  SlaveDevice* device{nullptr};
};

// The master's two ports: `main` is cabled to the first ESC's port 0; `ring` (ring segments only)
// to the port RingCable names.
enum class MasterPort : std::uint8_t { main, ring };

// The ring cable: from the master's ring port to `port` of the ESC at `position` (a port that no
// slave is cabled to, not port 0). Its delay away from the master and the skew of the way back.
struct RingCable {
  std::uint8_t position{0};
  std::uint8_t port{1};
  hal::Nanoseconds link_delay_ns{0};
  hal::Nanoseconds return_skew_ns{0};
};

// A cable between two slaves' spare ports (a loop through the tree, docs/redundancy.md form 4): from
// `a`'s port `a_port` to `b`'s port `b_port`, the same delay both ways. Ring segments only.
struct LoopCable {
  std::uint8_t a{0};
  std::uint8_t a_port{1};
  std::uint8_t b{0};
  std::uint8_t b_port{1};
  hal::Nanoseconds link_delay_ns{0};
};
constexpr std::size_t kMaxLoopCables = 4;

// What became of one frame.
struct FrameOutcome {
  bool returned{false};            // false: lost (see the segment's counters for why)
  MasterPort port{MasterPort::main};  // the master port it came back on (when returned)
  hal::Nanoseconds first_bit_back{0};  // its start arrives back at the master
  hal::Nanoseconds last_bit_back{0};   // its end arrives back at the master
};

struct SegmentCounters {
  std::uint64_t frames{0};
  std::uint64_t returned{0};
  std::uint64_t lost_no_link{0};        // the sending port's cable is cut or the ESC behind it is off
  std::uint64_t lost_circulating{0};    // a ring walk that reached no master port (every port of an ESC closed)
  std::uint64_t lost_open_port{0};      // sent out of an open port without a link
  std::uint64_t lost_not_ethercat{0};   // destroyed by the first ESC (DL control bit 0)
  std::uint64_t lost_malformed{0};      // a datagram ran past the frame's end
  std::uint64_t dropped_by_fault{0};
  std::uint64_t corrupted_by_fault{0};
  std::uint64_t delayed_by_fault{0};    // returned late by delay_frames
  std::uint64_t lost_port_corruption{0};  // damaged on a cable (corrupt_port): broken FCS at the master
  std::uint64_t taken_late{0};  // sent before the instant the segment had already reached: taken then
};

class SimulatedSegment {
 public:
  SimulatedSegment() = default;
  SimulatedSegment(const SimulatedSegment&) = delete;
  SimulatedSegment& operator=(const SimulatedSegment&) = delete;
  SimulatedSegment(SimulatedSegment&&) = delete;
  SimulatedSegment& operator=(SimulatedSegment&&) = delete;
  ~SimulatedSegment() = default;

  // Builds the segment (slaves in auto-increment order: each one's upstream comes earlier) and
  // powers every ESC up at `now`. Fails on an inconsistent description (nothing is built).
  Status build(Span<const SegmentSlave> slaves, hal::Nanoseconds now) noexcept;
  // The same slaves plus the ring cable. Refused (nothing built) when `ring` names no slave, port 0,
  // a port the ESC does not have, or a port a slave is already cabled to.
  // `loops`: cables between spare ports of two slaves (at most kMaxLoopCables), refused like the ring
  // cable onto a port that is taken, port 0 or a missing port.
  Status build_ring(Span<const SegmentSlave> slaves, const RingCable& ring, hal::Nanoseconds now,
                    Span<const LoopCable> loops = {}) noexcept;
  bool has_ring() const noexcept { return has_ring_; }
  const RingCable& ring_cable() const noexcept { return ring_; }

  std::size_t slave_count() const noexcept { return count_; }
  const SegmentSlave& slave(std::size_t position) const noexcept { return slaves_[position]; }
  Esc& esc(std::size_t position) noexcept { return escs_[position]; }
  const Esc& esc(std::size_t position) const noexcept { return escs_[position]; }
  // The true clock offsets, each slave's system time against position 0's, into out[0 ..
  // slave_count()), all read at one instant: `now`, or the latest instant any ESC's clock was
  // advanced to if that is later (a frame's walk advances a far slave's clock past the host's `now`
  // by its propagation delay, and a clock cannot be read before its last advance). Returns that instant.
  hal::Nanoseconds true_clock_offsets(hal::Nanoseconds now, Span<std::int64_t> out) const noexcept;

  // Processes one Ethernet frame in place as the slaves do. `sent_at` is when its first bit left
  // the master; a frame sent before the instant the segment has already been advanced to (a host
  // that read it late, after an idle step moved the clocks on) enters at that instant instead, as
  // one late frame, never in the segment's past (counted: taken_late). A frame that does not come back is reported as such (returned = false), not as an
  // error; errors are only for arguments (an empty span, the ring port of a segment without a ring
  // cable). `from`: the master port it is sent from.
  Result<FrameOutcome> process(ByteSpan frame, hal::Nanoseconds sent_at, MasterPort from = MasterPort::main) noexcept;

  // Lets time pass for every ESC and device (SYNC0 pulses, watchdogs, device physics).
  void advance_to(hal::Nanoseconds now) noexcept;

  // --- fault injection (from tests or a running simulator) ---
  // Cuts the cable into `position`'s port 0: that slave and everything behind it drop off; the
  // upstream port closes (auto loop control) so the frame returns without them.
  Status cut_link(std::size_t position) noexcept;
  Status restore_link(std::size_t position) noexcept;
  // The ring cable (master ring port <-> its ESC) cut and reconnected; refused on a tree.
  Status cut_ring_cable() noexcept;
  Status restore_ring_cable() noexcept;
  bool ring_cable_cut() const noexcept { return has_ring_ && ring_cut_; }
  // Loop cable `index` (build_ring's `loops`) cut and reconnected.
  Status set_loop_cable_cut(std::size_t index, bool cut) noexcept;
  // A hung application: the ESC still forwards and answers registers, AL control/mailbox/process
  // data are no longer served.
  Status freeze(std::size_t position, bool frozen) noexcept;
  // A dead slave (power lost): its links go down on both sides. Power on = a fresh ESC in INIT.
  Status set_power(std::size_t position, bool on, hal::Nanoseconds now) noexcept;
  Status inject_device_fault(std::size_t position, std::uint16_t error_code) noexcept;
  // Every request of the slave for `state` refused with `al_status_code` (0: accepted again).
  Status refuse_state(std::size_t position, AlState state, std::uint16_t al_status_code) noexcept;
  // The slave named `name` powered on (e.g. the simulated robot's spare: one more device at a chain's end).
  Status power_on_named(const char* name, hal::Nanoseconds now) noexcept;
  // The slave's PDO mapping left wrong (kept through power cycles); refused by devices without one.
  Status corrupt_pdo_mapping(std::size_t position, PdoMappingFault fault) noexcept;
  // The slave's application drops it from OP to SAFE-OP with `al_status_code` (error indication set),
  // as a drive does that loses its synchronisation (0x001A) or its DC sync (0x002C). It keeps its
  // SyncManagers and FMMUs, so it still adds to the working counter. Refused unless the slave is
  // powered, in OP and has an application (junctions emulate their device).
  Status drop_to_safe_op(std::size_t position, std::uint16_t al_status_code) noexcept;
  // Power off and on again at once: the ESC loses every register (station address, SMs, FMMUs,
  // DC), comes back in INIT with its SII unchanged; its neighbours count a lost link.
  Status power_cycle(std::size_t position, hal::Nanoseconds now) noexcept;
  // A device of another type (its SII product code differs) plugged in at `position` in place of
  // the planned one (foreign = true), or the right one put back (false). Modelled as a power cycle.
  Status plug_device(std::size_t position, bool foreign, hal::Nanoseconds now) noexcept;
  // A cable replaced: the link into `position`'s port 0 goes down and up again (the slaves behind
  // keep their power and configuration).
  Status replace_cable(std::size_t position) noexcept;
  // The next `count` frames received on `position`'s `port` are damaged on that cable: that ESC
  // counts an invalid frame (0x0300 + 2 * port), every ESC the damaged frame reaches afterwards a
  // forwarded RX error on its receiving port (0x0308 + port), and the frame is lost at the master
  // (broken FCS). Port 0 is the cable from upstream, ports 1..3 the cables from the slaves behind.
  Status corrupt_port(std::size_t position, unsigned port, std::uint32_t count) noexcept;
  // The next `count` frames are lost on the way back / come back with one bit flipped (a
  // corruption the Ethernet FCS did not catch, for testing the master's own checks).
  void drop_frames(std::uint32_t count) noexcept { drop_pending_ = count; }
  void corrupt_frames(std::uint32_t count) noexcept { corrupt_pending_ = count; }
  // The next `count` returned frames come back `delay` later than the segment's own timing (a host
  // or NIC that held them: late, not lost; the slaves saw them on time). On the in-process NIC
  // (SimulatedNic), whose receive honours FrameOutcome::last_bit_back; `sim --iface` has `stall MS`.
  void delay_frames(std::uint32_t count, hal::Nanoseconds delay) noexcept {
    delay_pending_ = count;
    delay_ = delay;
  }
  bool link_cut(std::size_t position) const noexcept { return position < count_ && cut_[position]; }

  // --- observation ---
  const SegmentCounters& counters() const noexcept { return counters_; }
  // When the last processed frame's start reached `position`'s port 0 (-1 if it did not).
  hal::Nanoseconds last_arrival(std::size_t position) const noexcept { return arrival_[position]; }
  // The slave behind `position`'s `port`, or kUpstreamIsMaster when none is cabled there.
  std::uint8_t child(std::size_t position, unsigned port) const noexcept { return children_[position][port]; }

 private:
  void update_links() noexcept;
  bool cable_up(std::size_t position) const noexcept;
  bool ring_up() const noexcept;
  // The loop cable on `position`'s `port`, or loop_count_ when none ends there.
  std::size_t loop_at(std::size_t position, unsigned port) const noexcept;
  bool loop_up(std::size_t index) const noexcept;
  void enter(std::size_t position, ecat::MutableFrameView* view, hal::Nanoseconds t) noexcept;
  // The tree walk (frames from main on a segment without ring): sets `outcome.first_bit_back`;
  // false when the frame was lost.
  bool walk_tree(ecat::MutableFrameView* view, hal::Nanoseconds sent_at, FrameOutcome& outcome) noexcept;
  // The general walk by the ETG forwarding rule (ring segments, both master ports).
  bool walk_ring(ecat::MutableFrameView* view, MasterPort from, hal::Nanoseconds sent_at, FrameOutcome& outcome) noexcept;
  // Where the cable on `position`'s `port` leads, and its delay in that direction.
  struct CableEnd {
    bool master{false};
    MasterPort master_port{MasterPort::main};
    std::uint8_t position{0};
    std::uint8_t port{0};
    hal::Nanoseconds delay{0};
  };
  CableEnd far_end(std::size_t position, unsigned port) const noexcept;
  // The ring walk passes `position`'s processing unit at `t` (once per frame).
  void pass_processing_unit(std::size_t position, ecat::MutableFrameView* view, hal::Nanoseconds t) noexcept;
  // The frame is received at `position`'s `port`: injected cable damage and the error counters.
  void receive(std::size_t position, unsigned port) noexcept;

  // The delays a frame's passage reads, packed (a few cache lines for the whole segment).
  struct Timing {
    hal::Nanoseconds link_delay_ns{0};
    hal::Nanoseconds return_skew_ns{0};
    hal::Nanoseconds processing_delay_ns{0};
    hal::Nanoseconds forwarding_delay_ns{0};
  };
  std::array<Timing, kMaxSegmentSlaves> timing_{};
  std::array<SegmentSlave, kMaxSegmentSlaves> slaves_{};
  std::array<std::array<std::uint8_t, kMaxEscPorts>, kMaxSegmentSlaves> children_{};
  std::array<bool, kMaxSegmentSlaves> cut_{};
  std::array<hal::Nanoseconds, kMaxSegmentSlaves> arrival_{};
  hal::Nanoseconds now_{0};  // the latest instant every ESC has been advanced to
  std::size_t count_{0};
  std::uint32_t drop_pending_{0};
  std::uint32_t delay_pending_{0};
  hal::Nanoseconds delay_{0};
  std::uint32_t corrupt_pending_{0};
  std::uint64_t corrupt_sequence_{0};
  std::array<std::array<std::uint32_t, kMaxEscPorts>, kMaxSegmentSlaves> port_corrupt_pending_{};
  bool frame_damaged_{false};  // the frame in flight was damaged on a cable
  RingCable ring_{};
  bool has_ring_{false};
  bool ring_cut_{false};
  std::array<LoopCable, kMaxLoopCables> loops_{};
  std::array<bool, kMaxLoopCables> loop_cut_{};
  std::size_t loop_count_{0};
  // The ring walk's record of one frame at each ESC: port arrivals before its processing unit ran
  // (replayed to the ESC when it runs), whether it ran; the ESCs in processing order.
  struct Passage {
    std::array<bool, kMaxEscPorts> arrived{};
    std::array<hal::Nanoseconds, kMaxEscPorts> at{};
    bool processed{false};
  };
  std::array<Passage, kMaxSegmentSlaves> passage_{};
  std::array<std::uint8_t, kMaxSegmentSlaves> processed_order_{};
  std::size_t processed_count_{0};
  SegmentCounters counters_{};
  // Last: the segment's own state above stays together, before the ESCs' 30 KiB each.
  std::array<Esc, kMaxSegmentSlaves> escs_{};
};

}  // namespace rescue::drivers
