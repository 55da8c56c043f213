// The state machines whose tables `rescue-motion docs fsm` prints. A machine built with the engine
// is added here with one line (ViewOf<Def>::view()) and docs/fsm.md is regenerated from the command.
#pragma once

#include "core/base/span.hpp"
#include "fsm/engine/machine_view.hpp"

namespace rescue::fsm {

Span<const MachineView> documented_machines() noexcept;

// The machine called `name` (MachineView::name), or nullptr.
const MachineView* find_documented_machine(const char* name) noexcept;

}  // namespace rescue::fsm
