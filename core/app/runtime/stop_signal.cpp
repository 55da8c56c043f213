#include "core/app/runtime/stop_signal.hpp"

#include <csignal>

namespace rescue::app {
namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) { g_stop_signal = signal_number; }

}  // namespace

bool install_stop_handlers() noexcept {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  (void)sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  return sigaction(SIGINT, &action, nullptr) == 0 && sigaction(SIGTERM, &action, nullptr) == 0;
}

int stop_signal() noexcept { return static_cast<int>(g_stop_signal); }

}  // namespace rescue::app
