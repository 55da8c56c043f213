// tshark's view of a capture in the format of `rescue-motion decode` (design brief section 7), so
// the two can be compared line by line. Tests only.
//
// tshark prints, per frame, each EtherCAT field as a comma-separated list over the frame's
// datagrams (-E occurrence=a -E aggregator=,). Logical commands (LRD, LWR, LRW) have ecat.lad and
// no ecat.adp/ecat.ado; every other command has ecat.adp/ecat.ado and no ecat.lad. The lists are
// zipped back into datagrams in frame order.
#pragma once

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/run_command.hpp"

namespace rescue::test {

inline const char* const kTsharkFields =
    "-T fields -E separator=/t -E occurrence=a -E aggregator=, -e frame.number -e ecat.cmd -e ecat.idx "
    "-e ecat.adp -e ecat.ado -e ecat.lad -e ecat.subframe.length -e ecat.cnt";

inline std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  if (text.empty()) return parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (text.back() == separator) parts.emplace_back();
  return parts;
}

// tshark prints hex fields as 0x.. and decimal ones plainly (never with a leading zero octal-style).
inline unsigned long parse_number(const std::string& text) {
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  return std::stoul(text, nullptr, hex ? 16 : 10);
}

struct TsharkListing {
  int exit_status{-1};
  std::vector<std::string> lines;  // "frame command index address length wkc"
  std::string problem;             // non-empty when tshark's output could not be zipped
};

inline TsharkListing tshark_listing(const std::string& capture_path) {
  static const char* const kMnemonics[] = {"NOP", "APRD", "APWR", "APRW", "FPRD", "FPWR", "FPRW", "BRD",
                                           "BWR", "BRW",  "LRD",  "LWR",  "LRW",  "ARMW", "FRMW"};
  TsharkListing listing;
  const CommandOutput out = run_command("tshark -r '" + capture_path + "' " + kTsharkFields + " 2>/dev/null");
  listing.exit_status = out.exit_status;
  for (const std::string& row : split_lines(out.out)) {
    const std::vector<std::string> f = split(row, '\t');
    if (f.size() < 8 || f[1].empty()) continue;  // not an EtherCAT frame
    const auto cmd = split(f[1], ',');
    const auto idx = split(f[2], ',');
    const auto adp = split(f[3], ',');
    const auto ado = split(f[4], ',');
    const auto lad = split(f[5], ',');
    const auto len = split(f[6], ',');
    const auto cnt = split(f[7], ',');
    std::size_t next_physical = 0;
    std::size_t next_logical = 0;
    for (std::size_t i = 0; i < cmd.size(); ++i) {
      const unsigned long c = parse_number(cmd[i]);
      if (c >= 15 || i >= idx.size() || i >= len.size() || i >= cnt.size()) {
        listing.problem = "frame " + f[0] + ": field lists of different lengths";
        return listing;
      }
      char address[32];
      if (c >= 10 && c <= 12) {
        if (next_logical >= lad.size()) {
          listing.problem = "frame " + f[0] + ": missing ecat.lad";
          return listing;
        }
        std::snprintf(address, sizeof address, "0x%08lx", parse_number(lad[next_logical++]));
      } else {
        if (next_physical >= adp.size() || next_physical >= ado.size()) {
          listing.problem = "frame " + f[0] + ": missing ecat.adp/ecat.ado";
          return listing;
        }
        std::snprintf(address, sizeof address, "0x%04lx:0x%04lx", parse_number(adp[next_physical]),
                      parse_number(ado[next_physical]));
        ++next_physical;
      }
      listing.lines.push_back(f[0] + " " + kMnemonics[c] + " " + std::to_string(parse_number(idx[i])) + " " + address +
                              " " + std::to_string(parse_number(len[i])) + " " + std::to_string(parse_number(cnt[i])));
    }
  }
  return listing;
}

}  // namespace rescue::test
