// rescue-motion docs fsm|tasks|shared-memory: documentation printed from the firmware's own tables, so docs/ cannot
// drift from the code (a test compares docs/fsm.md with this command's output).
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "core/app/config/task_table.hpp"
#include "core/app/shm/segment_layout.hpp"
#include "ecat/master/slave_recovery.hpp"
#include "fsm/engine/machine_view.hpp"
#include "fsm/engine/table_docs.hpp"
#include "fsm/machines/documented_machines.hpp"

namespace rescue::app {
namespace {

const OptionSpec kOptions[] = {
    {"format", "markdown|dot", "Markdown tables (default) or a Graphviz digraph per machine"},
    {"machine", "NAME", "only this state machine (default: all)"},
};

// A topic or option value the command does not know: a usage error (exit 2), worded as bench's.
int usage_error(const char* what, const char* given, const char* hint) noexcept {
  (void)std::fprintf(stderr, "rescue-motion docs: %s '%s' (%s)\n", what, given, hint);
  return 2;
}

int docs_main(const ParsedArgs& args) {
  const char* topic = args.positional(0);
  if (std::strcmp(topic, "tasks") == 0) {
    write_task_table_markdown(stdout);
    return std::fflush(stdout) == 0 ? 0 : fail("docs", "cannot write to standard output");
  }
  if (std::strcmp(topic, "shared-memory") == 0) {
    shm::write_segment_map_markdown(stdout);
    return std::fflush(stdout) == 0 ? 0 : fail("docs", "cannot write to standard output");
  }
  if (std::strcmp(topic, "fsm") != 0) return usage_error("unknown topic", topic, "known: fsm, tasks, shared-memory");
  const char* format = args.value("format") != nullptr ? args.value("format") : "markdown";
  const bool dot = std::strcmp(format, "dot") == 0;
  if (!dot && std::strcmp(format, "markdown") != 0) return usage_error("unknown --format", format, "known: markdown, dot");

  // The machines of fsm/, then the master's online recovery (ecat/master/slave_recovery.hpp).
  const char* only = args.value("machine");
  constexpr fsm::MachineView kRecovery = fsm::ViewOf<ecat::SlaveRecoveryTable>::view();
  if (only != nullptr && fsm::find_documented_machine(only) == nullptr && std::strcmp(only, kRecovery.name) != 0) {
    return usage_error("unknown --machine", only, "see rescue-motion docs fsm");
  }
  bool first = true;
  const auto print = [&](const fsm::MachineView& machine) {
    if (only != nullptr && std::strcmp(only, machine.name) != 0) return;
    if (!first) std::printf("\n");
    first = false;
    if (dot) {
      fsm::write_dot(stdout, machine);
    } else {
      fsm::write_markdown(stdout, machine);
    }
  };
  for (const fsm::MachineView& machine : fsm::documented_machines()) print(machine);
  print(kRecovery);
  return std::fflush(stdout) == 0 ? 0 : fail("docs", "cannot write to standard output");
}

}  // namespace

const CommandSpec kDocsCommand{
    "docs", "docs fsm|tasks|shared-memory [--format markdown|dot] [--machine NAME]",
    "print documentation generated from the firmware's tables",
    "Topics:\n"
    "  fsm    every state machine: states, inputs, the (state, input) grid, guards and actions.\n"
    "  tasks  the firmware's tasks (paper Table I): scheduling, CPU, period, shared memory, role.\n"
    "  shared-memory  the tasks' shared-memory segment byte by byte: header, then every member.\n"
    "docs/fsm.md, docs/tasks.md and docs/shared-memory.md hold this output; a state-machine diagram:\n"
    "  rescue-motion docs fsm --format dot | dot -Tsvg > fsm.svg",
    Span<const OptionSpec>(kOptions), 1, 1, docs_main};

}  // namespace rescue::app
