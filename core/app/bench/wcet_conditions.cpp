#include "core/app/bench/wcet_conditions.hpp"

#include <sys/utsname.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include "core/app/bench/bench_header.hpp"
#include "core/app/bench/rt_duty_rest.hpp"

namespace rescue::app {

void read_load_average(char* out, std::size_t size) noexcept {
  (void)std::snprintf(out, size, "n/a");
  std::FILE* loadavg = std::fopen("/proc/loadavg", "r");
  if (loadavg == nullptr) return;
  char line[128];
  if (std::fgets(line, sizeof line, loadavg) != nullptr) {
    // The first three fields as the kernel wrote them: "0.52 0.58 0.59 1/123 4567".
    std::size_t end = 0;
    for (int field = 0; field < 3 && line[end] != '\0'; ++field) {
      end += std::strspn(line + end, " ");
      end += std::strcspn(line + end, " \n");
    }
    if (end > 0) (void)std::snprintf(out, size, "%.*s", static_cast<int>(end), line);
  }
  (void)std::fclose(loadavg);
}

void describe_wcet_conditions(char* out, std::size_t size, const char* load_at_start, bool real_time, bool rt_applied) noexcept {
  utsname system{};
  const bool have_uname = ::uname(&system) == 0;
  char load_at_end[64];
  read_load_average(load_at_end, sizeof load_at_end);
  char throttle[64];
  RtDutyRest::describe_throttle(throttle, sizeof throttle);
  (void)std::snprintf(out, size,
                      "kernel %s, PREEMPT_RT %s, %ld CPUs online, load average (1 5 15 min) %s at start, %s at end, "
                      "real-time set-up %s, real-time throttling %s (rested 10 ms every 100 ms)",
                      have_uname ? system.release : "n/a", kernel_is_preempt_rt() ? "yes" : "no", ::sysconf(_SC_NPROCESSORS_ONLN),
                      load_at_start, load_at_end, !real_time ? "normal scheduling (--scheduling normal: no SCHED_FIFO, no CPU pinning)"
                      : rt_applied ? "applied (SCHED_FIFO, CPU pinned, memory locked)" : "not all applied (see rt: lines)", throttle);
}

}  // namespace rescue::app
