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
#include "core/app/runtime/task_ports.hpp"
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
      : storage(state_dir.c_str()), parser(*ports->message_parser().joint_commands), worker(storage), manager(manager_ports()) {}

  JointManagerPorts manager_ports() {
    JointManagerPorts p = ports->joint_manager(storage, wall, events);
    p.save_requests = &worker;  // the storage worker, inline
    p.save_results = &worker;
    return p;
  }

  bool bring_up(const ecat::MasterOptions& options = {}, const MotionIntakeSettings& intake = default_intake_settings()) {
    restored = manager.restore(rig->clock.now()).restored;
    if (!rig->bus.bring_up(options, restored).ok()) return false;
    handler = std::make_unique<EthercatHandler>(rig->bus, ports->ethercat_handler(), restored, intake);
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
  // Brought up, in OP, every joint initialized and enabled (100 periods); false when the bring-up failed.
  bool start_enabled(const MotionIntakeSettings& intake = default_intake_settings()) {
    if (!rig->built.ok() || !bring_up({}, intake)) return false;
    run_until_op();
    initialize_robot();
    for (int i = 0; i < 100; ++i) period();
    return true;
  }
  // The latest published sample of `joint` (the handler's seqlock).
  JointSample sample_of(std::size_t joint) const {
    RobotSample s{};
    (void)links->samples.try_read(s);
    return s[joint];
  }
  // RC task `task` completes one period under owner word `word` commanding `joint` at `position_rad`,
  // just before the handler's next period (its heartbeat too).
  void owner_period(std::size_t task, std::uint64_t word, std::size_t joint, double position_rad) {
    const hal::Nanoseconds now = rig->bus.next_wakeup() - 100 * hal::kNsPerUs;
    ReferenceSpace& space = links->motion.references[task];
    space.begin();
    for (std::size_t j = 0; j < kJointCount; ++j) space.set(j, j == joint ? position_rad : 0.0);
    space.complete(word, space.completed() + 1, joint_bit(joint), now);
    links->rc_heartbeat_ns[task].store(now);
  }

  std::unique_ptr<rescue::testing::SimulatedRobotRig> rig = std::make_unique<rescue::testing::SimulatedRobotRig>();
  std::unique_ptr<TaskLinks> links = std::make_unique<TaskLinks>();
  std::unique_ptr<TaskPorts> ports = std::make_unique<TaskPorts>(*links);  // as `run` wires the tasks
  ErrorJointsFileStorage storage;
  MessageSink<JointCommand>& parser;  // the test plays the message parser
  hal::ManualWallClock wall;
  NoEvents events;
  rescue::app::testing::InlineStorageWorker worker;  // the storage worker, inline (joint_manager_fakes.hpp)
  JointManager manager;
  std::unique_ptr<EthercatHandler> handler;
  JointMask restored{0};
};

}  // namespace rescue::app
