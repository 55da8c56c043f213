// Issue 35, item 10: over veth a recovery took 24.5 s (five "recovery failed ... in Resetting"), and
// the recovery campaign's "stuck" count, which only looked at the end of the run, said 0. Here the
// campaign's random schedules (toolchain/veth-recovery-campaign.py: overlapping cuts, restores,
// power-offs, power-ons and SAFE-OP drops of drives, at most 3 at once, 0.15 to 2 s apart) run on the
// simulated robot in virtual time, seeded, and every recovery is judged as it happens: a joint
// whose faults all cleared is back in the exchange within kBackWithinPeriods (the issue 22 bound of
// 1 s), plus what was left at its return of the hold-off of a failure reported before it; a
// recovery that fails after its joint returned explains nothing and is counted. At the end every
// slave is in OP at its address.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "tests/support/simulated_robot_rig.hpp"

namespace rescue::ecat {
namespace {

constexpr int kBackWithinPeriods = 1000;  // 1 ms periods: 1 s
constexpr int kSchedulePeriods = 20000;   // 20 s of faults per seed
constexpr int kSeeds = 4;

MasterOptions recovery_options() {
  MasterOptions options = testing::fast_options();
  options.online_recovery = true;
  return options;
}

struct Judged {
  int faults{0};
  int returns{0};
  int recoveries{0};
  int slow{0};
  int failed_after_return{0};
  int longest{0};  // periods from a return to the exchange
  std::string first_slow;
};

// The drives a set of faults holds out of the exchange: the cut or switched-off slaves and every slave
// behind them, and the dropped ones until they are recovered.
SlaveMask held_by(SlaveMask cut, SlaveMask off) {
  SlaveMask held = 0;
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    if (((cut | off) & slave_bit(p)) != 0) held |= subtree_of(drivers::kRobotNetworkPlan, p);
  }
  return held;
}

Judged run_schedule(std::uint64_t seed) {
  Judged out;
  auto rig = testing::simulated_robot_in_op(recovery_options());
  std::mt19937_64 rng(seed);
  std::vector<std::size_t> drives;
  for (std::size_t j = 0; j < kJointCount; ++j) drives.push_back(slave_position_of_joint(j));
  SlaveMask cut = 0;
  SlaveMask off = 0;
  std::array<int, kMaxSlaves> returned_at{};   // period the slave's faults cleared; -1: not waiting
  std::array<int, kMaxSlaves> hold_off_until{};  // period a failure reported before its return lets it wait to
  returned_at.fill(-1);
  drivers::JointReferences refs{};
  drivers::JointFeedback fb{};
  int next_fault = 500;
  const auto release = [&](SlaveMask before, SlaveMask after, int k) {
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      const SlaveMask bit = slave_bit(p);
      if ((before & bit) != 0 && (after & bit) == 0) {
        returned_at[p] = k;
        ++out.returns;
      }
      if ((after & bit) != 0) returned_at[p] = -1;
    }
  };
  for (int k = 0; k < kSchedulePeriods + 3000; ++k) {
    if (k == next_fault && k < kSchedulePeriods) {
      const SlaveMask before = held_by(cut, off);
      const int active = ecat::popcount(cut) + ecat::popcount(off);
      std::vector<int> verbs;
      if (active < 3) verbs = {0, 1, 2};  // cut, power-off, SAFE-OP drop
      if (cut != 0) verbs.insert(verbs.end(), {3, 3});
      if (off != 0) verbs.insert(verbs.end(), {4, 4});
      const int verb = verbs[rng() % verbs.size()];
      const std::size_t p = drives[rng() % drives.size()];
      const auto pick = [&](SlaveMask m) {  // a slave of the set, at random
        std::vector<std::size_t> in;
        for (std::size_t q = 0; q < kSlaveCount; ++q) {
          if ((m & slave_bit(q)) != 0) in.push_back(q);
        }
        return in[rng() % in.size()];
      };
      if (verb == 0 && (cut & slave_bit(p)) == 0) {
        EXPECT_TRUE(rig->segment.cut_link(p).ok());
        cut |= slave_bit(p);
      } else if (verb == 1 && (off & slave_bit(p)) == 0) {
        EXPECT_TRUE(rig->segment.set_power(p, false, rig->clock.now()).ok());
        off |= slave_bit(p);
      } else if (verb == 2 && (before & slave_bit(p)) == 0 && returned_at[p] < 0 &&
                 rig->segment.esc(p).al_state() == reg::AlState::op) {
        EXPECT_TRUE(rig->segment.drop_to_safe_op(p, reg::al_code::kSynchronizationError).ok());
        returned_at[p] = k;  // reachable at once: taken back like a return
        ++out.returns;
      } else if (verb == 3) {
        const std::size_t q = pick(cut);
        EXPECT_TRUE(rig->segment.restore_link(q).ok());
        cut &= ~slave_bit(q);
      } else if (verb == 4) {
        const std::size_t q = pick(off);
        EXPECT_TRUE(rig->segment.set_power(q, true, rig->clock.now()).ok());
        off &= ~slave_bit(q);
      } else {
        next_fault += 1;
        continue;
      }
      ++out.faults;
      release(before, held_by(cut, off), k);
      next_fault = k + 150 + static_cast<int>(rng() % 1850);
    }
    if (k == kSchedulePeriods) {  // every fault cleared at the end
      const SlaveMask before = held_by(cut, off);
      for (std::size_t q = 0; q < kSlaveCount; ++q) {
        if ((cut & slave_bit(q)) != 0) {
          EXPECT_TRUE(rig->segment.restore_link(q).ok());
        }
        if ((off & slave_bit(q)) != 0) {
          EXPECT_TRUE(rig->segment.set_power(q, true, rig->clock.now()).ok());
        }
      }
      cut = 0;
      off = 0;
      release(before, 0, k);
    }
    (void)rig->cycle(refs, fb);
    LinkReport report;
    while (rig->bus.master().pop_report(report)) {
      for (std::size_t p = 0; p < kSlaveCount; ++p) {
        if ((report.slaves & slave_bit(p)) == 0) continue;
        if (report.kind == LinkEventKind::recovery_failed) {
          if (returned_at[p] >= 0) {
            ++out.failed_after_return;
          } else {
            hold_off_until[p] = k + static_cast<int>(report.found[2]);
          }
        }
        if (report.kind == LinkEventKind::recovered && returned_at[p] >= 0) {
          const int took = k - returned_at[p];
          const int explained = std::max(0, hold_off_until[p] - returned_at[p]) + kBackWithinPeriods;
          ++out.recoveries;
          out.longest = std::max(out.longest, took);
          if (took > explained) {
            ++out.slow;
            if (out.first_slow.empty()) {
              out.first_slow = std::string(kSlaves[p].name) + " " + std::to_string(took) + " periods after its return at " +
                               std::to_string(returned_at[p]) + " (" + std::to_string(explained) + " explained)";
            }
          }
          returned_at[p] = -1;
        }
      }
    }
    // Not recovered within what explains it, by now: slow too (counted once, when it passes the bound).
    for (std::size_t p = 0; p < kSlaveCount; ++p) {
      if (returned_at[p] < 0) continue;
      const int explained = std::max(0, hold_off_until[p] - returned_at[p]) + kBackWithinPeriods;
      if (k - returned_at[p] == explained + 1) {
        ++out.slow;
        if (out.first_slow.empty()) {
          out.first_slow = std::string(kSlaves[p].name) + " not back " + std::to_string(explained) +
                           " periods after its return at " + std::to_string(returned_at[p]) + " (state " +
                           to_string(rig->bus.master().recovery_state(p)) + ")";
        }
      }
    }
  }
  for (std::size_t p = 0; p < kSlaveCount; ++p) {
    EXPECT_EQ(rig->segment.esc(p).al_state(), reg::AlState::op) << "seed " << seed << ": " << kSlaves[p].name;
  }
  EXPECT_EQ(rig->bus.master().recovering(), 0u) << "seed " << seed;
  return out;
}

TEST(MasterRandomFaultSchedules, EveryRecoveryEndsWithinWhatAHoldOffExplains) {
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Judged j = run_schedule(static_cast<std::uint64_t>(seed));
    std::printf("seed %d: %d faults, %d returns, %d recoveries, longest %d periods, slow %d, failed after a return %d%s%s\n",
                seed, j.faults, j.returns, j.recoveries, j.longest, j.slow, j.failed_after_return,
                j.first_slow.empty() ? "" : "; first slow: ", j.first_slow.c_str());
    EXPECT_GT(j.faults, 15) << "seed " << seed;
    EXPECT_EQ(j.slow, 0) << "seed " << seed << ": " << j.first_slow;
    EXPECT_EQ(j.failed_after_return, 0) << "seed " << seed;
  }
}

}  // namespace
}  // namespace rescue::ecat
