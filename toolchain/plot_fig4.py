#!/usr/bin/env python3
"""Draws the paper's Fig. 4 from `rescue-motion bench fig4`'s CSV: four panels in one PNG, the
execution time per period of the EtherCAT handler and of the RC task, without and with the Table I
CPU affinity (rows: task, columns: case; each row shares its y axis so the cases compare directly).

Usage: plot_fig4.py FIG4_CSV OUT_PNG
FIG4_CSV columns: case,task,period,execution_ns,latency_ns (one row per task, case and period).
Needs matplotlib (Debian: python3-matplotlib); `bench fig4` runs it with /usr/bin/python3.
"""
import csv
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = [("without_affinity", "without CPU affinity"), ("with_affinity", "with Table I CPU affinity")]
TASKS = [("ethercat", "EtherCAT handler"), ("rc", "RC task (rescue motion)")]


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    series = {}
    with open(argv[1], newline="") as f:
        for row in csv.DictReader(f):
            key = (row["task"], row["case"])
            series.setdefault(key, []).append(int(row["execution_ns"]) / 1000.0)
    fig, axes = plt.subplots(len(TASKS), len(CASES), figsize=(12, 7), sharey="row", squeeze=False)
    for r, (task, task_title) in enumerate(TASKS):
        for c, (case, case_title) in enumerate(CASES):
            ax = axes[r][c]
            values = series.get((task, case), [])
            ax.plot(range(len(values)), values, linewidth=0.5, color="tab:blue" if c == 0 else "tab:green")
            if values:
                mean = statistics.fmean(values)
                ax.axhline(mean, color="black", linewidth=0.8, linestyle="--")
                ax.set_title(f"{task_title}, {case_title}\nmean {mean:.1f} us, max {max(values):.1f} us", fontsize=10)
            ax.set_xlabel("period (1 ms)")
            ax.set_ylabel("execution time (us)")
            ax.grid(True, linewidth=0.3)
    fig.suptitle("Fig. 4: execution time per period under load (rescue-motion bench fig4)")
    fig.tight_layout()
    fig.savefig(argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
