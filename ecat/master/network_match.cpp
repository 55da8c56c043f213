#include "ecat/master/network_match.hpp"

#include <algorithm>
#include <cinttypes>

namespace rescue::ecat {
namespace {

constexpr std::uint8_t u8(std::size_t v) noexcept { return static_cast<std::uint8_t>(v); }

std::uint8_t slot_with_alias(const NetworkPlan& plan, std::uint16_t alias) noexcept {
  if (alias == 0) return kNoPosition;
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if (plan[p].station_alias == alias) return u8(p);
  }
  return kNoPosition;
}

// Indices (into `seq`, entries kNoPosition skipped) of a longest strictly increasing subsequence.
std::array<bool, kMaxFoundSlaves> longest_increasing(const std::array<std::uint8_t, kMaxFoundSlaves>& seq,
                                                     std::size_t n) noexcept {
  std::array<std::uint8_t, kMaxFoundSlaves> length{};
  std::array<std::uint8_t, kMaxFoundSlaves> previous{};
  std::size_t best_end = kMaxFoundSlaves;
  std::uint8_t best = 0;
  for (std::size_t i = 0; i < n; ++i) {
    previous[i] = kNoPosition;
    if (seq[i] == kNoPosition) continue;
    length[i] = 1;
    for (std::size_t k = 0; k < i; ++k) {
      if (seq[k] != kNoPosition && seq[k] < seq[i] && length[k] + 1 > length[i]) {
        length[i] = u8(length[k] + 1);
        previous[i] = u8(k);
      }
    }
    if (length[i] > best) {
      best = length[i];
      best_end = i;
    }
  }
  std::array<bool, kMaxFoundSlaves> in_run{};
  for (std::size_t i = best_end; i < n; i = previous[i] == kNoPosition ? n : previous[i]) in_run[i] = true;
  return in_run;
}

void add(NetworkMatch& match, DifferenceKind kind, std::size_t planned, std::size_t found) noexcept {
  if (is_fatal(kind)) match.fatal = true;
  // Capacity covers two differences per found device plus every planned slot.
  (void)match.differences.push_back(NetworkDifference{kind, u8(planned), u8(found)});
}

}  // namespace

const char* to_string(DifferenceKind kind) noexcept {
  switch (kind) {
    case DifferenceKind::missing: return "missing";
    case DifferenceKind::extra: return "extra";
    case DifferenceKind::wrong_device: return "wrong device";
    case DifferenceKind::wrong_position: return "wrong position";
    case DifferenceKind::duplicate_alias: return "duplicate alias";
    case DifferenceKind::process_data_size: return "process data size";
    case DifferenceKind::revision: return "revision";
    case DifferenceKind::known_lost_present: return "held out, present";
  }
  return "?";
}

std::size_t NetworkMatch::count(DifferenceKind kind) const noexcept {
  return static_cast<std::size_t>(
      std::count_if(differences.begin(), differences.end(), [kind](const NetworkDifference& d) { return d.kind == kind; }));
}

NetworkMatch match_network(const NetworkPlan& plan, Span<const FoundSlave> found, SlaveMask held_out) noexcept {
  NetworkMatch match;
  match.slot_of_found.fill(kNoPosition);
  match.found_of_slot.fill(kNoPosition);
  match.held_out = held_out & kAllSlaves;
  match.may_be_absent = subtrees_of(plan, match.held_out);
  const std::size_t n = found.size() < kMaxFoundSlaves ? found.size() : kMaxFoundSlaves;
  // By order: every planned slot when all answer, else the slots that must answer.
  const SlaveMask skipped_by_order = n >= kMaxSlaves ? SlaveMask{0} : match.may_be_absent;

  // 1. Candidate slot of each found device: its alias, else its place among the expected ones.
  std::array<std::uint8_t, kMaxFoundSlaves> candidate{};
  candidate.fill(kNoPosition);
  SlaveMask claimed = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint8_t c = slot_with_alias(plan, found[a].station_alias);
    if (c == kNoPosition) continue;
    if ((claimed & slave_bit(c)) != 0) {
      add(match, DifferenceKind::duplicate_alias, c, a);
      continue;
    }
    candidate[a] = c;
    claimed |= slave_bit(c);
  }
  std::size_t expected_index = 0;  // a-th found <-> a-th planned slot not known lost
  for (std::size_t a = 0; a < n; ++a) {
    std::size_t c = kMaxSlaves;
    for (std::size_t p = 0, k = 0; p < kMaxSlaves; ++p) {
      if ((skipped_by_order & slave_bit(p)) != 0) continue;
      if (k++ == expected_index) {
        c = p;
        break;
      }
    }
    ++expected_index;
    if (candidate[a] != kNoPosition || slot_with_alias(plan, found[a].station_alias) != kNoPosition) continue;
    if (c < kMaxSlaves && (claimed & slave_bit(c)) == 0) {
      candidate[a] = u8(c);
      claimed |= slave_bit(c);
    } else {
      add(match, DifferenceKind::extra, kNoPosition, a);
    }
  }

  // 2. Identity: the device type of the slot.
  SlaveMask accounted = 0;
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint8_t c = candidate[a];
    if (c == kNoPosition) continue;
    accounted |= slave_bit(c);
    if (found[a].vendor_id != plan[c].vendor_id || found[a].product_code != plan[c].product_code) {
      add(match, DifferenceKind::wrong_device, c, a);
      candidate[a] = kNoPosition;
    }
  }

  // 3. Order along the frame: the longest increasing run of slots is right, the rest misplaced.
  const std::array<bool, kMaxFoundSlaves> in_order = longest_increasing(candidate, n);
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint8_t c = candidate[a];
    if (c == kNoPosition) continue;
    if (!in_order[a]) {
      add(match, DifferenceKind::wrong_position, c, a);
      continue;
    }
    if ((match.held_out & slave_bit(c)) != 0) {
      // Answers where planned: part of the topology (addressed, distributed clocks), not operated.
      add(match, DifferenceKind::known_lost_present, c, a);
      match.slot_of_found[a] = c;
      match.found_of_slot[c] = u8(a);
      match.present |= slave_bit(c);
      continue;
    }
    if (found[a].revision != plan[c].revision) add(match, DifferenceKind::revision, c, a);
    if (found[a].pdo_sizes_known &&
        (found[a].output_bits != 8U * plan[c].output_bytes || found[a].input_bits != 8U * plan[c].input_bytes)) {
      add(match, DifferenceKind::process_data_size, c, a);
      continue;
    }
    match.slot_of_found[a] = c;
    match.found_of_slot[c] = u8(a);
    match.present |= slave_bit(c);
    match.operated |= slave_bit(c);
  }

  // 4. Planned slots nobody answered for.
  for (std::size_t p = 0; p < kMaxSlaves; ++p) {
    if ((accounted & slave_bit(p)) == 0 && (match.may_be_absent & slave_bit(p)) == 0) {
      add(match, DifferenceKind::missing, p, kNoPosition);
    }
  }
  // Devices beyond our capacity are extra by definition.
  for (std::size_t a = n; a < found.size(); ++a) add(match, DifferenceKind::extra, kNoPosition, a);
  return match;
}

std::size_t describe(const NetworkDifference& d, const NetworkPlan& plan, Span<const FoundSlave> found, char* out,
                     std::size_t size) noexcept {
  if (size == 0) return 0;
  static constexpr SlavePlan kNoSlave{"?", 0, 0, 0, "?", 0, 0, 0, 0, kNoBranch, 0, 0, false, false, nullptr};
  static const FoundSlave kNoDevice{};
  const SlavePlan& s = d.planned < kMaxSlaves ? plan[d.planned] : kNoSlave;
  const FoundSlave& f = d.found < found.size() ? found[d.found] : kNoDevice;
  int n = 0;
  switch (d.kind) {
    case DifferenceKind::missing:
      n = std::snprintf(out, size, "missing: %s (position %u, %s 0x%08" PRIx32 ":0x%08" PRIx32 ") does not answer",
                        s.name, d.planned, s.device_name, s.vendor_id, s.product_code);
      break;
    case DifferenceKind::extra:
      n = std::snprintf(out, size, "extra: device at position %u (%s 0x%08" PRIx32 ":0x%08" PRIx32 " alias 0x%04x) is not planned",
                        d.found, f.name.data(), f.vendor_id, f.product_code, f.station_alias);
      break;
    case DifferenceKind::wrong_device:
      n = std::snprintf(out, size, "wrong device: position %u holds %s 0x%08" PRIx32 ":0x%08" PRIx32
                        " where %s expects %s 0x%08" PRIx32 ":0x%08" PRIx32,
                        d.found, f.name.data(), f.vendor_id, f.product_code, s.name, s.device_name, s.vendor_id,
                        s.product_code);
      break;
    case DifferenceKind::wrong_position:
      n = std::snprintf(out, size, "wrong position: %s (alias 0x%04x) found at position %u, planned at %u", s.name,
                        f.station_alias, d.found, d.planned);
      break;
    case DifferenceKind::duplicate_alias:
      n = std::snprintf(out, size, "duplicate alias: device at position %u also claims %s (alias 0x%04x)", d.found,
                        s.name, s.station_alias);
      break;
    case DifferenceKind::process_data_size:
      n = std::snprintf(out, size, "process data size: %s maps %" PRIu32 " output / %" PRIu32
                        " input bits, planned %u / %u", s.name, f.output_bits, f.input_bits,
                        8U * s.output_bytes, 8U * s.input_bytes);
      break;
    case DifferenceKind::revision:
      n = std::snprintf(out, size, "revision (warning): %s has revision 0x%08" PRIx32 ", planned 0x%08" PRIx32, s.name,
                        f.revision, s.revision);
      break;
    case DifferenceKind::known_lost_present:
      n = std::snprintf(out, size, "held out of service, present (warning): %s answers at position %u; brought into "
                        "the topology and distributed clocks, kept out of operation", s.name, d.found);
      break;
  }
  if (n < 0) {
    out[0] = '\0';
    return 0;
  }
  return static_cast<std::size_t>(n) < size ? static_cast<std::size_t>(n) : size - 1;
}

void print_differences(std::FILE* stream, const NetworkMatch& match, const NetworkPlan& plan,
                       Span<const FoundSlave> found) noexcept {
  std::array<char, kDifferenceLineCapacity> line{};
  for (const NetworkDifference& d : match.differences) {
    (void)describe(d, plan, found, line.data(), line.size());
    (void)std::fprintf(stream, "%s\n", line.data());
  }
}

}  // namespace rescue::ecat
