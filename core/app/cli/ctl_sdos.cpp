#include "core/app/cli/ctl_sdos.hpp"

#include <algorithm>
#include <array>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/app/cli/ctl_sdo.hpp"
#include "core/app/cli/ctl_target.hpp"
#include "core/robot/robot.hpp"
#include "ecat/mailbox/coe_information.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using protocol::SdoInfoOp;
using protocol::SdoStatus;
namespace info = ecat::coe::info;

// ctl's capacities: a drive's dictionary is some hundred objects and a thousand entries; names are
// cut at kNameBytes.
constexpr std::size_t kMaxObjects = 1024;
constexpr std::size_t kMaxEntries = 2048;
constexpr std::size_t kNameBytes = 128;
constexpr std::size_t kListBytes = 2 + 2 * kMaxObjects;  // the list type, then the indexes

struct Name {
  std::array<std::uint8_t, kNameBytes> bytes{};
  std::size_t size{0};
};

struct Value {
  bool read{false};
  SdoStatus status{SdoStatus::ok};
  std::uint32_t abort_code{0};
  std::array<char, protocol::kSdoTextSize> text{};
  std::uint16_t size{0};
  std::array<std::uint8_t, protocol::kSdoDataSize> data{};
};

struct Entry {
  std::uint8_t subindex{0};
  std::uint16_t data_type{0};
  std::uint16_t bit_length{0};
  std::uint16_t access{0};
  Name name{};
  Value value{};
};

struct Object {
  std::uint16_t index{0};
  std::uint16_t data_type{0};
  std::uint8_t max_subindex{0};
  std::uint8_t object_code{0};
  Name name{};
  std::size_t first_entry{0};
  std::size_t entry_count{0};
};

struct Dictionary {
  std::array<std::uint8_t, kListBytes> list{};
  std::array<Object, kMaxObjects> objects{};
  std::size_t object_count{0};
  std::array<Entry, kMaxEntries> entries{};
  std::size_t entry_count{0};
};

// Why the dialog stopped at a refusal (Errc::refused): the answer's status and what was asked.
struct Refusal {
  SdoStatus status{SdoStatus::ok};
  std::uint32_t abort_code{0};
  std::uint16_t mailbox_error{0};
  std::array<char, protocol::kSdoTextSize> text{};
  char what[32]{};
};
Refusal g_refusal;

Error refused(const protocol::SdoInfoResultPayload& r, const char* what) noexcept {
  g_refusal.status = r.status;
  g_refusal.abort_code = r.abort_code;
  g_refusal.mailbox_error = r.mailbox_error;
  g_refusal.text = r.text;
  (void)std::snprintf(g_refusal.what, sizeof g_refusal.what, "%s", what);
  return make_error(Errc::refused, "refused");
}

Name name_of(ConstByteSpan bytes) noexcept {
  Name n;
  n.size = std::min(bytes.size(), kNameBytes);
  std::copy_n(bytes.data(), n.size, n.bytes.data());
  return n;
}

// One sdo_info exchange; its answer must echo the request. Errors: the exchange's, mismatch.
Result<protocol::SdoInfoResultPayload> ask(CtlPeer& peer, const protocol::SdoPayload& who, SdoInfoOp op,
                                           std::uint16_t index, std::uint8_t subindex, std::uint16_t offset) noexcept {
  Message m;
  m.header.type = MessageType::sdo_info;
  protocol::SdoInfoPayload& q = m.sdo_info;
  q.target = who.target;
  q.joint = who.joint;
  q.slave = who.slave;
  q.op = op;
  q.index = index;
  q.subindex = subindex;
  q.offset = offset;
  const Result<Message> answer = peer.exchange(m);
  if (!answer.ok()) return answer.error();
  if (answer.value().header.type != MessageType::sdo_info_result) {
    return make_error(Errc::mismatch, "an answer that is not an SDO Information result");
  }
  const protocol::SdoInfoResultPayload& r = answer.value().sdo_info_result;
  const protocol::SdoInfoPayload& e = r.request;
  if (e.op != op || e.index != index || e.subindex != subindex || e.offset != offset || e.target != q.target ||
      e.joint != q.joint || e.slave != q.slave) {
    return make_error(Errc::mismatch, "an answer to another SDO Information request");
  }
  return r;
}

// The OD list (every object), window by window, into dict.list; returns its bytes.
Result<std::size_t> read_list(CtlPeer& peer, const protocol::SdoPayload& who, Dictionary& dict) noexcept {
  std::size_t offset = 0;
  std::size_t total = 0;
  do {
    const Result<protocol::SdoInfoResultPayload> answer =
        ask(peer, who, SdoInfoOp::od_list, info::kListAll, 0, static_cast<std::uint16_t>(offset));
    if (!answer.ok()) return answer.error();
    const protocol::SdoInfoResultPayload& r = answer.value();
    if (r.status != SdoStatus::ok) return refused(r, "the object list");
    if (offset == 0) total = r.total;
    if (r.total != total) return make_error(Errc::mismatch, "the object list changed between its windows");
    if (total > kListBytes) return make_error(Errc::capacity_exceeded, "objects", kMaxObjects);
    if (r.length == 0 && offset < total) return make_error(Errc::mismatch, "a window of the object list without data");
    // The codec checked offset + length <= total, and total fits the list.
    std::copy_n(r.data.data(), r.length, dict.list.data() + offset);
    offset += r.length;
  } while (offset < total);
  return total;
}

// One entry's value by SDO upload (an upload the slave refuses is kept with its reason).
Status read_value(CtlPeer& peer, const protocol::SdoPayload& who, std::uint16_t index, Entry& entry) noexcept {
  Message m;
  m.header.type = MessageType::sdo_upload;
  m.sdo = who;
  m.sdo.index = index;
  m.sdo.subindex = entry.subindex;
  m.sdo.size = 0;
  const Result<Message> answer = peer.exchange(m);
  if (!answer.ok()) return answer.error();
  if (answer.value().header.type != MessageType::sdo_result) return make_error(Errc::mismatch, "not an SDO result");
  const protocol::SdoResultPayload& r = answer.value().sdo_result;
  if (r.index != index || r.subindex != entry.subindex) return make_error(Errc::mismatch, "the result of another upload");
  Value& v = entry.value;
  v.read = true;
  v.status = r.status;
  v.abort_code = r.abort_code;
  v.text = r.text;
  v.size = r.status == SdoStatus::ok ? r.size : std::uint16_t{0};
  std::copy_n(r.data.data(), v.size, v.data.data());
  return Status::success();
}

// One object's description and its entries' (and values), appended to dict.
Status read_object(CtlPeer& peer, const protocol::SdoPayload& who, std::uint16_t index, bool values,
                   Dictionary& dict) noexcept {
  char what[32];
  (void)std::snprintf(what, sizeof what, "object 0x%04X", index);
  const Result<protocol::SdoInfoResultPayload> answer = ask(peer, who, SdoInfoOp::object_description, index, 0, 0);
  if (!answer.ok()) return answer.error();
  if (answer.value().status != SdoStatus::ok) return refused(answer.value(), what);
  const Result<info::ObjectDescription> described =
      info::decode_object_description(ConstByteSpan(answer.value().data.data(), answer.value().length));
  if (!described.ok()) return described.error();
  const info::ObjectDescription& d = described.value();
  if (d.index != index) return make_error(Errc::mismatch, "the description of another object");
  Object& o = dict.objects[dict.object_count++];
  o.index = index;
  o.data_type = d.data_type;
  o.max_subindex = d.max_subindex;
  o.object_code = d.object_code;
  o.name = name_of(d.name);
  o.first_entry = dict.entry_count;
  for (unsigned sub = 0; sub <= d.max_subindex; ++sub) {
    (void)std::snprintf(what, sizeof what, "entry 0x%04X:%02X", index, sub);
    const Result<protocol::SdoInfoResultPayload> e =
        ask(peer, who, SdoInfoOp::entry_description, index, static_cast<std::uint8_t>(sub), 0);
    if (!e.ok()) return e.error();
    if (e.value().status == SdoStatus::aborted) continue;  // a gap the slave does not describe
    if (e.value().status != SdoStatus::ok) return refused(e.value(), what);
    const Result<info::EntryDescription> entry =
        info::decode_entry_description(ConstByteSpan(e.value().data.data(), e.value().length));
    if (!entry.ok()) return entry.error();
    if (entry.value().index != index || entry.value().subindex != static_cast<std::uint8_t>(sub)) {
      return make_error(Errc::mismatch, "the description of another entry");
    }
    if (dict.entry_count >= kMaxEntries) return make_error(Errc::capacity_exceeded, "entries", kMaxEntries);
    Entry& out = dict.entries[dict.entry_count++];
    out = Entry{};
    out.subindex = static_cast<std::uint8_t>(sub);
    out.data_type = entry.value().data_type;
    out.bit_length = entry.value().bit_length;
    out.access = entry.value().access;
    out.name = name_of(entry.value().name);
    ++o.entry_count;
    if (values) {
      RESCUE_TRY(read_value(peer, who, index, out));
    }
  }
  return Status::success();
}

Status read_dictionary(CtlPeer& peer, const protocol::SdoPayload& who, bool values, Dictionary& dict) noexcept {
  const Result<std::size_t> size = read_list(peer, who, dict);
  if (!size.ok()) return size.error();
  const Result<info::OdList> list = info::decode_od_list(ConstByteSpan(dict.list.data(), size.value()));
  if (!list.ok()) return list.error();
  if (list.value().count > kMaxObjects) return make_error(Errc::capacity_exceeded, "objects", kMaxObjects);
  for (std::size_t i = 0; i < list.value().count; ++i) {
    RESCUE_TRY(read_object(peer, who, list.value().index(i), values, dict));
  }
  return Status::success();
}

// How a value is shown: by its data type when it is a number of its own width, else text or bytes.
enum class Shown : std::uint8_t { unsigned_number, signed_number, real, text, bytes };

Shown shown_as(const Entry& e) noexcept {
  const std::size_t n = e.value.size;
  switch (e.data_type) {
    case 0x0001: case 0x0005: case 0x0006: case 0x0007: case 0x0016: case 0x001B:
      return n >= 1 && n <= 8 ? Shown::unsigned_number : Shown::bytes;
    case 0x0002: case 0x0003: case 0x0004: case 0x0010: case 0x0015:
      return n >= 1 && n <= 8 ? Shown::signed_number : Shown::bytes;
    case 0x0008: return n == 4 ? Shown::real : Shown::bytes;
    case 0x0009: return Shown::text;
    default: return Shown::bytes;
  }
}

std::uint64_t raw_of(const Value& v) noexcept {
  std::uint64_t raw = 0;
  for (std::size_t i = 0; i < v.size && i < 8; ++i) raw |= static_cast<std::uint64_t>(v.data[i]) << (8U * i);
  return raw;
}

std::int64_t signed_of(const Value& v) noexcept {
  const std::uint64_t raw = raw_of(v);
  const unsigned bits = 8U * static_cast<unsigned>(std::min<std::size_t>(v.size, 8));
  if (bits == 64) return static_cast<std::int64_t>(raw);
  const std::uint64_t sign = std::uint64_t{1} << (bits - 1);
  return static_cast<std::int64_t>((raw ^ sign) - sign);
}

float real_of(const Value& v) noexcept {
  const auto raw = static_cast<std::uint32_t>(raw_of(v));
  float f = 0;
  std::memcpy(&f, &raw, sizeof f);
  return f;
}

void print_hex(const Value& v, const char* separator) noexcept {
  for (std::size_t i = 0; i < v.size; ++i) (void)std::printf("%s%02x", i == 0 ? "" : separator, v.data[i]);
}

void print_value_text(const Entry& e) noexcept {
  const Value& v = e.value;
  if (v.status != SdoStatus::ok) {
    (void)std::printf(" = (upload %s: ", protocol::to_string(v.status));
    print_text_string(v.text.data());
    (void)std::printf(")");
    return;
  }
  const int digits = static_cast<int>(2 * std::min<std::size_t>(v.size, 8));
  switch (shown_as(e)) {
    case Shown::unsigned_number:
      (void)std::printf(" = 0x%0*" PRIX64 " %" PRIu64, digits, raw_of(v), raw_of(v));
      break;
    case Shown::signed_number:
      (void)std::printf(" = 0x%0*" PRIX64 " %" PRId64, digits, raw_of(v), signed_of(v));
      break;
    case Shown::real: (void)std::printf(" = 0x%08" PRIX64 " %g", raw_of(v), static_cast<double>(real_of(v))); break;
    case Shown::text:
      (void)std::printf(" = \"");
      print_text_bytes(v.data.data(), v.size);
      (void)std::printf("\"");
      break;
    case Shown::bytes:
      (void)std::printf(" = ");
      print_hex(v, " ");
      break;
  }
}

void print_value_json(const Entry& e) noexcept {
  const Value& v = e.value;
  if (v.status != SdoStatus::ok) {
    (void)std::printf(R"(,"value":{"ok":false,"status":"%s")", protocol::to_string(v.status));
    if (v.status == SdoStatus::aborted) (void)std::printf(R"(,"abort_code":"0x%08)" PRIX32 "\"", v.abort_code);
    (void)std::printf(R"(,"reason":)");
    print_json_string(v.text.data());
    (void)std::printf("}");
    return;
  }
  (void)std::printf(R"(,"value":{"ok":true,"bytes":")");
  print_hex(v, "");
  (void)std::printf("\"");
  switch (shown_as(e)) {
    case Shown::unsigned_number: (void)std::printf(R"(,"number":%)" PRIu64, raw_of(v)); break;
    case Shown::signed_number: (void)std::printf(R"(,"number":%)" PRId64, signed_of(v)); break;
    case Shown::real:  // JSON has no NaN or infinity: those keep their bytes only
      if (std::isfinite(real_of(v))) (void)std::printf(R"(,"number":%.9g)", static_cast<double>(real_of(v)));
      break;
    case Shown::text:
      (void)std::printf(R"(,"text":)");
      print_json_bytes(v.data.data(), v.size);
      break;
    case Shown::bytes: break;
  }
  (void)std::printf("}");
}

struct Who {
  const char* name;
  std::size_t position;
  bool drive;
};

void print_text(const Who& who, const Dictionary& dict, bool values) noexcept {
  (void)std::printf("%s (position %zu): %zu objects, as the slave describes them (CoE SDO Information)\n", who.name,
                    who.position, dict.object_count);
  for (std::size_t i = 0; i < dict.object_count; ++i) {
    const Object& o = dict.objects[i];
    (void)std::printf("SDO 0x%04X, %s, max subindex %u, \"", o.index, info::object_code_name(o.object_code),
                      static_cast<unsigned>(o.max_subindex));
    print_text_bytes(o.name.bytes.data(), o.name.size);
    (void)std::printf("\"\n");
    for (std::size_t k = 0; k < o.entry_count; ++k) {
      const Entry& e = dict.entries[o.first_entry + k];
      char access[7];
      info::access_text(e.access, access);
      (void)std::printf("  0x%04X:%02X, %s, %s, %u bit, \"", o.index, e.subindex, access, info::data_type_name(e.data_type),
                        static_cast<unsigned>(e.bit_length));
      print_text_bytes(e.name.bytes.data(), e.name.size);
      (void)std::printf("\"");
      if (values) print_value_text(e);
      (void)std::printf("\n");
    }
  }
}

void print_who_json(const Who& who) noexcept {
  (void)std::printf(R"(,"slave":"%s","position":%zu,"joint":%s%s%s)", who.name, who.position, who.drive ? "\"" : "",
                    who.drive ? who.name : "null", who.drive ? "\"" : "");
}

void print_json(const Who& who, const Dictionary& dict, bool values) noexcept {
  begin_json(true);
  print_who_json(who);
  (void)std::printf(R"(,"values":%s,"objects":[)", values ? "true" : "false");
  for (std::size_t i = 0; i < dict.object_count; ++i) {
    const Object& o = dict.objects[i];
    (void)std::printf(R"(%s{"index":"0x%04X","object_code":"%s","data_type":"0x%04X","max_subindex":%u,"name":)",
                      i == 0 ? "" : ",", o.index, info::object_code_name(o.object_code), o.data_type,
                      static_cast<unsigned>(o.max_subindex));
    print_json_bytes(o.name.bytes.data(), o.name.size);
    (void)std::printf(R"(,"entries":[)");
    for (std::size_t k = 0; k < o.entry_count; ++k) {
      const Entry& e = dict.entries[o.first_entry + k];
      char access[7];
      info::access_text(e.access, access);
      (void)std::printf(R"(%s{"subindex":"0x%02X","data_type":"%s","data_type_code":"0x%04X","bits":%u,"access":"%s","name":)",
                        k == 0 ? "" : ",", e.subindex, info::data_type_name(e.data_type), e.data_type,
                        static_cast<unsigned>(e.bit_length), access);
      print_json_bytes(e.name.bytes.data(), e.name.size);
      if (values) print_value_json(e);
      (void)std::printf("}");
    }
    (void)std::printf("]}");
  }
  (void)std::printf("]");
  end_json();
}

int print_refusal(const Who& who) noexcept {
  const Refusal& r = g_refusal;
  if (ctl_output().json) {
    begin_json(false);
    print_who_json(who);
    (void)std::printf(R"(,"status":"%s","asked":"%s")", protocol::to_string(r.status), r.what);
    if (r.status == SdoStatus::aborted) (void)std::printf(R"(,"abort_code":"0x%08)" PRIX32 "\"", r.abort_code);
    if (r.status == SdoStatus::mailbox_error) (void)std::printf(R"(,"mailbox_error":"0x%04X")", r.mailbox_error);
    (void)std::printf(R"(,"reason":)");
    print_json_string(r.text.data());
    end_json();
    return static_cast<int>(CtlExit::refused);
  }
  (void)std::printf("sdos: %s (position %zu): %s: refused: %s: ", who.name, who.position, r.what, protocol::to_string(r.status));
  print_text_string(r.text.data());
  if (r.status == SdoStatus::aborted) (void)std::printf(" (SDO abort code 0x%08" PRIX32 ")", r.abort_code);
  (void)std::printf("\n");
  return static_cast<int>(CtlExit::refused);
}

}  // namespace

int ctl_sdos(const ParsedArgs& args, CtlPeer& peer) noexcept {
  protocol::SdoPayload target;
  const Status parsed = parse_sdo_slave(args.positional(1), target);
  if (!parsed.ok()) {
    char text[192];
    (void)std::snprintf(text, sizeof text, "sdos %s", parsed.error().what);
    return ctl_error(CtlExit::usage, text);
  }
  const std::size_t position = sdo_slave_position(target.target, target.joint, target.slave);
  const Who who{planned_slave_name(position), position, position < kSlaveCount && kSlaves[position].joint < kJointCount};
  const bool values = args.has("values");
  static Dictionary dict;  // about 1 MB: not on the stack
  dict.object_count = 0;
  dict.entry_count = 0;
  const Status read = read_dictionary(peer, target, values, dict);
  if (read.ok()) {
    if (ctl_output().json) {
      print_json(who, dict, values);
    } else {
      print_text(who, dict, values);
    }
    return 0;
  }
  char text[192];
  switch (read.error().code) {
    case Errc::refused: return print_refusal(who);
    case Errc::capacity_exceeded:
      (void)std::snprintf(text, sizeof text, "sdos: %s: the dictionary has more %s than ctl holds (%u)", who.name,
                          read.error().what, static_cast<unsigned>(read.error().detail0));
      return ctl_error(CtlExit::local, text);
    case Errc::mismatch:
    case Errc::truncated:
    case Errc::malformed:
      (void)std::snprintf(text, sizeof text, "sdos: %s: %s", who.name, read.error().what);
      return ctl_error(CtlExit::bad_answer, text);
    default: break;
  }
  const Result<CtlTarget> robot = peer.target();
  if (!robot.ok()) return ctl_error(exit_of(robot.error().code), robot.error().what);
  return ctl_unreachable(read.error(), robot.value());
}

}  // namespace rescue::app
