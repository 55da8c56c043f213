// ctl reg_read SLAVE ADDR [LEN] (docs/operator.md "ESC registers"): a read-only read of LEN bytes
// (1..64, default 1) of a slave's ESC registers from ADDR (0x0000..0xFFFF, hex with 0x or decimal),
// like IgH's `ethercat reg_read`; SLAVE a slave's name (ctl slaves) or its position. The robot's
// master sends one FPRD in its cyclic frames and answers a period or more later (reg_read,
// reg_result). A lost slave is refused with the reason (exit 1). There is no reg_write.
#pragma once

#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/command_line.hpp"

namespace rescue::app {

Result<protocol::Message> build_reg_read(const ParsedArgs& args, CtlPeer& peer) noexcept;
int print_reg_result(const protocol::Message& request, const protocol::Message& answer) noexcept;

}  // namespace rescue::app
