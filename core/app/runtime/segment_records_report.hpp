// The records of the shared segment each task refused as damaged (docs/shared-memory.md "Records:
// what each reader checks"): what each task counts, published live in its health slot
// (TaskHealth::damaged_records), and the end-of-run report's lines, so a refusal counted deep in a
// task is seen by the operator. No heap.
#pragma once

#include <cstdint>
#include <cstdio>

#include "core/app/links/run_control.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/message_parser.hpp"
#include "core/app/tasks/rc_task_frame.hpp"
#include "core/app/tasks/socket_handler.hpp"

namespace rescue::app {

// Each task's running total: the handler's demands, notices, SDO requests and owner heartbeats; the
// joint manager's commands and reports; the parser's RC heartbeats; an RC task's inputs; the socket
// handler's SDO results.
std::uint64_t damaged_records_of(const EthercatHandler& handler) noexcept;
std::uint64_t damaged_records_of(const JointManager& manager) noexcept;
std::uint64_t damaged_records_of(const MessageParser& parser) noexcept;
std::uint64_t damaged_records_of(const RcTaskCounters& rc) noexcept;
std::uint64_t damaged_records_of(const SocketHandler& socket) noexcept;

// Adds to `slot` what this process's task counted since it last published (`published`: this
// process's own, so a restarted task process adds its count to its predecessors'). Saturates.
void publish_damaged_records(TaskHealth& slot, std::uint64_t total, std::uint64_t& published) noexcept;

// `key: value` lines of the run's summary: `segment_records_refused_TASK` per task (the socket
// handler n/a when the run has no operator port), `segment_records_refused_supervisor` (its
// liveness watch), and
// `segment_records_refused` (all of them).
void print_segment_records_refused(std::FILE* out, const RunControl& run, std::uint64_t supervisor_damaged_beats,
                                   bool operator_port) noexcept;

}  // namespace rescue::app
