// The table of ctl's verbs (ctl_verbs.hpp): one entry per verb, in `ctl --help`'s order. The plain
// queries need no arguments and print one answer type: they are built and printed by the two
// templates below; every other verb names its group file's functions.
#include <algorithm>
#include <cstring>

#include "core/app/cli/ctl_joint_commands.hpp"
#include "core/app/cli/ctl_network.hpp"
#include "core/app/cli/ctl_output.hpp"
#include "core/app/cli/ctl_pdos.hpp"
#include "core/app/cli/ctl_registers.hpp"
#include "core/app/cli/ctl_rescan.hpp"
#include "core/app/cli/ctl_robot_queries.hpp"
#include "core/app/cli/ctl_sdo.hpp"
#include "core/app/cli/ctl_sdos.hpp"
#include "core/app/cli/ctl_sii.hpp"
#include "core/app/cli/ctl_states.hpp"
#include "core/app/cli/ctl_target.hpp"
#include "core/app/cli/ctl_verbs.hpp"

namespace rescue::app {
namespace {

using protocol::Message;
using protocol::MessageType;

template <MessageType kRequest>
Result<Message> query(const ParsedArgs& /*args*/, CtlPeer& /*peer*/) noexcept {
  Message m;
  m.header.type = kRequest;
  return m;
}

template <MessageType kAnswer, void (*kPrint)(const Message&, bool) noexcept>
int answer_of(const Message& /*request*/, const Message& answer) noexcept {
  if (answer.header.type != kAnswer) return ctl_unexpected_answer(answer);
  kPrint(answer, ctl_output().json);
  return 0;
}

constexpr auto kStatusBuild = query<MessageType::get_status>;
constexpr auto kStatusPrint = answer_of<MessageType::status, print_status>;

constexpr CtlVerb kVerbs[] = {
    {"status", "status", kStatusBuild, kStatusPrint, nullptr, 0, 0, CtlRun::exchange},
    {"slaves", "slaves [-v]", build_slaves, print_slaves_answer, nullptr, 0, 0, CtlRun::exchange},
    {"master", "master", query<MessageType::get_master>, answer_of<MessageType::master, print_master>, nullptr, 0, 0,
     CtlRun::exchange},
    {"tasks", "tasks", query<MessageType::get_tasks>, answer_of<MessageType::tasks, print_tasks>, nullptr, 0, 0,
     CtlRun::exchange},
    {"diag", "diag [--reset [SLAVE]]", build_diag, print_diag_answer, nullptr, 0, 1, CtlRun::exchange},
    {"graph", "graph [--format text|dot]", build_graph, print_graph_answer, nullptr, 0, 0, CtlRun::exchange},
    {"watch", "watch [--interval SECONDS] [--count N]", kStatusBuild, kStatusPrint, nullptr, 0, 0, CtlRun::repeated},
    {"init", "init [JOINTS]", build_joint_command, print_command_reply, nullptr, 0, 1, CtlRun::exchange},
    {"enable", "enable [JOINTS]", build_joint_command, print_command_reply, nullptr, 0, 1, CtlRun::exchange},
    {"disable", "disable [JOINTS]", build_joint_command, print_command_reply, nullptr, 0, 1, CtlRun::exchange},
    {"hold", "hold [JOINTS]", build_joint_command, print_command_reply, nullptr, 0, 1, CtlRun::exchange},
    {"mode", "mode JOINT MODE (MODE: csp, csv or cst)", build_mode, print_command_reply, nullptr, 2, 2,
     CtlRun::exchange},
    {"clear", "clear JOINTS [--moved] (name the repaired joints)", build_joint_command, print_command_reply, nullptr, 1,
     1, CtlRun::exchange},
    {"move", "move EFFECTOR POSE (EFFECTOR: left or right; POSE: x,y,z,roll,pitch,yaw in m and rad)", build_move,
     print_command_reply, nullptr, 2, 2, CtlRun::exchange},
    {"hand", "hand left|right open|close", build_hand, print_command_reply, nullptr, 2, 2, CtlRun::exchange},
    {"owner", "owner [TASK] (TASK: 0..3)", build_owner, print_owner_answer, nullptr, 0, 1, CtlRun::exchange},
    {"version", "version", query<MessageType::get_version>, answer_of<MessageType::version, print_version>, nullptr, 0,
     0, CtlRun::exchange},
    {"upload", "upload SLAVE INDEX:SUB [--type T] (e.g. upload l_elbow 0x100A:00, upload 1 0x1018:01)", build_sdo_request,
     print_sdo_result, nullptr, 2, 2, CtlRun::exchange},
    {"download", "download SLAVE INDEX:SUB VALUE [--type T] (e.g. download l_elbow 0x6065:00 5000 --type u32)",
     build_sdo_request, print_sdo_result, nullptr, 3, 3, CtlRun::exchange},
    {"pdos", "pdos [SLAVE] (SLAVE: a joint, a slave's name or position)", nullptr, nullptr, ctl_pdos, 0, 1, CtlRun::own},
    {"sdos", "sdos SLAVE [--values] (SLAVE: a joint, a slave's name or position)", nullptr, nullptr, ctl_sdos, 1, 1,
     CtlRun::own},
    {"sii_read", "sii_read SLAVE [--raw] (SLAVE: a slave's name or position)", nullptr, nullptr, ctl_sii_read, 1, 1,
     CtlRun::own},
    {"xml", "xml SLAVE (SLAVE: a slave's name or position)", nullptr, nullptr, ctl_xml, 1, 1, CtlRun::own},
    {"reg_read", "reg_read SLAVE ADDR [LEN] (e.g. reg_read l_elbow 0x0130 2; LEN 1..64, default 1)", build_reg_read,
     print_reg_result, nullptr, 2, 3, CtlRun::exchange},
    {"states", "states [SLAVES] INIT|PREOP|SAFEOP|OP (SLAVES: names or positions, comma-separated, or all)",
     build_states, print_states_result, nullptr, 1, 2, CtlRun::exchange},
    {"rescan", "rescan", build_rescan, print_rescan_result, nullptr, 0, 0, CtlRun::exchange},
    {"keygen", "keygen [--key FILE]", nullptr, nullptr, ctl_keygen, 0, 0, CtlRun::own},
};

}  // namespace

Span<const CtlVerb> ctl_verbs() noexcept { return {kVerbs}; }

const CtlVerb* find_ctl_verb(const char* name) noexcept {
  const CtlVerb* v = std::find_if(std::begin(kVerbs), std::end(kVerbs),
                                  [name](const CtlVerb& e) { return std::strcmp(e.name, name) == 0; });
  return v != std::end(kVerbs) ? v : nullptr;
}

}  // namespace rescue::app
