/* SOEM 1.4.0's cable redundancy measured the way toolchain/compare-ring-with-soem.sh measures ours:
 * ec_init_redundant on two interfaces (the simulator's main and ring ports), ec_config_map, ec_configdc,
 * OP, then CYCLES 1 ms cycles of process data. Times are seconds after the first cycle; the script
 * breaks and repairs a cable at BREAK_S and REPAIR_S (it writes to the simulator), this program only
 * measures. Every cycle one slave's system time difference (0x092C, sign and magnitude) is read, in
 * turn, so each slave is read every slave-count cycles.
 * Prints `key: value unit` lines: cycles with the full working counter and without (SOEM's own count:
 * the expected working counter of ec_group 0), the longest run of cycles without it, the largest
 * |0x092C| before the break, from BREAK_S + 0.1 s to the repair, and from REPAIR_S + 0.1 s to the end,
 * and the slaves not in OP at the end (SOEM's view of what is lost).
 * Usage: soem_ring_cycle IFACE RING_IFACE CYCLES BREAK_S REPAIR_S */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "ethercat.h"

static char io_map[8192];

static double seconds_since(const struct timespec *start) {
  struct timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  return (double)(now.tv_sec - start->tv_sec) + (double)(now.tv_nsec - start->tv_nsec) / 1e9;
}

/* 0x092C: bit 31 the sign (1: local copy of system time smaller), bits 0-30 the magnitude in ns. */
static long dc_difference_magnitude(uint32 raw) { return (long)(raw & 0x7FFFFFFFu); }

/* The largest magnitude 0x092C can show (the simulated ESC, as a real one, saturates there): a clock
 * that far off is not a figure in ns, so it is printed as `saturated`, with how many reads were. */
static const long kDcDifferenceLimit = 0x7FFFFFFFL;

static void print_dc(const char *key, long value, int samples, int saturated) {
  if (samples == 0) printf("%s: n/a (no read)\n", key);
  else if (value >= kDcDifferenceLimit) printf("%s: saturated (%d of %d reads at 0x092C's limit, 2^31-1 ns)\n", key, saturated, samples);
  else printf("%s: %ld ns\n", key, value);
}

int main(int argc, char **argv) {
  if (argc != 6) {
    fprintf(stderr, "usage: soem_ring_cycle IFACE RING_IFACE CYCLES BREAK_S REPAIR_S\n");
    return 2;
  }
  const int cycles = atoi(argv[3]);
  const double break_s = atof(argv[4]), repair_s = atof(argv[5]);
  if (!ec_init_redundant(argv[1], argv[2])) { printf("ec_init_redundant: failed\n"); return 1; }
  const int found = ec_config_init(FALSE);
  printf("slaves: %d\n", found);
  if (found <= 0) return 1;
  ec_config_map(&io_map);
  ec_configdc();
  ec_statecheck(0, EC_STATE_SAFE_OP, EC_TIMEOUTSTATE * 4);
  const int expected = ec_group[0].outputsWKC * 2 + ec_group[0].inputsWKC;
  ec_slave[0].state = EC_STATE_OPERATIONAL;
  ec_send_processdata();
  ec_receive_processdata(EC_TIMEOUTRET);
  ec_writestate(0);
  for (int tries = 200; tries-- > 0 && ec_slave[0].state != EC_STATE_OPERATIONAL;) {
    ec_send_processdata();
    ec_receive_processdata(EC_TIMEOUTRET);
    ec_statecheck(0, EC_STATE_OPERATIONAL, 50000);
  }
  if (ec_slave[0].state != EC_STATE_OPERATIONAL) { printf("op: no\n"); return 1; }
  printf("op: yes\nexpected_wkc: %d\n", expected);
  fflush(stdout);  /* the script starts its break schedule at this line */

  int full = 0, short_cycles = 0, run = 0, longest_run = 0;
  long dc_before = 0, dc_broken = 0, dc_repaired = 0;
  int n_before = 0, n_broken = 0, n_repaired = 0;
  int sat_before = 0, sat_broken = 0, sat_repaired = 0;
  struct timespec start, next;
  clock_gettime(CLOCK_MONOTONIC, &start);
  next = start;
  for (int i = 0; i < cycles; ++i) {
    next.tv_nsec += 1000000;
    if (next.tv_nsec >= 1000000000) { next.tv_nsec -= 1000000000; next.tv_sec++; }
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, NULL);
    ec_send_processdata();
    const int wkc = ec_receive_processdata(EC_TIMEOUTRET);
    if (wkc >= expected) { ++full; run = 0; } else { ++short_cycles; if (++run > longest_run) longest_run = run; }
    const int slave = 1 + i % found;
    uint32 raw = 0;
    if (ec_FPRD(ec_slave[slave].configadr, ECT_REG_DCSYSDIFF, sizeof raw, &raw, EC_TIMEOUTRET) > 0 &&
        ec_slave[slave].hasdc) {
      const long magnitude = dc_difference_magnitude(etohl(raw));
      const double t = seconds_since(&start);
      const int at_limit = magnitude >= kDcDifferenceLimit;
      if (t < break_s) { if (magnitude > dc_before) dc_before = magnitude; ++n_before; sat_before += at_limit; }
      else if (t >= break_s + 0.1 && t < repair_s) { if (magnitude > dc_broken) dc_broken = magnitude; ++n_broken; sat_broken += at_limit; }
      else if (t >= repair_s + 0.1) { if (magnitude > dc_repaired) dc_repaired = magnitude; ++n_repaired; sat_repaired += at_limit; }
    }
  }
  ec_readstate();
  int not_op = 0;
  for (int s = 1; s <= ec_slavecount; ++s) not_op += (ec_slave[s].state & 0x0F) != EC_STATE_OPERATIONAL;
  printf("cycles: %d\ncycles_full_wkc: %d\ncycles_without_full_wkc: %d\nlongest_run_without_full_wkc: %d cycles\n",
         cycles, full, short_cycles, longest_run);
  print_dc("dc_max_abs_before_break", dc_before, n_before, sat_before);
  print_dc("dc_max_abs_after_break_100ms", dc_broken, n_broken, sat_broken);
  print_dc("dc_max_abs_after_repair_100ms", dc_repaired, n_repaired, sat_repaired);
  printf("slaves_not_op_at_end: %d\n", not_op);
  ec_slave[0].state = EC_STATE_INIT;
  ec_writestate(0);
  ec_close();
  return 0;
}
