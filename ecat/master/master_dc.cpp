// Master bring-up, distributed clocks: delays, offsets, static drift compensation, SYNC0.
#include "ecat/master/master.hpp"

#include <algorithm>
#include "ecat/codec/registers.hpp"
#include "ecat/master/station_io.hpp"

namespace rescue::ecat {
namespace {

constexpr std::uint16_t kEscFeatureDc = 0x0004;       // 0x0008 bit 2: distributed clocks
constexpr std::uint8_t kSyncUnitToEcat = 0x00;        // 0x0980: SYNC/LATCH driven by EtherCAT

std::uint32_t u32(std::size_t v) noexcept { return static_cast<std::uint32_t>(v); }

}  // namespace

Status Master::configure_dc() noexcept {
  // Which slaves have a DC unit (ESC features 0x0008 bit 2). Every present slave counts, held-out
  // ones too: they forward the frames and have their own propagation delay.
  dc_slaves_ = 0;
  Status st = for_each_slave(
      link_, plan_, present(), Command::FPRD, reg::kEscFeatures, 2, [](std::size_t, ByteSpan) {},
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan data) {
        if (wkc == 1 && (load_le16(data.data()) & kEscFeatureDc) != 0) dc_slaves_ |= slave_bit(p);
      },
      options_.frame_timeout);
  if (!st.ok()) return fail("DC", st.error());
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((operated() & slave_bit(p)) != 0 && plan_[p].dc_sync0 && (dc_slaves_ & slave_bit(p)) == 0) {
      return fail("DC", make_error(Errc::unsupported, "slave planned for SYNC0 has no DC unit", u32(p)));
    }
  }
  std::size_t reference = kMaxSlaves;
  for (std::size_t p = 0; p < kMaxSlaves && reference == kMaxSlaves; ++p) {
    if ((dc_slaves_ & slave_bit(p)) != 0) reference = p;
  }
  if (reference == kMaxSlaves) return fail("DC", make_error(Errc::unsupported, "no slave with a DC unit"));
  reference_station_ = plan_[reference].station_address;

  // 1. Latch the receive time of every port of every slave with one broadcast write. On a closed
  // ring the frame would leave the last slave for the master's ring port and no port would latch its
  // return: the ring's end is closed for that one frame, so the line is measured as a tree.
  const Result<std::uint32_t> ring_end = close_ring_end();
  if (!ring_end.ok()) return fail("DC ring end", ring_end.error());
  std::array<std::uint8_t, 4> zero{};
  const hal::Nanoseconds latched_at = link_.clock().now();
  const Result<std::uint16_t> latch =
      link_.transfer(Command::BWR, make_address(0, reg::kDcReceiveTimePort0), ByteSpan(zero), options_.frame_timeout);
  const Status reopened = reopen_ring_end(ring_end.value());
  if (!latch.ok()) return fail("DC latch", latch.error());
  if (!reopened.ok()) return fail("DC ring end", reopened.error());

  // 2. Read the four port times and the 64-bit local time of the port 0 latch.
  std::array<PortReceiveTimes, kMaxSlaves> times{};
  std::array<std::uint64_t, kMaxSlaves> local_receive{};
  SlaveMask answered = 0;
  st = for_each_slave(
      link_, plan_, dc_slaves_, Command::FPRD, reg::kDcReceiveTimePort0, 16, [](std::size_t, ByteSpan) {},
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan data) {
        if (wkc != 1) return;
        for (std::size_t k = 0; k < kEscPorts; ++k) times[p].port[k] = load_le32(data.data() + 4 * k);
        answered |= slave_bit(p);
      },
      options_.frame_timeout);
  if (st.ok()) {
    st = for_each_slave(
        link_, plan_, dc_slaves_, Command::FPRD, reg::kDcReceiveTimeEpu, 8, [](std::size_t, ByteSpan) {},
        [&](std::size_t p, std::uint16_t wkc, ConstByteSpan data) {
          if (wkc == 1) local_receive[p] = load_le64(data.data());
        },
        options_.frame_timeout);
  }
  if (!st.ok()) return fail("DC port times", st.error());
  if (answered != dc_slaves_) return fail("DC port times", make_error(Errc::io_error, "port times not read", dc_slaves_ & ~answered));

  // 3. Delays through the tree.
  const Result<DcDelays> delays = compute_propagation_delays(plan_, dc_slaves_, times);
  if (!delays.ok()) return fail("DC delays", delays.error());
  report_.delays = delays.value();

  // 4. Offsets and delays: system time = the master's clock at the latch.
  const auto epoch = static_cast<std::uint64_t>(latched_at);
  SlaveMask refused = 0;
  const auto check = [&](std::size_t p, std::uint16_t wkc, ConstByteSpan) {
    if (wkc != 1) refused |= slave_bit(p);
  };
  st = for_each_slave(
      link_, plan_, dc_slaves_, Command::FPWR, reg::kDcSystemTimeOffset, 8,
      [&](std::size_t p, ByteSpan out) { store_le64(out.data(), system_time_offset(epoch, report_.delays[p], local_receive[p])); },
      check, options_.frame_timeout);
  if (st.ok()) {
    st = for_each_slave(
        link_, plan_, dc_slaves_, Command::FPWR, reg::kDcSystemTimeDelay, 4,
        [&](std::size_t p, ByteSpan out) { store_le32(out.data(), report_.delays[p]); }, check, options_.frame_timeout);
  }
  if (!st.ok()) return fail("DC offsets", st.error());
  if (refused != 0) return fail("DC offsets", make_error(Errc::io_error, "DC offset/delay not written", refused));
  return Status::success();
}

// The last present slave in processing order is the ring's end: its ports other than port 0 that lead
// to no planned child (the ring-return cable's) are closed by DL control. Returns the DL control it
// had, for reopen_ring_end; without a ring NIC nothing is written.
Result<std::uint32_t> Master::close_ring_end() noexcept {
  if (!link_.redundant()) return std::uint32_t{0};
  std::size_t last = kMaxSlaves;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((present() & slave_bit(p)) != 0) last = p;
  }
  if (last == kMaxSlaves) return make_error(Errc::not_found, "no slave present");
  const std::uint16_t station = plan_[last].station_address;
  std::array<std::uint8_t, 4> control{};
  const Result<std::uint16_t> read =
      link_.transfer(Command::FPRD, make_address(station, reg::kDlControl), ByteSpan(control), options_.frame_timeout);
  if (!read.ok()) return read.error();
  if (read.value() != 1) return make_error(Errc::io_error, "DL control not read", u32(last));
  const std::uint32_t before = load_le32(control.data());
  std::uint32_t closed = before;
  const ChildPorts children = child_ports(plan_, present(), last);
  for (unsigned port = 1; port < kEscPorts; ++port) {
    bool to_child = false;
    for (std::size_t k = 0; k < children.count; ++k) to_child = to_child || children.port[k] == port;
    if (!to_child) closed |= 0x03U << reg::dl_control_loop_shift(port);
  }
  ring_end_station_ = station;
  store_le32(control.data(), closed);
  const Result<std::uint16_t> written =
      link_.transfer(Command::FPWR, make_address(station, reg::kDlControl), ByteSpan(control), options_.frame_timeout);
  if (!written.ok()) return written.error();
  if (written.value() != 1) return make_error(Errc::io_error, "ring end not closed", u32(last));
  return before;
}

Status Master::reopen_ring_end(std::uint32_t before) noexcept {
  if (!link_.redundant()) return Status::success();
  std::array<std::uint8_t, 4> control{};
  store_le32(control.data(), before);
  const Result<std::uint16_t> written =
      link_.transfer(Command::FPWR, make_address(ring_end_station_, reg::kDlControl), ByteSpan(control), options_.frame_timeout);
  if (!written.ok()) return written.error();
  if (written.value() != 1) return make_error(Errc::io_error, "ring end not reopened", ring_end_station_);
  return Status::success();
}

Status Master::compensate_static_drift() noexcept {
  // The reference's system time, written into every other slave (FRMW 0x0910), many times in a
  // row: each write is one step of the slaves' drift control loops (ETG.1000.4 9.3.4). The frames
  // are streamed, drift_compensation_in_flight on their way at a time, so the wire sets the pace,
  // not the round trip. Every drift_compensation_check_every frames the slaves' system time
  // differences are read: two readings in a row within the target end it (one could be a loop
  // passing through zero).
  std::array<std::uint8_t, 8> time{};
  std::uint32_t lost = 0;
  unsigned within_target = 0;
  const unsigned check_every = options_.drift_compensation_check_every == 0 ? 1 : options_.drift_compensation_check_every;
  constexpr unsigned kStopCheckEvery = 256;  // frames between two looks at stop_requested
  unsigned i = 0;
  // Too many frames lost is a dead segment only once nothing came back for the bring-up's
  // repeat_silence: a simulator the host did not run loses frames without being silent.
  hal::Nanoseconds last_answer_at = link_.clock().now();
  while (i < options_.drift_compensation_frames) {
    if (options_.stop_requested != nullptr && options_.stop_requested()) {
      return fail("DC drift", make_error(Errc::refused, "stopped on request"));
    }
    if (options_.drift_compensation_target_ns != 0 && i != 0 && i % check_every == 0) {
      const Result<DcSnapshot> check = read_dc_snapshot();
      if (!check.ok()) return fail("DC drift", check.error());
      within_target = check.value().max_difference_ns <= options_.drift_compensation_target_ns ? within_target + 1 : 0;
      if (within_target >= 2) break;
    }
    const unsigned to_check = check_every - i % check_every;
    const unsigned n = std::min({options_.drift_compensation_frames - i, to_check, kStopCheckEvery});
    const Result<StreamOutcome> streamed =
        link_.stream(Command::FRMW, make_address(reference_station_, reg::kDcSystemTime), ByteSpan(time), n,
                     options_.drift_compensation_in_flight, options_.frame_timeout);
    if (!streamed.ok()) return fail("DC drift", streamed.error());
    i += n;
    lost += streamed.value().lost;
    if (streamed.value().returned > 0) {
      last_reference_time_ = load_le64(time.data());
      last_reference_read_at_ = streamed.value().last_back_at;
      last_answer_at = streamed.value().last_back_at;
    }
    if (lost > options_.drift_compensation_frames / 100 + 3 && link_.clock().now() - last_answer_at >= link_.repeat_silence()) {
      return fail("DC drift", make_error(Errc::timeout, "no frame came back", lost));
    }
  }
  report_.dc_static_frames = i;
  const Result<DcSnapshot> snapshot = read_dc_snapshot();
  if (!snapshot.ok()) return fail("DC drift", snapshot.error());
  report_.dc_max_difference_ns = snapshot.value().max_difference_ns;
  return Status::success();
}

Status Master::start_sync0() noexcept {
  // A fresh reference time, then a start time far enough ahead to configure every slave,
  // aligned to the cycle so that SYNC0 fires on whole multiples of it.
  std::array<std::uint8_t, 8> time{};
  const hal::Nanoseconds before = link_.clock().now();
  const Result<std::uint16_t> read = link_.transfer(Command::FRMW, make_address(reference_station_, reg::kDcSystemTime),
                                                    ByteSpan(time), options_.frame_timeout);
  if (!read.ok()) return fail("SYNC0", read.error());
  last_reference_time_ = load_le64(time.data());
  last_reference_read_at_ = before;
  const auto period = static_cast<std::uint64_t>(options_.cycle_time);
  const std::uint64_t earliest = last_reference_time_ + static_cast<std::uint64_t>(options_.sync0_start_margin);
  const std::uint64_t start = (earliest / period + 1) * period;
  report_.sync0_start = start;
  dc_sync_ = DcCycleSync(options_.cycle_time, start, options_.sync0_target_phase);

  SlaveMask sync_slaves = 0;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((operated() & slave_bit(p)) != 0 && plan_[p].dc_sync0) sync_slaves |= slave_bit(p);
  }
  SlaveMask refused = 0;
  const auto check = [&](std::size_t p, std::uint16_t wkc, ConstByteSpan) {
    if (wkc != 1) refused |= slave_bit(p);
  };
  // Order as the ESC wants it: off, unit to ECAT, cycle time, start time, then on.
  const std::array<std::uint8_t, 1> off{0};
  const std::array<std::uint8_t, 1> unit{kSyncUnitToEcat};
  const std::array<std::uint8_t, 1> on{static_cast<std::uint8_t>(reg::kDcActivateCyclic | reg::kDcActivateSync0)};
  std::array<std::uint8_t, 4> cycle_bytes{};
  store_le32(cycle_bytes.data(), static_cast<std::uint32_t>(period));
  std::array<std::uint8_t, 8> start_bytes{};
  store_le64(start_bytes.data(), start);
  Status st = write_each_slave(link_, plan_, sync_slaves, reg::kDcActivation, ConstByteSpan(off), check, options_.frame_timeout);
  if (st.ok()) st = write_each_slave(link_, plan_, sync_slaves, reg::kDcCyclicUnitControl, ConstByteSpan(unit), check, options_.frame_timeout);
  if (st.ok()) st = write_each_slave(link_, plan_, sync_slaves, reg::kDcSync0CycleTime, ConstByteSpan(cycle_bytes), check, options_.frame_timeout);
  if (st.ok()) st = write_each_slave(link_, plan_, sync_slaves, reg::kDcStartTime, ConstByteSpan(start_bytes), check, options_.frame_timeout);
  if (st.ok()) st = write_each_slave(link_, plan_, sync_slaves, reg::kDcActivation, ConstByteSpan(on), check, options_.frame_timeout);
  if (!st.ok()) return fail("SYNC0", st.error());
  if (refused != 0) return fail("SYNC0", make_error(Errc::io_error, "SYNC0 configuration not written", refused));
  return Status::success();
}

Result<DcSnapshot> Master::read_dc_snapshot() noexcept {
  DcSnapshot snapshot;
  const Status st = for_each_slave(
      link_, plan_, dc_slaves_ & ~monitor_.out_of_exchange(), Command::FPRD, reg::kDcSystemTimeDifference, 4,
      [](std::size_t, ByteSpan) {},
      [&](std::size_t p, std::uint16_t wkc, ConstByteSpan data) {
        if (wkc != 1) return;
        const std::uint32_t raw = load_le32(data.data());
        snapshot.difference_ns[p] = raw & ~reg::kDcDiffLocalSmaller;
        snapshot.answered |= slave_bit(p);
        if (snapshot.difference_ns[p] > snapshot.max_difference_ns) snapshot.max_difference_ns = snapshot.difference_ns[p];
      },
      options_.frame_timeout);
  if (!st.ok()) return st.error();
  return snapshot;
}

}  // namespace rescue::ecat
