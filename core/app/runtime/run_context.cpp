// The one RunContext of the process (run_context.hpp says why it is a global).
#include "core/app/runtime/run_context.hpp"

#include <unistd.h>

#include <array>

#include "core/app/runtime/task_cpu.hpp"

namespace rescue::app::runner {

RunContext g_run;

void observe_task_cpu(hal::Clock& clock, bool done) noexcept {
  RunControl& state = run_control();
  std::array<int, kRunHealthSlots + 1> pids{};
  pids[0] = static_cast<int>(::getpid());
  for (std::size_t k = 0; k < kRunHealthSlots; ++k) pids[k + 1] = state.health[k].pid.load(std::memory_order_relaxed);
  // Moving: an RC task's references drove joints in the handler's last period (the Motion owner's).
  const bool moving = shared_links().motion.owner_joints.load(std::memory_order_relaxed) != 0;
  run_task_cpu().observe(Span<const int>(pids.data(), pids.size()), clock, moving, done);
}

}  // namespace rescue::app::runner
