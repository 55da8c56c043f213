#include "core/app/tasks/joint_event_printer.hpp"

namespace rescue::app {

void JointEventPrinter::print(const JointEvent& event) noexcept {
  char line[512];
  (void)format_event(event, line, sizeof line);
  const double t = static_cast<double>(event.time - origin_) / static_cast<double>(hal::kNsPerSec);
  (void)std::fprintf(out_, "[%8.3f s] %s%s\n", t, prefix_, line);
}

}  // namespace rescue::app
