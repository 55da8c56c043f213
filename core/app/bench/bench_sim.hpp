// `rescue-motion bench sim`: how fast the simulated robot runs on virtual time. The master drives
// the in-process simulated robot (23 slaves, 21 joint drives) in OP, every joint enabled, for
// --cycles cycles of 1 ms, twice: the joints held where they are, then every joint moving (CSP
// triangles, CSV speed waves); --motion hold|move runs only one of them. For each run it prints the host time per simulated cycle (the
// whole cycle: master and simulator; and the simulator's part alone, i.e. the segment processing
// the frame and time advancing), median and p99, the simulated seconds per host second and the
// host seconds an hour of robot time takes. docs/simulator.md, "Speed", quotes the figures.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_sim(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
