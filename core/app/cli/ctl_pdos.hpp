// ctl pdos [SLAVE] (issue 36 item 1; like IgH's `ethercat pdos`): the sync managers, the PDO
// assignment and the PDO mapping the master configures on every joint drive (this build's tables,
// drivers/joint/joint_drive_pdo.hpp), and with SLAVE (a joint, a slave's name or position, as for
// upload) the same objects read back from that drive by SDO upload (0x1C12/0x1C13, 0x1600/0x1A00),
// each marked same or differs; a junction is said to map none.
#pragma once

#include "core/app/cli/ctl_verbs.hpp"

namespace rescue::app {

// CtlConverse: exit 0 when printed (read back: whatever it holds; a junction: it maps none), refused
// when an upload was refused or aborted, unreachable when the robot did not answer, usage for a bad SLAVE.
int ctl_pdos(const ParsedArgs& args, CtlPeer& peer) noexcept;

}  // namespace rescue::app
