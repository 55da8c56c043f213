#include "ecat/command.hpp"

#include <array>
#include <cstring>

namespace rescue::ecat {
namespace {

constexpr std::array<const char*, kCommandCount> kMnemonics{
    "NOP", "APRD", "APWR", "APRW", "FPRD", "FPWR", "FPRW", "BRD",
    "BWR", "BRW",  "LRD",  "LWR",  "LRW",  "ARMW", "FRMW",
};

}  // namespace

const char* mnemonic(Command c) noexcept {
  const auto raw = static_cast<std::uint8_t>(c);
  return raw < kCommandCount ? kMnemonics[raw] : "?";
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
