"""The exceedance plot of toolchain/wcet/pwcet.py: one panel per task, per-period exceedance probability
(log) against execution time; the measured periods as points, the GEV fit turned into a per-period curve,
its bootstrap interval as a band, the 1e-9 and 1e-12 levels, and the verdict in the title. The per-period
quantile comes from pwcet.py as an argument (`period_quantile`), so this file imports nothing of it."""
import math

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def draw(plots, path, exceedances, confidence, period_quantile):
    fig, axes = plt.subplots(len(plots), 1, figsize=(8, 4.5 * len(plots)), squeeze=False)
    for ax, task in zip(axes[:, 0], plots):
        panel(ax, task, exceedances, confidence, period_quantile)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def panel(ax, task, exceedances, confidence, period_quantile):
    samples = np.sort(task["samples"])
    n = len(samples)
    measured = 1.0 - np.arange(1, n + 1) / (n + 1.0)  # empirical exceedance of each measured period
    ax.plot(samples / 1e3, measured, ".", ms=3, color="black", label=f"measured periods (n = {n})")
    ax.axvline(samples[-1] / 1e3, color="black", lw=0.8, ls=":", label=f"observed maximum {samples[-1] / 1e3:.1f} us")
    levels = np.logspace(math.log10(1.0 / n), -13, 60)
    if task["fit"] is not None and not task["refusals"]:
        fit, block = task["fit"], task["block"]
        curve = np.array([period_quantile(fit, p, block) for p in levels])
        ax.plot(curve / 1e3, levels, color="tab:blue", label="GEV fit of the block maxima, per period")
        boot = np.array([[period_quantile(b["fit"], p, block) for p in levels] for b in task["boot"]])
        tail = (1.0 - confidence) / 2.0
        low, high = np.quantile(boot, tail, axis=0), np.quantile(boot, 1.0 - tail, axis=0)
        ax.fill_betweenx(levels, low / 1e3, high / 1e3, color="tab:blue", alpha=0.2,
                         label=f"{confidence:g} confidence interval (parametric bootstrap)")
        for p in exceedances:
            x = period_quantile(fit, p, block)
            ax.plot([x / 1e3], [p], "o", color="tab:red")
            ax.annotate(f"pWCET({p:.0e}) = {x / 1e3:.1f} us", (x / 1e3, p), textcoords="offset points", xytext=(6, 4), fontsize=8)
        verdict = "all tests passed"
    else:
        verdict = "NO pWCET: a test failed"
        ax.text(0.02, 0.05, "NO pWCET, failed:\n" + "\n".join(task["refusals"]), transform=ax.transAxes,
                color="tab:red", fontsize=7, va="bottom")
    for i, p in enumerate(exceedances):
        ax.axhline(p, color="tab:red", lw=0.6, ls="--", label="exceedance per period of the pWCET" if i == 0 else None)
    ax.set_yscale("log")
    ax.set_ylim(1e-13, 1.0)
    ax.set_xlabel("execution time of one period (us)")
    ax.set_ylabel("probability a period exceeds it")
    ax.set_title(f"{task['name']}: block maxima of {task['block']} periods; {verdict}", fontsize=9)
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
