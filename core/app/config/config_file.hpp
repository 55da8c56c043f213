// The configuration file of `rescue-motion run --config FILE` (docs/configuration.md): `key = value`
// lines, `# comment` lines, and `[task]` sections that set a task's priority and CPU over the task
// table (config/task_table.hpp). The file is untrusted bytes: its size and every line's length are
// bounded, every byte is checked, every key validated against its allowed range, and an unknown key is
// refused. Errors are values naming the line, the key and what is allowed. No heap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/app/config/nic_option.hpp"
#include "core/app/config/task_table.hpp"
#include "core/base/span.hpp"

namespace rescue::app {

constexpr std::size_t kConfigMaxBytes = 65536;  // a larger file is refused, not truncated
constexpr std::size_t kConfigMaxLine = 512;         // bytes per line, without its newline
constexpr std::size_t kConfigTextCapacity = 256;    // a path or address value, with its terminator
constexpr std::size_t kConfigTaskCount = 6;         // TaskId values
constexpr int kConfigMaxCpu = 1023;                 // CPU_SETSIZE - 1

using ConfigText = std::array<char, kConfigTextCapacity>;  // zero-terminated; empty = not set

struct ConfigTaskPlacement {
  bool has_priority{false};
  bool has_cpu{false};
  int priority{0};
  int cpu{0};
  std::uint32_t priority_line{0};
};

struct ConfigFile {
  bool has_nic{false};
  NicChoice nic{};
  ConfigText nic_text{};
  ConfigText ring_nic_text{};  // ring_nic: the second master port (cable redundancy; empty: none)
  ConfigText state_dir{};
  ConfigText key_file{};
  ConfigText listen{};
  bool has_duration{false};
  double duration_s{0.0};
  bool has_control_port{false};
  std::uint16_t control_port{0};
  bool has_sensor_port{false};
  std::uint16_t sensor_port{0};
  bool has_robot_id{false};
  std::uint32_t robot_id{0};  // this robot's identity in every datagram (docs/protocol.md), 1..999999999
  bool has_auto_clear_power_cycled{false};
  bool auto_clear_power_cycled{false};  // `run --auto-clear-power-cycled`
  std::uint32_t task_silent_ms{0};      // 0: not set (config::kTaskSilentAfterNs)
  std::array<ConfigTaskPlacement, kConfigTaskCount> tasks{};  // indexed by TaskId
};

// Why a file was refused. `what` and `allowed` are static strings; `key` is the key (or section, or
// the start of the line) as written, truncated to fit.
struct ConfigError {
  std::uint32_t line{0};  // 1-based; 0 for the whole file (size, unreadable)
  std::array<char, 48> key{};
  const char* what{""};
  const char* allowed{""};
  std::uint32_t os_errno{0};
  std::array<char, 768> detail{};  // a refused file (hal/files/trusted_file.hpp): the path, what is wrong, the fix
};

struct ConfigOutcome {
  bool ok{true};
  ConfigError error{};
};

// Parses the bytes of a configuration file into `out` (reset first).
ConfigOutcome parse_config(Span<const std::uint8_t> bytes, ConfigFile& out) noexcept;

// The rule of a path value (state_dir, key_file), the same in the file and on the command line
// (--state-dir, --key): absolute (the service's working directory is not the operator's), at most
// kConfigTextCapacity - 1 bytes. nullptr when `path` keeps it, else what is wrong.
const char* path_value_problem(const char* path) noexcept;
constexpr const char* kPathValueRule = "an absolute path of at most 255 bytes";

// Reads `path` (at most kConfigMaxBytes) and parses it.
ConfigOutcome load_config_file(const char* path, ConfigFile& out) noexcept;

// "FILE:LINE: key 'KEY': WHAT (allowed: ALLOWED)"; returns the length written (truncated to size).
std::size_t format_config_error(const char* file, const ConfigError& error, char* out, std::size_t size) noexcept;

// The task placements of the file over the task table (config/task_table.hpp).
void apply_task_placements(const ConfigFile& config) noexcept;

}  // namespace rescue::app
