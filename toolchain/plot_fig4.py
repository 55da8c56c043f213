#!/usr/bin/env python3
"""Draws the paper's Fig. 4 from `rescue-motion bench fig4`'s CSV: six panels in one PNG, the
execution time per period without and with the Table I CPU affinity (columns: case; each row shares
its y axis so the cases compare directly). Rows:
  1. the EtherCAT handler alone (handler_only_ns): what the paper's Fig. 4 measures;
  2. the handler's whole period against the in-process simulated robot (execution_ns), with its
     two other parts drawn under it: the simulator's share (simulator_ns) and the wait for the
     frame (frame_wait_ns);
  3. the RC task (execution_ns).

Usage: plot_fig4.py FIG4_CSV OUT_PNG
FIG4_CSV columns: case,task,period,execution_ns,latency_ns,handler_only_ns,simulator_ns,frame_wait_ns
(one row per task, case and period; the last three are 0 for the RC task).
Needs matplotlib (Debian: python3-matplotlib); `bench fig4` runs it with /usr/bin/python3.
"""
import csv
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = [("without_affinity", "without CPU affinity"), ("with_affinity", "with Table I CPU affinity")]
# (task, column, title)
ROWS = [
    ("ethercat", "handler_only_ns", "EtherCAT handler alone (paper's Fig. 4)"),
    ("ethercat", "execution_ns", "Handler period with simulator and frame wait"),
    ("rc", "execution_ns", "RC task (rescue motion)"),
]
PARTS = [("simulator_ns", "simulator", "tab:orange"), ("frame_wait_ns", "wait for the frame", "tab:red")]


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    series = {}
    with open(argv[1], newline="") as f:
        for row in csv.DictReader(f):
            for column in ("execution_ns", "handler_only_ns", "simulator_ns", "frame_wait_ns"):
                key = (row["task"], row["case"], column)
                series.setdefault(key, []).append(int(row[column]) / 1000.0)
    fig, axes = plt.subplots(len(ROWS), len(CASES), figsize=(12, 10), sharey="row", squeeze=False)
    for r, (task, column, task_title) in enumerate(ROWS):
        for c, (case, case_title) in enumerate(CASES):
            ax = axes[r][c]
            values = series.get((task, case, column), [])
            ax.plot(range(len(values)), values, linewidth=0.5, color="tab:blue" if c == 0 else "tab:green",
                    label="whole period" if r == 1 else None)
            if r == 1:
                for part, label, colour in PARTS:
                    p = series.get((task, case, part), [])
                    ax.plot(range(len(p)), p, linewidth=0.5, color=colour, label=label)
                ax.legend(fontsize=7, loc="upper right")
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
