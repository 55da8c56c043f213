// Documentation printed from a machine's own tables (fsm/engine/machine_view.hpp): a Markdown section and a
// Graphviz dot diagram. `rescue-motion docs fsm` prints them; docs/fsm.md holds their output and a
// test checks that it still equals what the tables print, so the docs cannot drift from the code.
#pragma once

#include <cstdio>

#include "fsm/engine/machine_view.hpp"

namespace rescue::fsm {

// The [state][input] grid alone: a cell is the target state, "To (guard)" for a guarded row, or "-"
// for a pair that is not in the table (refused and counted).
void write_markdown_grid(std::FILE* out, const MachineView& machine) noexcept;

// A whole Markdown section: states (meaning, entry/exit actions), inputs, the grid, and the rows with
// their guards and actions.
void write_markdown(std::FILE* out, const MachineView& machine) noexcept;

// A Graphviz digraph: one node per state, one edge per (from, to) pair labelled with its inputs
// (guards in brackets), and a point marking the initial state.
void write_dot(std::FILE* out, const MachineView& machine) noexcept;

}  // namespace rescue::fsm
