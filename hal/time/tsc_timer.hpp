// TscTimer: cycle-accurate execution-time measurement (the paper's RDTSC figures), converted to
// nanoseconds with a ratio calibrated against CLOCK_MONOTONIC.
//
// Ordering (Intel, "How to Benchmark Code Execution Times on Intel IA-32 and IA-64 Instruction Set
// Architectures", and the SDM's RDTSC/RDTSCP entries): RDTSC is not serialising, so the CPU may
// read the counter before earlier instructions finish or after later ones start.
//   start(): LFENCE; RDTSC        - the read waits for everything before it to complete
//   stop():  RDTSCP; LFENCE       - RDTSCP waits for the measured code; LFENCE keeps later code
//                                   from starting before the read
// so the interval covers exactly the code between the two calls.
//
// Sources, chosen once at calibrate():
//   tsc            x86-64 with an invariant TSC (CPUID 0x80000007 EDX bit 8): constant rate across
//                  P-/C-states and synchronised across cores, so ticks from any CPU compare.
//   arm_counter    AArch64 generic timer CNTVCT_EL0 (constant rate CNTFRQ_EL0 by architecture),
//                  read after ISB.
//   clock_gettime  everything else (a TSC that is not invariant measures nothing reliable):
//                  CLOCK_MONOTONIC in ns, one tick = 1 ns.
#pragma once

#include <cmath>
#include <cstdint>
#include <ctime>

#if defined(__x86_64__) || defined(__i386__)
#include <x86intrin.h>
#endif

#include "hal/time/clock.hpp"

namespace rescue::hal {

enum class TimerSource : std::uint8_t { tsc, arm_counter, clock_gettime };
const char* to_string(TimerSource source) noexcept;

// CPUID 0x80000007 EDX bit 8, "Invariant TSC" (Intel SDM vol. 3, 18.17.1; AMD APM vol. 3).
constexpr bool invariant_tsc_bit(std::uint32_t cpuid_80000007_edx) noexcept {
  return (cpuid_80000007_edx & (1U << 8U)) != 0;
}
// CPUID 0x80000001 EDX bit 27, "RDTSCP".
constexpr bool rdtscp_bit(std::uint32_t cpuid_80000001_edx) noexcept { return (cpuid_80000001_edx & (1U << 27U)) != 0; }

// Ratio of two (ticks, ns) readings taken some time apart: ticks per nanosecond, 0 when unusable.
constexpr double ticks_per_ns_between(std::uint64_t ticks0, Nanoseconds ns0, std::uint64_t ticks1, Nanoseconds ns1) noexcept {
  return (ticks1 > ticks0 && ns1 > ns0) ? static_cast<double>(ticks1 - ticks0) / static_cast<double>(ns1 - ns0) : 0.0;
}

class TscTimer {
 public:
  static constexpr Nanoseconds kDefaultCalibration = 20 * kNsPerMs;

  // Probes the CPU and, for the TSC, compares it with CLOCK_MONOTONIC over `calibration` ns (slept).
  // Call at start-up (before init complete); never fails: the fallback always works.
  static TscTimer calibrate(Nanoseconds calibration = kDefaultCalibration) noexcept;
  // CLOCK_MONOTONIC only, e.g. to compare, or where the TSC must not be used.
  static TscTimer monotonic_fallback(const char* reason) noexcept;

  TimerSource source() const noexcept { return source_; }
  // Why this source: "invariant TSC", "TSC not invariant (CPUID 0x80000007 EDX bit 8 clear)", ...
  const char* reason() const noexcept { return reason_; }
  double ticks_per_ns() const noexcept { return ticks_per_ns_; }

  // Read at the start and at the end of the measured code; stop() - start() is the duration in
  // ticks (to_ns converts). Inline: the reads are the measurement.
  std::uint64_t start() const noexcept {
    switch (source_) {
      case TimerSource::tsc: return tsc_start();
      case TimerSource::arm_counter: return arm_counter_read();
      case TimerSource::clock_gettime: break;
    }
    return monotonic_ns();
  }
  std::uint64_t stop() const noexcept {
    switch (source_) {
      case TimerSource::tsc: return rdtscp_ ? tsc_stop() : tsc_start();
      case TimerSource::arm_counter: return arm_counter_read();
      case TimerSource::clock_gettime: break;
    }
    return monotonic_ns();
  }
  Nanoseconds to_ns(std::uint64_t ticks) const noexcept {
    return static_cast<Nanoseconds>(std::llround(static_cast<double>(ticks) * ns_per_tick_));
  }

  // The raw instruction sequences (x86 only; 0 elsewhere).
  static std::uint64_t tsc_start() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    _mm_lfence();
    return __rdtsc();
#else
    return 0;
#endif
  }
  static std::uint64_t tsc_stop() noexcept {
#if defined(__x86_64__) || defined(__i386__)
    unsigned int cpu = 0;
    const std::uint64_t ticks = __rdtscp(&cpu);
    _mm_lfence();
    return ticks;
#else
    return 0;
#endif
  }

 private:
  TscTimer(TimerSource source, const char* reason, double ticks_per_ns, bool rdtscp) noexcept
      : source_(source), reason_(reason), ticks_per_ns_(ticks_per_ns), ns_per_tick_(1.0 / ticks_per_ns), rdtscp_(rdtscp) {}

  static std::uint64_t arm_counter_read() noexcept {
#if defined(__aarch64__)
    std::uint64_t ticks = 0;
    // ISB: the counter read is not speculated ahead of earlier instructions.
    asm volatile("isb\n\tmrs %0, cntvct_el0" : "=r"(ticks) : : "memory");
    return ticks;
#else
    return 0;
#endif
  }
  static std::uint64_t monotonic_ns() noexcept {
    timespec ts{};
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);  // cannot fail for CLOCK_MONOTONIC
    return static_cast<std::uint64_t>(ts.tv_sec) * static_cast<std::uint64_t>(kNsPerSec) +
           static_cast<std::uint64_t>(ts.tv_nsec);
  }

  TimerSource source_;
  const char* reason_;
  double ticks_per_ns_;
  double ns_per_tick_;
  bool rdtscp_;
};

}  // namespace rescue::hal
