// rescue-motion: one binary, several subcommands sharing one parser (design brief section 7).
#include <cstdio>
#include <cstring>

#include "core/app/cli/commands.hpp"
#include "core/app/config/build_info.hpp"

namespace {

using rescue::app::CommandSpec;

// constexpr: only the addresses are used, fixed at link time, so no initialisation order issue.
constexpr const CommandSpec* kCommands[] = {
    &rescue::app::kRunCommand,    &rescue::app::kSimCommand,   &rescue::app::kCtlCommand,
    &rescue::app::kDecodeCommand, &rescue::app::kBenchCommand, &rescue::app::kDocsCommand,
};

void print_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: rescue-motion COMMAND [OPTIONS]\n\n"
               "Motion-control firmware of the rescue robot: drives 21 joints over EtherCAT,\n"
               "on the robot's NIC or on the built-in simulated segment.\n\ncommands:\n");
  for (const CommandSpec* cmd : kCommands) std::fprintf(out, "  %-8s %s\n", cmd->name, cmd->summary);
  std::fprintf(out,
               "\n'rescue-motion COMMAND --help' describes each command; 'rescue-motion --version' prints\n"
               "the program's version and build type, as 'ctl version' shows them.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    print_usage(stderr);
    std::fprintf(stderr, "rescue-motion: missing command\n");
    return 2;
  }
  const char* name = argv[1];
  if (std::strcmp(name, "--help") == 0 || std::strcmp(name, "-h") == 0 || std::strcmp(name, "help") == 0) {
    print_usage(stdout);
    return 0;
  }
  if (std::strcmp(name, "--version") == 0) {
    // The same words as ctl version's client line (git describe of the build, not the project's number).
    std::printf("rescue-motion %s (%s build)\n", rescue::app::build_program_version(), rescue::app::build_type());
    return 0;
  }
  for (const CommandSpec* cmd : kCommands) {
    if (std::strcmp(cmd->name, name) != 0) continue;
    auto parsed = rescue::app::parse_args(*cmd, argc - 2, argv + 2);
    if (!parsed.ok()) {
      const auto& err = parsed.error();
      const int index = static_cast<int>(err.detail0) + 2;
      if (std::strcmp(err.what, "missing argument") == 0 || index >= argc) {
        std::fprintf(stderr, "rescue-motion %s: %s (usage: rescue-motion %s)\n", cmd->name, err.what, cmd->usage);
      } else {
        std::fprintf(stderr, "rescue-motion %s: %s: '%s' (see rescue-motion %s --help)\n", cmd->name, err.what,
                     argv[index], cmd->name);
      }
      return 2;
    }
    if (parsed.value().help_requested()) {
      if (cmd->help != nullptr) return cmd->help(parsed.value());
      rescue::app::print_command_help(stdout, *cmd);
      return 0;
    }
    return cmd->main(parsed.value());
  }
  std::fprintf(stderr, "rescue-motion: unknown command '%s' (see rescue-motion --help)\n", name);
  return 2;
}
