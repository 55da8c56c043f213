// libFuzzer target: the configuration file parser (core/app/config/config_file.hpp) on arbitrary bytes
// (an operator's editor, a damaged disk). Beyond "no crash, no out-of-bounds read": a refusal names a
// line inside the file and a non-empty reason, an accepted file's texts are zero-terminated within
// their capacity, and its values lie in their documented ranges.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "core/app/config/config_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rescue::app;
  static ConfigFile config;
  const ConfigOutcome o = parse_config(rescue::Span<const std::uint8_t>(data, size), config);
  if (!o.ok) {
    if (o.error.what == nullptr || o.error.what[0] == '\0' || o.error.allowed[0] == '\0') std::abort();
    if (o.error.line > size + 1) std::abort();
    if (std::memchr(o.error.key.data(), '\0', o.error.key.size()) == nullptr) std::abort();
    char line[512];
    (void)format_config_error("fuzz", o.error, line, sizeof line);
    return 0;
  }
  for (const ConfigText* t : {&config.nic_text, &config.state_dir, &config.key_file, &config.listen}) {
    if (std::memchr(t->data(), '\0', t->size()) == nullptr) std::abort();
  }
  if (config.has_duration && !(config.duration_s > 0.0 && config.duration_s <= 604800.0)) std::abort();
  if (config.has_control_port && config.control_port == 0) std::abort();
  for (const ConfigTaskPlacement& t : config.tasks) {
    if (t.has_priority && (t.priority < 0 || t.priority > 99)) std::abort();
    if (t.has_cpu && (t.cpu < 0 || t.cpu > kConfigMaxCpu)) std::abort();
  }
  return 0;
}
