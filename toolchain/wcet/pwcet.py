#!/usr/bin/python3
"""Probabilistic WCET (MBPTA) from per-period execution times: block maxima, i.i.d. tests, a GEV fit
with its goodness of fit, and the time exceeded with probability 1e-9 and 1e-12 per period with a
parametric-bootstrap confidence interval. docs/timing.md "pWCET: the method" is the reference.

Input: one file per task, one non-negative integer (ns, one period's execution time) per line, in
period order; lines starting with '#' are comments. The task is named after the file (stem).
Output: `TASK.key: value` lines; a figure that does not apply is n/a.
Exit status: 0 every task has a pWCET; 2 a test failed for some task (its pWCET is n/a);
64 usage error; 65 bad input (the message names FILE:LINE); 66 an input cannot be read.
Runs on Debian's python3 with python3-numpy, python3-scipy (and python3-matplotlib for --plot).
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy import optimize, stats

EXIT_REFUSED, EXIT_USAGE, EXIT_DATAERR, EXIT_NOINPUT = 2, 64, 65, 66
MIN_BLOCKS = 40            # fewer maxima than this make a GEV fit (3 parameters) and its tests meaningless
LJUNG_BOX_LAGS = 10        # autocorrelation lags of the maxima tested together
EXCEEDANCES = (1e-9, 1e-12)


class BadInput(Exception):
    pass


def read_samples(path):
    """Execution times of one file in period order; BadInput names FILE:LINE of the first bad line."""
    values = []
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            text = line.strip()
            if text.startswith("#"):
                continue
            if not text.isdigit():  # also refuses '', '-5', '1.5', '1e3', '+3'
                what = "empty line" if not text else ("negative value" if text.startswith("-") else "not a non-negative integer")
                raise BadInput(f"{path}:{number}: {what}: {text!r} (expected one execution time in ns per line)")
            values.append(int(text))
    if not values:
        raise BadInput(f"{path}:1: no samples (the file has no execution time)")
    return np.array(values, dtype=float)


def block_maxima(samples, block):
    whole = len(samples) // block
    return samples[: whole * block].reshape(whole, block).max(axis=1)


def ljung_box(x, lags):
    """Ljung-Box Q over lags 1..h and its chi-square p-value (h degrees of freedom)."""
    n = len(x)
    d = x - x.mean()
    denominator = float(np.dot(d, d))
    if denominator == 0.0:
        return math.nan, math.nan
    q = sum(float(np.dot(d[:-k], d[k:])) ** 2 / denominator ** 2 / (n - k) for k in range(1, lags + 1))
    q *= n * (n + 2)
    return q, float(stats.chi2.sf(q, lags))


# GEV with shape xi (xi > 0 heavy tail, xi < 0 bounded tail, xi = 0 Gumbel); scipy's c is -xi.
# The largest shape accepted: from 0.5 up the fitted tail has no finite variance (refused above).
MAX_SHAPE = 0.5
def gev_nll(theta, x):
    mu, log_sigma, xi = theta
    sigma = math.exp(log_sigma)
    z = (x - mu) / sigma
    if abs(xi) < 1e-8:
        return len(x) * log_sigma + float(np.sum(z + np.exp(-z)))
    t = 1.0 + xi * z
    if np.any(t <= 0.0):
        return math.inf
    lt = np.log(t)
    return len(x) * log_sigma + (1.0 + 1.0 / xi) * float(np.sum(lt)) + float(np.sum(np.exp(-lt / xi)))


def gumbel_nll(theta, z):
    return gev_nll((theta[0], theta[1], 0.0), z)


def gev_fit(x):
    """Maximum likelihood (mu, sigma, xi) of x, with the shape held at xi >= 0: a fitted xi < 0 claims an
    upper end point the samples cannot show at 1e-9, so the Gumbel (xi = 0), the light tail's safe bound,
    is fitted instead. Standardised for conditioning; starts at the Gumbel moments."""
    centre, spread = float(np.mean(x)), float(np.std(x))
    if spread == 0.0:
        return None
    z = (x - centre) / spread
    scale0 = math.sqrt(6.0) / math.pi
    options = {"xatol": 1e-5, "fatol": 1e-7, "maxiter": 2000}
    gumbel = optimize.minimize(gumbel_nll, np.array([-0.5772 * scale0, math.log(scale0)]), args=(z,),
                               method="Nelder-Mead", options=options)
    best = optimize.minimize(gev_nll, np.array([gumbel.x[0], gumbel.x[1], 0.05]), args=(z,),
                             method="Nelder-Mead", options=options)
    if np.isfinite(best.fun) and best.x[2] > 0.0 and best.fun < gumbel.fun:
        mu, log_sigma, xi = best.x
    elif np.isfinite(gumbel.fun):
        (mu, log_sigma), xi = gumbel.x, 0.0
    else:
        return None
    return centre + spread * mu, spread * math.exp(log_sigma), float(xi)


def gev_cdf(x, fit):
    mu, sigma, xi = fit
    z = (np.asarray(x, dtype=float) - mu) / sigma
    if abs(xi) < 1e-8:
        return np.exp(-np.exp(-z))
    t = np.maximum(1.0 + xi * z, 0.0)
    with np.errstate(divide="ignore"):
        return np.exp(-t ** (-1.0 / xi))


def gev_sample(fit, size, rng):
    """Inverse transform: mu + sigma ((-log U)^-xi - 1) / xi."""
    mu, sigma, xi = fit
    e = -np.log(rng.uniform(size=size))
    return mu - sigma * np.log(e) if abs(xi) < 1e-8 else mu + sigma * (e ** -xi - 1.0) / xi


def period_quantile(fit, exceedance, block):
    """Time exceeded with `exceedance` per period: the block maximum's quantile at 1-(1-p)^block."""
    block_exceedance = -math.expm1(block * math.log1p(-exceedance))
    return float(stats.genextreme.isf(block_exceedance, -fit[2], loc=fit[0], scale=fit[1]))


def ks_statistic(x, fit):
    """One-sample Kolmogorov-Smirnov distance between x and the fitted GEV."""
    f = gev_cdf(np.sort(x), fit)
    n = len(f)
    return float(max(np.max(np.arange(1, n + 1) / n - f), np.max(f - np.arange(n) / n)))


def analyse(name, samples, args):
    """Every figure of one task as ordered (key, value) pairs, the refusal reasons, and the plot data."""
    out = [("samples", len(samples)), ("block_size", args.block)]
    maxima = block_maxima(samples, args.block)
    out += [("blocks", len(maxima)), ("observed_max_ns", int(samples.max())), ("alpha", args.alpha)]
    refusals = []

    q, p_lb = ljung_box(maxima, min(LJUNG_BOX_LAGS, len(maxima) // 4))
    out += [("independence_test", f"Ljung-Box on the block maxima, {min(LJUNG_BOX_LAGS, len(maxima) // 4)} lags"),
            ("independence_p", fmt_p(p_lb))]
    if not math.isfinite(p_lb):
        refusals.append("independence: Ljung-Box undefined (the block maxima do not vary)")
    elif p_lb < args.alpha:
        refusals.append(f"independence: Ljung-Box p = {fmt_p(p_lb)} < alpha {args.alpha}")

    half = len(maxima) // 2
    p_ks2 = float(stats.ks_2samp(maxima[:half], maxima[half:]).pvalue)
    out += [("identical_distribution_test", "two-sample Kolmogorov-Smirnov, first half of the block maxima against the second"),
            ("identical_distribution_p", fmt_p(p_ks2))]
    if not p_ks2 >= args.alpha:
        refusals.append(f"identical distribution: two-sample KS p = {fmt_p(p_ks2)} < alpha {args.alpha}")

    fit = gev_fit(maxima)
    plot = {"name": name, "samples": samples, "block": args.block, "fit": None, "refusals": refusals}
    if fit is None:
        refusals.append("fit: the block maxima are all equal or the GEV likelihood has no maximum")
        out += [("gev_location_ns", "n/a"), ("gev_scale_ns", "n/a"), ("gev_shape_xi", "n/a"),
                ("goodness_of_fit_test", "n/a"), ("goodness_of_fit_p", "n/a")]
    else:
        out += [("gev_location_ns", f"{fit[0]:.1f}"), ("gev_scale_ns", f"{fit[1]:.1f}"), ("gev_shape_xi", f"{fit[2]:.4f}" + (" (held at 0: Gumbel)" if fit[2] == 0.0 else ""))]
        boot = bootstrap(maxima, fit, args)
        d = ks_statistic(maxima, fit)
        p_gof = (1 + sum(1 for b in boot if b["ks"] >= d)) / (len(boot) + 1)
        out += [("goodness_of_fit_test", f"Kolmogorov-Smirnov against the fitted GEV, p-value by parametric bootstrap ({len(boot)} refits)"),
                ("goodness_of_fit_p", fmt_p(p_gof))]
        if not p_gof >= args.alpha:
            refusals.append(f"goodness of fit: KS p = {fmt_p(p_gof)} < alpha {args.alpha}")
        if fit[2] >= MAX_SHAPE:
            # A tail this heavy has no finite variance (xi >= 1: no finite mean): execution times of
            # bounded code paths are not like that, so the maxima measured are interference (a
            # preempted or delayed period), and extrapolating them gives no time bound (a single
            # run gave pWCET(1e-9) = 7e12 ns with xi 1.44).
            # xi >= 1 is refused the same way, named for what it lacks: a mean (not a usable bound either).
            lacks = "no finite mean" if fit[2] >= 1.0 else "no finite variance"
            refusals.append(f"heavy tail: GEV shape xi = {fit[2]:.2f} >= {MAX_SHAPE} ({lacks}: interference, not the program's paths)")
        plot.update(fit=fit, boot=boot)

    out.append(("interval", f"{args.confidence:g} two-sided, parametric bootstrap percentile ({args.bootstrap} resamples of the maxima, refitted)"))
    for p in EXCEEDANCES:
        key = f"pwcet_{p:.0e}".replace("e-0", "e-")
        if refusals:
            out += [(key + "_ns", "n/a"), (key + "_ci_low_ns", "n/a"), (key + "_ci_high_ns", "n/a")]
            continue
        low, high = interval([period_quantile(b["fit"], p, args.block) for b in plot["boot"]], args.confidence)
        out += [(key + "_ns", f"{period_quantile(fit, p, args.block):.0f}"),
                (key + "_ci_low_ns", f"{low:.0f}"), (key + "_ci_high_ns", f"{high:.0f}")]
    out.append(("verdict", "pWCET given (all tests passed)" if not refusals else "refused: " + "; ".join(refusals)))
    return out, plot


def bootstrap(maxima, fit, args):
    """Parametric bootstrap: samples of the fitted GEV, refitted; each gives a fit and its KS statistic."""
    rng = np.random.default_rng(args.seed)
    results = []
    for _ in range(args.bootstrap):
        x = gev_sample(fit, len(maxima), rng)
        refit = gev_fit(x)
        if refit is not None:
            results.append({"fit": refit, "ks": ks_statistic(x, refit)})
    return results


def interval(values, confidence):
    finite = np.array([v for v in values if math.isfinite(v)])
    tail = (1.0 - confidence) / 2.0
    if len(finite) < len(values):  # infinite quantiles (xi >> 0 refits): the upper bound is unbounded
        return float(np.quantile(finite, tail)) if len(finite) else math.inf, math.inf
    return float(np.quantile(finite, tail)), float(np.quantile(finite, 1.0 - tail))


def fmt_p(p):
    return "n/a" if not math.isfinite(p) else f"{p:.4g}"


def parse(argv):
    parser = argparse.ArgumentParser(
        description="pWCET at 1e-9 and 1e-12 per period from per-period execution times (docs/timing.md, 'pWCET: the method').",
        epilog="Exit status: 0 pWCET given for every task; 2 a test failed (no pWCET); 64 usage; 65 bad input; 66 unreadable input.")
    parser.add_argument("inputs", nargs="+", metavar="FILE", help="one execution time in ns per line, period order; '#' comments; task = file stem")
    parser.add_argument("--block", type=int, default=50, help="periods per block (default 50)")
    parser.add_argument("--alpha", type=float, default=0.05, help="significance level of each test (default 0.05)")
    parser.add_argument("--confidence", type=float, default=0.95, help="confidence of the pWCET interval (default 0.95)")
    parser.add_argument("--bootstrap", type=int, default=500, help="parametric bootstrap resamples (default 500)")
    parser.add_argument("--seed", type=int, default=1, help="bootstrap random seed (default 1: the same input gives the same output)")
    parser.add_argument("--plot", metavar="FILE.png", help="draw the exceedance curves, one panel per task")
    parser.error = lambda message: (parser.print_usage(sys.stderr), print(f"pwcet: {message}", file=sys.stderr), sys.exit(EXIT_USAGE))
    args = parser.parse_args(argv)
    if args.block < 1 or not 0.0 < args.alpha < 1.0 or not 0.0 < args.confidence < 1.0 or args.bootstrap < 20:
        parser.error("--block >= 1, 0 < --alpha < 1, 0 < --confidence < 1, --bootstrap >= 20")
    return args


def main(argv):
    args = parse(argv)
    tasks = []
    for path in args.inputs:
        try:
            samples = read_samples(path)
        except OSError as e:
            print(f"pwcet: {path}: cannot read: {e.strerror}", file=sys.stderr)
            return EXIT_NOINPUT
        except BadInput as e:
            print(f"pwcet: {e}", file=sys.stderr)
            return EXIT_DATAERR
        if len(samples) // args.block < MIN_BLOCKS:
            print(f"pwcet: {path}: too few samples for the method: {len(samples)} periods make "
                  f"{len(samples) // args.block} blocks of {args.block}; need at least {MIN_BLOCKS} blocks "
                  f"({MIN_BLOCKS * args.block} periods)", file=sys.stderr)
            return EXIT_DATAERR
        tasks.append((os.path.splitext(os.path.basename(path))[0], samples))
    status, plots = 0, []
    for name, samples in tasks:
        lines, plot = analyse(name, samples, args)
        for key, value in lines:
            print(f"{name}.{key}: {value}")
        plots.append(plot)
        if plot["refusals"]:
            status = EXIT_REFUSED
    if args.plot:
        import pwcet_plot  # matplotlib only when asked
        pwcet_plot.draw(plots, args.plot, EXCEEDANCES, args.confidence, period_quantile)
        print(f"plot: {args.plot}")
    return status


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    sys.exit(main(sys.argv[1:]))
