#!/usr/bin/python3
"""Per-period instruction counts from callgrind's dumps (instructions.sh, run-instructions.sh).

Reads the dump files' paths from standard input, in dump order; each dump's trigger
(`Client Request: TASK`, core/app/tasks/period_mark.hpp) names the task whose period it ends and its
total is that period's instructions. Per TASK named on the command line prints, under PREFIX:
`PREFIX.TASK_instructions_periods`, `_per_period` (the mean), `_max_period` (with its period) and
`_median_period`; a task's first period is left out (its dump also holds the bring-up's NIC
toggles). Exit 1 when a task has no period. Usage: callgrind_periods.py PREFIX TASK... < PATHS
"""
import sys


def main():
    prefix, tasks = sys.argv[1], sys.argv[2:]
    counts = {t: [] for t in tasks}
    for path in sys.stdin.read().split():
        trigger, total = "", None
        with open(path) as f:
            for line in f:
                if line.startswith("desc: Trigger:"):
                    trigger = line
                elif line.startswith(("totals:", "summary:")):
                    total = int(line.split()[1])
        task = trigger.rsplit(":", 1)[-1].strip()
        if task in counts and total is not None:
            counts[task].append(total)
    status = 0
    for t in tasks:
        c = counts[t][1:]
        if not c:
            print(f"{prefix}.{t}_instructions_per_period: n/a (not driven)")
            status = 1
            continue
        k = max(range(len(c)), key=c.__getitem__)
        print(f"{prefix}.{t}_instructions_periods: {len(c)}")
        print(f"{prefix}.{t}_instructions_per_period: {sum(c) // len(c)} instructions")
        print(f"{prefix}.{t}_instructions_max_period: {c[k]} instructions (period {k + 1})")
        print(f"{prefix}.{t}_instructions_median_period: {sorted(c)[len(c) // 2]} instructions")
    return status


if __name__ == "__main__":
    sys.exit(main())
