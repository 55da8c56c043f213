// Explicit instantiations of the header-only containers. Without them a template is compiled only
// inside tests (which do not use the firmware flags) and is never seen by clang-tidy/cppcheck, which
// analyse firmware .cpp files: this unit puts every member under -Werror -Wconversion and analysis.
// One such unit per folder (core/concurrency/templates_compiled.cpp), so no folder includes another's.
#include <cstdint>

#include "core/containers/fixed_vector.hpp"
#include "core/containers/ring_buffer.hpp"

namespace rescue {

template class FixedVector<std::uint32_t, 8>;
template class RingBuffer<std::uint32_t, 8>;

}  // namespace rescue
