#include "hal/time/tsc_timer.hpp"

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#endif

namespace rescue::hal {
namespace {

// One (ticks, ns) pair whose ns is the middle of two clock reads around the tick read; the bracket
// width bounds the error. The best of a few tries is kept: an interrupt only widens a bracket.
struct Reading {
  std::uint64_t ticks{0};
  Nanoseconds ns{0};
  Nanoseconds bracket{INT64_MAX};
};

template <typename ReadTicks>
Reading best_reading(MonotonicClock& clock, ReadTicks read_ticks) noexcept {
  Reading best;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const Nanoseconds before = clock.now();
    const std::uint64_t ticks = read_ticks();
    const Nanoseconds after = clock.now();
    if (after - before < best.bracket) best = Reading{ticks, before + (after - before) / 2, after - before};
  }
  return best;
}

template <typename ReadTicks>
double calibrate_against_monotonic(Nanoseconds duration, ReadTicks read_ticks) noexcept {
  MonotonicClock clock;
  const Reading first = best_reading(clock, read_ticks);
  // Both counters run on whether this thread runs or sleeps: only the two readings need to be
  // tight (best_reading's brackets), so the interval is slept, not spun (a spin held a CPU for the
  // whole interval, and during run's bring-up that CPU is the one the rest of the start-up needs).
  clock.sleep_until(first.ns + duration);
  const Reading second = best_reading(clock, read_ticks);
  return ticks_per_ns_between(first.ticks, first.ns, second.ticks, second.ns);
}

}  // namespace

const char* to_string(TimerSource source) noexcept {
  switch (source) {
    case TimerSource::tsc: return "tsc";
    case TimerSource::arm_counter: return "arm_counter";
    case TimerSource::clock_gettime: return "clock_gettime";
  }
  return "unknown";
}

TscTimer TscTimer::monotonic_fallback(const char* reason) noexcept {
  return {TimerSource::clock_gettime, reason, 1.0, false};
}

TscTimer TscTimer::calibrate(Nanoseconds calibration) noexcept {
#if defined(__x86_64__) || defined(__i386__)
  unsigned int eax = 0;
  unsigned int ebx = 0;
  unsigned int ecx = 0;
  unsigned int edx = 0;
  // __get_cpuid checks the maximum extended leaf first and fails when it is below the one asked.
  if (__get_cpuid(0x80000007U, &eax, &ebx, &ecx, &edx) == 0) {
    return monotonic_fallback("CPUID leaf 0x80000007 absent: TSC invariance unknown");
  }
  if (!invariant_tsc_bit(edx)) return monotonic_fallback("TSC not invariant (CPUID 0x80000007 EDX bit 8 clear)");
  const bool rdtscp = __get_cpuid(0x80000001U, &eax, &ebx, &ecx, &edx) != 0 && rdtscp_bit(edx);
  const double ratio = calibrate_against_monotonic(calibration, [] { return tsc_start(); });
  if (!(ratio > 0.0)) return monotonic_fallback("TSC calibration failed (counter did not advance)");
  return {TimerSource::tsc, rdtscp ? "invariant TSC, RDTSCP" : "invariant TSC, no RDTSCP (LFENCE;RDTSC at stop)", ratio,
          rdtscp};
#elif defined(__aarch64__)
  std::uint64_t frequency = 0;
  asm volatile("mrs %0, cntfrq_el0" : "=r"(frequency));
  if (frequency == 0) {
    const double ratio = calibrate_against_monotonic(calibration, [] { return arm_counter_read(); });
    if (!(ratio > 0.0)) return monotonic_fallback("CNTFRQ_EL0 is 0 and CNTVCT_EL0 did not advance");
    return {TimerSource::arm_counter, "CNTVCT_EL0, calibrated (CNTFRQ_EL0 is 0)", ratio, false};
  }
  (void)calibration;  // the architecture states the rate
  return {TimerSource::arm_counter, "CNTVCT_EL0 at CNTFRQ_EL0",
          static_cast<double>(frequency) / static_cast<double>(kNsPerSec), false};
#else
  (void)calibration;
  return monotonic_fallback("no cycle counter on this architecture");
#endif
}

}  // namespace rescue::hal
