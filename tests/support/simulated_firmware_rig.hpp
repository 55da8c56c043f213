// Test support: the firmware's two tasks (EtherCAT handler with the real master, joint manager with
// the real error-joints file) over one TaskLinks on the whole simulated robot in virtual time, as
// `run` wires them; one thread steps both tasks, handler first. Nothing here is firmware.
#pragma once

#include <memory>
#include <string>

#include "core/app/links/task_links.hpp"
#include "core/app/tasks/error_joints_storage.hpp"
#include "core/app/tasks/ethercat_handler.hpp"
#include "core/app/tasks/joint_manager.hpp"
#include "core/app/tasks/predefined_messages.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "hal/time/wall_clock.hpp"
#include "tests/support/joint_manager_fakes.hpp"
#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::app {

class NoEvents final : public JointEventSink {
 public:
  void on_event(const JointEvent&) noexcept override {}
};

// The firmware's two tasks over one TaskLinks, as `run` wires them.
struct SimulatedFirmware {
  explicit SimulatedFirmware(const std::string& state_dir)
      : storage(state_dir.c_str()),
        reports(links->lost_reports),
        notices(links->notices),
        commands(links->joint_commands),
        parser(links->joint_commands),
        samples(links->samples),
        demand(links->demand),
        worker(storage),
        manager(ports()) {}

  JointManagerPorts ports() {
    JointManagerPorts p{&reports, &notices, &commands, &samples, &storage, &wall, &events, &demand};
    p.save_requests = &worker;
    p.save_results = &worker;
    return p;
  }

  bool bring_up(const ecat::MasterOptions& options = {}) {
    restored = manager.restore(rig->clock.now()).restored;
    if (!rig->bus.bring_up(options, restored).ok()) return false;
    handler = std::make_unique<EthercatHandler>(rig->bus, *links, restored);
    return true;
  }
  // One millisecond: the handler's cycle, then the joint manager's step.
  drivers::JointCycleResult period() {
    rig->clock.sleep_until(rig->bus.next_wakeup());
    const drivers::JointCycleResult r = handler->cycle();
    manager.step(rig->clock.now());
    return r;
  }
  void run_until_op() {
    for (int i = 0; i < 3000 && period().state != ecat::MasterState::op; ++i) {
    }
    period();
  }
  void initialize_robot() {
    for (const JointCommand& c : initialize_robot_commands(kAllJoints & ~restored)) ASSERT_TRUE(parser.try_send(c));
  }

  std::unique_ptr<rescue::testing::SimulatedRobotRig> rig = std::make_unique<rescue::testing::SimulatedRobotRig>();
  std::unique_ptr<TaskLinks> links = std::make_unique<TaskLinks>();
  ErrorJointsFileStorage storage;
  SpscMessageSource<LostJointsReport, TaskLinks::kReportQueueDepth> reports;
  SpscMessageSink<JointManagerNotice, TaskLinks::kNoticeQueueDepth> notices;
  SpscMessageSource<JointCommand, TaskLinks::kCommandQueueDepth> commands;
  SpscMessageSink<JointCommand, TaskLinks::kCommandQueueDepth> parser;
  SeqlockSampleSource samples;
  SeqlockDemandSink demand;
  hal::ManualWallClock wall;
  NoEvents events;
  rescue::app::testing::InlineStorageWorker worker;  // the storage worker, inline (joint_manager_fakes.hpp)
  JointManager manager;
  std::unique_ptr<EthercatHandler> handler;
  JointMask restored{0};
};

}  // namespace rescue::app
