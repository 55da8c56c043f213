#include "core/app/cli/ctl_deadline.hpp"

#include <sys/time.h>
#include <unistd.h>

#include <csignal>

#include "core/app/cli/ctl_output.hpp"

namespace rescue::app {
namespace {

void ctl_deadline_passed(int /*signal*/) {
  static const char kText[] =
      "rescue-motion ctl: stopped: no result within --timeout (a file or the network blocked)\n";
  (void)!::write(STDERR_FILENO, kText, sizeof kText - 1);
  ::_exit(static_cast<int>(CtlExit::unreachable));
}

}  // namespace

void arm_ctl_deadline(double seconds) noexcept {
  struct sigaction action {};
  action.sa_handler = ctl_deadline_passed;
  (void)::sigaction(SIGALRM, &action, nullptr);
  itimerval timer{};
  const double total = seconds + 0.5;  // the exchange's own deadline comes first
  timer.it_value.tv_sec = static_cast<time_t>(total);
  timer.it_value.tv_usec = static_cast<suseconds_t>((total - static_cast<double>(timer.it_value.tv_sec)) * 1e6);
  (void)::setitimer(ITIMER_REAL, &timer, nullptr);
}

void disarm_ctl_deadline() noexcept {
  itimerval timer{};
  (void)::setitimer(ITIMER_REAL, &timer, nullptr);
}

}  // namespace rescue::app
