#include "core/app/cli/ctl_sdo.hpp"

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/robot/robot.hpp"
#include "ecat/mailbox/coe.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using protocol::SdoStatus;

enum class ValueType : std::uint8_t { none, u8, u16, u32, i8, i16, i32, string, hex };

struct TypeName {
  const char* name;
  std::size_t size;  // 0: any
  ValueType type;
  bool is_signed;
};
constexpr TypeName kTypes[] = {
    {"u8", 1, ValueType::u8, false},   {"u16", 2, ValueType::u16, false}, {"u32", 4, ValueType::u32, false},
    {"i8", 1, ValueType::i8, true},    {"i16", 2, ValueType::i16, true},  {"i32", 4, ValueType::i32, true},
    {"string", 0, ValueType::string, false}, {"hex", 0, ValueType::hex, false},
};

template <typename Match>
const TypeName* find_type(Match match) noexcept {
  const TypeName* t = std::find_if(std::begin(kTypes), std::end(kTypes), match);
  return t != std::end(kTypes) ? t : nullptr;
}

const TypeName* type_named(const char* name) noexcept {
  return find_type([name](const TypeName& t) { return std::strcmp(t.name, name) == 0; });
}

const TypeName* type_of(ValueType v) noexcept {
  return find_type([v](const TypeName& t) { return t.type == v; });
}

// The --type of this invocation, for printing the answer (one client process).
ValueType g_type = ValueType::none;
char g_text[512];

Error bad(const char* text) noexcept { return make_error(Errc::invalid_argument, text); }

// One hexadecimal number (0x optional), the whole of [begin, end).
bool parse_hex(const char* begin, const char* end, std::uint32_t max, std::uint32_t& out) noexcept {
  if (end - begin > 2 && begin[0] == '0' && (begin[1] == 'x' || begin[1] == 'X')) begin += 2;
  if (begin == end || end - begin > 8) return false;
  std::uint32_t v = 0;
  for (const char* p = begin; p < end; ++p) {
    const char c = *p;
    std::uint32_t d = 0;
    if (c >= '0' && c <= '9') d = static_cast<std::uint32_t>(c - '0');
    else if (c >= 'a' && c <= 'f') d = static_cast<std::uint32_t>(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F') d = static_cast<std::uint32_t>(c - 'A' + 10);
    else return false;
    v = v * 16 + d;
  }
  if (v > max) return false;
  out = v;
  return true;
}

}  // namespace

Status parse_sdo_slave(const char* name, protocol::SdoPayload& sdo) noexcept {
  const std::size_t joint = joint_index_by_name(name);
  if (joint < kJointCount) {
    sdo.target = protocol::SdoTarget::joint;
    sdo.joint = static_cast<std::uint8_t>(joint);
    return Status::success();
  }
  const std::size_t position = planned_slave_named(name);
  if (position >= kSlaveCount) {
    (void)std::snprintf(g_text, sizeof g_text,
                        "SLAVE: '%.40s' is not a slave; a joint's or a slave's name (ctl slaves) or a position 0..%zu",
                        name, kSlaveCount - 1);
    return bad(g_text);
  }
  sdo.target = protocol::SdoTarget::slave;
  sdo.joint = 0;
  sdo.slave = static_cast<std::uint8_t>(position);
  return Status::success();
}

std::size_t sdo_slave_position(protocol::SdoTarget target, std::uint8_t joint, std::uint8_t slave) noexcept {
  if (target == protocol::SdoTarget::slave) return slave < kSlaveCount ? slave : kSlaveCount;
  return joint < kJointCount ? slave_position_of_joint(joint) : kSlaveCount;
}

namespace {

// The slave a result names (its position).
std::size_t position_of(const protocol::SdoResultPayload& r) noexcept { return sdo_slave_position(r.target, r.joint, r.slave); }

Status address_of(const char* text, protocol::SdoPayload& sdo) noexcept {
  const char* colon = std::strchr(text, ':');
  const char* end = text + std::strlen(text);
  std::uint32_t index = 0;
  std::uint32_t sub = 0;
  const bool ok = parse_hex(text, colon != nullptr ? colon : end, 0xFFFF, index) && index != 0 &&
                  (colon == nullptr || parse_hex(colon + 1, end, 0xFF, sub));
  if (!ok) {
    (void)std::snprintf(g_text, sizeof g_text,
                        "INDEX:SUB: '%.40s' is not an object address; both hexadecimal, e.g. 0x100A:00", text);
    return bad(g_text);
  }
  sdo.index = static_cast<std::uint16_t>(index);
  sdo.subindex = static_cast<std::uint8_t>(sub);
  return Status::success();
}

// VALUE as `type` into sdo.data/size.
Status value_of(const char* text, const TypeName& type, protocol::SdoPayload& sdo) noexcept {
  sdo.data.fill(0);
  if (type.type == ValueType::string) {
    const std::size_t n = std::strlen(text);
    if (n == 0 || n > protocol::kSdoDataSize) return bad("VALUE: a string of 1..256 characters");
    std::memcpy(sdo.data.data(), text, n);
    sdo.size = static_cast<std::uint16_t>(n);
    return Status::success();
  }
  if (type.type == ValueType::hex) {
    std::size_t n = 0;
    const char* p = text;
    if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) p += 2;
    while (*p != '\0') {
      if (*p == ' ' || *p == ':') {
        ++p;
        continue;
      }
      std::uint32_t byte = 0;
      if (p[1] == '\0' || !parse_hex(p, p + 2, 0xFF, byte) || n >= protocol::kSdoDataSize) {
        return bad("VALUE: hex bytes, two digits each (e.g. 0a0b0c or \"0a 0b 0c\"), at most 256");
      }
      sdo.data[n++] = static_cast<std::uint8_t>(byte);
      p += 2;
    }
    if (n == 0) return bad("VALUE: hex bytes, two digits each (e.g. 0a0b0c)");
    sdo.size = static_cast<std::uint16_t>(n);
    return Status::success();
  }
  char* end = nullptr;
  errno = 0;
  std::uint32_t bits = 0;
  const unsigned width = 8U * static_cast<unsigned>(type.size);
  if (type.is_signed) {
    const long long v = std::strtoll(text, &end, 0);
    const long long lo = -(1LL << (width - 1));
    const long long hi = (1LL << (width - 1)) - 1;
    if (end == text || *end != '\0' || errno != 0 || v < lo || v > hi) {
      (void)std::snprintf(g_text, sizeof g_text, "VALUE: '%.40s' is not an %s (%lld..%lld)", text, type.name, lo, hi);
      return bad(g_text);
    }
    bits = static_cast<std::uint32_t>(v);
  } else {
    const unsigned long long hi = (1ULL << width) - 1;
    const unsigned long long v = text[0] == '-' ? hi + 1 : std::strtoull(text, &end, 0);
    if (text[0] == '-' || end == text || *end != '\0' || errno != 0 || v > hi) {
      (void)std::snprintf(g_text, sizeof g_text, "VALUE: '%.40s' is not a %s (0..%llu, decimal or 0x hex)", text, type.name, hi);
      return bad(g_text);
    }
    bits = static_cast<std::uint32_t>(v);
  }
  for (std::size_t i = 0; i < type.size; ++i) sdo.data[i] = static_cast<std::uint8_t>(bits >> (8U * i));
  sdo.size = static_cast<std::uint16_t>(type.size);
  return Status::success();
}

bool printable(const std::uint8_t* data, std::size_t n) noexcept {
  if (n == 0) return true;
  for (std::size_t i = 0; i < n; ++i) {
    if (data[i] < 0x20 || data[i] > 0x7E) return false;
  }
  return true;
}

// How an uploaded value is shown: the --type, else by its size.
ValueType shown_as(const protocol::SdoResultPayload& r) noexcept {
  if (g_type != ValueType::none) return g_type;
  switch (r.size) {
    case 1: return ValueType::u8;
    case 2: return ValueType::u16;
    case 4: return ValueType::u32;
    default: return printable(r.data.data(), r.size) ? ValueType::string : ValueType::hex;
  }
}

std::uint32_t raw_number(const protocol::SdoResultPayload& r, std::size_t size) noexcept {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < size && i < r.size && i < 4; ++i) v |= static_cast<std::uint32_t>(r.data[i]) << (8U * i);
  return v;
}

std::int64_t signed_number(std::uint32_t raw, std::size_t size) noexcept {
  switch (size) {
    case 1: return static_cast<std::int8_t>(raw);
    case 2: return static_cast<std::int16_t>(raw);
    default: return static_cast<std::int32_t>(raw);
  }
}

void print_hex_bytes(const protocol::SdoResultPayload& r, const char* separator) noexcept {
  for (std::size_t i = 0; i < r.size; ++i) (void)std::printf("%s%02x", i == 0 ? "" : separator, r.data[i]);
}

const char* verb_of(const protocol::SdoResultPayload& r) noexcept {
  return r.request_type == MessageType::sdo_download ? "download" : "upload";
}

void print_value(const protocol::SdoResultPayload& r, bool json) noexcept {
  const ValueType shown = shown_as(r);
  const TypeName* t = type_of(shown);
  if (json) {
    (void)std::printf(R"(,"type":"%s","value":)", t != nullptr ? t->name : "hex");
  }
  if (shown == ValueType::string) {
    if (json) {
      print_json_bytes(r.data.data(), r.size);
    } else {
      print_text_bytes(r.data.data(), r.size);
      (void)std::putchar('\n');
    }
  } else if (shown == ValueType::hex || t == nullptr) {
    if (json) {
      (void)std::putchar('"');
      print_hex_bytes(r, "");
      (void)std::putchar('"');
    } else {
      print_hex_bytes(r, " ");
      (void)std::printf("\n");
    }
  } else {
    const std::uint32_t raw = raw_number(r, t->size);
    const int digits = static_cast<int>(2 * t->size);
    if (t->is_signed) {
      const std::int64_t v = signed_number(raw, t->size);
      if (json) (void)std::printf("%" PRId64 ",\"hex\":\"0x%0*" PRIX32 "\"", v, digits, raw);
      else (void)std::printf("0x%0*" PRIX32 " %" PRId64 "\n", digits, raw, v);
    } else {
      if (json) (void)std::printf("%" PRIu32 ",\"hex\":\"0x%0*" PRIX32 "\"", raw, digits, raw);
      else (void)std::printf("0x%0*" PRIX32 " %" PRIu32 "\n", digits, raw, raw);
    }
  }
}

}  // namespace

Result<Message> build_sdo_request(const ParsedArgs& args, CtlPeer& peer) noexcept {
  const bool download = std::strcmp(args.positional(0), "download") == 0;
  const TypeName* type = nullptr;
  if (args.value("type") != nullptr) {
    type = type_named(args.value("type"));
    if (type == nullptr) return bad("--type must be u8, u16, u32, i8, i16, i32, string or hex");
    g_type = type->type;
  }
  Message m;
  m.header.type = download ? MessageType::sdo_download : MessageType::sdo_upload;
  RESCUE_TRY(parse_sdo_slave(args.positional(1), m.sdo));
  RESCUE_TRY(address_of(args.positional(2), m.sdo));
  if (!download) return m;
  if (type == nullptr) {
    // No --type: the object's size decides, as the drive reports it now.
    Message probe;
    probe.header.type = MessageType::sdo_upload;
    probe.sdo = m.sdo;
    probe.sdo.size = 0;
    const Result<CtlTarget> target = peer.target();
    if (!target.ok()) return target.error();
    const Result<Message> answer = ctl_exchange(target.value(), probe);
    if (!answer.ok()) return answer.error();
    const protocol::SdoResultPayload& r = answer.value().sdo_result;
    if (answer.value().header.type != MessageType::sdo_result || r.status != SdoStatus::ok) {
      (void)std::snprintf(g_text, sizeof g_text,
                          "download without --type: reading the object's size failed (%s: %s); give --type",
                          protocol::to_string(r.status), r.text.data());
      return make_error(Errc::refused, g_text);
    }
    const bool negative = args.positional(3)[0] == '-';
    switch (r.size) {
      case 1: type = type_of(negative ? ValueType::i8 : ValueType::u8); break;
      case 2: type = type_of(negative ? ValueType::i16 : ValueType::u16); break;
      case 4: type = type_of(negative ? ValueType::i32 : ValueType::u32); break;
      default: type = type_of(ValueType::string); break;
    }
  }
  if (type == nullptr) return bad("no type");
  RESCUE_TRY(value_of(args.positional(3), *type, m.sdo));
  return m;
}

int print_sdo_result(const Message& /*request*/, const Message& answer) noexcept {
  if (answer.header.type != MessageType::sdo_result) return ctl_unexpected_answer(answer);
  const bool json = ctl_output().json;
  const protocol::SdoResultPayload& r = answer.sdo_result;
  const bool ok = r.status == SdoStatus::ok;
  const std::size_t position = position_of(r);
  const char* name = position < kSlaveCount ? kSlaves[position].name : "?";
  const bool upload = r.request_type == MessageType::sdo_upload;
  const TypeName* asked = g_type != ValueType::none ? type_of(g_type) : nullptr;
  if (ok && upload && asked != nullptr && asked->size != 0 && asked->size != r.size) {
    // --type u8 on a 152-byte string would show its first byte as the value (issue 36 item 4).
    (void)std::snprintf(g_text, sizeof g_text,
                        "upload: %s 0x%04X:%02X holds %u bytes, --type %s is %zu; give --type hex or string, or the "
                        "object's own type", name, r.index, r.subindex, static_cast<unsigned>(r.size), asked->name, asked->size);
    return ctl_error(CtlExit::usage, g_text);
  }
  if (json) {
    begin_json(ok);
    const bool drive = position < kSlaveCount && kSlaves[position].joint < kJointCount;
    (void)std::printf(R"(,"slave":"%s","position":%zu,"joint":%s%s%s)", name, position, drive ? "\"" : "",
                      drive ? name : "null", drive ? "\"" : "");
    (void)std::printf(R"(,"index":"0x%04X","subindex":"0x%02X","status":"%s")", r.index, r.subindex,
                      protocol::to_string(r.status));
    if (ok) {
      (void)std::printf(R"(,"segmented":%s,"exchanges":%)" PRIu32, (r.flags & protocol::kSdoSegmented) != 0 ? "true" : "false",
                        r.exchanges);
      if (upload) {
        (void)std::printf(R"(,"size":%u)", static_cast<unsigned>(r.size));
        print_value(r, true);
      }
    } else {
      if (r.status == SdoStatus::aborted) (void)std::printf(R"(,"abort_code":"0x%08)" PRIX32 "\"", r.abort_code);
      if (r.status == SdoStatus::mailbox_error) (void)std::printf(R"(,"mailbox_error":"0x%04X")", r.mailbox_error);
      (void)std::printf(R"(,"reason":)");
      print_json_string(r.text.data());
    }
    end_json();
    return ok ? 0 : static_cast<int>(CtlExit::refused);
  }
  if (ok) {
    if (upload) print_value(r, false);
    else (void)std::printf("download: %s 0x%04X:%02X written\n", name, r.index, r.subindex);
    return 0;
  }
  if (r.status == SdoStatus::aborted) {
    (void)std::printf("%s: %s 0x%04X:%02X: aborted: ", verb_of(r), name, r.index, r.subindex);
    print_text_string(r.text.data());
    (void)std::printf(" (SDO abort code 0x%08" PRIX32 ")\n", r.abort_code);
  } else {
    (void)std::printf("%s: %s 0x%04X:%02X: refused: %s: ", verb_of(r), name, r.index, r.subindex, protocol::to_string(r.status));
    print_text_string(r.text.data());
    (void)std::printf("\n");
  }
  return static_cast<int>(CtlExit::refused);
}

}  // namespace rescue::app
