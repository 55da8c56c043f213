#include "drivers/sim/segment/fault_command.hpp"

#include <array>
#include <cstring>

namespace rescue::drivers {
namespace {

constexpr std::size_t kMaxTokens = 4;
constexpr std::size_t kMaxLine = 256;

struct Token {
  const char* text{nullptr};
  std::size_t length{0};
  bool is(const char* word) const noexcept { return std::strlen(word) == length && std::strncmp(text, word, length) == 0; }
};

struct Verb {
  const char* word;
  FaultKind kind;
  bool needs_slave;
  bool needs_value;
  bool needs_port{false};
  bool needs_state{false};
};

constexpr std::array<Verb, 19> kVerbs{{
    {"cut", FaultKind::cut, true, false},
    {"restore", FaultKind::restore, true, false},
    {"freeze", FaultKind::freeze, true, false},
    {"thaw", FaultKind::thaw, true, false},
    {"power-off", FaultKind::power_off, true, false},
    {"power-on", FaultKind::power_on, true, false},
    {"drop", FaultKind::drop, false, true},
    {"corrupt", FaultKind::corrupt, false, true},
    {"drive-fault", FaultKind::drive_fault, true, true},
    {"power-cycle", FaultKind::power_cycle, true, false},
    {"replace-cable", FaultKind::replace_cable, true, false},
    {"foreign", FaultKind::foreign, true, false},
    {"original", FaultKind::original, true, false},
    {"corrupt-port", FaultKind::corrupt_port, true, true, true},
    {"safe-op", FaultKind::safe_op, true, true},
    {"half-mapped", FaultKind::half_mapped, true, false},
    {"foreign-mapping", FaultKind::foreign_mapping, true, false},
    {"refuse", FaultKind::refuse, true, true, false, true},
    {"extra-slave", FaultKind::extra_slave, false, false},
}};

bool is_space(char c) noexcept { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// Decimal or 0x-hexadecimal, at most 32 bits.
bool parse_number(const Token& t, std::uint32_t& out) noexcept {
  std::size_t i = 0;
  unsigned base = 10;
  if (t.length > 2 && t.text[0] == '0' && (t.text[1] == 'x' || t.text[1] == 'X')) {
    base = 16;
    i = 2;
  }
  if (i >= t.length) return false;
  std::uint64_t v = 0;
  for (; i < t.length; ++i) {
    const char c = t.text[i];
    unsigned digit = 0;
    if (c >= '0' && c <= '9') {
      digit = static_cast<unsigned>(c - '0');
    } else if (base == 16 && c >= 'a' && c <= 'f') {
      digit = static_cast<unsigned>(c - 'a') + 10U;
    } else if (base == 16 && c >= 'A' && c <= 'F') {
      digit = static_cast<unsigned>(c - 'A') + 10U;
    } else {
      return false;
    }
    v = v * base + digit;
    if (v > 0xFFFFFFFFULL) return false;
  }
  out = static_cast<std::uint32_t>(v);
  return true;
}

bool find_slave(const Token& t, const SimulatedSegment& segment, std::size_t& position) noexcept {
  for (std::size_t p = 0; p < segment.slave_count(); ++p) {
    const char* name = segment.slave(p).name;
    if (name != nullptr && t.is(name)) {
      position = p;
      return true;
    }
  }
  std::uint32_t number = 0;
  if (parse_number(t, number) && number < segment.slave_count()) {
    position = number;
    return true;
  }
  return false;
}

}  // namespace

Result<FaultCommand> parse_fault_command(const char* text, std::size_t length, const SimulatedSegment& segment) noexcept {
  if (text == nullptr) return make_error(Errc::invalid_argument, "no fault command");
  std::array<Token, kMaxTokens> tokens{};
  std::size_t count = 0;
  bool in_word = false;
  for (std::size_t i = 0; i < length && i < kMaxLine && text[i] != '\0'; ++i) {
    if (is_space(text[i])) {
      in_word = false;
      continue;
    }
    if (!in_word) {
      if (count == kMaxTokens) return make_error(Errc::malformed, "too many words in fault command", static_cast<std::uint32_t>(i));
      tokens[count].text = text + i;
      ++count;
      in_word = true;
    }
    ++tokens[count - 1].length;
  }
  if (count == 0) return make_error(Errc::invalid_argument, "empty fault command");
  const Verb* verb = nullptr;
  for (const Verb& v : kVerbs) {
    if (tokens[0].is(v.word)) verb = &v;
  }
  if (verb == nullptr) return make_error(Errc::not_found, "unknown fault command");
  const std::size_t expected = 1U + (verb->needs_slave ? 1U : 0U) + (verb->needs_port ? 1U : 0U) + (verb->needs_state ? 1U : 0U) +
                               (verb->needs_value ? 1U : 0U);
  if (count != expected) return make_error(Errc::invalid_argument, "wrong number of words for fault command",
                                           static_cast<std::uint32_t>(count), static_cast<std::uint32_t>(expected));
  FaultCommand command;
  command.kind = verb->kind;
  std::size_t next = 1;
  if (verb->needs_slave && tokens[next].is(kRingCableWord)) {
    const bool cable_verb = command.kind == FaultKind::cut || command.kind == FaultKind::restore || command.kind == FaultKind::replace_cable;
    if (!cable_verb) return make_error(Errc::invalid_argument, "the ring cable takes cut, restore and replace-cable only");
    if (!segment.has_ring()) return make_error(Errc::not_found, "no ring cable: the segment is a tree");
    command.ring_cable = true;
    ++next;
  } else if (verb->needs_slave) {
    if (!find_slave(tokens[next], segment, command.position)) return make_error(Errc::not_found, "unknown slave");
    ++next;
  }
  if (verb->needs_port) {
    if (!parse_number(tokens[next], command.port)) return make_error(Errc::invalid_argument, "bad port in fault command");
    if (command.port >= kMaxEscPorts) return make_error(Errc::out_of_range, "port above 3", command.port);
    ++next;
  }
  if (verb->needs_state) {
    if (tokens[next].is("pre-op")) {
      command.state = AlState::pre_op;
    } else if (tokens[next].is("safe-op")) {
      command.state = AlState::safe_op;
    } else if (tokens[next].is("op")) {
      command.state = AlState::op;
    } else {
      return make_error(Errc::invalid_argument, "bad state in fault command (pre-op, safe-op, op)");
    }
    ++next;
  }
  if (verb->needs_value && !parse_number(tokens[next], command.value)) {
    return make_error(Errc::invalid_argument, "bad number in fault command");
  }
  if ((command.kind == FaultKind::drive_fault || command.kind == FaultKind::safe_op || command.kind == FaultKind::refuse) &&
      command.value > 0xFFFF) {
    return make_error(Errc::out_of_range, "error code above 0xFFFF", command.value);
  }
  return command;
}

Status apply_fault_command(const FaultCommand& command, SimulatedSegment& segment, hal::Nanoseconds now) noexcept {
  switch (command.kind) {
    case FaultKind::cut: return command.ring_cable ? segment.cut_ring_cable() : segment.cut_link(command.position);
    case FaultKind::restore: return command.ring_cable ? segment.restore_ring_cable() : segment.restore_link(command.position);
    case FaultKind::freeze: return segment.freeze(command.position, true);
    case FaultKind::thaw: return segment.freeze(command.position, false);
    case FaultKind::power_off: return segment.set_power(command.position, false, now);
    case FaultKind::power_on: return segment.set_power(command.position, true, now);
    case FaultKind::drop:
      segment.drop_frames(command.value);
      return Status::success();
    case FaultKind::corrupt:
      segment.corrupt_frames(command.value);
      return Status::success();
    case FaultKind::drive_fault:
      return segment.inject_device_fault(command.position, static_cast<std::uint16_t>(command.value));
    case FaultKind::power_cycle: return segment.power_cycle(command.position, now);
    case FaultKind::replace_cable:
      if (!command.ring_cable) return segment.replace_cable(command.position);
      {
        Status st = segment.cut_ring_cable();
        if (st.ok()) st = segment.restore_ring_cable();
        return st;
      }
    case FaultKind::foreign: return segment.plug_device(command.position, true, now);
    case FaultKind::original: return segment.plug_device(command.position, false, now);
    case FaultKind::corrupt_port: return segment.corrupt_port(command.position, command.port, command.value);
    case FaultKind::safe_op: return segment.drop_to_safe_op(command.position, static_cast<std::uint16_t>(command.value));
    case FaultKind::half_mapped: return segment.corrupt_pdo_mapping(command.position, PdoMappingFault::half_written);
    case FaultKind::refuse:
      return segment.refuse_state(command.position, command.state, static_cast<std::uint16_t>(command.value));
    case FaultKind::extra_slave: return segment.power_on_named("spare", now);
    case FaultKind::foreign_mapping: return segment.corrupt_pdo_mapping(command.position, PdoMappingFault::foreign_default);
  }
  return make_error(Errc::invalid_argument, "fault kind");
}

}  // namespace rescue::drivers
