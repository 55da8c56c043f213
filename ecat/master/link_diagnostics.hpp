// Link-quality diagnostics: the ESC error counters (0x0300-0x0313) of every slave, read in a
// low-rate round robin piggybacked on the cyclic frame (one FPRW of 20 zero bytes to one slave
// every MasterOptions::diag_interval_cycles periods: the read returns the counters and the write
// clears them, so each answer is the increase since the last one), kept per slave and port, and a
// warning when a port's receive errors rise, naming the cable (the two slaves at its ends).
//
// Registers, per the ESC datasheet (ET1100/ET1200 section "Error counters"):
//   0x0300 + 2n  invalid frame counter of port n (frame with an FCS or length error)
//   0x0301 + 2n  RX error counter of port n (PHY symbol errors, also outside frames)
//   0x0308 + n   forwarded RX error counter of port n (a frame already marked damaged upstream)
//   0x030C       ECAT processing unit error counter
//   0x030D       PDI error counter
//   0x0310 + n   lost link counter of port n
// Invalid-frame and RX errors of port n blame the cable plugged into port n; forwarded errors only
// say the damage is further up the path, so they never raise a warning.
//
// Warning rule: per port a score decays by 1/8 per read of that slave and gains 8 per receive
// error (invalid frame + RX error); crossing kWarnScore (3 errors in quick succession, or a steady
// trickle) raises one warning; the port is re-armed when its score falls below half of it.
#pragma once

#include <array>
#include <cstdint>
#include <cstdio>

#include "core/containers/ring_buffer.hpp"
#include "ecat/dc/dc_delay.hpp"
#include "ecat/link/network_plan.hpp"
#include "hal/time/clock.hpp"

namespace rescue::ecat {


struct PortCounters {
  std::uint32_t invalid_frames{0};
  std::uint32_t rx_errors{0};
  std::uint32_t forwarded_errors{0};
  std::uint32_t lost_links{0};
};

struct SlaveErrorCounters {
  std::array<PortCounters, kEscPorts> ports{};
  std::uint32_t processing_unit_errors{0};
  std::uint32_t pdi_errors{0};
  std::uint32_t reads{0};  // answers taken
};

// One warning: a port whose receive errors rise, and the cable it names.
struct PortErrorWarning {
  std::uint8_t slave{0};
  std::uint8_t port{0};
  std::uint8_t peer{kMasterEnd};  // the slave at the cable's other end, kMasterEnd, or kNoPosition (nothing planned)
  std::uint32_t errors{0};        // receive errors counted on that port so far
  std::uint64_t cycle{0};
  hal::Nanoseconds time{0};
};

// The slave at the other end of the cable on `position`'s `port`: its upstream for port 0 (the
// master for the first slave), the slave planned behind that port otherwise (kNoPosition: none).
std::uint8_t cable_peer(const NetworkPlan& plan, std::size_t position, unsigned port) noexcept;

class LinkDiagnostics {
 public:
  static constexpr std::uint16_t kReadLength = 0x14;  // 0x0300..0x0313
  static constexpr std::uint32_t kScorePerError = 8;
  static constexpr std::uint32_t kWarnScore = 3 * kScorePerError;
  static constexpr std::size_t kWarningCapacity = 16;

  explicit LinkDiagnostics(const NetworkPlan& plan) noexcept : plan_(plan) {}

  void reset() noexcept;
  // Zeroes the counters, scores and warnings (current and earlier) of `slaves` (ctl diag --reset);
  // the sweeps and the round robin go on. Warnings queued for them are kept (already raised).
  void reset_slaves(SlaveMask slaves) noexcept;
  // Resets done (reset_slaves calls): a new table to publish at once.
  std::uint64_t resets() const noexcept { return resets_; }
  // The slave to read next among `candidates` (round robin), or kMaxSlaves when none.
  std::size_t next(SlaveMask candidates) noexcept;
  // An answer of FPRW 0x0300 (kReadLength bytes, working counter 3 expected).
  void observe(std::size_t position, const std::uint8_t* data, std::uint64_t cycle, hal::Nanoseconds time) noexcept;

  const SlaveErrorCounters& counters(std::size_t position) const noexcept { return counters_[position]; }
  // Whether `port` of `position` is in warning (raised, not yet re-armed).
  bool warned(std::size_t position, unsigned port) const noexcept { return warned_[position][port]; }
  // Whether `port` of `position` was ever warned about since the last reset (stays set once quiet).
  bool ever_warned(std::size_t position, unsigned port) const noexcept { return ((static_cast<unsigned>(ever_warned_[position]) >> port) & 1U) != 0; }
  // Completed round-robin sweeps (next() wrapped around): a low-rate moment to publish the table.
  std::uint64_t sweeps() const noexcept { return sweeps_; }
  [[nodiscard]] bool pop_warning(PortErrorWarning& out) noexcept { return warnings_.pop(out); }
  std::uint64_t warnings_dropped() const noexcept { return warnings_dropped_; }

  // The table (like IgH's `ethercat crc`): one line per slave in `slaves`, per port
  // invalid/rx/forwarded/lost, then processing-unit and PDI errors. `name(position)` names a slave.
  void print_table(std::FILE* out, SlaveMask slaves, const char* (*name)(std::size_t position)) const noexcept;

 private:
  const NetworkPlan& plan_;
  std::array<SlaveErrorCounters, kMaxSlaves> counters_{};
  std::array<std::array<std::uint32_t, kEscPorts>, kMaxSlaves> score_{};
  std::array<std::array<bool, kEscPorts>, kMaxSlaves> warned_{};
  std::array<std::uint8_t, kMaxSlaves> ever_warned_{};  // bit n: port n
  std::size_t rotate_{0};
  std::uint64_t sweeps_{0};
  std::uint64_t resets_{0};
  RingBuffer<PortErrorWarning, kWarningCapacity> warnings_{};
  std::uint64_t warnings_dropped_{0};
};

}  // namespace rescue::ecat
