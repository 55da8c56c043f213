// Test support for the ESC and segment tests: a configurable device, the robot's segment with such
// devices as joints, and a helper that sends one datagram at a time through a segment.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "core/robot/robot.hpp"
#include "drivers/sim/devices/junction_device.hpp"
#include "drivers/sim/devices/minimal_sii.hpp"
#include "drivers/sim/segment/robot_segment.hpp"
#include "drivers/sim/segment/simulated_segment.hpp"
#include "ecat/codec/frame.hpp"
#include "ecat/codec/registers.hpp"

namespace rescue::drivers::testing {

namespace reg = ecat::reg;
using ecat::Command;

// Mailbox at 0x1000 (master -> slave, 128 bytes) and 0x1080 (slave -> master, 128 bytes), 6 bytes of
// outputs and 8 bytes of inputs, as a small drive would have.
constexpr std::uint16_t kMailboxOut = 0x1000;
constexpr std::uint16_t kMailboxIn = 0x1080;
constexpr std::uint16_t kMailboxSize = 128;
constexpr std::uint16_t kOutputs = 0x1100;
constexpr std::uint16_t kInputs = 0x1200;
constexpr std::uint16_t kOutputBytes = 6;
constexpr std::uint16_t kInputBytes = 8;

class TestDevice final : public SlaveDevice {
 public:
  explicit TestDevice(std::uint16_t alias = 0, bool with_mailbox = true) {
    SiiIdentity id{};
    id.vendor_id = 0x00000A5C;
    id.product_code = 0x7E570001;
    id.revision = 1;
    id.serial = 42;
    id.station_alias = alias;
    id.pdi_control = 0x0008;  // a microcontroller behind the ESC: no device emulation
    if (with_mailbox) {
      id.mailbox_out_offset = kMailboxOut;
      id.mailbox_out_size = kMailboxSize;
      id.mailbox_in_offset = kMailboxIn;
      id.mailbox_in_size = kMailboxSize;
      id.mailbox_protocols = 0x0004;
    }
    length_ = build_minimal_sii(ByteSpan(sii_), id, "TestDevice").value_or(0);
  }

  ConstByteSpan sii_image() const noexcept override { return {sii_.data(), length_}; }
  ProcessDataLayout process_data_layout() const noexcept override { return layout; }
  std::uint16_t on_state_change(AlState from, AlState to, EscPdi&) noexcept override {
    transitions.push_back({from, to});
    if (to == AlState::pre_op) return refuse_pre_op;
    if (to == AlState::safe_op && from == AlState::pre_op) return refuse_safe_op;
    if (to == AlState::op) return refuse_op;
    return 0;
  }
  void on_mailbox(ConstByteSpan message, EscPdi& esc) noexcept override {
    received.emplace_back(message.begin(), message.end());
    if (echo_mailbox) {
      // Echo the message's first `echo_length` bytes back.
      last_post = esc.post_mailbox(ConstByteSpan(message.data(), echo_length));
    }
  }
  void on_cycle(ConstByteSpan outputs, ByteSpan inputs, const CycleContext& ctx, EscPdi&) noexcept override {
    cycles.push_back(ctx);
    for (std::size_t i = 0; i < inputs.size(); ++i) inputs[i] = i < outputs.size() ? outputs[i] : static_cast<std::uint8_t>(cycles.size());
    last_outputs.assign(outputs.begin(), outputs.end());
  }
  void step(hal::Nanoseconds now, EscPdi&) noexcept override { last_step = now; }
  void inject_fault(std::uint16_t code) noexcept override { fault = code; }

  ProcessDataLayout layout{2, kOutputBytes, 3, kInputBytes};
  std::uint16_t refuse_pre_op{0};
  std::uint16_t refuse_safe_op{0};
  std::uint16_t refuse_op{0};
  bool echo_mailbox{true};
  std::size_t echo_length{16};
  Status last_post{};
  std::vector<std::pair<AlState, AlState>> transitions;
  std::vector<std::vector<std::uint8_t>> received;
  std::vector<CycleContext> cycles;
  std::vector<std::uint8_t> last_outputs;
  hal::Nanoseconds last_step{-1};
  std::uint16_t fault{0};

 private:
  std::array<std::uint8_t, 512> sii_{};
  std::size_t length_{0};
};

struct DatagramResult {
  std::uint16_t wkc{0};
  std::uint16_t adp{0};
  std::uint16_t irq{0};
  std::vector<std::uint8_t> data;
  bool returned{false};
};

// A segment plus the devices it drives, and a clock for sending frames one by one.
class Rig {
 public:
  Rig() : own_segment_(std::make_unique<SimulatedSegment>()), segment(*own_segment_) {}
  // Drives a segment someone else owns (e.g. a SimulatedRobot's).
  explicit Rig(SimulatedSegment& external) : segment(external) {}

  // The robot: junctions and 21 test devices as joints.
  // With options.ring: the ring configuration. With `ring_on_the_tree`: the tree plus that ring cable.
  static std::unique_ptr<Rig> robot(const RobotSegmentOptions& options = {}, const RingCable* ring_on_the_tree = nullptr) {
    auto rig = std::make_unique<Rig>();
    std::array<SlaveDevice*, kSlaveCount> devices{};
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (kSlaves[p].kind == SlaveKind::junction) {
        rig->junctions.push_back(std::make_unique<JunctionDevice>(p));
        devices[p] = rig->junctions.back().get();
      } else {
        rig->devices.push_back(std::make_unique<TestDevice>(kSlaves[p].station_address));
        devices[p] = rig->devices.back().get();
        rig->by_position[p] = rig->devices.back().get();
      }
    }
    std::array<SegmentSlave, kSlaveCount> slaves{};
    EXPECT_TRUE(describe_robot_segment(Span<SlaveDevice* const>(devices), options, Span<SegmentSlave>(slaves)).ok());
    if (options.ring || ring_on_the_tree != nullptr) {
      const RingCable ring = ring_on_the_tree != nullptr ? *ring_on_the_tree : robot_ring_cable();
      EXPECT_TRUE(rig->segment.build_ring(Span<const SegmentSlave>(slaves), ring, 0).ok());
    } else {
      EXPECT_TRUE(rig->segment.build(Span<const SegmentSlave>(slaves), 0).ok());
    }
    return rig;
  }

  // One slave with a test device on an ESC configured as `config`.
  static std::unique_ptr<Rig> single(const EscConfig& config = joint_esc_config(), std::uint16_t alias = 0,
                                     bool with_mailbox = true) {
    auto rig = std::make_unique<Rig>();
    rig->devices.push_back(std::make_unique<TestDevice>(alias, with_mailbox));
    SegmentSlave s;
    s.name = "single";
    s.esc = config;
    s.link_delay_ns = kPhyPairDelayNs;
    s.device = rig->devices.back().get();
    EXPECT_TRUE(rig->segment.build(Span<const SegmentSlave>(&s, 1), 0).ok());
    return rig;
  }

  TestDevice& device(std::size_t i = 0) { return *devices[i]; }
  // The test device at a position of the robot (joints only).
  TestDevice& device_at(std::size_t position) { return *by_position[position]; }

  // Sends one frame with one datagram and returns it as it came back; time then moves on by `gap`.
  DatagramResult exchange(Command command, std::uint32_t address, std::vector<std::uint8_t> data,
                          hal::Nanoseconds gap = 20 * hal::kNsPerUs) {
    ecat::FrameBuilder builder;
    builder.reset(ecat::MacAddress{0, 0, 0, 0, 0, 1});
    const auto slot = builder.add(command, index_++, address, static_cast<std::uint16_t>(data.size()),
                                  ConstByteSpan(data.data(), data.size()));
    EXPECT_TRUE(slot.ok());
    const ConstByteSpan built = builder.finish();
    std::array<std::uint8_t, ecat::kMaxFrameSize> frame{};
    std::memcpy(frame.data(), built.data(), built.size());
    const auto outcome = segment.process(ByteSpan(frame.data(), built.size()), now, send_port);
    EXPECT_TRUE(outcome.ok());
    DatagramResult r;
    r.returned = outcome.ok() && outcome.value().returned;
    if (r.returned) last_outcome = outcome.value();
    now += gap;
    if (!r.returned) return r;
    auto parsed = ecat::FrameView::parse(ConstByteSpan(frame.data(), built.size()));
    EXPECT_TRUE(parsed.ok());
    for (const ecat::DatagramView d : parsed.value()) {
      r.wkc = d.wkc();
      r.adp = d.adp();
      r.irq = d.irq();
      r.data.assign(d.data().begin(), d.data().end());
    }
    return r;
  }
  DatagramResult read(Command command, std::uint16_t adp, std::uint16_t ado, std::size_t length) {
    return exchange(command, ecat::make_address(adp, ado), std::vector<std::uint8_t>(length, 0));
  }
  DatagramResult write(Command command, std::uint16_t adp, std::uint16_t ado, std::vector<std::uint8_t> data) {
    return exchange(command, ecat::make_address(adp, ado), std::move(data));
  }
  std::uint16_t read16(std::uint16_t station, std::uint16_t ado) {
    const auto r = read(Command::FPRD, station, ado, 2);
    return r.data.size() == 2 ? static_cast<std::uint16_t>(r.data[0] | (r.data[1] << 8)) : 0;
  }
  std::uint16_t write16(std::uint16_t station, std::uint16_t ado, std::uint16_t value) {
    return write(Command::FPWR, station, ado, {static_cast<std::uint8_t>(value), static_cast<std::uint8_t>(value >> 8)}).wkc;
  }
  // Lets virtual time pass (devices and ESCs advance).
  void wait(hal::Nanoseconds duration) {
    now += duration;
    segment.advance_to(now);
  }

  // Station addresses 0x1000 + position, as a master assigns them.
  void assign_station_addresses() {
    for (std::size_t p = 0; p < segment.slave_count(); ++p) {
      const auto station = static_cast<std::uint16_t>(kStationAddressBase + p);
      EXPECT_EQ(write(Command::APWR, ecat::position_adp(static_cast<std::uint16_t>(p)), reg::kStationAddress,
                      {static_cast<std::uint8_t>(station), static_cast<std::uint8_t>(station >> 8)})
                    .wkc,
                1);
    }
  }


 private:
  std::unique_ptr<SimulatedSegment> own_segment_;

 public:
  SimulatedSegment& segment;
  hal::Nanoseconds now{0};
  FrameOutcome last_outcome{};
  MasterPort send_port{MasterPort::main};  // the master port exchange() sends from (ring segments)
  std::vector<std::unique_ptr<TestDevice>> devices;
  std::vector<std::unique_ptr<JunctionDevice>> junctions;
  std::array<TestDevice*, kMaxSegmentSlaves> by_position{};

 private:
  std::uint8_t index_{0};
};

// A frame with one broadcast read of the ESC type register (2 bytes), as the NIC tests send it.
inline std::vector<std::uint8_t> brd_frame(std::uint8_t index) {
  ecat::FrameBuilder b;
  b.reset(ecat::MacAddress{0, 0, 0, 0, 0, 1});
  EXPECT_TRUE(b.add(Command::BRD, index, ecat::make_address(0, reg::kType), 2).ok());
  const ConstByteSpan f = b.finish();
  return {f.begin(), f.end()};
}

inline std::vector<std::uint8_t> le16(std::uint16_t v) {
  return {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8)};
}
inline std::vector<std::uint8_t> le32(std::uint32_t v) {
  return {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v >> 16),
          static_cast<std::uint8_t>(v >> 24)};
}
inline std::vector<std::uint8_t> le64(std::uint64_t v) {
  std::vector<std::uint8_t> out(8);
  for (int i = 0; i < 8; ++i) out[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
  return out;
}
inline std::uint64_t from_le(const std::vector<std::uint8_t>& d) {
  std::uint64_t v = 0;
  for (std::size_t i = d.size(); i-- > 0;) v = (v << 8) | d[i];
  return v;
}

// SyncManager registers (8 bytes) as a master writes them.
inline std::vector<std::uint8_t> sm_config(std::uint16_t start, std::uint16_t length, std::uint8_t control,
                                           std::uint8_t activate) {
  return {static_cast<std::uint8_t>(start), static_cast<std::uint8_t>(start >> 8), static_cast<std::uint8_t>(length),
          static_cast<std::uint8_t>(length >> 8), control, 0, activate, 0};
}
// FMMU registers (16 bytes).
inline std::vector<std::uint8_t> fmmu_config(std::uint32_t logical, std::uint16_t length, std::uint16_t physical,
                                             std::uint8_t type, std::uint8_t start_bit = 0, std::uint8_t stop_bit = 7,
                                             std::uint8_t physical_bit = 0) {
  std::vector<std::uint8_t> f(16, 0);
  for (int i = 0; i < 4; ++i) f[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(logical >> (8 * i));
  f[4] = static_cast<std::uint8_t>(length);
  f[5] = static_cast<std::uint8_t>(length >> 8);
  f[6] = start_bit;
  f[7] = stop_bit;
  f[8] = static_cast<std::uint8_t>(physical);
  f[9] = static_cast<std::uint8_t>(physical >> 8);
  f[10] = physical_bit;
  f[11] = type;
  f[12] = 1;
  return f;
}

constexpr std::uint8_t kMailboxWriteControl = 0x26;  // mailbox, master writes, PDI interrupt
constexpr std::uint8_t kMailboxReadControl = 0x22;   // mailbox, master reads, PDI interrupt
constexpr std::uint8_t kOutputsControl = 0x64;       // buffered, master writes, PDI interrupt, watchdog
constexpr std::uint8_t kInputsControl = 0x20;        // buffered, master reads, PDI interrupt

// Configures the mailbox SyncManagers of `station` as a master does from the SII.
inline void configure_mailbox(Rig& rig, std::uint16_t station) {
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::sync_manager(0), sm_config(kMailboxOut, kMailboxSize, kMailboxWriteControl, 1)).wkc, 1);
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::sync_manager(1), sm_config(kMailboxIn, kMailboxSize, kMailboxReadControl, 1)).wkc, 1);
}
// Process-data SyncManagers and FMMUs: outputs at logical `logical`, inputs right after.
inline void configure_process_data(Rig& rig, std::uint16_t station, std::uint32_t logical) {
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::sync_manager(2), sm_config(kOutputs, kOutputBytes, kOutputsControl, 1)).wkc, 1);
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::sync_manager(3), sm_config(kInputs, kInputBytes, kInputsControl, 1)).wkc, 1);
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::fmmu(0), fmmu_config(logical, kOutputBytes, kOutputs, 2)).wkc, 1);
  EXPECT_EQ(rig.write(Command::FPWR, station, reg::fmmu(1), fmmu_config(logical + kOutputBytes, kInputBytes, kInputs, 1)).wkc, 1);
}
// Requests `state` and returns the AL status then.
inline std::uint16_t request_state(Rig& rig, std::uint16_t station, AlState state, bool acknowledge = false) {
  (void)rig.write16(station, reg::kAlControl, static_cast<std::uint16_t>(static_cast<unsigned>(state) | (acknowledge ? 0x10U : 0U)));
  return rig.read16(station, reg::kAlStatus);
}

}  // namespace rescue::drivers::testing
