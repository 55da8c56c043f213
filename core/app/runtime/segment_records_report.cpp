#include "core/app/runtime/segment_records_report.hpp"

#include <cinttypes>
#include <limits>

#include "core/app/links/task_links.hpp"

namespace rescue::app {
namespace {

// The summary's key of each StatTask slot.
const char* const kTaskKeys[kRunHealthSlots] = {"ethercat_handler", "joint_manager", "socket_handler",
                                                "message_parser",   "rc_rescue",     "rc_teleop"};

}  // namespace

std::uint64_t damaged_records_of(const EthercatHandler& handler) noexcept {
  return handler.damaged_demands() + handler.tracker().damaged_notices() + handler.sdo_relay().damaged_requests() +
         handler.motion_intake().counters().damaged_beats;
}
std::uint64_t damaged_records_of(const JointManager& manager) noexcept { return manager.damaged_records(); }
std::uint64_t damaged_records_of(const MessageParser& parser) noexcept { return parser.damaged_beats(); }
std::uint64_t damaged_records_of(const RcTaskCounters& rc) noexcept { return rc.damaged_inputs; }
std::uint64_t damaged_records_of(const SocketHandler& socket) noexcept { return socket.damaged_records(); }

void publish_damaged_records(TaskHealth& slot, std::uint64_t total, std::uint64_t& published) noexcept {
  if (total == published) return;
  const std::uint64_t added = total - published;
  published = total;
  const std::uint32_t now = slot.damaged_records.load(std::memory_order_relaxed);
  const std::uint64_t sum = static_cast<std::uint64_t>(now) + added;
  const std::uint64_t most = std::numeric_limits<std::uint32_t>::max();
  slot.damaged_records.store(static_cast<std::uint32_t>(sum < most ? sum : most), std::memory_order_relaxed);
}

void print_segment_records_refused(std::FILE* out, const RunControl& run, std::uint64_t supervisor_damaged_beats,
                                   bool operator_port) noexcept {
  std::uint64_t total = supervisor_damaged_beats;
  for (std::size_t k = 0; k < kRunHealthSlots; ++k) {
    if (!operator_port && static_cast<StatTask>(k) == StatTask::socket_handler) {
      (void)std::fprintf(out, "segment_records_refused_%s: n/a\n", kTaskKeys[k]);
      continue;
    }
    const std::uint32_t n = run.health[k].damaged_records.load(std::memory_order_relaxed);
    total += n;
    (void)std::fprintf(out, "segment_records_refused_%s: %" PRIu32 "\n", kTaskKeys[k], n);
  }
  (void)std::fprintf(out, "segment_records_refused_supervisor: %" PRIu64 "\n", supervisor_damaged_beats);
  (void)std::fprintf(out, "segment_records_refused: %" PRIu64 "\n", total);
}

}  // namespace rescue::app
