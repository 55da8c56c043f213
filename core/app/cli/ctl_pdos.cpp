#include "core/app/cli/ctl_pdos.hpp"

#include <array>
#include <cinttypes>
#include <cstdio>

#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/app/cli/ctl_sdo.hpp"
#include "core/app/cli/ctl_target.hpp"
#include "core/base/le_stream.hpp"
#include "core/robot/robot.hpp"
#include "drivers/joint/joint_drive_pdo.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;
using Entries = Span<const drivers::PdoMappingEntry>;

// One sync manager of a joint drive as the master configures it: its assignment object, the one PDO
// assigned, the PDO's entries and bytes.
struct SyncManagerPlan {
  std::uint8_t sync_manager;
  const char* direction;
  std::uint16_t assignment;  // 0x1C12 (outputs) or 0x1C13 (inputs)
  std::uint16_t pdo;         // 0x1600 or 0x1A00
  Entries entries;
  std::size_t bytes;
};
const std::array<SyncManagerPlan, 2> kPlan{{
    {drivers::kJointOutputsSyncManager, "outputs", 0x1C12, drivers::kJointRxPdoIndex, Entries(drivers::kJointRxMapping),
     drivers::kJointOutputBytes},
    {drivers::kJointInputsSyncManager, "inputs", 0x1C13, drivers::kJointTxPdoIndex, Entries(drivers::kJointTxMapping),
     drivers::kJointInputBytes},
}};
constexpr std::size_t kMaxEntries = 8;

// What was read back from the drive, per sync manager (valid only when read).
struct ReadBack {
  std::uint32_t assigned_count{0};
  std::uint32_t assigned_pdo{0};
  std::uint32_t entry_count{0};
  std::array<std::uint32_t, kMaxEntries> words{};
};

// One uploaded value, up to 4 bytes, little-endian; an error with ctl's exit status in detail0.
Result<std::uint32_t> upload(CtlPeer& peer, std::uint8_t joint, std::uint16_t index, std::uint8_t sub) noexcept {
  Message m;
  m.header.type = MessageType::sdo_upload;
  m.sdo.joint = joint;
  m.sdo.index = index;
  m.sdo.subindex = sub;
  const Result<Message> answer = peer.exchange(m);
  if (!answer.ok()) return answer.error();
  const protocol::SdoResultPayload& r = answer.value().sdo_result;
  if (answer.value().header.type != MessageType::sdo_result) return make_error(Errc::mismatch, "not an SDO result");
  if (r.status != protocol::SdoStatus::ok) return make_error(Errc::refused, "upload refused", index, sub);
  LeReader in(ConstByteSpan(r.data.data(), r.size < 4 ? r.size : 4));
  if (r.size >= 4) return in.u32();
  if (r.size >= 2) return std::uint32_t{in.u16()};
  return std::uint32_t{in.u8()};
}

Status read_back(CtlPeer& peer, std::uint8_t joint, const SyncManagerPlan& sm, ReadBack& out) noexcept {
  const Result<std::uint32_t> count = upload(peer, joint, sm.assignment, 0);
  if (!count.ok()) return count.error();
  out.assigned_count = count.value();
  const Result<std::uint32_t> pdo = upload(peer, joint, sm.assignment, 1);
  if (!pdo.ok()) return pdo.error();
  out.assigned_pdo = pdo.value();
  const Result<std::uint32_t> entries = upload(peer, joint, sm.pdo, 0);
  if (!entries.ok()) return entries.error();
  out.entry_count = entries.value();
  for (std::size_t i = 0; i < sm.entries.size() && i < kMaxEntries; ++i) {
    const Result<std::uint32_t> word = upload(peer, joint, sm.pdo, static_cast<std::uint8_t>(i + 1));
    if (!word.ok()) return word.error();
    out.words[i] = word.value();
  }
  return Status::success();
}

bool assignment_same(const SyncManagerPlan& sm, const ReadBack& r) noexcept {
  return r.assigned_count == 1 && r.assigned_pdo == sm.pdo;
}
bool entry_same(const SyncManagerPlan& sm, const ReadBack& r, std::size_t i) noexcept {
  return r.entry_count == sm.entries.size() && r.words[i] == sm.entries[i].mapping_word();
}

void print_text(const char* joint, const std::array<ReadBack, 2>* back) noexcept {
  (void)std::printf("%s: the PDOs the master configures%s\n", joint != nullptr ? joint : "every joint drive",
                    back != nullptr ? ", read back from the drive by SDO" : " (ctl pdos JOINT reads a drive's back)");
  for (std::size_t s = 0; s < kPlan.size(); ++s) {
    const SyncManagerPlan& sm = kPlan[s];
    (void)std::printf("SM%u %s: 0x%04X assigns PDO 0x%04X, %zu bytes", static_cast<unsigned>(sm.sync_manager),
                      sm.direction, sm.assignment, sm.pdo, sm.bytes);
    if (back != nullptr) {
      const ReadBack& r = (*back)[s];
      if (assignment_same(sm, r)) {
        (void)std::printf("  [same]");
      } else {
        (void)std::printf("  [differs: %" PRIu32 " PDO(s), first 0x%04" PRIX32 "]", r.assigned_count, r.assigned_pdo);
      }
    }
    (void)std::printf("\n");
    for (std::size_t i = 0; i < sm.entries.size(); ++i) {
      const drivers::PdoMappingEntry& e = sm.entries[i];
      (void)std::printf("  0x%04X:%02X %2u bit  offset %2u  %-*s", e.index, e.subindex, e.bit_length, e.byte_offset,
                        back != nullptr ? 28 : 0, e.name);
      if (back != nullptr) {
        const ReadBack& r = (*back)[s];
        if (entry_same(sm, r, i)) {
          (void)std::printf("  [same]");
        } else {
          (void)std::printf("  [differs: 0x%08" PRIX32 ", %" PRIu32 " entries]", r.words[i], r.entry_count);
        }
      }
      (void)std::printf("\n");
    }
  }
}

void print_json(const char* joint, const std::array<ReadBack, 2>* back) noexcept {
  begin_json(true);
  (void)std::printf(",\"joint\":");
  if (joint != nullptr) {
    print_json_string(joint);
  } else {
    (void)std::printf("null");
  }
  (void)std::printf(",\"sync_managers\":[");
  bool all_same = true;
  for (std::size_t s = 0; s < kPlan.size(); ++s) {
    const SyncManagerPlan& sm = kPlan[s];
    (void)std::printf(R"(%s{"sync_manager":%u,"direction":"%s","assignment":"0x%04X","pdo":"0x%04X","bytes":%zu,)",
                      s == 0 ? "" : ",", static_cast<unsigned>(sm.sync_manager), sm.direction, sm.assignment, sm.pdo,
                      sm.bytes);
    if (back != nullptr) {
      const bool same = assignment_same(sm, (*back)[s]);
      all_same = all_same && same;
      (void)std::printf(R"("assignment_read_back":"%s",)", same ? "same" : "differs");
    }
    (void)std::printf("\"entries\":[");
    for (std::size_t i = 0; i < sm.entries.size(); ++i) {
      const drivers::PdoMappingEntry& e = sm.entries[i];
      (void)std::printf(R"(%s{"index":"0x%04X","subindex":"0x%02X","bits":%u,"offset":%u,"name":)", i == 0 ? "" : ",",
                        e.index, e.subindex, e.bit_length, e.byte_offset);
      print_json_string(e.name);
      if (back != nullptr) {
        const bool same = entry_same(sm, (*back)[s], i);
        all_same = all_same && same;
        (void)std::printf(R"(,"read_back":"%s","read_back_word":"0x%08)" PRIX32 "\"", same ? "same" : "differs",
                          (*back)[s].words[i]);
      }
      (void)std::printf("}");
    }
    (void)std::printf("]}");
  }
  (void)std::printf("],\"read_back_same\":");
  if (back != nullptr) {
    (void)std::printf("%s", all_same ? "true" : "false");
  } else {
    (void)std::printf("null");
  }
  end_json();
}

// A junction: an ESC without an application, so no sync manager of process data and no PDO.
int print_junction(const char* name, std::size_t position) noexcept {
  if (!ctl_output().json) {
    (void)std::printf("%s (position %zu): a junction: it maps no PDO (no process data, no mailbox)\n", name, position);
    return 0;
  }
  begin_json(true);
  (void)std::printf(R"(,"joint":null,"slave":"%s","position":%zu,"sync_managers":[],"read_back_same":null)", name, position);
  end_json();
  return 0;
}

}  // namespace

int ctl_pdos(const ParsedArgs& args, CtlPeer& peer) noexcept {
  const bool json = ctl_output().json;
  if (args.positional_count() < 2) {
    if (json) {
      print_json(nullptr, nullptr);
    } else {
      print_text(nullptr, nullptr);
    }
    return 0;
  }
  protocol::SdoPayload slave;
  const Status parsed = parse_sdo_slave(args.positional(1), slave);
  if (!parsed.ok()) {
    char text[192];
    (void)std::snprintf(text, sizeof text, "pdos %s", parsed.error().what);
    return ctl_error(CtlExit::usage, text);
  }
  const std::size_t position = sdo_slave_position(slave.target, slave.joint, slave.slave);
  const std::size_t joint = position < kSlaveCount ? kSlaves[position].joint : kJointCount;
  if (joint >= kJointCount) return print_junction(planned_slave_name(position), position);
  std::array<ReadBack, 2> back{};
  for (std::size_t s = 0; s < kPlan.size(); ++s) {
    const Status read = read_back(peer, static_cast<std::uint8_t>(joint), kPlan[s], back[s]);
    if (read.ok()) continue;
    const Errc code = read.error().code;
    if (code == Errc::refused) {
      char text[160];
      (void)std::snprintf(text, sizeof text,
                          "pdos: %s: the upload of 0x%04X:%02X was refused or aborted (ctl upload %s "
                          "0x%04X:%02X says why)",
                          kJoints[joint].name, static_cast<unsigned>(read.error().detail0),
                          static_cast<unsigned>(read.error().detail1), kJoints[joint].name,
                          static_cast<unsigned>(read.error().detail0), static_cast<unsigned>(read.error().detail1));
      return ctl_error(CtlExit::refused, text);
    }
    if (code == Errc::mismatch) return ctl_error(CtlExit::bad_answer, "pdos: an answer that is not an SDO result");
    const Result<CtlTarget> target = peer.target();
    if (!target.ok()) return ctl_error(exit_of(target.error().code), target.error().what);
    return ctl_unreachable(read.error(), target.value());
  }
  if (json) {
    print_json(kJoints[joint].name, &back);
  } else {
    print_text(kJoints[joint].name, &back);
  }
  return 0;
}

}  // namespace rescue::app
