// The verbs of `rescue-motion ctl` (cmd_ctl.cpp), one table: ctl refuses a verb that is not in it,
// and tests/core/app/cli/test_ctl_verbs_are_all_documented_in_operator_docs.cpp requires every verb
// in it to appear in `ctl --help` and in docs/operator.md's generated transcript
// (toolchain/operator-transcript.sh), so a new verb cannot land without its documentation.
#pragma once

#include <algorithm>
#include <cstring>
#include <iterator>

namespace rescue::app {

inline constexpr const char* kCtlVerbs[] = {
    "keygen", "status", "slaves", "master", "tasks", "diag", "watch", "init",
    "enable", "disable", "hold",  "mode",   "clear", "move",  "hand", "owner", "version", "graph",
    "upload", "download",
};

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
};

inline bool is_ctl_verb(const char* verb) noexcept {
  return std::any_of(std::begin(kCtlVerbs), std::end(kCtlVerbs), [verb](const char* v) { return std::strcmp(v, verb) == 0; });
}

}  // namespace rescue::app
