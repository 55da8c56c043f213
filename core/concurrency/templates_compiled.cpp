// Explicit instantiations of the header-only concurrency templates, for the same reason as
// core/containers/templates_compiled.cpp: every member compiled under the firmware flags and analysed.
#include <cstdint>

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

template class Seqlock<Sample>;
template class SpscQueue<Sample, 16>;
template class SpscMessageSink<Sample, 16>;
template class SpscMessageSource<Sample, 16>;

}  // namespace rescue
