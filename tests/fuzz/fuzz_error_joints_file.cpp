// libFuzzer target: the error-joints file decoder on arbitrary bytes (it reads a file that may be
// damaged, truncated or foreign). Properties beyond "no crash, no out-of-bounds read": every record it
// keeps re-encodes and decodes to itself, and a status of success implies nothing was rejected.
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "core/robot/error_joints_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue;
  const ErrorJointsDecoded d = decode_error_joints(ConstByteSpan(data, size));
  if (d.status.ok() && d.records_rejected != 0) std::abort();
  if (d.contents.records.size() > kJointCount) std::abort();
  std::array<std::uint8_t, kErrorJointsMaxFileSize> buf{};
  auto encoded = encode_error_joints(d.contents, ByteSpan(buf));
  if (!encoded.ok()) std::abort();  // whatever the decoder keeps must be valid
  const ErrorJointsDecoded again = decode_error_joints(ConstByteSpan(buf.data(), encoded.value()));
  if (!again.status.ok() || again.contents.records.size() != d.contents.records.size()) std::abort();
  return 0;
}
