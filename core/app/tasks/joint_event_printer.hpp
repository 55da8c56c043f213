// Prints the joint manager's events, one line each, to a stdio stream: what `rescue-motion run` shows
// ("error-joints file: restored ...", "reconfiguration step 3: ...", "l_elbow: Enabled --comm_lost--> Error").
// It is not an event sink: in the firmware the joint manager's sink is a JointEventQueue
// (joint_event_queue.hpp) and the logger thread prints what it pops, so the joint manager's
// real-time thread never formats, never takes the stdio lock and never waits on a terminal.
#pragma once

#include <cstdio>

#include "core/app/tasks/joint_events.hpp"

namespace rescue::app {

class JointEventPrinter {
 public:
  // `prefix` starts every line (e.g. "joint-manager: "); `out` must outlive the printer.
  JointEventPrinter(std::FILE* out, const char* prefix) noexcept : out_(out), prefix_(prefix) {}
  void print(const JointEvent& event) noexcept;
  // Times print relative to `origin` (the program's start), as the other tasks' lines do.
  void set_origin(hal::Nanoseconds origin) noexcept { origin_ = origin; }

 private:
  std::FILE* out_;
  const char* prefix_;
  hal::Nanoseconds origin_{0};
};

}  // namespace rescue::app
