// ctl rescan (docs/operator.md "Rescan"): the robot's master identifies the segment again while it
// cycles (each device's SII identity by auto-increment position, read in the cyclic frames beside
// the slaves in service, which it does not disturb) and compares it with the plan as bring-up does;
// ctl prints each device found (vendor, product, revision, serial, alias, the planned slave it
// answers as) and every difference (missing, extra, wrong device, wrong position, revision), like
// IgH's `ethercat rescan` followed by `ethercat slaves -v`. Exit 0 when the rescan ran, whatever it
// found; 1 when it could not (another under way, the recovery identifying a slave, a device whose
// SII could not be read).
#pragma once

#include "core/app/cli/ctl_verbs.hpp"
#include "core/app/config/command_line.hpp"

namespace rescue::app {

Result<protocol::Message> build_rescan(const ParsedArgs& args, CtlPeer& peer) noexcept;
int print_rescan_result(const protocol::Message& request, const protocol::Message& answer) noexcept;

}  // namespace rescue::app
