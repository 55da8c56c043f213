// Test support: a figure of a command's `key: value` output (the benchmarks' and run's lines).
#pragma once

#include <string>

namespace rescue::test {

// The value of the line `key: value` in `text` ("" when absent; a line, not the first one).
inline std::string value_of(const std::string& text, const std::string& key) {
  const std::string want = "\n" + key + ": ";
  const std::size_t at = text.find(want);
  if (at == std::string::npos) return "";
  const std::size_t from = at + want.size();
  return text.substr(from, text.find('\n', from) - from);
}

}  // namespace rescue::test
