#include "ecat/codec/command.hpp"

#include <cstring>

namespace rescue::ecat {
namespace {

// A plain array: cppcheck cannot see std::array's element type without the system headers.
constexpr const char* kMnemonics[kCommandCount] = {
    "NOP", "APRD", "APWR", "APRW", "FPRD", "FPWR", "FPRW", "BRD",
    "BWR", "BRW",  "LRD",  "LWR",  "LRW",  "ARMW", "FRMW",
};

}  // namespace

const char* mnemonic(Command c) noexcept {
  const auto raw = static_cast<std::uint8_t>(c);
  if (raw >= kCommandCount) return "?";
  return kMnemonics[raw];
}

bool command_from_mnemonic(const char* text, Command& out) noexcept {
  for (std::uint8_t i = 0; i < kCommandCount; ++i) {
    if (std::strcmp(kMnemonics[i], text) == 0) {
      out = static_cast<Command>(i);
      return true;
    }
  }
  return false;
}

}  // namespace rescue::ecat
