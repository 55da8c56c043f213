#include "core/app/bench/wcet_scenarios.hpp"

#include <cstring>

namespace rescue::app {
namespace {

const WcetScenarioSpec kScenarios[] = {
    {WcetScenario::typical, false, "typical", "every joint Enabled following its reference, the RC tasks doing the rescue motion"},
    {WcetScenario::recovery, false, "recovery",
     "every slave power-cycled at once, again and again: recovery and re-integration of all 23, loss of every joint, "
     "re-initialise, RC reshaping"},
    {WcetScenario::services, false, "services", "segmented SDO transfers back to back, a diagnostics reset every period, capture on"},
    {WcetScenario::worst, false, "worst",
     "recovery and services at once, every other loss a repaired cable cut, PDO mappings rewritten, frames damaged "
     "while joints are down, the re-initialise of every joint at once: every service busy together"},
    {WcetScenario::worst_ring, true, "worst-ring",
     "worst on the ring configuration: both copies sent and merged every period, every other loss a cut of the "
     "master's cable opening the ring (the ring DC service across the break), repaired; frames damaged while joints "
     "are down and while every joint is Enabled (the exchange sent again)"},
    {WcetScenario::mixed, false, "mixed", "typical for the first half, recovery and services for the second: not i.i.d. by construction (must be refused)"},
};

}  // namespace

Span<const WcetScenarioSpec> wcet_scenarios() noexcept { return {kScenarios}; }

const WcetScenarioSpec* find_wcet_scenario(const char* name) noexcept {
  for (const WcetScenarioSpec& spec : kScenarios) {
    if (name != nullptr && std::strcmp(spec.name, name) == 0) return &spec;
  }
  return nullptr;
}

WcetStress wcet_stress(WcetScenario scenario, std::int64_t k, std::int64_t periods) noexcept {
  switch (scenario) {
    case WcetScenario::typical: return {};
    case WcetScenario::recovery: return {true, false, false, false, false, false, false};
    case WcetScenario::services: return {false, true, false, false, false, false, false};
    case WcetScenario::worst:
    case WcetScenario::worst_ring: return {true, true, true, true, true, true, true};
    // The second half as `worst` was before the cuts and the held re-initialise: the parser busy at
    // random periods (its requests while joints are down), unlike the first half.
    case WcetScenario::mixed: return k < periods / 2 ? WcetStress{} : WcetStress{true, true, false, false, false, false, false};
  }
  return {};
}

}  // namespace rescue::app
