#include "core/app/sim/run_scenario.hpp"

#include <cstring>

#include "core/app/config/firmware_config.hpp"

namespace rescue::app {
namespace {

constexpr std::uint32_t kDamagedFrames = 5;  // cable-damage: frames damaged on the cable
// rescue: the cut 0.3 s into the forwarding phase (forwarding lasts 1.25 s there with the palms'
// stopping budget, docs/kinematics.md), wherever a loaded host puts that phase in wall time.
constexpr hal::Nanoseconds kRescueCutIntoForwarding = 300 * hal::kNsPerMs;

// Every scenario acts on l_elbow (the joint whose incoming cable is cut, damaged or power-cycled).
enum class Lost : std::uint8_t { nothing, the_joint, its_branch_from_it };

struct ScenarioRow {
  const char* name;
  hal::Nanoseconds cut_after_op;
  hal::Nanoseconds run_on;   // after acting, without --duration
  ScenarioKind kind;
  Lost lost;                 // what the firmware must report lost
  bool mapping_fault{false};
  drivers::PdoMappingFault fault{drivers::PdoMappingFault::half_written};
  hal::Nanoseconds repeat_every{0};  // cable damage again this often after the first (0: once)
};

constexpr ScenarioRow kScenarios[] = {
    {"link-cut", hal::kNsPerSec, config::kScenarioRunOnNs, ScenarioKind::link_cut, Lost::its_branch_from_it},
    {"power-cycle", hal::kNsPerSec, config::kScenarioRunOnNs, ScenarioKind::power_cycle, Lost::the_joint},
    {"half-mapped", hal::kNsPerSec, config::kScenarioRunOnNs, ScenarioKind::power_cycle, Lost::the_joint, true,
     drivers::PdoMappingFault::half_written},
    {"foreign-mapping", hal::kNsPerSec, config::kScenarioRunOnNs, ScenarioKind::power_cycle, Lost::the_joint, true,
     drivers::PdoMappingFault::foreign_default},
    {"cable-damage", hal::kNsPerSec, config::kScenarioRunOnNs, ScenarioKind::cable_damage, Lost::nothing},
    // flaky-cable: the damage of cable-damage, again every 2 s (a cable that goes on failing: ctl diag
    // --reset, then the counters rise again; or, after swapping it, they stay at 0).
    {"flaky-cable", hal::kNsPerSec, config::kScenarioRunOnNs, ScenarioKind::cable_damage, Lost::nothing, false,
     drivers::PdoMappingFault::half_written, 2 * hal::kNsPerSec},
    // rescue: run_on only bounds the run; it stops 0.2 s after the rescue motion ended (task_loops.cpp).
    // rescue: cut_after_op is only the earliest; the cut waits for the forwarding phase (parse_scenario).
    {"rescue", 0, 10 * hal::kNsPerSec, ScenarioKind::rescue, Lost::its_branch_from_it},
};

}  // namespace

Result<Scenario> parse_scenario(const char* name) noexcept {
  Scenario scenario{};
  if (name == nullptr || std::strcmp(name, "none") == 0) return scenario;
  for (const ScenarioRow& row : kScenarios) {
    if (std::strcmp(name, row.name) != 0) continue;
    scenario.kind = row.kind;
    scenario.name = row.name;
    scenario.cut_joint = joint_index_by_name("l_elbow");
    scenario.cut_after_op = row.cut_after_op;
    scenario.expected_lost = row.lost == Lost::the_joint            ? joint_bit(scenario.cut_joint)
                             : row.lost == Lost::its_branch_from_it ? joints_lost_by_link_failure_at(scenario.cut_joint)
                                                                    : JointMask{0};
    if (row.kind == ScenarioKind::power_cycle) {
      scenario.may_miss_first_frame = joints_lost_by_link_failure_at(scenario.cut_joint) & ~joint_bit(scenario.cut_joint);
    }
    scenario.run_on = row.run_on;
    scenario.mapping_fault = row.mapping_fault;
    scenario.fault = row.fault;
    scenario.repeat_every = row.repeat_every;
    if (row.kind == ScenarioKind::rescue) {
      scenario.rescue_motion = true;
      scenario.motion_phase_s = {1.0, 1.0, 1.0};  // lowering, forwarding, backwarding
      scenario.cut_into_forwarding = kRescueCutIntoForwarding;
    }
    return scenario;
  }
  return make_error(Errc::invalid_argument,
                    "unknown scenario (known: none, link-cut, rescue, power-cycle, half-mapped, foreign-mapping, cable-damage, flaky-cable)");
}

Status ScenarioRunner::before_bring_up() noexcept {
  if (!scenario_.mapping_fault) return Status::success();
  if (segment_ == nullptr) return make_error(Errc::unsupported, "scenarios need the simulated robot (--nic sim)");
  return segment_->corrupt_pdo_mapping(slave_position_of_joint(scenario_.cut_joint), scenario_.fault);
}

bool ScenarioRunner::on_cycle(hal::Nanoseconds now, bool network_op, bool rescue_forwarding) noexcept {
  if (acted_ && scenario_.repeat_every > 0 && segment_ != nullptr && now - last_repeat_ >= scenario_.repeat_every) {
    last_repeat_ = now;  // flaky-cable: damaged again, silently (the first action is the one reported)
    (void)segment_->corrupt_port(slave_position_of_joint(scenario_.cut_joint), 0, kDamagedFrames);
  }
  if (scenario_.kind == ScenarioKind::none || acted_) return false;
  if (op_at_ < 0) {
    if (!network_op) return false;
    op_at_ = now;
  }
  if (now - op_at_ < scenario_.cut_after_op) return false;
  if (scenario_.cut_into_forwarding >= 0) {
    if (forwarding_since_ < 0 && rescue_forwarding) forwarding_since_ = now;
    if (forwarding_since_ < 0 || now - forwarding_since_ < scenario_.cut_into_forwarding) return false;
  }
  acted_ = true;
  acted_at_ = now;
  last_repeat_ = now;
  if (segment_ == nullptr) {
    action_status_ = make_error(Errc::unsupported, "scenarios need the simulated robot (--nic sim)");
    return true;
  }
  const std::size_t position = slave_position_of_joint(scenario_.cut_joint);
  switch (scenario_.kind) {
    case ScenarioKind::power_cycle:
      action_status_ = scenario_.mapping_fault ? segment_->corrupt_pdo_mapping(position, scenario_.fault) : Status::success();
      if (action_status_.ok()) action_status_ = segment_->power_cycle(position, now);
      break;
    case ScenarioKind::cable_damage: action_status_ = segment_->corrupt_port(position, 0, kDamagedFrames); break;
    default: action_status_ = segment_->cut_link(position); break;
  }
  return true;
}

}  // namespace rescue::app
