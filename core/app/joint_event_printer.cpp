#include "core/app/joint_event_printer.hpp"

namespace rescue::app {

void JointEventPrinter::on_event(const JointEvent& event) noexcept {
  char line[512];
  (void)format_event(event, line, sizeof line);
  std::fprintf(out_, "%s[%lld.%03lld s] %s\n", prefix_, static_cast<long long>(event.time / hal::kNsPerSec),
               static_cast<long long>((event.time % hal::kNsPerSec) / hal::kNsPerMs), line);
}

}  // namespace rescue::app
