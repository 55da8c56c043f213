// What this build of the program is (ctl version, docs/operator.md): `git describe` of the source it
// was configured from (.dirty when the tree had changes then; a new commit reconfigures) and the
// CMake build type. Generated at configure time (build_info.cpp.in).
#pragma once

namespace rescue::app {

const char* build_program_version() noexcept;  // e.g. "fa09471-dirty", "v0.2.0-5-gabc1234"
const char* build_type() noexcept;             // Debug, Release, RelWithDebInfo, ...

}  // namespace rescue::app
