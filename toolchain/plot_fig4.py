#!/usr/bin/env python3
"""Draws the paper's Fig. 4 from `rescue-motion bench fig4`'s CSV: eight panels in one PNG, the
execution time per period without and with the Table I CPU affinity (columns: case). Each panel has
its own y scale (a 9 us handler beside a 200 us period would be a flat line on a shared one); the
mean and the maximum are in each panel's legend, the mean drawn dashed. Rows:
  1. the EtherCAT handler alone (handler_only_ns): what the paper's Fig. 4 measures;
  2. the handler's whole period against the in-process simulated robot (execution_ns), with its
     two other parts drawn under it: the simulator's share (simulator_ns) and the wait for the
     frame (frame_wait_ns);
  3. the RC task (execution_ns);
  4. the wake-up latency of both tasks (latency_ns: how late each period started).
The conditions (kernel, PREEMPT_RT, CPUs, affinity applied or degraded, load: CONDITIONS, which
`bench fig4` passes) are printed under the title and stored in the PNG's Description text chunk.

Usage: plot_fig4.py FIG4_CSV OUT_PNG [CONDITIONS]
FIG4_CSV columns: case,task,period,execution_ns,latency_ns,handler_only_ns,simulator_ns,frame_wait_ns
(one row per task, case and period; the last three are 0 for the RC task).
Needs matplotlib (Debian: python3-matplotlib); `bench fig4` runs it with /usr/bin/python3.
"""
import csv
import statistics
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

CASES = [("without_affinity", "without CPU affinity"), ("with_affinity", "with Table I CPU affinity")]
# (task, column, title)
ROWS = [
    ("ethercat", "handler_only_ns", "EtherCAT handler alone (paper's Fig. 4)"),
    ("ethercat", "execution_ns", "Handler period with simulator and frame wait"),
    ("rc", "execution_ns", "RC task (rescue motion)"),
    ("latency", "latency_ns", "Wake-up latency"),
]
LATENCY_TASKS = [("ethercat", "EtherCAT handler", "tab:purple"), ("rc", "RC task", "tab:brown")]
PARTS = [("simulator_ns", "simulator", "tab:orange"), ("frame_wait_ns", "wait for the frame", "tab:red")]


def mean_max_label(name, values):
    return f"{name}: mean {statistics.fmean(values):.1f} us, max {max(values):.1f} us"


def main(argv):
    if len(argv) not in (3, 4):
        sys.stderr.write(__doc__)
        return 2
    conditions = argv[3] if len(argv) == 4 else "conditions not given"
    series = {}
    with open(argv[1], newline="") as f:
        for row in csv.DictReader(f):
            for column in ("execution_ns", "latency_ns", "handler_only_ns", "simulator_ns", "frame_wait_ns"):
                key = (row["task"], row["case"], column)
                series.setdefault(key, []).append(int(row[column]) / 1000.0)
    fig, axes = plt.subplots(len(ROWS), len(CASES), figsize=(12, 13), squeeze=False)
    for r, (task, column, task_title) in enumerate(ROWS):
        for c, (case, case_title) in enumerate(CASES):
            ax = axes[r][c]
            ax.set_title(f"{task_title}, {case_title}", fontsize=10)
            if task == "latency":
                lines = [(series.get((t, case, column), []), name, colour) for t, name, colour in LATENCY_TASKS]
                ax.set_ylabel("wake-up latency (us)")
            else:
                colour = "tab:blue" if c == 0 else "tab:green"
                lines = [(series.get((task, case, column), []), "whole period" if r == 1 else "execution", colour)]
                if r == 1:
                    lines += [(series.get((task, case, part), []), label, colour) for part, label, colour in PARTS]
                ax.set_ylabel("execution time (us)")
            for values, name, colour in lines:
                if not values:
                    continue
                ax.plot(range(len(values)), values, linewidth=0.5, color=colour, label=mean_max_label(name, values))
                ax.axhline(statistics.fmean(values), color=colour, linewidth=0.8, linestyle="--")
            ax.legend(fontsize=7, loc="upper right")
            ax.set_xlabel("period (1 ms)")
            ax.grid(True, linewidth=0.3)
    fig.suptitle("Fig. 4: execution time per period under load (rescue-motion bench fig4)\n" + textwrap.fill(conditions, 110),
                 fontsize=9)
    fig.tight_layout(rect=(0, 0, 1, 0.95))  # room for the title and the conditions
    fig.savefig(argv[2], dpi=110, metadata={"Description": conditions})
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
