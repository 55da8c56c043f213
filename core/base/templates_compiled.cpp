// Explicit instantiations of core's header-only templates. Without them a template is compiled only
// inside tests (which do not use the firmware flags) and is never seen by clang-tidy/cppcheck, which
// analyse firmware .cpp files: this unit puts every member under -Werror -Wconversion and analysis.
#include <cstdint>

#include "core/containers/fixed_vector.hpp"
#include "core/containers/ring_buffer.hpp"
#include "core/concurrency/seqlock.hpp"
#include "core/concurrency/spsc_message_port.hpp"
#include "core/concurrency/spsc_queue.hpp"

namespace rescue {

namespace {
struct Sample {
  std::uint64_t sequence;
  std::int32_t position;
  std::uint16_t status;
};
}  // namespace

template class FixedVector<std::uint32_t, 8>;
template class RingBuffer<std::uint32_t, 8>;
template class Seqlock<Sample>;
template class SpscQueue<Sample, 16>;
template class SpscMessageSink<Sample, 16>;
template class SpscMessageSource<Sample, 16>;

}  // namespace rescue
