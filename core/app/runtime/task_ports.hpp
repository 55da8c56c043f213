// How a task reaches the tasks' shared state (docs/architecture.md, "How a task reaches shared
// state"): through its ports, and every task's ports over one TaskLinks are built here and nowhere
// else. A task is constructed from its ports, so its constructor shows its inputs and outputs; it
// sees only the queues, seqlocks and words it uses, at the end it uses them: a queue's sink
// (producer) or source (consumer), a seqlock it writes (Seqlock*) or reads (const Seqlock*).
// run_firmware builds one over the shared-memory segment (a forked task process finds it at the
// same address); the benches and the tests' rigs build one over their own TaskLinks, so every task
// is wired as `run` wires it. No heap: the queue ends live in this object.
#pragma once

#include <array>

#include "core/app/links/joint_demand_sink.hpp"
#include "core/app/links/joint_sample_source.hpp"
#include "core/app/links/task_links.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/error_joints_worker.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/message_parser.hpp"
#include "core/app/tasks/motion_intake.hpp"
#include "core/app/tasks/rc_task_frame.hpp"
#include "core/app/tasks/socket_handler.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "core/concurrency/spsc_queue.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {

// The Motion intake's ports (the EtherCAT handler's, and a test's intake of its own): pointers
// only, nothing to own.
MotionIntakePorts motion_intake_ports(TaskLinks& links) noexcept;

// What a task's period loop (runtime/task_loops.cpp) reaches around its object, for every task: its
// heartbeat (the supervisor's liveness watch, the socket handler's age of figures), its timing for
// ctl tasks, its health slot, and the run's coordination (start and stop words, drop counters,
// end-of-run figures, run_control.hpp).
struct TaskLoopPorts {
  std::atomic<std::int64_t>* heartbeat_ns{nullptr};  // its slot of TaskLinks::task_heartbeat_ns
  Seqlock<TaskStat>* stats{nullptr};                 // its slot of TaskLinks::task_stats
  TaskHealth* health{nullptr};                       // its slot of RunControl::health
  RunControl* run{nullptr};
  // The EtherCAT handler's loop only (null for the others): the rescue RC task's state, whose
  // motion's end ends a rescue scenario.
  const Seqlock<RcTaskState>* rescue_state{nullptr};
};

class TaskPorts {
 public:
  explicit TaskPorts(TaskLinks& links) noexcept;
  TaskPorts(const TaskPorts&) = delete;
  TaskPorts& operator=(const TaskPorts&) = delete;
  TaskPorts(TaskPorts&&) = delete;
  TaskPorts& operator=(TaskPorts&&) = delete;
  ~TaskPorts() = default;

  EthercatHandlerPorts ethercat_handler() noexcept;
  RcTaskPorts rc_task(RcTaskId task) noexcept;
  MessageParserPorts message_parser() noexcept;
  // The joint manager's ports: TaskLinks', the queues to its storage worker (here too: the worker is a
  // thread of the joint manager's process, tasks/error_joints_worker.hpp), and what is its own: the
  // error-joints file's storage, Unix time, its events.
  JointManagerPorts joint_manager(ErrorJointsStorage& storage, hal::WallClock& wall, JointEventSink& events) noexcept;
  // The storage worker's ends of those queues.
  MessageSource<ErrorJointsSaveRequest>& storage_worker_requests() noexcept { return worker_requests_; }
  MessageSink<ErrorJointsSaveResult>& storage_worker_results() noexcept { return worker_results_; }
  // What the socket handler reaches of TaskLinks; stale_after, rc_tasks and version (the run's
  // settings, not shared state) are the caller's to add.
  SocketHandlerPorts socket_handler() noexcept;
  // The period loop's ports of the task that publishes its timing in `slot`.
  TaskLoopPorts task_loop(StatTask slot) noexcept;

 private:
  template <typename T, std::size_t N>
  using Sink = SpscMessageSink<T, N>;
  template <typename T, std::size_t N>
  using Source = SpscMessageSource<T, N>;
  // The joint manager has one write in flight at a time: two slots.
  static constexpr std::size_t kSaveQueueDepth = 2;

  // Largest and most aligned first: the storage worker's queues (their indices on cache lines of their own).
  SpscQueue<ErrorJointsSaveRequest, kSaveQueueDepth> save_request_queue_;
  SpscQueue<ErrorJointsSaveResult, kSaveQueueDepth> save_result_queue_;
  TaskLinks& links_;
  // EtherCAT handler <-> joint manager (reconfiguration steps 1 and 4).
  Sink<LostJointsReport, TaskLinks::kReportQueueDepth> handler_reports_;
  Source<JointManagerNotice, TaskLinks::kNoticeQueueDepth> handler_notices_;
  Source<LostJointsReport, TaskLinks::kReportQueueDepth> manager_reports_;
  Sink<JointManagerNotice, TaskLinks::kNoticeQueueDepth> manager_notices_;
  // Message parser -> joint manager (the joint handle queue) and back (outcomes).
  Sink<JointCommand, TaskLinks::kCommandQueueDepth> parser_commands_;
  Source<JointCommand, TaskLinks::kCommandQueueDepth> manager_commands_;
  Sink<JointCommandOutcome, TaskLinks::kOutcomeQueueDepth> manager_outcomes_;
  Source<JointCommandOutcome, TaskLinks::kOutcomeQueueDepth> parser_outcomes_;
  SeqlockSampleSource manager_samples_;
  SeqlockDemandSink manager_demand_;
  // Joint manager <-> its storage worker.
  Sink<ErrorJointsSaveRequest, kSaveQueueDepth> save_requests_;
  Source<ErrorJointsSaveResult, kSaveQueueDepth> save_results_;
  Source<ErrorJointsSaveRequest, kSaveQueueDepth> worker_requests_;
  Sink<ErrorJointsSaveResult, kSaveQueueDepth> worker_results_;
  // Socket handler and runtime -> message parser, and back.
  Sink<ControlRequest, TaskLinks::kRequestQueueDepth> socket_requests_;
  Source<ControlRequest, TaskLinks::kRequestQueueDepth> parser_network_;
  Source<ControlRequest, TaskLinks::kRequestQueueDepth> parser_local_;
  Sink<ControlReply, TaskLinks::kReplyQueueDepth> parser_replies_;
  Source<ControlReply, TaskLinks::kReplyQueueDepth> socket_replies_;
  Sink<ControlReply, TaskLinks::kReplyQueueDepth> parser_local_replies_;
  // Socket handler <-> EtherCAT handler: ctl upload/download and their answers.
  Sink<SdoLinkRequest, config::kSdoQueueDepth> socket_sdo_requests_;
  Source<SdoLinkRequest, config::kSdoQueueDepth> handler_sdo_requests_;
  Sink<SdoLinkResult, config::kSdoQueueDepth> handler_sdo_results_;
  Source<SdoLinkResult, config::kSdoQueueDepth> socket_sdo_results_;
  // Socket handler <-> EtherCAT handler: ctl reg_read and its answer.
  Sink<RegReadLinkRequest, config::kRegQueueDepth> socket_reg_requests_;
  Source<RegReadLinkRequest, config::kRegQueueDepth> handler_reg_requests_;
  Sink<RegReadLinkResult, config::kRegQueueDepth> handler_reg_results_;
  Source<RegReadLinkResult, config::kRegQueueDepth> socket_reg_results_;
  // Socket handler <-> EtherCAT handler: ctl states and its answer.
  Sink<StatesLinkRequest, config::kStatesQueueDepth> socket_states_requests_;
  Source<StatesLinkRequest, config::kStatesQueueDepth> handler_states_requests_;
  Sink<StatesLinkResult, config::kStatesQueueDepth> handler_states_results_;
  Source<StatesLinkResult, config::kStatesQueueDepth> socket_states_results_;
  // Socket handler <-> EtherCAT handler: ctl rescan and its answer.
  Sink<RescanLinkRequest, config::kRescanQueueDepth> socket_rescan_requests_;
  Source<RescanLinkRequest, config::kRescanQueueDepth> handler_rescan_requests_;
  Sink<RescanLinkResult, config::kRescanQueueDepth> handler_rescan_results_;
  Source<RescanLinkResult, config::kRescanQueueDepth> socket_rescan_results_;
  // Message parser -> RC task k.
  std::array<Sink<RcTaskInput, TaskLinks::kRcInputQueueDepth>, protocol::kMaxRcTasks> parser_rc_inputs_;
  std::array<Source<RcTaskInput, TaskLinks::kRcInputQueueDepth>, protocol::kMaxRcTasks> rc_inputs_;
};

}  // namespace rescue::app
