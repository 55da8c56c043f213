#include "core/app/sim/run_scenario.hpp"

#include <cstring>

#include "core/app/config/firmware_config.hpp"

namespace rescue::app {
namespace {

constexpr std::uint32_t kDamagedFrames = 5;  // cable-damage: frames damaged on the cable

}  // namespace

Result<Scenario> parse_scenario(const char* name) noexcept {
  Scenario scenario{};
  if (name == nullptr || std::strcmp(name, "none") == 0) return scenario;
  if (std::strcmp(name, "link-cut") == 0) {
    scenario.kind = ScenarioKind::link_cut;
    scenario.name = "link-cut";
    scenario.cut_joint = joint_index_by_name("l_elbow");
    scenario.cut_after_op = hal::kNsPerSec;
    scenario.expected_lost = joints_lost_by_link_failure_at(scenario.cut_joint);
    scenario.run_on = config::kScenarioRunOnNs;
    return scenario;
  }
  if (std::strcmp(name, "power-cycle") == 0) {
    scenario.kind = ScenarioKind::power_cycle;
    scenario.name = "power-cycle";
    scenario.cut_joint = joint_index_by_name("l_elbow");
    scenario.cut_after_op = hal::kNsPerSec;
    scenario.expected_lost = joint_bit(scenario.cut_joint);
    scenario.run_on = config::kScenarioRunOnNs;
    return scenario;
  }
  if (std::strcmp(name, "cable-damage") == 0) {
    scenario.kind = ScenarioKind::cable_damage;
    scenario.name = "cable-damage";
    scenario.cut_joint = joint_index_by_name("l_elbow");
    scenario.cut_after_op = hal::kNsPerSec;
    scenario.run_on = config::kScenarioRunOnNs;
    return scenario;
  }
  if (std::strcmp(name, "rescue") == 0) {
    scenario.kind = ScenarioKind::rescue;
    scenario.name = "rescue";
    scenario.cut_joint = joint_index_by_name("l_elbow");
    scenario.cut_after_op = 3 * hal::kNsPerSec;
    scenario.expected_lost = joints_lost_by_link_failure_at(scenario.cut_joint);
    scenario.run_on = 2500 * hal::kNsPerMs;
    scenario.rescue_motion = true;
    scenario.motion_phase_s = {1.0, 1.0, 1.0};
    return scenario;
  }
  return make_error(Errc::invalid_argument, "unknown scenario (known: none, link-cut, rescue, power-cycle, cable-damage)");
}

bool ScenarioRunner::on_cycle(hal::Nanoseconds now, bool network_op) noexcept {
  if (scenario_.kind == ScenarioKind::none || acted_) return false;
  if (op_at_ < 0) {
    if (!network_op) return false;
    op_at_ = now;
  }
  if (now - op_at_ < scenario_.cut_after_op) return false;
  acted_ = true;
  acted_at_ = now;
  if (segment_ == nullptr) {
    action_status_ = make_error(Errc::unsupported, "scenarios need the simulated robot (--nic sim)");
    return true;
  }
  const std::size_t position = slave_position_of_joint(scenario_.cut_joint);
  switch (scenario_.kind) {
    case ScenarioKind::power_cycle: action_status_ = segment_->power_cycle(position, now); break;
    case ScenarioKind::cable_damage: action_status_ = segment_->corrupt_port(position, 0, kDamagedFrames); break;
    default: action_status_ = segment_->cut_link(position); break;
  }
  return true;
}

}  // namespace rescue::app
