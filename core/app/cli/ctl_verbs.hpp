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
    "enable", "disable", "hold",  "mode",   "clear", "move",  "hand", "owner", "version",
    "upload", "download",
};

inline bool is_ctl_verb(const char* verb) noexcept {
  return std::any_of(std::begin(kCtlVerbs), std::end(kCtlVerbs), [verb](const char* v) { return std::strcmp(v, verb) == 0; });
}

}  // namespace rescue::app
