// The logger's print passes (docs/firmware.md): the handler's side (its events, OP reached, the
// scenario's failure, captured frames to the file), the joint manager's side (its events), and what the
// operator's side prints of the segment (the motion's owner and RC task phases, the replies to its
// local requests). Nothing here runs on a real-time thread.
#pragma once

#include <array>
#include <cstdint>

#include "core/app/links/task_links.hpp"
#include "core/app/tasks/joint_event_printer.hpp"
#include "core/app/tasks/joint_event_queue.hpp"
#include "core/base/result.hpp"
#include "hal/time/clock.hpp"

namespace rescue::app::runner {

// The logger's side of the joint manager's events: prints what is queued, and how many a full queue
// dropped since the last pass.
void print_joint_events(JointEventQueue& events, JointEventPrinter& printer) noexcept;

// What the logger last printed of the motion (owner, RC task modes and phases).
struct MotionLog {
  std::uint64_t owner_word{MotionOwner::kNobody};
  std::array<RcTaskState, kRcTasksRun> last{};
  std::array<bool, kRcTasksRun> seen{};
  std::uint8_t rescue_phase_reached{0};
};

// The motion as the segment shows it at one instant (read before anything else of the pass is
// printed: a line caused by the motion never comes before the line of its cause).
struct MotionSnapshot {
  std::uint64_t owner_word{MotionOwner::kNobody};
  std::array<RcTaskState, kRcTasksRun> state{};
  std::array<bool, kRcTasksRun> read{};
};

MotionSnapshot read_motion() noexcept;
void print_motion_changes(MotionLog& log, const MotionSnapshot& snap, hal::Nanoseconds at) noexcept;
// The message parser's replies to the operator side's local requests (clear, initialize, owner, disable).
void print_local_replies(hal::Nanoseconds at) noexcept;

// After the tasks stopped: the frames still queued are written, the figures printed, the file closed.
Status finish_capture(const char* path) noexcept;

// The handler's side of the logger (in the handler's process: its events and capture queue are its
// own): the scenario's action, OP reached, handler events, captured frames to the file.
void handler_side_pass() noexcept;
// After the handler's loop (in its process): when the network never reached OP, one line saying so
// and the master's report (the slave that refused or did not follow, its AL status code).
void report_if_never_in_op() noexcept;
// The joint manager's side of the logger (in its process, or the main thread with --threads).
void manager_side_pass() noexcept;

}  // namespace rescue::app::runner
