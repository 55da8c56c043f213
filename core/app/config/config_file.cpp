#include "core/app/config/config_file.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "hal/files/trusted_file.hpp"

namespace rescue::app {
namespace {

struct Text {  // a view into the file's bytes (never zero-terminated)
  const std::uint8_t* data{nullptr};
  std::size_t size{0};
  bool equals(const char* s) const noexcept {
    const std::size_t n = std::strlen(s);
    return n == size && (n == 0 || std::memcmp(data, s, n) == 0);
  }
};

bool is_space(std::uint8_t c) noexcept { return c == ' ' || c == '\t'; }

Text trim(Text t) noexcept {
  while (t.size > 0 && is_space(t.data[0])) {
    ++t.data;
    --t.size;
  }
  while (t.size > 0 && is_space(t.data[t.size - 1])) --t.size;
  return t;
}

bool is_name_byte(std::uint8_t c) noexcept {
  return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}

struct TaskSection {
  const char* name;
  TaskId id;
  int min_priority;
  const char* priority_range;
};
// clang-format off
constexpr TaskSection kSections[] = {
  {"ethercat_handler", TaskId::ethercat_handler, 1, "1..99 (SCHED_FIFO)"},
  {"joint_manager", TaskId::joint_manager, 1, "1..99 (SCHED_FIFO)"},
  {"rc_tasks", TaskId::rc_tasks, 1, "1..99 (SCHED_FIFO)"},
  {"socket_handler", TaskId::socket_handler, 0, "0..99 (0: SCHED_OTHER)"},
  {"message_parser", TaskId::message_parser, 0, "0..99 (0: SCHED_OTHER)"},
};
// clang-format on
constexpr const char* kSectionNames =
    "[ethercat_handler], [joint_manager], [rc_tasks], [socket_handler], [message_parser]";
constexpr const char* kTopKeys =
    "nic, ring_nic, state_dir, key_file, listen, duration, control_port, sensor_port, robot_id, auto_clear_power_cycled, "
    "task_silent_ms (before any section)";
constexpr const char* kCpuRange = "0..1023";

class Parser {
 public:
  explicit Parser(ConfigFile& out) noexcept : out_(out) {}

  ConfigOutcome parse(Span<const std::uint8_t> bytes) noexcept {
    out_ = ConfigFile{};
    if (bytes.size() > kConfigMaxBytes) return fail_file("file larger than 65536 bytes", "at most 65536 bytes");
    std::size_t pos = 0;
    while (pos < bytes.size() && outcome_.ok) {
      std::size_t end = pos;
      while (end < bytes.size() && bytes[end] != '\n') ++end;
      ++line_;
      Text line{bytes.data() + pos, end - pos};
      if (line.size > 0 && line.data[line.size - 1] == '\r') --line.size;  // CRLF accepted
      parse_line(line);
      pos = end + 1;
    }
    if (outcome_.ok) check_whole();
    return outcome_;
  }

 private:
  void parse_line(Text line) noexcept {
    if (line.size > kConfigMaxLine) return fail(line, "line longer than 512 bytes", "at most 512 bytes per line");
    for (std::size_t i = 0; i < line.size; ++i) {
      const std::uint8_t c = line.data[i];
      if ((c < 0x20 && c != '\t') || c >= 0x7F) {
        return fail(line, "control or non-ASCII byte in the line", "printable ASCII, spaces and tabs");
      }
    }
    const Text t = trim(line);
    if (t.size == 0 || t.data[0] == '#') return;
    if (t.data[0] == '[') return parse_section(t);
    std::size_t eq = 0;
    while (eq < t.size && t.data[eq] != '=') ++eq;
    if (eq == t.size) return fail(t, "not a 'key = value' line, a [section] or a # comment", "key = value");
    const Text key = trim(Text{t.data, eq});
    const Text value = trim(Text{t.data + eq + 1, t.size - eq - 1});
    if (key.size == 0) return fail(t, "no key before '='", "key = value");
    for (std::size_t i = 0; i < key.size; ++i) {
      if (!is_name_byte(key.data[i])) return fail(key, "key has a character other than a-z, 0-9, _", "lower-case names");
    }
    if (value.size == 0) return fail(key, "empty value", "a value after '='");
    if (section_ == nullptr) return top_key(key, value);
    task_key(key, value);
  }

  void parse_section(Text t) noexcept {
    if (t.data[t.size - 1] != ']') return fail(t, "section without closing ']'", kSectionNames);
    const Text name = trim(Text{t.data + 1, t.size - 2});
    for (const TaskSection& s : kSections) {
      if (!name.equals(s.name)) continue;
      const auto index = static_cast<std::size_t>(s.id);
      if (seen_section_[index]) return fail(name, "section given twice", "each section once");
      seen_section_[index] = true;
      section_ = &s;
      return;
    }
    fail(name, "unknown section", kSectionNames);
  }

  // Each top-level key once.
  bool first_time(Text key, bool& seen) noexcept {
    if (seen) {
      fail(key, "key given twice", "each key once");
      return false;
    }
    seen = true;
    return true;
  }

  void top_key(Text key, Text value) noexcept {
    if (key.equals("nic")) {
      if (!first_time(key, seen_.nic) || !copy_text(key, value, out_.nic_text, false)) return;
      const Result<NicChoice> nic = parse_nic_option(out_.nic_text.data());
      if (!nic.ok()) return fail(key, nic.error().what, "sim or raw:IFACE (an interface name of at most 15 bytes)");
      out_.nic = nic.value();
      out_.has_nic = true;
    } else if (key.equals("ring_nic")) {
      // Its syntax here; whether it pairs with `nic` (another interface, both raw or both sim) when run
      // has both (parse_ring_nic_option), since --nic may override the file's.
      if (!first_time(key, seen_.ring_nic) || !copy_text(key, value, out_.ring_nic_text, false)) return;
      if (!parse_nic_option(out_.ring_nic_text.data()).ok()) {
        return fail(key, "not a NIC", "sim or raw:IFACE (an interface name of at most 15 bytes)");
      }
    } else if (key.equals("state_dir")) {
      if (first_time(key, seen_.state_dir)) (void)copy_text(key, value, out_.state_dir, true);
    } else if (key.equals("key_file")) {
      if (first_time(key, seen_.key_file)) (void)copy_text(key, value, out_.key_file, true);
    } else if (key.equals("listen")) {
      if (!first_time(key, seen_.listen) || !copy_text(key, value, out_.listen, false)) return;
      in_addr address{};
      if (inet_pton(AF_INET, out_.listen.data(), &address) != 1) {
        return fail(key, "not an IPv4 address", "dotted IPv4, e.g. 0.0.0.0 or 192.168.10.2");
      }
    } else if (key.equals("duration")) {
      if (!first_time(key, seen_.duration)) return;
      if (!parse_seconds(value, out_.duration_s) || !(out_.duration_s >= 0.001) || out_.duration_s > 604800.0) {
        return fail(key, "not a duration in range",
                    "decimal seconds, at least 0.001 (one period), at most 604800 (leave it out: run until SIGTERM)");
      }
      out_.has_duration = true;
    } else if (key.equals("control_port")) {
      if (first_time(key, seen_.control_port) && port(key, value, out_.control_port)) out_.has_control_port = true;
    } else if (key.equals("sensor_port")) {
      if (first_time(key, seen_.sensor_port) && port(key, value, out_.sensor_port)) out_.has_sensor_port = true;
    } else if (key.equals("robot_id")) {
      if (!first_time(key, seen_.robot_id)) return;
      std::int64_t n = 0;
      if (!parse_integer(value, n) || n < 1) return fail(key, "robot id out of range", "1..999999999");
      out_.robot_id = static_cast<std::uint32_t>(n);
      out_.has_robot_id = true;
    } else if (key.equals("auto_clear_power_cycled")) {
      if (!first_time(key, seen_.auto_clear_power_cycled)) return;
      if (value.equals("true")) {
        out_.auto_clear_power_cycled = true;
      } else if (value.equals("false")) {
        out_.auto_clear_power_cycled = false;
      } else {
        return fail(key, "not a boolean", "true or false");
      }
      out_.has_auto_clear_power_cycled = true;
    } else if (key.equals("task_silent_ms")) {
      // The supervisor's liveness limit (docs/tasks.md "Liveness"): above host jitter, below the
      // drives' 100 ms watchdog by default; up to 10 s allowed for slow hosts and debugging.
      std::int64_t n = 0;
      if (!first_time(key, seen_.task_silent_ms)) return;
      if (!parse_integer(value, n) || n < 2 || n > 10000) return fail(key, "not a time in range", "whole ms, 2..10000");
      out_.task_silent_ms = static_cast<std::uint32_t>(n);
    } else if (key.equals("priority") || key.equals("cpu")) {
      fail(key, "task key outside a task section", kSectionNames);
    } else {
      fail(key, "unknown key", kTopKeys);
    }
  }

  void task_key(Text key, Text value) noexcept {
    ConfigTaskPlacement& task = out_.tasks[static_cast<std::size_t>(section_->id)];
    std::int64_t n = 0;
    if (key.equals("priority")) {
      if (task.has_priority) return fail(key, "key given twice in this section", "each key once");
      if (!parse_integer(value, n) || n < section_->min_priority || n > 99) {
        return fail(key, "priority out of range", section_->priority_range);
      }
      task.has_priority = true;
      task.priority = static_cast<int>(n);
      task.priority_line = line_;
    } else if (key.equals("cpu")) {
      if (task.has_cpu) return fail(key, "key given twice in this section", "each key once");
      if (!parse_integer(value, n) || n < 0 || n > kConfigMaxCpu) return fail(key, "CPU out of range", kCpuRange);
      task.has_cpu = true;
      task.cpu = static_cast<int>(n);
    } else {
      fail(key, "unknown key in a task section", "priority, cpu");
    }
  }

  bool port(Text key, Text value, std::uint16_t& out) noexcept {
    std::int64_t n = 0;
    if (!parse_integer(value, n) || n < 1 || n > 65535) {
      fail(key, "port out of range", "1..65535");
      return false;
    }
    out = static_cast<std::uint16_t>(n);
    return true;
  }

  // Digits only, at most 9 of them (no sign, no overflow).
  static bool parse_integer(Text v, std::int64_t& out) noexcept {
    if (v.size == 0 || v.size > 9) return false;
    std::int64_t n = 0;
    for (std::size_t i = 0; i < v.size; ++i) {
      if (v.data[i] < '0' || v.data[i] > '9') return false;
      n = n * 10 + (v.data[i] - '0');
    }
    out = n;
    return true;
  }

  // DIGITS[.DIGITS], at most 7 integer and 9 fraction digits.
  static bool parse_seconds(Text v, double& out) noexcept {
    std::size_t i = 0;
    std::int64_t whole = 0;
    while (i < v.size && v.data[i] >= '0' && v.data[i] <= '9' && i < 7) whole = whole * 10 + (v.data[i++] - '0');
    if (i == 0) return false;
    double fraction = 0.0;
    if (i < v.size && v.data[i] == '.') {
      ++i;
      double scale = 0.1;
      std::size_t digits = 0;
      while (i < v.size && v.data[i] >= '0' && v.data[i] <= '9' && digits < 9) {
        fraction += scale * (v.data[i++] - '0');
        scale /= 10.0;
        ++digits;
      }
      if (digits == 0) return false;
    }
    if (i != v.size) return false;
    out = static_cast<double>(whole) + fraction;
    return true;
  }

  bool copy_text(Text key, Text value, ConfigText& out, bool absolute_path) noexcept {
    if (value.size >= out.size()) {
      fail(key, "value too long", absolute_path ? kPathValueRule : "at most 255 bytes");
      return false;
    }
    std::memcpy(out.data(), value.data, value.size);
    out[value.size] = '\0';
    const char* problem = absolute_path ? path_value_problem(out.data()) : nullptr;
    if (problem != nullptr) {
      out[0] = '\0';
      fail(key, problem, kPathValueRule);
      return false;
    }
    return true;
  }

  // Across keys: the ports differ, and the priorities keep the design's order (Table I).
  void check_whole() noexcept {
    if (out_.has_control_port && out_.has_sensor_port && out_.control_port == out_.sensor_port) {
      error_.line = 0;
      set_key("sensor_port");
      return fail_whole("control_port and sensor_port are equal", "two different ports");
    }
    struct Rank {
      TaskId above;
      TaskId below;
    };
    constexpr Rank kOrder[] = {{TaskId::ethercat_handler, TaskId::joint_manager}, {TaskId::joint_manager, TaskId::rc_tasks}};
    for (const Rank& r : kOrder) {
      const ConfigTaskPlacement& a = out_.tasks[static_cast<std::size_t>(r.above)];
      const ConfigTaskPlacement& b = out_.tasks[static_cast<std::size_t>(r.below)];
      if (!a.has_priority && !b.has_priority) continue;
      const int pa = a.has_priority ? a.priority : task_spec(r.above).priority;
      const int pb = b.has_priority ? b.priority : task_spec(r.below).priority;
      if (pa > pb) continue;
      error_.line = a.has_priority ? a.priority_line : b.priority_line;
      set_key("priority");
      return fail_whole("priorities out of the design's order",
                        "ethercat_handler above joint_manager above rc_tasks (Table I, docs/tasks.md)");
    }
  }

  void set_key(const char* key) noexcept { (void)std::snprintf(error_.key.data(), error_.key.size(), "%s", key); }

  void fail(Text key, const char* what, const char* allowed) noexcept {
    error_.line = line_;
    const std::size_t n = key.size < error_.key.size() - 1 ? key.size : error_.key.size() - 1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint8_t c = key.data[i];
      error_.key[i] = (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : '?';
    }
    error_.key[n] = '\0';
    fail_whole(what, allowed);
  }

  void fail_whole(const char* what, const char* allowed) noexcept {
    error_.what = what;
    error_.allowed = allowed;
    outcome_.ok = false;
    outcome_.error = error_;
  }

  ConfigOutcome fail_file(const char* what, const char* allowed) noexcept {
    error_.line = 0;
    fail_whole(what, allowed);
    return outcome_;
  }

  ConfigFile& out_;
  ConfigOutcome outcome_{};
  ConfigError error_{};
  std::uint32_t line_{0};
  const TaskSection* section_{nullptr};
  std::array<bool, kConfigTaskCount> seen_section_{};
  struct Seen {
    bool nic, ring_nic, state_dir, key_file, listen, duration, control_port, sensor_port, robot_id, auto_clear_power_cycled,
        task_silent_ms;
  } seen_{};
};

}  // namespace

const char* path_value_problem(const char* path) noexcept {
  const std::size_t length = std::strlen(path);
  if (length >= kConfigTextCapacity) return "value too long";
  if (length == 0 || path[0] != '/') return "not an absolute path";
  return nullptr;
}

ConfigOutcome parse_config(Span<const std::uint8_t> bytes, ConfigFile& out) noexcept {
  Parser parser(out);
  return parser.parse(bytes);
}

ConfigOutcome load_config_file(const char* path, ConfigFile& out) noexcept {
  ConfigOutcome outcome;
  outcome.ok = false;
  outcome.error.allowed =
      "a regular file of at most 65536 bytes, it and the directories above it owned by this user or root and not "
      "writable by group or others";
  // StrictModes (docs/security.md): the file decides the key file and the state directory, so
  // another user must not be able to write it; and nothing at its name may hang start-up.
  hal::FileProblem why;
  const Result<hal::OpenFile> file = hal::open_trusted_for_read(path, hal::Secrecy::public_file, why);
  if (!file.ok()) {
    if (file.error().code == Errc::not_found && file.error().detail0 != 0) {
      outcome.error.os_errno = file.error().detail0;
      outcome.error.what = "cannot open the file";
      return outcome;
    }
    outcome.error.what = "refused";
    outcome.error.detail = why.text;
    return outcome;
  }
  const int fd = file.value().fd();
  static std::array<std::uint8_t, kConfigMaxBytes + 1> buffer;  // start-up only; one more byte detects a larger file
  std::size_t size = 0;
  for (;;) {
    const ssize_t n = ::read(fd, buffer.data() + size, buffer.size() - size);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      outcome.error.os_errno = static_cast<std::uint32_t>(errno);
      outcome.error.what = "cannot read the file";
      return outcome;
    }
    if (n == 0) break;
    size += static_cast<std::size_t>(n);
    if (size == buffer.size()) break;
  }
  return parse_config(Span<const std::uint8_t>(buffer.data(), size), out);
}

std::size_t format_config_error(const char* file, const ConfigError& e, char* out, std::size_t size) noexcept {
  if (size == 0) return 0;
  char where[32] = "";
  if (e.line != 0) (void)std::snprintf(where, sizeof where, ":%u", e.line);
  char key[80] = "";
  if (e.key[0] != '\0') (void)std::snprintf(key, sizeof key, " key '%s':", e.key.data());
  char os[64] = "";
  if (e.os_errno != 0) {
    char reason[48];
    // GNU strerror_r (thread-safe): returns the text, in `reason` or a static string.
    (void)std::snprintf(os, sizeof os, " (%s)", strerror_r(static_cast<int>(e.os_errno), reason, sizeof reason));
  }
  const int n = e.detail[0] != '\0' ? std::snprintf(out, size, "%s: %s", file, e.detail.data())
                                     : std::snprintf(out, size, "%s%s:%s %s%s (allowed: %s)", file, where, key, e.what, os, e.allowed);
  if (n < 0) return 0;
  return static_cast<std::size_t>(n) < size ? static_cast<std::size_t>(n) : size - 1;
}

void apply_task_placements(const ConfigFile& config) noexcept {
  for (std::size_t i = 0; i < config.tasks.size(); ++i) {
    const ConfigTaskPlacement& t = config.tasks[i];
    const auto id = static_cast<TaskId>(i);
    if (t.has_priority) set_task_priority(id, t.priority);
    if (t.has_cpu) set_task_cpu(id, t.cpu);
  }
}

}  // namespace rescue::app
