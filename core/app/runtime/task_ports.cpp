// TaskPorts (task_ports.hpp): every task's ports over one TaskLinks.
#include "core/app/runtime/task_ports.hpp"

namespace rescue::app {

MotionIntakePorts motion_intake_ports(TaskLinks& links) noexcept {
  MotionIntakePorts p;
  p.references = &links.motion.references;
  p.owner = &links.motion.owner;
  p.rc_heartbeat_ns = &links.rc_heartbeat_ns;
  p.owner_misses = &links.motion.owner_misses;
  p.owner_releases = &links.motion.owner_releases;
  p.owner_joints = &links.motion.owner_joints;
  return p;
}

static_assert(protocol::kMaxRcTasks == 4, "one queue end per RC task below");
TaskPorts::TaskPorts(TaskLinks& links) noexcept
    : links_(links),
      handler_reports_(links.lost_reports),
      handler_notices_(links.notices),
      manager_reports_(links.lost_reports),
      manager_notices_(links.notices),
      parser_commands_(links.joint_commands),
      manager_commands_(links.joint_commands),
      manager_outcomes_(links.command_outcomes),
      parser_outcomes_(links.command_outcomes),
      manager_samples_(links.samples),
      manager_demand_(links.demand),
      save_requests_(save_request_queue_),
      save_results_(save_result_queue_),
      worker_requests_(save_request_queue_),
      worker_results_(save_result_queue_),
      socket_requests_(links.control_requests),
      parser_network_(links.control_requests),
      parser_local_(links.local_requests),
      parser_replies_(links.control_replies),
      socket_replies_(links.control_replies),
      parser_local_replies_(links.local_replies),
      socket_sdo_requests_(links.sdo_requests),
      handler_sdo_requests_(links.sdo_requests),
      handler_sdo_results_(links.sdo_results),
      socket_sdo_results_(links.sdo_results),
      socket_reg_requests_(links.reg_requests),
      handler_reg_requests_(links.reg_requests),
      handler_reg_results_(links.reg_results),
      socket_reg_results_(links.reg_results),
      socket_states_requests_(links.states_requests),
      handler_states_requests_(links.states_requests),
      handler_states_results_(links.states_results),
      socket_states_results_(links.states_results),
      socket_rescan_requests_(links.rescan_requests),
      handler_rescan_requests_(links.rescan_requests),
      handler_rescan_results_(links.rescan_results),
      socket_rescan_results_(links.rescan_results),
      parser_rc_inputs_{{Sink<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[0]),
                         Sink<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[1]),
                         Sink<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[2]),
                         Sink<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[3])}},
      rc_inputs_{{Source<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[0]),
                  Source<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[1]),
                  Source<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[2]),
                  Source<RcTaskInput, TaskLinks::kRcInputQueueDepth>(links.rc_inputs[3])}} {}

EthercatHandlerPorts TaskPorts::ethercat_handler() noexcept {
  EthercatHandlerPorts p;
  p.demand = &links_.demand;
  p.samples = &links_.samples;
  p.reports = &handler_reports_;
  p.notices = &handler_notices_;
  p.motion = motion_intake_ports(links_);
  p.sdo_requests = &handler_sdo_requests_;
  p.sdo_results = &handler_sdo_results_;
  p.reg_requests = &handler_reg_requests_;
  p.reg_results = &handler_reg_results_;
  p.states_requests = &handler_states_requests_;
  p.states_results = &handler_states_results_;
  p.rescan_requests = &handler_rescan_requests_;
  p.rescan_results = &handler_rescan_results_;
  p.master_status = &links_.master_status;
  p.link_diag = &links_.link_diag;
  p.slave_info = &links_.slave_info;
  p.diag_reset = &links_.diag_reset;
  p.sii_images = &links_.sii_images;
  return p;
}

RcTaskPorts TaskPorts::rc_task(RcTaskId task) noexcept {
  const auto k = static_cast<std::size_t>(task);
  RcTaskPorts p;
  p.samples = &links_.samples;
  p.joint_status = &links_.joint_status;
  p.inputs = &rc_inputs_[k];
  p.owner = &links_.motion.owner;
  p.references = &links_.motion.references[k];
  p.state = &links_.motion.task_state[k];
  p.heartbeat_ns = &links_.rc_heartbeat_ns[k];
  return p;
}

MessageParserPorts TaskPorts::message_parser() noexcept {
  MessageParserPorts p;
  p.network = &parser_network_;
  p.local = &parser_local_;
  p.network_replies = &parser_replies_;
  p.local_replies = &parser_local_replies_;
  p.joint_commands = &parser_commands_;
  p.outcomes = &parser_outcomes_;
  p.samples = &links_.samples;
  p.joint_status = &links_.joint_status;
  for (std::size_t k = 0; k < protocol::kMaxRcTasks; ++k) p.rc_inputs[k] = &parser_rc_inputs_[k];
  p.rc_heartbeat_ns = &links_.rc_heartbeat_ns;
  p.owner = &links_.motion.owner;
  return p;
}

JointManagerPorts TaskPorts::joint_manager(ErrorJointsStorage& storage, hal::WallClock& wall, JointEventSink& events) noexcept {
  JointManagerPorts p{};
  p.storage = &storage;
  p.wall_clock = &wall;
  p.events = &events;
  p.save_requests = &save_requests_;
  p.save_results = &save_results_;
  p.reports = &manager_reports_;
  p.notices = &manager_notices_;
  p.commands = &manager_commands_;
  p.samples = &manager_samples_;
  p.demand = &manager_demand_;
  p.outcomes = &manager_outcomes_;
  p.joint_status = &links_.joint_status;
  return p;
}

SocketHandlerPorts TaskPorts::socket_handler() noexcept {
  SocketHandlerPorts p;
  p.requests = &socket_requests_;
  p.replies = &socket_replies_;
  p.sensors = &links_.sensors;
  p.counters = &links_.socket_counters;
  p.samples = &links_.samples;
  p.joint_status = &links_.joint_status;
  p.master = &links_.master_status;
  p.diag = &links_.link_diag;
  p.slave_info = &links_.slave_info;
  p.diag_reset = &links_.diag_reset;
  p.sii_images = &links_.sii_images;
  p.tasks = &links_.task_stats;
  p.drops = &links_.run.dropped;
  p.health = &links_.run.health;
  p.motion = &links_.motion;
  p.handler_heartbeat = &links_.task_heartbeat_ns[static_cast<std::size_t>(StatTask::ethercat_handler)];
  p.rc_heartbeat_ns = &links_.rc_heartbeat_ns;
  p.sdo_requests = &socket_sdo_requests_;
  p.sdo_results = &socket_sdo_results_;
  p.reg_requests = &socket_reg_requests_;
  p.reg_results = &socket_reg_results_;
  p.states_requests = &socket_states_requests_;
  p.states_results = &socket_states_results_;
  p.rescan_requests = &socket_rescan_requests_;
  p.rescan_results = &socket_rescan_results_;
  return p;
}

TaskLoopPorts TaskPorts::task_loop(StatTask slot) noexcept {
  const auto k = static_cast<std::size_t>(slot);
  TaskLoopPorts p;
  p.heartbeat_ns = &links_.task_heartbeat_ns[k];
  p.stats = &links_.task_stats[k];
  p.health = &links_.run.health[k];
  p.run = &links_.run;
  if (slot == StatTask::ethercat_handler) p.rescue_state = &links_.motion.task_state[static_cast<std::size_t>(RcTaskId::rescue)];
  return p;
}

}  // namespace rescue::app
