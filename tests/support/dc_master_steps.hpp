// What a master does to bring distributed clocks up, written out for the DC tests: latch receive
// times with a broadcast write of 0x0900, derive each slave's propagation delay from the latched
// port times through the tree (as ETG.1020 and open-source masters do), write offsets and delays,
// then distribute the reference time with FRMW every cycle.
#pragma once

#include <array>
#include <cstdint>

#include "tests/support/segment_test_support.hpp"

namespace rescue::drivers::testing {

struct LatchedTimes {
  std::array<std::array<std::uint32_t, 4>, kMaxSegmentSlaves> port{};
  std::array<std::uint64_t, kMaxSegmentSlaves> epu{};
};

inline LatchedTimes latch_receive_times(Rig& rig) {
  LatchedTimes t;
  EXPECT_EQ(rig.write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0)).wkc, rig.segment.slave_count());
  for (std::size_t p = 0; p < rig.segment.slave_count(); ++p) {
    const auto station = static_cast<std::uint16_t>(kStationAddressBase + p);
    const auto ports = rig.read(Command::FPRD, station, reg::kDcReceiveTimePort0, 16);
    EXPECT_EQ(ports.wkc, 1);
    for (unsigned n = 0; n < 4; ++n) {
      t.port[p][n] = static_cast<std::uint32_t>(from_le(std::vector<std::uint8_t>(ports.data.begin() + 4 * n, ports.data.begin() + 4 * n + 4)));
    }
    t.epu[p] = from_le(rig.read(Command::FPRD, station, reg::kDcReceiveTimeEpu, 8).data);
  }
  return t;
}

// A port the frame went out of and came back through: link up and loop open (from DL status).
inline bool port_open(Rig& rig, std::size_t p, unsigned port) {
  const std::uint16_t dl = rig.read16(static_cast<std::uint16_t>(kStationAddressBase + p), reg::kDlStatus);
  return (dl & reg::dl_status_communication(port)) != 0 && (dl & reg::dl_status_loop_closed(port)) == 0;
}

// Propagation delay of every slave from the reference (position 0), from the latched times only.
inline std::array<std::int64_t, kMaxSegmentSlaves> master_delays(Rig& rig, const LatchedTimes& t) {
  constexpr std::array<unsigned, 4> kOrder{0, 3, 1, 2};
  std::array<std::int64_t, kMaxSegmentSlaves> delay{};
  for (std::size_t p = 1; p < rig.segment.slave_count(); ++p) {
    const SegmentSlave& s = rig.segment.slave(p);
    const std::size_t parent = s.upstream;
    // The port the parent received the frame on just before it sent it to this slave.
    unsigned previous = 0;
    for (const unsigned port : kOrder) {
      if (port == s.upstream_port) break;
      if (port == 0 || port_open(rig, parent, port)) previous = port;
    }
    const auto there_and_back = static_cast<std::int32_t>(t.port[parent][s.upstream_port] - t.port[parent][previous]);
    // Time the frame spent in this slave's own subtree (0 for the end of a line).
    unsigned last = 0;
    for (const unsigned port : kOrder) {
      if (port != 0 && port_open(rig, p, port)) last = port;
    }
    const auto inside = static_cast<std::int32_t>(t.port[p][last] - t.port[p][0]);
    // The frame went down the parent's earlier branches first.
    const auto earlier_branches = static_cast<std::int32_t>(t.port[parent][previous] - t.port[parent][0]);
    delay[p] = delay[parent] + earlier_branches + (there_and_back - inside) / 2;
  }
  return delay;
}

// Offsets so every slave's system time equals `master_time` at the latch (delays included), and
// the delays, written as a master does.
inline void write_offsets_and_delays(Rig& rig, const LatchedTimes& t, const std::array<std::int64_t, kMaxSegmentSlaves>& delay,
                                     std::uint64_t master_time) {
  for (std::size_t p = 0; p < rig.segment.slave_count(); ++p) {
    const auto station = static_cast<std::uint16_t>(kStationAddressBase + p);
    const std::uint64_t offset = master_time - t.epu[p] + static_cast<std::uint64_t>(delay[p]);
    EXPECT_EQ(rig.write(Command::FPWR, station, reg::kDcSystemTimeOffset, le64(offset)).wkc, 1);
    EXPECT_EQ(rig.write(Command::FPWR, station, reg::kDcSystemTimeDelay, le32(static_cast<std::uint32_t>(delay[p]))).wkc, 1);
  }
}

// The model's own propagation delays (what a perfect master would measure), from the arrival times
// of one latch frame.
inline std::array<std::int64_t, kMaxSegmentSlaves> model_delays(Rig& rig) {
  (void)rig.write(Command::BWR, 0, reg::kDcReceiveTimePort0, le32(0));
  std::array<std::int64_t, kMaxSegmentSlaves> delays{};
  for (std::size_t p = 0; p < rig.segment.slave_count(); ++p) delays[p] = rig.segment.last_arrival(p) - rig.segment.last_arrival(0);
  return delays;
}

// Addresses, latch, offsets and delays (the model's, or as a master measures them).
inline void prepare_distributed_clocks(Rig& rig, std::uint64_t master_time, bool use_model_delays) {
  rig.assign_station_addresses();
  const LatchedTimes t = latch_receive_times(rig);
  write_offsets_and_delays(rig, t, use_model_delays ? model_delays(rig) : master_delays(rig, t), master_time);
}

// One cycle of drift compensation: the reference's time to every other slave (FRMW, 64 bit).
inline void distribute_reference_time(Rig& rig, hal::Nanoseconds cycle) {
  const auto r = rig.exchange(Command::FRMW, ecat::make_address(kStationAddressBase, reg::kDcSystemTime), std::vector<std::uint8_t>(8, 0), cycle);
  EXPECT_EQ(r.wkc, rig.segment.slave_count());
}

// Largest |system time - reference system time| over all slaves at one true instant.
inline std::int64_t worst_sync_error(const Rig& rig, hal::Nanoseconds at) {
  const std::uint64_t reference = rig.segment.esc(0).system_time_at(at);
  std::int64_t worst = 0;
  for (std::size_t p = 1; p < rig.segment.slave_count(); ++p) {
    const auto e = static_cast<std::int64_t>(rig.segment.esc(p).system_time_at(at) - reference);
    worst = std::max(worst, e < 0 ? -e : e);
  }
  return worst;
}

// Largest |0x092C| (the slaves' own view of their difference) over all slaves.
inline std::int64_t worst_reported_difference(const Rig& rig) {
  std::int64_t worst = 0;
  for (std::size_t p = 1; p < rig.segment.slave_count(); ++p) {
    const std::uint32_t raw = rig.segment.esc(p).register_u32(reg::kDcSystemTimeDifference);
    worst = std::max<std::int64_t>(worst, raw & 0x7FFFFFFFU);
  }
  return worst;
}

}  // namespace rescue::drivers::testing
