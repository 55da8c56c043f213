// `rescue-motion bench codec`: building and decoding the robot's cyclic frame with the codec the
// master uses, per frame, with the TSC; and the same figures as a fraction of the frame's time on a
// 100 Mbit/s wire. The frame, as the master's cycle sends it (ecat/link/network_plan.hpp):
//
//   FRMW station 0x1000 (junction_a, the DC reference) reg 0x0910, 8 bytes: system time
//   LRW  torso      region: 3 joints x (13 out + 15 in) =  84 bytes
//   LRW  left arm   region: 7 joints x 28               = 196 bytes
//   LRW  right arm  region: 7 joints x 28               = 196 bytes
//   LRW  lower body region: 4 joints x 28               = 112 bytes
//
// Assumption (the master's plan): each branch's region holds its joints' outputs then inputs, so an
// LRW carries out + in per joint (not max(out, in) with overlapping FMMUs). Build = reset, five
// add() with the outputs copied in, finish(). Decode = parse the returned frame, read the DC time,
// check each LRW's working counter against 3 per joint, copy the inputs out.
#pragma once

#include "core/app/config/command_line.hpp"

namespace rescue::app {

int bench_codec(const ParsedArgs& args) noexcept;

}  // namespace rescue::app
