// TaskPorts (core/app/runtime/task_ports.hpp), where every task's ports are built: each queue's
// producer end reaches its consumer's end, each RC task gets its own input queue, reference space,
// state and heartbeat, the socket handler's SDO requests reach the EtherCAT handler and its answers
// come back, the seqlocks a task only reads are the ones the writer publishes (the handler's figures
// for the operator, the joint manager's status), and each task's loop gets its own heartbeat, timing
// and health slot.
#include <gtest/gtest.h>

#include <memory>

#include "core/app/runtime/task_ports.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app {
namespace {

class NoEvents final : public JointEventSink {
 public:
  void on_event(const JointEvent&) noexcept override {}
};

// Sends `message` into a producer's end and takes what comes out of the consumer's end.
template <typename T>
T through(MessageSink<T>* in, MessageSource<T>* out, const T& message) {
  EXPECT_TRUE(in->try_send(message));
  T got{};
  EXPECT_TRUE(out->try_receive(got));
  return got;
}

struct Rig {
  std::unique_ptr<TaskLinks> links = std::make_unique<TaskLinks>();
  std::unique_ptr<TaskPorts> ports = std::make_unique<TaskPorts>(*links);
  ErrorJointsFileStorage storage{"/nonexistent"};  // never touched here
  hal::ManualWallClock wall;
  NoEvents events;
};

TEST(TaskPorts, TheHandlerAndTheJointManagerMeetOnTheReportAndNoticeQueues) {
  Rig rig;
  const EthercatHandlerPorts handler = rig.ports->ethercat_handler();
  const JointManagerPorts manager = rig.ports->joint_manager(rig.storage, rig.wall, rig.events);
  EXPECT_EQ(through(handler.reports, manager.reports, LostJointsReport{0x5, 7, 0, 0}).cycle, 7U);
  JointManagerNotice notice{};
  notice.joints = 0x5;
  EXPECT_EQ(through(manager.notices, handler.notices, notice).joints, 0x5U);
  // The handler publishes the samples the joint manager reads; it reads the demand the manager publishes.
  RobotSample sample{};
  sample[3].position_rad = 0.25;
  handler.samples->write(sample);
  RobotSample read{};
  ASSERT_TRUE(manager.samples->read(read));
  EXPECT_DOUBLE_EQ(read[3].position_rad, 0.25);
  RobotDemand demand{};
  demand[2].position_ref_rad = -0.5;
  manager.demand->publish(demand);
  RobotDemand taken{};
  ASSERT_TRUE(handler.demand->try_read(taken));
  EXPECT_DOUBLE_EQ(taken[2].position_ref_rad, -0.5);
  // The handler's intake sees the motion's part of the same links.
  EXPECT_EQ(handler.motion.owner, &rig.links->motion.owner);
  EXPECT_EQ(handler.motion.references, &rig.links->motion.references);
  EXPECT_EQ(handler.motion.rc_heartbeat_ns, &rig.links->rc_heartbeat_ns);
}

TEST(TaskPorts, TheParserReachesTheJointManagerAndEachRcTaskOnItsOwnQueue) {
  Rig rig;
  const MessageParserPorts parser = rig.ports->message_parser();
  const JointManagerPorts manager = rig.ports->joint_manager(rig.storage, rig.wall, rig.events);
  JointCommand command{};
  command.joints = 0x3;
  EXPECT_EQ(through(parser.joint_commands, manager.commands, command).joints, 0x3U);
  JointCommandOutcome outcome{};
  outcome.request = 9;
  EXPECT_EQ(through(manager.outcomes, parser.outcomes, outcome).request, 9U);

  const RcTaskPorts rescue = rig.ports->rc_task(RcTaskId::rescue);
  const RcTaskPorts teleop = rig.ports->rc_task(RcTaskId::teleop);
  RcTaskInput input{};
  input.sequence = 42;
  ASSERT_TRUE(parser.rc_inputs[1]->try_send(input));
  RcTaskInput out{};
  EXPECT_FALSE(rescue.inputs->try_receive(out)) << "task 1's input is not task 0's";
  ASSERT_TRUE(teleop.inputs->try_receive(out));
  EXPECT_EQ(out.sequence, 42U);
  input.sequence = 43;
  EXPECT_EQ(through(parser.rc_inputs[0], rescue.inputs, input).sequence, 43U);
  EXPECT_EQ(rescue.references, &rig.links->motion.references[0]);
  EXPECT_EQ(teleop.references, &rig.links->motion.references[1]);
  EXPECT_EQ(teleop.state, &rig.links->motion.task_state[1]);
  EXPECT_EQ(teleop.heartbeat_ns, &rig.links->rc_heartbeat_ns[1]);
  EXPECT_EQ(teleop.owner, parser.owner);
  EXPECT_EQ(teleop.samples, parser.samples);
  EXPECT_EQ(teleop.joint_status, parser.joint_status);
}

TEST(TaskPorts, TheSocketHandlerAndTheParserMeetOnTheRequestAndReplyQueues) {
  Rig rig;
  const SocketHandlerPorts socket = rig.ports->socket_handler();
  const MessageParserPorts parser = rig.ports->message_parser();
  ControlRequest request{};
  request.sequence = 5;
  ASSERT_TRUE(socket.requests->try_send(request));
  ControlRequest got{};
  EXPECT_FALSE(parser.local->try_receive(got)) << "the network's requests are not the runtime's";
  ASSERT_TRUE(parser.network->try_receive(got));
  EXPECT_EQ(got.sequence, 5U);
  ControlReply reply{};
  reply.request_sequence = 5;
  EXPECT_EQ(through(parser.network_replies, socket.replies, reply).request_sequence, 5U);
  EXPECT_EQ(socket.master, &rig.links->master_status);
  EXPECT_EQ(socket.slave_info, &rig.links->slave_info);  // ctl slaves -v: what the handler publishes
  EXPECT_EQ(socket.diag_reset, &rig.links->diag_reset);  // ctl diag --reset: what the handler polls
  EXPECT_EQ(socket.handler_heartbeat,
            &rig.links->task_heartbeat_ns[static_cast<std::size_t>(StatTask::ethercat_handler)]);
}

TEST(TaskPorts, TheSocketHandlerAndTheEthercatHandlerMeetOnTheSdoQueues) {
  Rig rig;
  const SocketHandlerPorts socket = rig.ports->socket_handler();
  const EthercatHandlerPorts handler = rig.ports->ethercat_handler();
  SdoLinkRequest request{};
  request.id = 7;
  request.sdo.index = 0x100A;
  const SdoLinkRequest got = through(socket.sdo_requests, handler.sdo_requests, request);
  EXPECT_EQ(got.id, 7U);
  EXPECT_EQ(got.sdo.index, 0x100A);
  SdoLinkResult result{};
  result.id = 7;
  EXPECT_EQ(through(handler.sdo_results, socket.sdo_results, result).id, 7U);
  // ctl reg_read: the same way, its own queue pair.
  RegReadLinkRequest read{};
  read.id = 9;
  read.read.address = 0x0130;
  const RegReadLinkRequest read_got = through(socket.reg_requests, handler.reg_requests, read);
  EXPECT_EQ(read_got.id, 9U);
  EXPECT_EQ(read_got.read.address, 0x0130);
  RegReadLinkResult read_result{};
  read_result.id = 9;
  EXPECT_EQ(through(handler.reg_results, socket.reg_results, read_result).id, 9U);
  // ctl states: its own queue pair too.
  StatesLinkRequest states{};
  states.id = 11;
  states.states.state = 2;
  const StatesLinkRequest states_got = through(socket.states_requests, handler.states_requests, states);
  EXPECT_EQ(states_got.id, 11U);
  EXPECT_EQ(states_got.states.state, 2);
  StatesLinkResult states_result{};
  states_result.id = 11;
  EXPECT_EQ(through(handler.states_results, socket.states_results, states_result).id, 11U);
  // ctl rescan: its own queue pair too.
  RescanLinkRequest rescan{};
  rescan.id = 12;
  EXPECT_EQ(through(socket.rescan_requests, handler.rescan_requests, rescan).id, 12U);
  RescanLinkResult rescan_result{};
  rescan_result.id = 12;
  EXPECT_EQ(through(handler.rescan_results, socket.rescan_results, rescan_result).id, 12U);
}

TEST(TaskPorts, TheHandlersFiguresAreTheOnesTheSocketHandlerAnswersFrom) {
  Rig rig;
  const EthercatHandlerPorts handler = rig.ports->ethercat_handler();
  const SocketHandlerPorts socket = rig.ports->socket_handler();
  EXPECT_EQ(handler.master_status, socket.master);
  EXPECT_EQ(handler.link_diag, socket.diag);
  EXPECT_EQ(handler.slave_info, socket.slave_info);
  EXPECT_EQ(handler.diag_reset, socket.diag_reset);
  EXPECT_EQ(handler.master_status, &rig.links->master_status);
  EXPECT_EQ(socket.health, &rig.links->run.health) << "ctl tasks: each task's thread, start and restarts";
}

TEST(TaskPorts, TheJointManagersStepPublishesTheStatusTheOtherTasksRead) {
  Rig rig;
  const JointManagerPorts ports = rig.ports->joint_manager(rig.storage, rig.wall, rig.events);
  EXPECT_EQ(ports.joint_status, &rig.links->joint_status);
  EXPECT_EQ(ports.joint_status, rig.ports->socket_handler().joint_status);
  EXPECT_EQ(ports.joint_status, rig.ports->message_parser().joint_status);
  EXPECT_EQ(ports.joint_status, rig.ports->rc_task(RcTaskId::rescue).joint_status);
  auto manager = std::make_unique<JointManager>(ports);
  RobotJointStatus status{};
  for (PublishedJointStatus& s : status) s.held_position_rad = 99.0;  // not what a step publishes
  rig.links->joint_status.write(status);
  manager->step(0);
  ASSERT_TRUE(rig.links->joint_status.try_read(status));
  const RobotJointStatus expected = published_status(manager->statuses());
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_EQ(status[j].state, expected[j].state) << "joint " << j;
    EXPECT_DOUBLE_EQ(status[j].held_position_rad, expected[j].held_position_rad) << "joint " << j;
  }
}

TEST(TaskPorts, EachTaskLoopGetsItsOwnHeartbeatTimingAndHealthSlot) {
  Rig rig;
  for (std::size_t k = 0; k < kTaskStatSlots; ++k) {
    const auto slot = static_cast<StatTask>(k);
    const TaskLoopPorts loop = rig.ports->task_loop(slot);
    EXPECT_EQ(loop.heartbeat_ns, &rig.links->task_heartbeat_ns[k]);
    EXPECT_EQ(loop.stats, &(*rig.ports->socket_handler().tasks)[k]) << "ctl tasks reads the slot the loop writes";
    EXPECT_EQ(loop.health, &rig.links->run.health[k]);
    EXPECT_EQ(loop.run, &rig.links->run);
    if (slot == StatTask::ethercat_handler) {
      EXPECT_EQ(loop.heartbeat_ns, rig.ports->socket_handler().handler_heartbeat);
      EXPECT_EQ(loop.rescue_state, rig.ports->rc_task(RcTaskId::rescue).state) << "the rescue RC task's state";
    } else {
      EXPECT_EQ(loop.rescue_state, nullptr) << "only the handler's loop reads the rescue task's state";
    }
  }
}

TEST(TaskPorts, TheJointManagerAndItsStorageWorkerMeetOnTheirOwnQueues) {
  Rig rig;
  const JointManagerPorts manager = rig.ports->joint_manager(rig.storage, rig.wall, rig.events);
  EXPECT_EQ(manager.storage, &rig.storage);
  EXPECT_EQ(manager.wall_clock, &rig.wall);
  ErrorJointsSaveRequest request{};
  request.sequence = 3;
  EXPECT_EQ(through(manager.save_requests, &rig.ports->storage_worker_requests(), request).sequence, 3U);
  ErrorJointsSaveResult result{};
  result.sequence = 3;
  EXPECT_EQ(through(&rig.ports->storage_worker_results(), manager.save_results, result).sequence, 3U);
}

}  // namespace
}  // namespace rescue::app
