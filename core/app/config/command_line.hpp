// The one command-line parser shared by every subcommand of rescue-motion. Each subcommand
// declares its options in a table (CommandSpec); parsing checks them against the table, so an
// unknown option, a missing value or a stray argument is a one-line error, and --help prints the
// table. No heap: parsed arguments point into argv.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "core/base/result.hpp"
#include "core/base/span.hpp"
#include "core/containers/fixed_vector.hpp"

namespace rescue::app {

struct OptionSpec {
  const char* name;        // long name without the leading "--"
  const char* value_name;  // nullptr for a flag without a value
  const char* help;
  char short_name{'\0'};  // a one-letter alias ("-v"), '\0': none
};

class ParsedArgs;

struct CommandSpec {
  const char* name;
  const char* usage;    // e.g. "decode FILE"
  const char* summary;  // one line
  const char* details;  // further paragraphs for --help, may be ""
  Span<const OptionSpec> options;
  std::size_t min_positionals;
  std::size_t max_positionals;
  int (*main)(const ParsedArgs& args);
  // --help with these arguments, when the command describes more than its spec (bench NAME --help);
  // nullptr: print_command_help.
  int (*help)(const ParsedArgs& args){nullptr};
};

class ParsedArgs {
 public:
  static constexpr std::size_t kMaxOptions = 32;
  static constexpr std::size_t kMaxPositionals = 16;

  // Value of --name (given at most once: parse_args refuses a repeat), or nullptr when absent or a flag.
  const char* value(const char* name) const noexcept;
  bool has(const char* name) const noexcept;
  bool help_requested() const noexcept { return help_; }
  std::size_t positional_count() const noexcept { return positionals_.size(); }
  const char* positional(std::size_t i) const noexcept { return positionals_[i]; }

  // Typed access with range checks; `fallback` when the option is absent.
  Result<std::int64_t> integer(const char* name, std::int64_t fallback, std::int64_t min, std::int64_t max) const noexcept;
  Result<double> number(const char* name, double fallback, double min, double max) const noexcept;

 private:
  friend Result<ParsedArgs> parse_args(const CommandSpec& spec, int argc, const char* const* argv) noexcept;
  struct Entry {
    const char* name;
    const char* value;
  };
  FixedVector<Entry, kMaxOptions> options_;
  FixedVector<const char*, kMaxPositionals> positionals_;
  bool help_{false};
};

// argv[0] is the first argument after the subcommand name. On error, Error::what is a static
// description and the offending argument index is detail0.
Result<ParsedArgs> parse_args(const CommandSpec& spec, int argc, const char* const* argv) noexcept;

void print_command_help(std::FILE* out, const CommandSpec& spec) noexcept;

// Help text fits kHelpColumns (a terminal of 100 columns; the man page wraps again to 72). Lines break
// at spaces only, a continuation indented to its line's description column.
inline constexpr std::size_t kHelpColumns = 100;
// "  LEFT  TEXT": TEXT in the column after LEFT's 28 (on the next line when LEFT is wider).
void print_help_row(std::FILE* out, const char* left, const char* text) noexcept;
// Paragraphs of help, line by line: a continuation indented after the line's first run of two or more
// spaces ("  fsm    every state machine"), else to the line's own indentation.
void print_help_text(std::FILE* out, const char* text) noexcept;

// Prints "rescue-motion <cmd>: <what>: <reason>" to stderr; returns the exit status for failures.
int fail(const char* command, const char* what, const Error& error) noexcept;
int fail(const char* command, const char* message) noexcept;

}  // namespace rescue::app
