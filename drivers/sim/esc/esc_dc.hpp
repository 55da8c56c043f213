// The distributed-clock unit of a simulated ESC (registers 0x0900-0x09FF).
//
//   receive times   a write to 0x0900 makes the ESC latch, for that frame, the local time at which
//                   the frame's start arrived at each port (0x0900 + 4n, 32 bit) and at the
//                   processing unit (0x0918, 64 bit; the port 0 time, as real ESCs show).
//   system time     0x0910 reads the local copy of the system time (local time + offset 0x0920)
//                   latched when the frame's start arrived; 32- or 64-bit reads.
//   control loop    a write to 0x0910 (ARMW/FRMW/FPWR of the reference time) gives the difference
//                   d = received + delay(0x0928) - local copy at frame start. The ESC averages it
//                   into 0x092C (filter depth 0x0934), and corrects its clock:
//                     phase  a budget Kp * d, spread over the expected time to the next write
//                            at no more than 1000 ppm, Kp = 256 / speed counter start (0x0930)
//                     speed  speed += Ki * d / (local time since the previous write),
//                            Ki = 2^-(0x0935 & 0x0F), bounded by what the speed counter can do
//                   0x0932 shows the speed correction as a speed-counter difference. A write of
//                   0x0930 resets the loop. Converges in a few thousand writes from +-100 ppm.
//   SYNC0           0x0981 = cyclic operation + SYNC0 starts pulses at the start time 0x0990 (a
//                   start time in the past waits for the low 32 bits to come round, as ESCs do),
//                   then every 0x09A0 ns of system time. 0x0990 then reads the next pulse.
//
// docs/simulator.md derives the equations and shows the convergence.
#pragma once

#include <array>
#include <cstdint>

#include "drivers/sim/esc/esc_clock.hpp"
#include "drivers/sim/esc/esc_config.hpp"
#include "drivers/sim/esc/esc_memory.hpp"
#include "hal/time/clock.hpp"

namespace rescue::drivers {

class EscDc {
 public:
  // Power-up: clock started, registers at their reset values.
  void reset(EscMemory& memory, const EscConfig& config, hal::Nanoseconds now) noexcept;

  std::uint64_t local_at(hal::Nanoseconds t) const noexcept { return clock_.local_at(t); }
  std::uint64_t system_time_at(const EscMemory& memory, hal::Nanoseconds t) const noexcept;
  void advance(hal::Nanoseconds t) noexcept { clock_.advance(t); }
  void change_crystal_drift(hal::Nanoseconds t, double drift_ppm) noexcept { clock_.change_crystal_drift(t, drift_ppm); }
  const EscLocalClock& clock() const noexcept { return clock_; }

  // A frame's start reached the ESC (port 0) at `t`: latch the local copy of the system time.
  void on_frame_start(EscMemory& memory, hal::Nanoseconds t) noexcept;
  // Writes the receive times the frame saw (local times, only for ports it arrived at).
  void latch_receive_times(EscMemory& memory, const std::array<hal::Nanoseconds, kMaxEscPorts>& arrival,
                           const std::array<bool, kMaxEscPorts>& arrived) noexcept;

  // The master wrote `bytes` (4 or 8) of system time to 0x0910 in the frame that started at `t`.
  void on_system_time_write(EscMemory& memory, std::uint64_t received, unsigned bytes, hal::Nanoseconds t) noexcept;
  void on_speed_counter_start_write(EscMemory& memory) noexcept;
  // 0x0981 or the start time changed (written by the master in the frame at `t`).
  void on_activation_write(EscMemory& memory, hal::Nanoseconds t) noexcept;
  void on_start_time_write(EscMemory& memory) noexcept;

  // Segment time of the next SYNC0 pulse if one is due at or before `t`.
  bool sync0_due(const EscMemory& memory, hal::Nanoseconds t, hal::Nanoseconds& when) const noexcept;
  // Generates the pending pulse; returns its system time.
  std::uint64_t fire_sync0(EscMemory& memory) noexcept;
  bool sync0_active() const noexcept { return sync0_active_; }

  double mean_difference_ns() const noexcept { return mean_difference_; }

 private:
  // What the loop derives from the speed counter start (0x0930), recomputed when it changes:
  // the same doubles every write, without their divisions (docs/simulator.md, Speed).
  struct SpeedCounterTerms {
    std::uint16_t written{0};  // the register as written
    double kp{0.0};
    double max_speed{0.0};
    double start_plus_2_squared{0.0};
    double limit{0.0};  // of the speed counter difference
  };
  const SpeedCounterTerms& speed_counter_terms(const EscMemory& memory) noexcept;
  void update_speed_counter_diff(EscMemory& memory) noexcept;

  EscLocalClock clock_{};
  std::uint64_t start_time_written_{0};
  bool sync0_active_{false};
  std::uint64_t next_sync0_{0};
  // Control loop state.
  double mean_difference_{0.0};
  bool have_previous_write_{false};
  std::uint64_t previous_write_local_{0};
  double interval_estimate_ns_{1e6};
  SpeedCounterTerms terms_{};
  bool terms_valid_{false};
};

}  // namespace rescue::drivers
