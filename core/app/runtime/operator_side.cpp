// The operator's side of the run (operator_side.hpp).
#include "core/app/runtime/operator_side.hpp"

#include <cstdio>

#include "core/app/runtime/run_context.hpp"
#include "hal/time/wall_clock.hpp"

namespace rescue::app::runner {
namespace {

bool send_local(protocol::MessageType type, JointMask joints) noexcept {
  ControlRequest request;
  request.type = type;
  request.joints = joints;
  if (links().local_requests.try_push(request)) return true;
  run().dropped[static_cast<std::size_t>(DropCounter::local_requests_dropped)].fetch_add(1, std::memory_order_relaxed);
  (void)std::printf("operator: request queue full, %s dropped\n", protocol::to_string(type));
  return false;
}

// Whether the handler's latest published values show every joint of `joints` reachable.
bool all_reachable(JointMask joints) noexcept {
  RobotSample sample{};
  if (!links().samples.try_read(sample)) return false;
  for (std::size_t j = 0; j < kJointCount; ++j) {
    if ((joints & joint_bit(j)) != 0 && !sample[j].reachable) return false;
  }
  return true;
}

// The scenario's cut, from the handler's words in the segment (its process or thread).
void announce_scenario(OperatorSide& side) noexcept {
  const RunControl& state = run();
  if (side.scenario_announced || !state.scenario_acted.load(std::memory_order_acquire)) return;
  side.scenario_announced = true;
  if (!state.scenario_ok.load(std::memory_order_relaxed)) return;  // the handler's side says why
  const Scenario& wanted = g_run.tasks.options->scenario;
  char names[kJointNamesCapacity];
  format_joint_names(wanted.expected_lost, names, sizeof names);
  (void)std::printf("[%8.3f s] scenario %s: %s %s (expect %s lost)\n",
                    seconds(state.scenario_at.load(std::memory_order_relaxed) - g_run.tasks.start), wanted.name,
                    wanted.kind == ScenarioKind::power_cycle    ? "power-cycle the drive of"
                    : wanted.kind == ScenarioKind::cable_damage ? "damage 5 frames on the cable into"
                                                                : "cut the link into",
                    kJoints[wanted.cut_joint].name, names);
}

}  // namespace

void operator_side_pass(OperatorSide& side) noexcept {
  hal::Clock& clock = *g_run.tasks.clock;
  const MotionSnapshot motion = read_motion();
  announce_scenario(side);
  const bool op = run().op.load(std::memory_order_acquire);
  // The DFA takes its steps only for reachable joints: wait until the handler's published values
  // show every joint that is not recorded lost reachable (the first OP cycles may not).
  if (op && !side.clear_sent && all_reachable(side.to_clear)) {
    side.clear_sent = true;
    char names[kJointNamesCapacity];
    format_joint_names(side.to_clear, names, sizeof names);
    (void)std::printf("[%8.3f s] operator: clear repaired joints %s (then reset)\n", seconds(clock.now() - g_run.tasks.start), names);
    (void)send_local(protocol::MessageType::clear_joints, side.to_clear);
  }
  if (op && side.clear_sent && !side.initialized && all_reachable(kAllJoints & ~side.out_of_service)) {
    side.initialized = true;
    (void)std::printf("[%8.3f s] operator: initialize robot (select mode, set reference, enable)\n",
                      seconds(clock.now() - g_run.tasks.start));
    (void)send_local(protocol::MessageType::initialize, kAllJoints & ~side.out_of_service);
    if (g_run.tasks.options->scenario.rescue_motion) {
      // After the initialize (the parser takes one request at a time): the rescue RC task takes the motion.
      (void)std::printf("[%8.3f s] operator: owner %u (the rescue RC task takes the motion)\n",
                        seconds(clock.now() - g_run.tasks.start), static_cast<unsigned>(RcTaskId::rescue));
      ControlRequest take;
      take.type = protocol::MessageType::take_owner;
      take.task = static_cast<std::uint8_t>(RcTaskId::rescue);
      if (!links().local_requests.try_push(take)) {
        run().dropped[static_cast<std::size_t>(DropCounter::local_requests_dropped)].fetch_add(1, std::memory_order_relaxed);
        (void)std::printf("operator: request queue full, owner dropped\n");
      }
    }
  }
  print_local_replies(clock.now() - g_run.tasks.start);
  print_motion_changes(side.motion, motion, clock.now() - g_run.tasks.start);
  (void)std::fflush(stdout);
}

void disable_enabled_joints() noexcept {
  RobotDemand demand{};
  JointMask enabled = 0;
  if (links().demand.try_read(demand)) {
    for (std::size_t j = 0; j < kJointCount; ++j) {
      if (demand[j].enable) enabled |= joint_bit(j);
    }
  }
  if (enabled == 0 || !send_local(protocol::MessageType::disable, enabled)) return;
  hal::MonotonicClock wait_clock;
  const hal::Nanoseconds give_up = wait_clock.now() + MessageParser::kReplyTimeout + 100 * hal::kNsPerMs;
  while (links().local_replies.empty_approx() && wait_clock.now() < give_up) {
    wait_clock.sleep_until(wait_clock.now() + hal::kNsPerMs);
  }
  print_local_replies(g_run.tasks.clock->now() - g_run.tasks.start);
}

}  // namespace rescue::app::runner
