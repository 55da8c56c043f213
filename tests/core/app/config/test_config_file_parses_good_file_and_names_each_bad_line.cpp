// The configuration file (core/app/config/config_file.hpp): a good file sets every key; each kind of
// bad line is refused with its line number, its key and what is allowed; the task sections move tasks
// in the task table.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "core/app/config/config_file.hpp"

namespace rescue::app {
namespace {

ConfigOutcome parse(const std::string& text, ConfigFile& out) {
  return parse_config(Span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()), out);
}

std::string message(const ConfigOutcome& o) {
  char line[512];
  (void)format_config_error("f.conf", o.error, line, sizeof line);
  return line;
}

TEST(ConfigFile, GoodFileSetsEveryKey) {
  const std::string text =
      "# the motion PC\n"
      "nic = raw:enp2s0\r\n"
      "ring_nic = raw:enp3s0\n"
      "state_dir = /var/lib/rescue-motion\n"
      "key_file = /var/lib/rescue-motion/operator.key\n"
      "listen = 192.168.10.2\n"
      "duration = 1.5\n"
      "control_port = 47100\n"
      "\t sensor_port=47101 \n"
      "robot_id = 42\n"
      "auto_clear_power_cycled = true\n"
      "task_silent_ms = 45\n"
      "\n"
      "[ethercat_handler]\n"
      "priority = 90\n"
      "cpu = 3\n"
      "[joint_manager]\n"
      "priority = 85\n"
      "cpu = 2\n"
      "[socket_handler]\n"
      "priority = 0\n"
      "cpu = 1\n";
  ConfigFile c;
  const ConfigOutcome o = parse(text, c);
  ASSERT_TRUE(o.ok) << message(o);
  EXPECT_TRUE(c.has_nic);
  EXPECT_EQ(c.nic.kind, NicKind::raw);
  EXPECT_STREQ(c.nic.interface_name.data(), "enp2s0");
  EXPECT_STREQ(c.ring_nic_text.data(), "raw:enp3s0");
  EXPECT_STREQ(c.state_dir.data(), "/var/lib/rescue-motion");
  EXPECT_STREQ(c.key_file.data(), "/var/lib/rescue-motion/operator.key");
  EXPECT_STREQ(c.listen.data(), "192.168.10.2");
  EXPECT_TRUE(c.has_duration);
  EXPECT_DOUBLE_EQ(c.duration_s, 1.5);
  EXPECT_EQ(c.control_port, 47100);
  EXPECT_EQ(c.sensor_port, 47101);
  EXPECT_TRUE(c.has_robot_id);
  EXPECT_EQ(c.robot_id, 42U);
  EXPECT_TRUE(c.has_auto_clear_power_cycled);
  EXPECT_TRUE(c.auto_clear_power_cycled);
  EXPECT_EQ(c.task_silent_ms, 45U);
  const ConfigTaskPlacement& handler = c.tasks[static_cast<std::size_t>(TaskId::ethercat_handler)];
  EXPECT_TRUE(handler.has_priority);
  EXPECT_EQ(handler.priority, 90);
  EXPECT_EQ(handler.cpu, 3);
  EXPECT_FALSE(c.tasks[static_cast<std::size_t>(TaskId::message_parser)].has_priority);
}

TEST(ConfigFile, EmptyFileSetsNothing) {
  ConfigFile c;
  ASSERT_TRUE(parse("", c).ok);
  EXPECT_FALSE(c.has_nic);
  EXPECT_EQ(c.state_dir[0], '\0');
  EXPECT_FALSE(c.has_duration);
}

struct BadLine {
  const char* text;
  unsigned line;
  const char* key;
  const char* what;
  const char* allowed;  // a part of the allowed text
};

TEST(ConfigFile, EachKindOfBadLineIsNamed) {
  const BadLine cases[] = {
      {"nic = sim\nspeed = 3\n", 2, "speed", "unknown key", "nic, ring_nic, state_dir"},
      {"[joint_manager]\nperiod = 3\n", 2, "period", "unknown key in a task section", "priority, cpu"},
      {"[kinematics]\n", 1, "kinematics", "unknown section", "[ethercat_handler]"},
      {"[joint_manager\n", 1, "[joint_manager", "section without closing ']'", "[ethercat_handler]"},
      {"[joint_manager]\n[joint_manager]\n", 2, "joint_manager", "section given twice", "each section once"},
      {"nic = sim\nnic = sim\n", 2, "nic", "key given twice", "each key once"},
      {"[rc_tasks]\ncpu = 1\ncpu = 1\n", 3, "cpu", "key given twice in this section", "each key once"},
      {"just words\n", 1, "just words", "not a 'key = value' line, a [section] or a # comment", "key = value"},
      {"= 3\n", 1, "= 3", "no key before '='", "key = value"},
      {"Nic = sim\n", 1, "Nic", "key has a character other than a-z, 0-9, _", "lower-case"},
      {"nic =\n", 1, "nic", "empty value", "a value"},
      {"nic = tap:eth0\n", 1, "nic", "", "sim or raw:IFACE"},
      {"ring_nic = eth1\n", 1, "ring_nic", "not a NIC", "sim or raw:IFACE"},
      {"state_dir = var/lib\n", 1, "state_dir", "not an absolute path", "absolute path"},
      {"listen = 300.1.1.1\n", 1, "listen", "not an IPv4 address", "dotted IPv4"},
      {"duration = 0\n", 1, "duration", "not a duration in range", "at least 0.001"},
      {"duration = 0.0000000001\n", 1, "duration", "not a duration in range", "at least 0.001 (one period)"},
      {"duration = 604801\n", 1, "duration", "not a duration in range", "at most 604800"},
      {"duration = 1e3\n", 1, "duration", "not a duration in range", "decimal seconds"},
      {"duration = 1.\n", 1, "duration", "not a duration in range", "decimal seconds"},
      {"control_port = 0\n", 1, "control_port", "port out of range", "1..65535"},
      {"sensor_port = 65536\n", 1, "sensor_port", "port out of range", "1..65535"},
      {"robot_id = 0\n", 1, "robot_id", "robot id out of range", "1..999999999"},
      {"robot_id = -3\n", 1, "robot_id", "robot id out of range", "1..999999999"},
      {"auto_clear_power_cycled = yes\n", 1, "auto_clear_power_cycled", "not a boolean", "true or false"},
      {"auto_clear_power_cycled = false\nauto_clear_power_cycled = true\n", 2, "auto_clear_power_cycled", "key given twice", "each key once"},
      {"task_silent_ms = 1\n", 1, "task_silent_ms", "not a time in range", "2..10000"},
      {"task_silent_ms = 30.5\n", 1, "task_silent_ms", "not a time in range", "whole ms"},
      {"control_port = -5\n", 1, "control_port", "port out of range", "1..65535"},
      {"control_port = 99999999999\n", 1, "control_port", "port out of range", "1..65535"},
      {"[ethercat_handler]\npriority = 0\n", 2, "priority", "priority out of range", "1..99"},
      {"[message_parser]\npriority = 100\n", 2, "priority", "priority out of range", "0..99"},
      {"[joint_manager]\ncpu = 1024\n", 2, "cpu", "CPU out of range", "0..1023"},
      {"priority = 5\n", 1, "priority", "task key outside a task section", "[ethercat_handler]"},
      {"nic = s\x01m\n", 1, "nic = s?m", "control or non-ASCII byte in the line", "printable ASCII"},
      {"nic = s\xc3\xa9m\n", 1, "nic = s??m", "control or non-ASCII byte in the line", "printable ASCII"},
      {"control_port = 5\nsensor_port = 5\n", 0, "sensor_port", "control_port and sensor_port are equal", "different"},
      {"[joint_manager]\npriority = 85\n", 2, "priority", "priorities out of the design's order", "ethercat_handler above"},
  };
  for (const BadLine& b : cases) {
    ConfigFile c;
    const ConfigOutcome o = parse(b.text, c);
    ASSERT_FALSE(o.ok) << b.text;
    EXPECT_EQ(o.error.line, b.line) << b.text;
    EXPECT_STREQ(o.error.key.data(), b.key) << b.text;
    if (b.what[0] != '\0') {
      EXPECT_STREQ(o.error.what, b.what) << b.text;
    }
    EXPECT_NE(std::strstr(o.error.allowed, b.allowed), nullptr) << b.text << " allowed: " << o.error.allowed;
  }
}

TEST(ConfigFile, MessageNamesFileLineKeyAndAllowedRange) {
  ConfigFile c;
  const ConfigOutcome o = parse("[joint_manager]\ncpu = 4096\n", c);
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(message(o), "f.conf:2: key 'cpu': CPU out of range (allowed: 0..1023)");
}

TEST(ConfigFile, OversizedFileAndLineAreRefused) {
  ConfigFile c;
  const std::string big(kConfigMaxBytes + 1, '#');
  const ConfigOutcome file = parse(big, c);
  ASSERT_FALSE(file.ok);
  EXPECT_EQ(file.error.line, 0U);
  const std::string line = "state_dir = /" + std::string(kConfigMaxLine, 'a') + "\n";
  const ConfigOutcome long_line = parse(line, c);
  ASSERT_FALSE(long_line.ok);
  EXPECT_STREQ(long_line.error.what, "line longer than 512 bytes");
  const std::string path = "state_dir = /" + std::string(kConfigTextCapacity, 'a') + "\n";
  const ConfigOutcome long_value = parse(path, c);
  ASSERT_FALSE(long_value.ok);
  EXPECT_STREQ(long_value.error.what, "value too long");
}

TEST(ConfigFile, MissingFileIsAnErrorWithTheOsReason) {
  ConfigFile c;
  const ConfigOutcome o = load_config_file("/nonexistent/rescue-motion.conf", c);
  ASSERT_FALSE(o.ok);
  EXPECT_EQ(o.error.line, 0U);
  char line[256];
  (void)format_config_error("/nonexistent/rescue-motion.conf", o.error, line, sizeof line);
  EXPECT_NE(std::strstr(line, "cannot open the file (No such file or directory)"), nullptr) << line;
}

TEST(ConfigFile, TaskSectionsMoveTasksInTheTaskTable) {
  ConfigFile c;
  ASSERT_TRUE(parse("[joint_manager]\ncpu = 1\n[message_parser]\npriority = 15\n", c).ok);
  EXPECT_EQ(runner_priority(TaskId::message_parser), 0);  // normal priority until a file sets it
  apply_task_placements(c);
  EXPECT_EQ(task_spec(TaskId::joint_manager).cpu, 1);
  EXPECT_EQ(task_spec(TaskId::joint_manager).priority, 70);  // unchanged
  EXPECT_EQ(runner_priority(TaskId::message_parser), 15);
  EXPECT_EQ(runner_priority(TaskId::socket_handler), 0);
}

}  // namespace
}  // namespace rescue::app
