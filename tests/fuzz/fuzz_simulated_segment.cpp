// Fuzzes the simulated segment with what `rescue-motion sim --iface` takes off the wire: arbitrary
// frames (any EtherType, any datagrams, any lengths) through a junction with two slaves behind it,
// so every datagram kind reaches every register block, SyncManager, FMMU, the SII interface and the
// DC unit. Inputs starting with '#' are fault commands instead (the simulator's text interface).
// Every frame also goes round a ring (the same three slaves with a ring cable onto the last one's
// port 1, docs/redundancy.md), sent from the main and the ring port in turn: the ring walk.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "drivers/sim/segment/fault_command.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "drivers/sim/devices/minimal_sii.hpp"
#include "drivers/sim/segment/robot_segment.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"

namespace {

using namespace rescue;
using namespace rescue::drivers;

// A device with a mailbox and process data that answers every mailbox message.
class EchoDevice final : public SlaveDevice {
 public:
  EchoDevice() {
    SiiIdentity id{};
    id.pdi_control = 0x0008;
    id.mailbox_out_offset = 0x1000;
    id.mailbox_out_size = 64;
    id.mailbox_in_offset = 0x1040;
    id.mailbox_in_size = 64;
    id.mailbox_protocols = 0x0004;
    length_ = build_minimal_sii(ByteSpan(sii_), id, "fuzz").value_or(0);
  }
  ConstByteSpan sii_image() const noexcept override { return {sii_.data(), length_}; }
  ProcessDataLayout process_data_layout() const noexcept override { return {2, 4, 3, 4}; }
  std::uint16_t on_state_change(AlState, AlState, EscPdi&) noexcept override { return 0; }
  void on_mailbox(ConstByteSpan message, EscPdi& esc) noexcept override {
    (void)esc.post_mailbox(message.first(message.size() < 16 ? message.size() : 16));
  }
  void on_cycle(ConstByteSpan outputs, ByteSpan inputs, const CycleContext&, EscPdi&) noexcept override {
    for (std::size_t i = 0; i < inputs.size() && i < outputs.size(); ++i) inputs[i] = outputs[i];
  }
  void step(hal::Nanoseconds, EscPdi&) noexcept override {}
  void inject_fault(std::uint16_t) noexcept override {}

 private:
  std::array<std::uint8_t, 256> sii_{};
  std::size_t length_{0};
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static JunctionDevice junction(0);
  static EchoDevice first;
  static EchoDevice second;
  static SimulatedSegment segment;
  std::array<SegmentSlave, 3> slaves{};
  slaves[0].name = "junction";
  slaves[0].esc = junction_esc_config();
  slaves[0].device = &junction;
  slaves[1].name = "first";
  slaves[1].upstream = 0;
  slaves[1].upstream_port = 3;
  slaves[1].esc = joint_esc_config();
  slaves[1].device = &first;
  slaves[2].name = "second";
  slaves[2].upstream = 0;
  slaves[2].upstream_port = 1;
  slaves[2].esc = joint_esc_config();
  slaves[2].device = &second;
  if (!segment.build(Span<const SegmentSlave>(slaves), 0).ok()) __builtin_trap();
  static JunctionDevice ring_junction(0);
  static EchoDevice ring_first;
  static EchoDevice ring_second;
  static SimulatedSegment ring;
  slaves[0].device = &ring_junction;
  slaves[1].device = &ring_first;
  slaves[2].device = &ring_second;
  if (!ring.build_ring(Span<const SegmentSlave>(slaves), RingCable{2, 1, kPhyPairDelayNs, 3}, 0).ok()) __builtin_trap();

  if (size > 0 && data[0] == '#') {
    const auto command = parse_fault_command(reinterpret_cast<const char*>(data + 1), size - 1, segment);
    if (command.ok()) (void)apply_fault_command(command.value(), segment, 0);
    const auto ring_command = parse_fault_command(reinterpret_cast<const char*>(data + 1), size - 1, ring);
    if (ring_command.ok()) (void)apply_fault_command(ring_command.value(), ring, 0);
    return 0;
  }
  // The same frame three times (state carries over: SII busy, mailboxes, SM buffers, DC loop).
  for (int round = 0; round < 3; ++round) {
    std::vector<std::uint8_t> frame(data, data + size);  // exact size: reads past it are caught
    if (frame.empty()) break;
    const auto outcome = segment.process(ByteSpan(frame.data(), frame.size()), round * 300'000);
    if (!outcome.ok()) __builtin_trap();  // only an empty frame may be refused
    if (frame.size() != size) __builtin_trap();
    std::vector<std::uint8_t> round_the_ring(data, data + size);
    const MasterPort from = round == 1 ? MasterPort::ring : MasterPort::main;
    if (!ring.process(ByteSpan(round_the_ring.data(), round_the_ring.size()), round * 300'000, from).ok()) __builtin_trap();
  }
  return 0;
}
