// Prints the joint manager's events, one line each, to a stdio stream: what `rescue-motion run` shows
// ("error-joints file: restored ...", "reconfiguration step 3: ...", "l_elbow: Enabled --comm_lost--> Error").
// Formatting happens in the caller's thread; in the firmware the events are queued to a low-priority
// logger first, so the joint manager never waits on a terminal.
#pragma once

#include <cstdio>

#include "core/app/tasks/joint_events.hpp"

namespace rescue::app {

class JointEventPrinter final : public JointEventSink {
 public:
  // `prefix` starts every line (e.g. "joint-manager: "); `out` must outlive the printer.
  JointEventPrinter(std::FILE* out, const char* prefix) noexcept : out_(out), prefix_(prefix) {}
  void on_event(const JointEvent& event) noexcept override;
  // Times print relative to `origin` (the program's start), as the other tasks' lines do.
  void set_origin(hal::Nanoseconds origin) noexcept { origin_ = origin; }

 private:
  std::FILE* out_;
  const char* prefix_;
  hal::Nanoseconds origin_{0};
};

}  // namespace rescue::app
