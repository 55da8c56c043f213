// ctl sdos SLAVE [--values] (issue 36 item 2; IgH's `ethercat sdos`, SOEM's `slaveinfo -sdo`): a
// slave's object dictionary as the slave itself describes it through CoE SDO Information (Get OD
// List, then per object Get Object Description and per entry Get Entry Description), each request
// one sdo_info exchange through the EtherCAT handler's mailbox (a long OD list in windows of 256
// bytes); with --values each entry's value by SDO upload.
//
// SLAVE as for upload: a joint's name (its drive), a slave's name or a position. An entry the slave
// does not describe (a gap in an ARRAY or RECORD: SDO Info Error) is left out; a value the slave
// refuses to upload (write-only) is shown with its abort. Every answer is collected before anything
// is printed: the output is whole or it is an error.
#pragma once

#include "core/app/cli/ctl_verbs.hpp"

namespace rescue::app {

// CtlConverse: exit 0 when printed; refused when the robot or the slave refused (a lost slave, a
// slave without a mailbox: the junctions; a busy mailbox), with the reason; usage for a bad SLAVE;
// unreachable when the robot did not answer; bad_answer for an answer that is not the one asked for
// or does not decode; local when the dictionary exceeds ctl's capacity.
int ctl_sdos(const ParsedArgs& args, CtlPeer& peer) noexcept;

}  // namespace rescue::app
