// The verbs of `rescue-motion ctl`, one table (ctl_verb_table.cpp): each entry holds the verb's
// arguments (how many), the function that builds its request and the one that prints the answer,
// so a verb is one line here and one group file (ctl_*.cpp) that holds its parse and print.
// ctl refuses a verb that is not in it, and
// tests/core/app/cli/test_ctl_verbs_are_all_documented_in_operator_docs.cpp requires every verb
// in it to appear in `ctl --help` and in docs/operator.md's generated transcript
// (toolchain/operator-transcript.sh), so a new verb cannot land without its documentation.
#pragma once

#include <cstdint>

#include "core/app/config/command_line.hpp"
#include "core/app/links/protocol_messages.hpp"
#include "core/app/operator_protocol/ctl_client.hpp"
#include "core/base/result.hpp"
#include "core/base/span.hpp"

namespace rescue::app {

// The robot as a verb's build sees it: its target (address, key) resolved on first use only, so a
// bad argument is reported as usage before the key file is looked at (ctl_target.cpp).
class CtlPeer {
 public:
  explicit CtlPeer(const ParsedArgs& args) noexcept : args_(args) {}
  // Errors: invalid_argument (an option's value), another code for the key file.
  Result<CtlTarget> target() noexcept;
  // One exchange with the robot (ctl_exchange), within its own --timeout: the process's deadline is
  // set again for it, so a verb of several exchanges is bounded per exchange. Errors: the target's,
  // or the exchange's (timeout, io_error: unreachable; refused: another robot id).
  Result<protocol::Message> exchange(const protocol::Message& request) noexcept;

 private:
  const ParsedArgs& args_;
  bool resolved_{false};
  Result<CtlTarget> target_{CtlTarget{}};
};

// A verb's request from its arguments. `peer`: the robot, for a verb that must ask it something
// first (download without --type asks the object's size). Errors: invalid_argument (usage) with
// the text for the user; an error of that first exchange or of the key.
using CtlBuild = Result<protocol::Message> (*)(const ParsedArgs& args, CtlPeer& peer);
// Prints the robot's answer to `request`; returns ctl's exit status (CtlExit).
using CtlPrint = int (*)(const protocol::Message& request, const protocol::Message& answer);
// A verb that runs its own dialog (none, or several exchanges through `peer`) and prints; returns
// ctl's exit status.
using CtlConverse = int (*)(const ParsedArgs& args, CtlPeer& peer);

enum class CtlRun : std::uint8_t {
  exchange,  // one request, one answer
  repeated,  // the exchange again every --interval (watch)
  own,       // the verb's own dialog (`converse`): keygen asks nothing, pdos several things
};

struct CtlVerb {
  const char* name;
  const char* usage;      // the verb's synopsis, named when its arguments are wrong
  CtlBuild build;         // exchange, repeated
  CtlPrint print;         // exchange, repeated
  CtlConverse converse;   // own
  std::uint8_t min_args;  // positional arguments after the verb
  std::uint8_t max_args;
  CtlRun run;
};

Span<const CtlVerb> ctl_verbs() noexcept;
const CtlVerb* find_ctl_verb(const char* name) noexcept;
inline bool is_ctl_verb(const char* verb) noexcept { return verb != nullptr && find_ctl_verb(verb) != nullptr; }

// Options that belong to some verbs only: given to another verb, ctl refuses them by name.
struct CtlVerbOption {
  const char* option;
  const char* verbs[2];
  const char* error;
};
inline constexpr CtlVerbOption kCtlVerbOptions[] = {
    {"verbose", {"slaves", nullptr}, "-v, --verbose goes with slaves"},
    {"format", {"graph", nullptr}, "--format goes with graph"},
    {"reset", {"diag", nullptr}, "--reset goes with diag"},
    {"type", {"upload", "download"}, "--type goes with upload and download"},
    {"moved", {"clear", nullptr}, "--moved goes with clear JOINTS"},
    {"count", {"watch", nullptr}, "--count goes with watch"},
    {"interval", {"watch", nullptr}, "--interval goes with watch"},
    {"task", {"move", "hand"}, "--task goes with move and hand"},
    {"raw", {"sii_read", nullptr}, "--raw goes with sii_read"},
    {"values", {"sdos", nullptr}, "--values goes with sdos"},
};

}  // namespace rescue::app
