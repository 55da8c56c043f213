#include "fsm/engine/table_docs.hpp"

#include <algorithm>

namespace rescue::fsm {
namespace {

// The row for (state, input), or nullptr.
const RowView* row_for(const MachineView& m, std::size_t state, std::size_t input) noexcept {
  const RowView* it = std::find_if(m.rows.begin(), m.rows.end(),
                                   [&](const RowView& row) { return row.from == state && row.input == input; });
  return it != m.rows.end() ? it : nullptr;
}

const char* or_dash(const char* text) noexcept { return text[0] != '\0' ? text : "-"; }

}  // namespace

void write_markdown_grid(std::FILE* out, const MachineView& m) noexcept {
  std::fprintf(out, "| from \\ input |");
  for (const InputView& input : m.inputs) std::fprintf(out, " %s |", input.name);
  std::fprintf(out, "\n|---|");
  for (std::size_t i = 0; i < m.inputs.size(); ++i) std::fprintf(out, "---|");
  std::fprintf(out, "\n");
  for (std::size_t s = 0; s < m.states.size(); ++s) {
    std::fprintf(out, "| %s |", m.states[s].name);
    for (std::size_t i = 0; i < m.inputs.size(); ++i) {
      const RowView* row = row_for(m, s, i);
      if (row == nullptr) {
        std::fprintf(out, " - |");
      } else if (row->guard_text[0] != '\0') {
        std::fprintf(out, " %s (%s) |", m.states[row->to].name, row->guard_text);
      } else {
        std::fprintf(out, " %s |", m.states[row->to].name);
      }
    }
    std::fprintf(out, "\n");
  }
}

void write_markdown(std::FILE* out, const MachineView& m) noexcept {
  std::fprintf(out, "### State machine `%s`\n\n", m.name);
  std::fprintf(out, "Initial state: %s. %zu states, %zu inputs, %zu transitions; the other %zu (state, input) pairs "
                    "are refused and counted.\n\n",
               m.states[m.initial].name, m.states.size(), m.inputs.size(), m.rows.size(),
               m.states.size() * m.inputs.size() - m.rows.size());
  std::fprintf(out, "| state | meaning | on entry | on exit |\n|---|---|---|---|\n");
  for (const StateView& s : m.states) {
    std::fprintf(out, "| %s | %s | %s | %s |\n", s.name, s.meaning, or_dash(s.entry_text), or_dash(s.exit_text));
  }
  std::fprintf(out, "\n| input | meaning |\n|---|---|\n");
  for (const InputView& i : m.inputs) std::fprintf(out, "| %s | %s |\n", i.name, i.meaning);
  std::fprintf(out, "\nTransitions (target state of every pair, `-` = refused):\n\n");
  write_markdown_grid(out, m);
  std::fprintf(out, "\n| from | input | to | guard | action |\n|---|---|---|---|---|\n");
  for (const RowView& row : m.rows) {
    std::fprintf(out, "| %s | %s | %s | %s | %s |\n", m.states[row.from].name, m.inputs[row.input].name,
                 m.states[row.to].name, or_dash(row.guard_text), or_dash(row.action_text));
  }
}

void write_dot(std::FILE* out, const MachineView& m) noexcept {
  std::fprintf(out, "digraph %s {\n  rankdir=LR;\n  node [shape=box, style=rounded];\n", m.name);
  std::fprintf(out, "  start [shape=point, label=\"\"];\n  start -> %s;\n", m.states[m.initial].name);
  // One edge per (from, to) pair, its label listing every input that takes it, in table order.
  for (std::size_t from = 0; from < m.states.size(); ++from) {
    for (std::size_t to = 0; to < m.states.size(); ++to) {
      bool first = true;
      for (const RowView& row : m.rows) {
        if (row.from != from || row.to != to) continue;
        if (first) {
          std::fprintf(out, "  %s -> %s [label=\"", m.states[from].name, m.states[to].name);
        } else {
          std::fprintf(out, "\\n");
        }
        std::fprintf(out, "%s", m.inputs[row.input].name);
        if (row.guard_text[0] != '\0') std::fprintf(out, " [%s]", row.guard_text);
        first = false;
      }
      if (!first) std::fprintf(out, "\"];\n");
    }
  }
  std::fprintf(out, "}\n");
}

}  // namespace rescue::fsm
