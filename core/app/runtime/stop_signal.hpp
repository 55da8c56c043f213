// SIGINT and SIGTERM as a flag the program's loops poll: the clean way out of `run` and `sim`
// (drives disabled, state saved, counters printed). Installed without SA_RESTART, so a blocking
// receive wait returns early when a signal arrives.
#pragma once

namespace rescue::app {

// False when the OS refused to install the handlers.
[[nodiscard]] bool install_stop_handlers() noexcept;
// The signal that asked to stop, 0 while none has.
int stop_signal() noexcept;

}  // namespace rescue::app
