// The real devices' SII images in ../shared/vectors/sii that tests read (never copied into the
// project). Tests only.
#pragma once

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace rescue::test {

inline const std::string kSharedSiiDir = std::string(RESCUE_SHARED_DIR) + "/vectors/sii/";

// The whole image in `name` (e.g. "ek1100.bin"); empty when the shared vectors are absent.
inline std::vector<std::uint8_t> read_shared_sii(const char* name) {
  std::ifstream in(kSharedSiiDir + name, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace rescue::test
