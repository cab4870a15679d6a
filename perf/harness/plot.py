#!/usr/bin/env python3
"""Charts and summary of the perf harness.

Usage:  /usr/bin/python3 perf/harness/plot.py OUT_DIR

Input:  OUT_DIR/results.csv, written by the harness, one row per run (header
        row, comma separated, quoted where a cell holds a comma; an empty cell
        means "not applicable / unknown").  All columns of COLUMNS must be
        present; extra columns are ignored.  Needs only numpy and matplotlib.

Output (into OUT_DIR; the list of files written is printed):
  work_precision_<family>.png  study == work_precision, one panel per (size,
        material): error at the end time (log) against wall time per simulated
        second (log) = wall_per_step_s / dt, i.e. the summed step wall time
        over the simulated time (scene set-up excluded), the cost of reaching
        the end time; one line per (method, integrator), points labelled with
        dt; the Pareto front over every method, integrator and dt of the
        panel as a black step line, its points opaque and the dominated ones
        faint; failed runs are left out and counted in the legend as
        "(k failed)".  summary.md's tables keep time/step and add the
        per-simulated-second cost and the front.
  scaling.png  study == scaling, ok rows: wall time per step against dofs
        (log-log), one panel per family, one line per method, with the least
        squares slope of log t over log n in the legend.
  stability_<family>.png  study == stability: one panel per method, a grid of
        dt (x) by stiffness ratio (y); green "ok" cells with Newton its/step,
        red (orange for timeout/crash) cells with a short failure reason, grey
        where nothing ran.
  phases.png  for each family the largest size of the scaling study: stacked
        horizontal bars per method of the time per step split into phases,
        total annotated.
  chain.png  the chain built both ways (families chain and chain-articulated):
        scaling rows: cost per link per step against N, one line per (family,
        method), and the fastest method's per family with the reference
        engines' band; long_run rows: simulated time
        reached of the planned end time, the largest joint drift, Newton
        iterations per step, and the cost per simulated second at the largest dt
        each chain survived, against N, one line per (family, dt).
  contact.png  the contact families (contact-*; scaling and pattern_policy
        rows): wall time per step against DoFs and against active contacts
        (log-log, one line per family and pattern policy), and the share of
        the step each contact phase took (collision detection = broad +
        narrow phase + CCD; contact assembly; pattern analysis) against DoFs.
  summary.md  tables of every study, the reference runs and the failures.
A chart whose study has no rows is skipped with a printed line.  Exit status:
0 on success, 1 when results.csv is missing or lacks a column or a chart failed.
"""
import csv
import math
import os
import sys
import traceback
from collections import defaultdict

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

COLUMNS = (
    "suite study family size dofs material stiffness_ratio method solver "
    "preconditioner rtol newton_tol constraint_hessian near_rigid integrator dt steps end_time "
    "newton_iterations linear_iterations linear_solves truncated_solves factorizations reused_solves near_rigid_capped pattern_builds "
    "symbolic_analyses solver_object_builds nnz_h nnz_l factor_flops "
    "analysis_s ordering_s pattern_s slot_tables_s symbolic_s assembly_s factorization_s solve_s line_search_s other_s "
    "wall_per_step_s steady_per_step_s total_s ranks owned_dofs peak_rss_mb scene_rss_mb error reference joint_drift energy_gain state_hash "
    "contact_candidates active_contacts min_contact_distance contact_pattern_builds pattern_policy broad_phase_s narrow_phase_s "
    "ccd_s contact_assembly_s penetration_checks interpenetrations min_gap creep_um_per_s "
    "status reason").split()
# the studies whose rows the contact chart and table show
CONTACT_STUDIES = ("scaling", "pattern_policy")
# the two ways of building the chain (perf/harness/families.cc) and their line styles
CHAINS = {"chain": "-", "chain-articulated": "--", "chain-articulated-dense": ":"}
# µs per link per step of two established reduced-coordinate engines with
# explicit (semi-implicit Euler) stepping, measured for reference (they diverge
# on these chains at dt = 1e-2 and, for N = 50, at 1e-3: perf/harness/README.md)
REFERENCE_ENGINES_US = (0.4, 0.8)
# (column, legend label, colour) of the per-step phase bars.
PHASES = [("analysis_s", "analysis", "#9e9ac8"),
          ("assembly_s", "assembly", "#6baed6"),
          ("factorization_s", "factorization / PC set-up", "#fd8d3c"),
          ("solve_s", "solve", "#74c476"),
          ("line_search_s", "line search", "#f768a1"),
          ("other_s", "other", "#bdbdbd")]
MARKERS = "osD^vP*Xh<>p"
LINESTYLE = {"be": "-", "bdf2": "--"}
OK_C, FAIL_C, SOFT_C, NONE_C = "#7fc97f", "#ef6f6c", "#fdb863", "#e0e0e0"
DASH = "–"


# ---------------------------------------------------------------- reading ----
def read_rows(path):
    """Rows of the CSV as dicts of stripped strings; exits on a missing column."""
    with open(path, newline="", encoding="utf-8-sig") as f:
        reader = csv.DictReader(f)
        header = [h.strip() for h in (reader.fieldnames or [])]
        missing = [c for c in COLUMNS if c not in header]
        if missing:
            sys.exit(f"plot.py: error: {path} lacks column(s): {', '.join(missing)}")
        reader.fieldnames = header
        return [{k: (v or "").strip() for k, v in r.items() if k is not None}
                for r in reader]


def num(row, key):
    """The cell as a finite float, or None (empty, text, nan, inf)."""
    try:
        x = float(row.get(key, ""))
    except ValueError:
        return None
    return x if math.isfinite(x) else None


def pos(x):
    return x is not None and x > 0


def is_ok(row):
    return row["status"].lower() == "ok"


def steps(row):
    """Number of steps; falls back to end_time / dt when the cell is empty."""
    s, t, dt = num(row, "steps"), num(row, "end_time"), num(row, "dt")
    if pos(s):
        return s
    return max(1.0, round(t / dt)) if pos(t) and pos(dt) else None


def per_step(row, key):
    v, s = num(row, key), steps(row)
    return v / s if v is not None and s else None


def wall(row):
    """Wall time per step [s], from total_s / steps when the cell is empty."""
    w = num(row, "wall_per_step_s")
    return w if w is not None else per_step(row, "total_s")


def ratio(row):
    """Stiffness ratio; an empty cell means the base material (1)."""
    return num(row, "stiffness_ratio") or 1.0


def group(rows, key):
    """Rows grouped by key(row), groups in order of first appearance."""
    out = {}
    for r in rows:
        out.setdefault(key(r), []).append(r)
    return out


def sizes_of(rows):
    """Size labels sorted by dofs, e.g. "40x8x8, 80x16x16"."""
    d = {}
    for r in rows:
        d.setdefault(r["size"], num(r, "dofs") or 0)
    return ", ".join(s for s in sorted(d, key=lambda s: d[s]) if s) or "?"


def run_label(method, integ, multi):
    return f"{method} {integ}" if multi and integ else method


def stability_label(row, multi):
    """A stability panel: the method (and integrator), and the near-rigid cap
    β when the run set one (--near-rigid), so that capped runs get their own panel."""
    label = run_label(row["method"], row["integrator"], multi)
    beta = num(row, "near_rigid")
    return f"{label}, near-rigid β={beta:g}" if pos(beta) else label


# ------------------------------------------------------------- formatting ----
def fmt(x, digits=3):
    return DASH if x is None else f"{x:.{digits}g}"


def fmt_time(s):
    """Seconds as "12.3 ms" below one second, else "4.56 s"."""
    return DASH if s is None else f"{s * 1e3:.3g} ms" if abs(s) < 1 else f"{s:.3g} s"


def fmt_count(x):
    if x is None:
        return DASH
    for div, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if abs(x) >= div:
            return f"{x / div:.3g}{suffix}"
    return f"{x:.0f}"


def dt_label(dt):
    """dt as "1/60" when 1/dt is a whole number, otherwise 3 digits."""
    if not pos(dt):
        return DASH
    inv = 1.0 / dt
    if abs(inv - round(inv)) < 1e-6 * inv:
        return "1" if round(inv) == 1 else f"1/{round(inv)}"
    return f"{dt:.3g}"


def short_reason(reason):
    """Failure reason in a few characters: "DIVERGED_ITS", "Newton", ..."""
    low = reason.lower()
    if low.startswith("newton"):
        return "Newton"
    for needle, short in (("timeout", "timeout"), ("crash", "crashed"),
                          ("nonfinite", "non-finite"), ("non-finite", "non-finite")):
        if needle in low:
            return short
    # the last part's first word: "KSP_DIVERGED_ITS after 200 iterations, ..."
    tail = (reason.split(":")[-1].strip() or reason.strip() or "failed").split()[0]
    for prefix in ("KSP_", "PC_", "SNES_"):
        tail = tail[len(prefix):] if tail.startswith(prefix) else tail
    return tail[:19]


def save(fig, out, name, written):
    fig.savefig(os.path.join(out, name), dpi=120, bbox_inches="tight")
    plt.close(fig)
    written.append(name)


def panel_grid(n, w, h):
    ncols = 2 if n == 4 else min(n, 3)
    nrows = math.ceil(n / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(w * ncols, h * nrows),
                             squeeze=False)
    for ax in axes.flat[n:]:
        ax.axis("off")
    return fig, list(axes.flat[:n])


def log_axes(ax, plotted, title, xlabel, ylabel, legend_loc):
    """Log-log axes (a note instead when nothing was plotted), labels, grid."""
    if plotted:
        ax.set_xscale("log")
        ax.set_yscale("log")
    else:
        ax.text(0.5, 0.5, "no successful runs", ha="center", va="center",
                transform=ax.transAxes)
        ax.set(xticks=[], yticks=[])
    ax.set(title=title, xlabel=xlabel, ylabel=ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7.5, loc=legend_loc)


class PlainLogFormatter(matplotlib.ticker.LogFormatter):
    """Labels the ticks LogFormatter labels, as plain numbers ("30", "0.04")."""
    def __call__(self, x, pos=None):
        return f"{x:g}" if super().__call__(x, pos) else ""


# ----------------------------------------------------------------- charts ----
def pareto_front(points):
    """The non-dominated points of [(cost, error, ...)], sorted by cost: no
    other point is at most as costly and at most as wrong (and better in one).
    Sorted by cost (ties: error), a point is on the front when its error is
    below every error of a cheaper point."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p[0], p[1])):
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


def work_precision_panels(wp):
    """{(family, size, material): rows}: one panel per scene, since errors of
    different sizes or materials are measured against different references."""
    return group(wp, lambda r: (r["family"], r["size"], r["material"]))


def chart_work_precision(wp, out, style, written):
    """Per family, one panel per (size, material): error at the end time
    against wall time per simulated second (sim_cost: wall time per step / dt,
    which is the summed step time / simulated time, set-up excluded), one
    series per (method, integrator) with the points labelled by dt, and the
    Pareto front over every method, integrator and dt of the panel."""
    if not wp:
        print("skip work_precision_*.png: no work_precision rows")
        return
    for fam, fr in group(wp, lambda r: r["family"]).items():
        panels = work_precision_panels(fr)
        fig, axes = plt.subplots(len(panels), 1, figsize=(11, 6 * len(panels)), squeeze=False)
        for ax, ((_, size, material), pr) in zip(axes[:, 0], panels.items()):
            series = []  # (method, integrator, label, [(cost, error, dt)])
            for (method, integ), g in group(pr, lambda r: (r["method"], r["integrator"])).items():
                pts = sorted(((sim_cost(r), num(r, "error"), num(r, "dt")) for r in g
                              if is_ok(r) and pos(sim_cost(r)) and pos(num(r, "error"))),
                             key=lambda p: -p[2])  # along the series: dt falling
                nfail = sum(not is_ok(r) for r in g)
                series.append((method, integ,
                               f"{method} {integ}".strip() + (f" ({nfail} failed)" if nfail else ""),
                               pts))
            front = pareto_front([p for s in series for p in s[3]])
            on_front = set(front)
            for method, integ, label, pts in series:
                color, marker = style(method)
                ls = LINESTYLE.get(integ, ":")
                ax.plot([p[0] for p in pts], [p[1] for p in pts], ls, color=color, lw=1.2,
                        alpha=0.35)
                for faint in (True, False):  # dominated points faint, front points opaque
                    sel = [p for p in pts if (p not in on_front) == faint]
                    ax.plot([p[0] for p in sel], [p[1] for p in sel], ls="none", marker=marker,
                            color=color, ms=6, alpha=0.3 if faint else 1.0,
                            mec="black" if not faint else color, mew=0.8)
                ax.plot([], [], ls, marker=marker, color=color, label=label, ms=6, lw=1.2)
                if len(pr) <= 60:  # dt labels only while they stay readable
                    for p in pts:
                        ax.annotate(dt_label(p[2]), p[:2], textcoords="offset points",
                                    xytext=(4, 3), fontsize=6.5, color=color,
                                    alpha=1.0 if p in on_front else 0.45)
            if front:
                # the best error reachable within a budget: a step line through
                # the front, flat to the next cheaper-and-better point
                xs = [p[0] for p in front]
                ys = [p[1] for p in front]
                ax.plot(xs + [xs[-1] * 1.5], ys + [ys[-1]], color="black", lw=1.4,
                        drawstyle="steps-post", zorder=1,
                        label=f"Pareto front ({len(front)} of "
                              f"{sum(len(s[3]) for s in series)} runs; dominated runs faint)")
            dofs = num(pr[0], "dofs")
            end = num(pr[0], "end_time")
            log_axes(ax, bool(front),
                     f"Work–precision: {fam} {size}"
                     + (f" ({fmt_count(dofs)} DoFs, {material})" if dofs else f" ({material})")
                     + (f", error at t = {end:.3g} s" if end else "") + "; point labels = dt [s]",
                     "wall time per simulated second [s/s] = wall time per step / dt "
                     "(steps only, no set-up)",
                     "error: RMS node position vs reference / scene length [-]", "best")
            # outside the axes, so that it hides no point; handles long enough
            # to show the integrators' dashes
            ax.legend(fontsize=7.5, loc="upper left", bbox_to_anchor=(1.01, 1), handlelength=3.5)
            for axis in (ax.xaxis, ax.yaxis):  # 30 rather than 3×10¹ on a short log range
                axis.set_major_formatter(PlainLogFormatter(labelOnlyBase=False))
                axis.set_minor_formatter(PlainLogFormatter(labelOnlyBase=False,
                                                           minor_thresholds=(2, 0.5)))
        fig.tight_layout()
        save(fig, out, f"work_precision_{fam}.png", written)


def chart_scaling(sc, out, style, written):
    if not sc:
        print("skip scaling.png: no scaling rows")
        return
    fams = group(sc, lambda r: r["family"])
    fig, axes = panel_grid(len(fams), 6.5, 5)
    for ax, (fam, fr) in zip(axes, fams.items()):
        multi = len({r["integrator"] for r in fr}) > 1
        plotted = False
        for (method, integ), g in group(fr, lambda r: (r["method"], r["integrator"] if multi else "")).items():
            by_n = defaultdict(list)  # repeated runs of one size: median
            for r in g:
                if is_ok(r) and pos(num(r, "dofs")) and pos(wall(r)):
                    by_n[num(r, "dofs")].append(wall(r))
            ns = sorted(by_n)
            ts = [float(np.median(by_n[n])) for n in ns]
            label = run_label(method, integ, multi)
            if len(ns) >= 2:
                slope = np.polyfit(np.log(ns), np.log(ts), 1)[0]
                label += f" (slope {slope:.2f})"
            nfail = sum(not is_ok(r) for r in g)
            label += f" ({nfail} failed)" if nfail else ""
            color, marker = style(method)
            ax.plot(ns, ts, LINESTYLE.get(integ, "-"), marker=marker, color=color, label=label)
            plotted = plotted or bool(ns)
        log_axes(ax, plotted, f"{fam} ({sizes_of(fr)})", "degrees of freedom",
                 "wall time per step [s]", "upper left")
    fig.suptitle("Scaling: wall time per step vs problem size (slope of log t / log n)")
    fig.tight_layout()
    save(fig, out, "scaling.png", written)


def links(row):
    """N of a chain size label "N=50", or None."""
    size = row["size"]
    return int(size[2:]) if size.startswith("N=") and size[2:].isdigit() else None


def reached(row):
    """Simulated time the run reached [s]: steps done × dt."""
    s, dt = num(row, "steps"), num(row, "dt")
    return s * dt if s is not None and pos(dt) else 0.0


def sim_cost(row):
    """Wall time per simulated second of a run [s/s]."""
    w, dt = wall(row), num(row, "dt")
    return w / dt if pos(w) and pos(dt) else None


def chain_lines(ax, rows, key, value, style, label_of):
    """One line per key(row) of value(row) against N; failed rows left out of
    the line and counted in the label. True when anything was plotted."""
    plotted = False
    for k, g in group(rows, key).items():
        pts = sorted((links(r), value(r)) for r in g
                     if links(r) and value(r) is not None and value(r) > 0)
        nfail = sum(not is_ok(r) for r in g)
        color, marker, ls = style(k)
        label = label_of(k) + (f" ({nfail} failed)" if nfail else "")
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ls, color=color, marker=marker,
                label=label, ms=5)
        plotted = plotted or bool(pts)
    return plotted


def chart_chain(rows, out, style, written):
    chains = [r for r in rows if r["family"] in CHAINS and links(r)]
    sc = [r for r in chains if r["study"] == "scaling"]
    lr = [r for r in chains if r["study"] == "long_run"]
    if not sc and not lr:
        print("skip chain.png: no scaling or long_run rows of the chain families")
        return
    dts = sorted({num(r, "dt") for r in lr if pos(num(r, "dt"))}, reverse=True)
    dt_colors = {dt: plt.get_cmap("viridis")(i / max(1, len(dts) - 1) * 0.85)
                 for i, dt in enumerate(dts)}

    def method_style(k):
        color, marker = style(k[1])
        return color, marker, CHAINS[k[0]]

    def dt_style(k):
        return dt_colors[num({"dt": k[1]}, "dt")], "o" if k[0] == "chain" else "s", CHAINS[k[0]]

    by_method = lambda r: (r["family"], r["method"])  # noqa: E731
    by_dt = lambda r: (r["family"], r["dt"])  # noqa: E731
    method_label = lambda k: f"{k[0]} {k[1]}"  # noqa: E731
    dt_label_of = lambda k: f"{k[0]} dt={dt_label(num({'dt': k[1]}, 'dt'))}"  # noqa: E731
    end = max((num(r, "end_time") or 0 for r in lr), default=0)
    fig, axes = plt.subplots(2, 3, figsize=(19, 10.5))
    (a, b, c), (d, e, f) = axes
    p = chain_lines(a, [r for r in sc if is_ok(r)], by_method,
                    lambda r: (wall(r) or 0) / links(r) * 1e6, method_style, method_label)
    log_axes(a, p, "cost per link per step (scaling runs)", "links N", "wall time / (N · steps) [µs]",
             "upper left")
    fastest = {}  # (family, N) -> the scaling run of the fastest method
    for r in sc:
        if is_ok(r) and pos(wall(r)):
            k = (r["family"], links(r))
            if k not in fastest or wall(r) < wall(fastest[k]):
                fastest[k] = r
    p = chain_lines(b, list(fastest.values()), lambda r: r["family"],
                    lambda r: wall(r) / links(r) * 1e6,
                    lambda k: ("black", "o" if k == "chain" else "s", CHAINS[k]), lambda k: k)
    for r in fastest.values():
        b.annotate(r["method"], (links(r), wall(r) / links(r) * 1e6), textcoords="offset points",
                   xytext=(4, 3), fontsize=7)
    b.axhspan(*REFERENCE_ENGINES_US, color="#fdb863", alpha=0.5,
              label="explicit reduced-coordinate engines (measured for reference)")
    log_axes(b, p, "fastest method per N: cost per link per step", "links N",
             "wall time / (N · steps) [µs]", "upper left")
    p = chain_lines(c, lr, by_dt, lambda r: reached(r), dt_style, dt_label_of)
    log_axes(c, p, f"long runs: simulated time reached of {end:g} s (failed: Newton stalled)",
             "links N", "time reached [s]", "lower left")
    # a fixed range: when every run reaches the end the values differ only by
    # the rounding of steps × dt, which an autoscaled log axis would magnify
    shortest = min([reached(r) for r in lr if reached(r) > 0] + [end])
    c.set_ylim(min(0.5 * shortest, 0.1 * end), 1.5 * end)
    p = chain_lines(d, lr, by_dt, lambda r: num(r, "joint_drift"), dt_style, dt_label_of)
    log_axes(d, p, "long runs: largest joint drift (distance of the joint's two points)",
             "links N", "joint drift [m]", "center left")
    p = chain_lines(e, lr, by_dt, lambda r: per_step(r, "newton_iterations"), dt_style, dt_label_of)
    log_axes(e, p, "long runs: Newton iterations per step", "links N", "Newton iterations / step",
             "upper left")
    best = {}  # (family, N) -> the surviving long run of the largest dt
    for r in lr:
        if is_ok(r) and pos(num(r, "dt")):
            k = (r["family"], links(r))
            if k not in best or num(r, "dt") > num(best[k], "dt"):
                best[k] = r
    p = chain_lines(f, list(best.values()), lambda r: r["family"], sim_cost,
                    lambda k: ("black", "o" if k == "chain" else "s", CHAINS[k]), lambda k: k)
    for r in best.values():
        f.annotate(dt_label(num(r, "dt")), (links(r), sim_cost(r)), textcoords="offset points",
                   xytext=(4, 3), fontsize=7)
    log_axes(f, p, "cost per simulated second at the largest dt that survived (labels: dt)",
             "links N", "wall time / simulated time [s/s]", "upper left")
    for ax in (e,):  # iteration counts: plain numbers on the log axis
        ax.yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
        ax.yaxis.set_minor_formatter(matplotlib.ticker.ScalarFormatter())
    fig.suptitle("The chain built both ways: rigid bodies + compliant spherical joints "
                 "(solid) vs one articulated actor with exact joints (dashed)")
    fig.tight_layout()
    save(fig, out, "chain.png", written)


def stability_cells(g, dts, ratios):
    """{(i, j): row} for a panel; a failed run wins over an ok one in a cell."""
    cells = {}
    for r in g:
        dt = num(r, "dt")
        if dt not in dts:
            continue
        key = (ratios.index(ratio(r)), dts.index(dt))
        if key not in cells or is_ok(cells[key]):
            cells[key] = r
    return cells


def chart_stability(st, out, written):
    if not st:
        print("skip stability_*.png: no stability rows")
        return
    for fam, fr in group(st, lambda r: r["family"]).items():
        multi = len({r["integrator"] for r in fr}) > 1
        panels = group(fr, lambda r: stability_label(r, multi))
        dts = sorted({num(r, "dt") for r in fr if num(r, "dt") is not None})
        ratios = sorted({ratio(r) for r in fr})
        fig, axes = panel_grid(len(panels), max(3.8, 1.0 * len(dts) + 1.8),
                               max(2.8, 0.65 * len(ratios) + 1.6))
        for ax, (label, g) in zip(axes, panels.items()):
            img = np.full((len(ratios), max(1, len(dts)), 3), matplotlib.colors.to_rgb(NONE_C))
            for (i, j), r in stability_cells(g, dts, ratios).items():
                if is_ok(r):
                    its = per_step(r, "newton_iterations")
                    text, c = "ok" + (f"\n{its:.1f} it" if its is not None else ""), OK_C
                else:
                    text = short_reason(r["reason"])  # timeout / crash: orange
                    c = SOFT_C if text in ("timeout", "crashed") else FAIL_C
                img[i, j] = matplotlib.colors.to_rgb(c)
                ax.text(j, i, text, ha="center", va="center", fontsize=7)
            ax.imshow(img, origin="lower", aspect="auto")
            ax.set_xticks(range(len(dts)), [dt_label(d) for d in dts])
            ax.set_yticks(range(len(ratios)), [f"{k:g}" for k in ratios])
            ax.set_xticks(np.arange(-0.5, len(dts)), minor=True)
            ax.set_yticks(np.arange(-0.5, len(ratios)), minor=True)
            ax.grid(which="minor", color="white", lw=2)
            ax.tick_params(which="minor", length=0)
            ax.set_xlabel("time step dt [s]")
            ax.set_ylabel("stiffness ratio")
            ax.set_title(label, fontsize=10)
        fig.suptitle(f"Stability: {fam} ({sizes_of(fr)})")
        fig.legend(handles=[Patch(color=OK_C, label="ok (Newton its/step)"),
                            Patch(color=FAIL_C, label="failed"),
                            Patch(color=SOFT_C, label="timeout / crashed"),
                            Patch(color=NONE_C, label="not run")],
                   loc="lower center", ncol=4, fontsize=8, bbox_to_anchor=(0.5, -0.02))
        fig.tight_layout(rect=(0, 0.05, 1, 1))
        save(fig, out, f"stability_{fam}.png", written)


def phase_panels(sc):
    """[(family, size, [(label, [phase s/step], wall s/step, ok)])]: per family
    the largest size of the scaling study, one bar per method (ok run first)."""
    panels = []
    for fam, fr in group(sc, lambda r: r["family"]).items():
        fr = [r for r in fr if num(r, "dofs") is not None and steps(r)]
        if not fr:
            continue
        big = max(num(r, "dofs") for r in fr)
        fr = [r for r in fr if num(r, "dofs") == big]
        multi = len({r["integrator"] for r in fr}) > 1
        bars = []
        for label, g in group(fr, lambda r: run_label(r["method"], r["integrator"], multi)).items():
            r = sorted(g, key=lambda r: not is_ok(r))[0]
            parts = [per_step(r, col) or 0.0 for col, _, _ in PHASES]
            bars.append((label, parts, wall(r), is_ok(r)))
        panels.append((fam, fr[0]["size"] or f"{big:.0f} dofs", bars))
    return panels


def chart_phases(sc, out, written):
    panels = phase_panels(sc)
    if not panels:
        print("skip phases.png: no scaling rows with dofs and steps")
        return
    heights = [0.45 * len(b) + 1.4 for _, _, b in panels]
    fig, axes = plt.subplots(len(panels), 1, figsize=(10, sum(heights) + 0.8),
                             squeeze=False, gridspec_kw={"height_ratios": heights})
    for ax, (fam, size, bars) in zip(axes[:, 0], panels):
        top = max([sum(p) for _, p, _, _ in bars] + [w or 0 for _, _, w, _ in bars])
        scale, unit = (1e3, "ms") if top < 1 else (1.0, "s")
        y = np.arange(len(bars))
        left = np.zeros(len(bars))
        for k, (_, name, color) in enumerate(PHASES):
            widths = np.array([p[k] for _, p, _, _ in bars]) * scale
            ax.barh(y, widths, left=left, color=color, label=name, height=0.65)
            left += widths
        for yi, (_, parts, w, ok) in zip(y, bars):
            total = w if w is not None else (sum(parts) or None)
            ax.text(max(left[yi], (total or 0) * scale) + top * scale * 0.01, yi,
                    (fmt_time(total) if total else "no timing") + ("" if ok else " [failed]"),
                    va="center", fontsize=8)
        ax.set_yticks(y, [b[0] for b in bars])
        ax.invert_yaxis()
        ax.set_xlim(0, top * scale * 1.22 if top > 0 else 1)
        ax.set_xlabel(f"time per step [{unit}]")
        ax.set_title(f"{fam} ({size}): time per step by phase", fontsize=10)
        ax.grid(True, axis="x", alpha=0.3)
    axes[0, 0].legend(fontsize=8, ncol=3, loc="lower left", bbox_to_anchor=(0, 1.12))
    fig.tight_layout()
    save(fig, out, "phases.png", written)


def contact_rows(rows):
    """The contact families' scaling and pattern-policy rows."""
    return [r for r in rows if r["family"].startswith("contact-") and r["study"] in CONTACT_STUDIES]


def contact_shares(r):
    """(collision detection, contact assembly, analysis) as shares of the
    run's step time (wall per step × steps), or None without timings."""
    w, s = wall(r), steps(r)
    if not (pos(w) and s):
        return None
    total = w * s
    detect = sum(num(r, k) or 0.0 for k in ("broad_phase_s", "narrow_phase_s", "ccd_s"))
    return (detect / total, (num(r, "contact_assembly_s") or 0.0) / total,
            (num(r, "analysis_s") or 0.0) / total)


def chart_contact(rows, out, style, written):
    cr = [r for r in contact_rows(rows) if is_ok(r)]
    if not cr:
        print("skip contact.png: no ok rows of the contact families")
        return
    fig, axes = plt.subplots(1, 3, figsize=(19, 5.2))
    lines = group(cr, lambda r: (r["family"], r["pattern_policy"] or "reserve"))
    for k, ((fam, policy), g) in enumerate(sorted(lines.items())):
        color, marker = style(fam)
        dash = "--" if policy == "rebuild" else "-"
        label = fam + (" (rebuild on change)" if policy == "rebuild" else "")
        pts = sorted((num(r, "dofs"), wall(r), num(r, "active_contacts")) for r in g
                     if pos(num(r, "dofs")) and pos(wall(r)))
        if pts:
            axes[0].plot([p[0] for p in pts], [p[1] for p in pts], dash, marker=marker,
                         color=color, label=label)
        by_c = sorted((p[2], p[1]) for p in pts if pos(p[2]))
        if by_c:
            axes[1].plot([c for c, _ in by_c], [t for _, t in by_c], dash, marker=marker,
                         color=color, label=label)
        if policy == "rebuild":
            continue
        sh = sorted((num(r, "dofs"), contact_shares(r)) for r in g if pos(num(r, "dofs")))
        sh = [(n, x) for n, x in sh if x]
        for j, (name, ls) in enumerate((("detection", "-"), ("contact assembly", ":"),
                                        ("analysis", "-."))):
            if sh:
                axes[2].plot([n for n, _ in sh], [100 * x[j] for _, x in sh], ls, marker=marker,
                             color=color, label=f"{fam}: {name}")
    log_axes(axes[0], True, "time per step against size", "degrees of freedom",
             "wall time per step [s]", "upper left")
    log_axes(axes[1], True, "time per step against active contacts",
             "active contacts (last step)", "wall time per step [s]", "upper left")
    ax = axes[2]
    ax.set_xscale("log")
    ax.axhline(15, color="k", lw=0.8, ls="--")
    ax.text(0.01, 15, " 15 %", transform=ax.get_yaxis_transform(), va="bottom", fontsize=8)
    ax.set(title="share of the step", xlabel="degrees of freedom", ylabel="% of the step time",
           ylim=(0, 100))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6.5, loc="upper right", ncol=2)
    fig.suptitle("Contact families: cost per step, and where it goes")
    fig.tight_layout()
    save(fig, out, "contact.png", written)


def contact_row(r):
    sh = contact_shares(r)
    pct = lambda k: DASH if sh is None else f"{100 * sh[k]:.3g} %"  # noqa: E731
    return [r["family"], r["size"], fmt_count(num(r, "dofs")), r["study"], r["pattern_policy"] or "reserve",
            dt_label(num(r, "dt")), fmt_count(steps(r)), fmt_time(wall(r)),
            fmt(per_step(r, "newton_iterations")), fmt_count(num(r, "active_contacts")),
            fmt_count(num(r, "contact_candidates")), pct(0), pct(1), pct(2),
            fmt_count(num(r, "contact_pattern_builds")), fmt(num(r, "min_gap")),
            fmt_count(num(r, "interpenetrations")), fmt(num(r, "creep_um_per_s")), status_text(r)]


# ---------------------------------------------------------------- summary ----
def table(header, body):
    esc = lambda c: str(c).replace("|", "\\|") or DASH  # noqa: E731
    return (["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
            + ["| " + " | ".join(esc(c) for c in r) + " |" for r in body] + [""])


def status_text(r):
    return "ok" if is_ok(r) else f"{r['status'] or '?'}: {r['reason']}".rstrip(": ")


def scaling_row(r):
    its, lin = per_step(r, "newton_iterations"), per_step(r, "linear_iterations")
    flops, fact, newton = num(r, "factor_flops"), num(r, "factorization_s"), num(r, "newton_iterations")
    gflops = (flops * newton / fact / 1e9 if r["method"].split("-")[0] == "cholmod"
              and flops is not None and newton is not None and pos(fact) else None)
    asm, w, s = num(r, "assembly_s"), wall(r), steps(r)
    share = 100 * asm / (w * s) if asm is not None and pos(w) and s else None
    return [r["size"], fmt_count(num(r, "dofs")), r["method"], r["integrator"],
            fmt_time(w), fmt(its), fmt(lin), fmt_count(num(r, "nnz_l")),
            fmt(num(r, "peak_rss_mb")), fmt(gflops),
            DASH if share is None else f"{share:.3g} %", status_text(r)]


def long_run_row(r):
    """A long run's table row; the per-step figures only when a step was done."""
    w = wall(r) if pos(num(r, "steps")) else None
    return [r["family"], r["size"], r["method"], dt_label(num(r, "dt")),
            f"{reached(r):.3g} / {num(r, 'end_time') or 0:g} s",
            fmt(per_step(r, "newton_iterations")), fmt_time(w),
            fmt(w / links(r) * 1e6 if pos(w) and links(r) else None),
            fmt(sim_cost(r) if pos(w) else None), fmt(num(r, "joint_drift")),
            fmt(num(r, "energy_gain")), status_text(r)]


def summary(rows, out, written):
    ok = sum(map(is_ok, rows))
    suites = sorted({r["suite"] for r in rows if r["suite"]}) or ["(unnamed)"]
    studies = group(rows, lambda r: r["study"])
    L = [f"# Perf results: {', '.join(suites)}", "",
         f"{len(rows)} rows ({ok} ok, {len(rows) - ok} failed); studies: "
         + (", ".join(f"{k or '?'} {len(v)}" for k, v in studies.items()) or "none"), ""]
    L += [f"![{f}]({f})" for f in written if f.endswith(".png")] + [""]
    if studies.get("scaling"):
        L += ["## Scaling", ""]
        for fam, fr in group(studies["scaling"], lambda r: r["family"]).items():
            fr = sorted(fr, key=lambda r: (num(r, "dofs") or 0, r["method"]))
            L += [f"### {fam}", ""] + table(
                ["size", "dofs", "method", "integrator", "time/step", "Newton its/step",
                 "linear its/step", "nnz(L)", "peak MB", "factor GFLOP/s",
                 "assembly share", "status"], [scaling_row(r) for r in fr])
    if studies.get("work_precision"):
        L += ["## Work–precision", ""]
        L += ["Cost: time/step is the summed step wall time / steps; wall/simulated s is "
              "time/step / dt, the cost of simulating one second (set-up excluded), on which "
              "the Pareto front (●: no other run of the table is both cheaper and more "
              "accurate) is taken.", ""]
        for (fam, size, material), fr in work_precision_panels(studies["work_precision"]).items():
            front = {id(p[2]) for p in pareto_front(
                [(sim_cost(r), num(r, "error"), r) for r in fr
                 if is_ok(r) and pos(sim_cost(r)) and pos(num(r, "error"))])}
            fr = sorted(fr, key=lambda r: (r["method"], r["integrator"], -(num(r, "dt") or 0)))
            L += [f"### {fam} {size} ({fmt_count(num(fr[0], 'dofs'))} DoFs, {material})", ""] + table(
                ["method", "integrator", "dt", "rtol", "Newton tol", "error", "time/step",
                 "wall/simulated s [s/s]", "Pareto", "status"],
                [[r["method"], r["integrator"], dt_label(num(r, "dt")), r["rtol"],
                  r["newton_tol"], fmt(num(r, "error")), fmt_time(wall(r)),
                  fmt(sim_cost(r)), "●" if id(r) in front else "", status_text(r)]
                 for r in fr])
    if studies.get("stability"):
        L += ["## Stability", "", "Cells: `ok` with Newton its/step, the failure reason, or – (not run).", ""]
        for fam, fr in group(studies["stability"], lambda r: r["family"]).items():
            multi = len({r["integrator"] for r in fr}) > 1
            dts = sorted({num(r, "dt") for r in fr if num(r, "dt") is not None})
            ratios = sorted({ratio(r) for r in fr})
            for label, g in group(fr, lambda r: stability_label(r, multi)).items():
                cells = stability_cells(g, dts, ratios)
                body = []
                for i, k in enumerate(ratios):
                    line = [f"{k:g}"]
                    for j in range(len(dts)):
                        r = cells.get((i, j))
                        its = per_step(r, "newton_iterations") if r else None
                        line.append("" if r is None else "**" + short_reason(r["reason"]) + "**"
                                    if not is_ok(r) else "ok" if its is None else f"ok {its:.2g}")
                    body.append(line)
                L += [f"### {fam} ({sizes_of(g)}), {label}", ""] + table(
                    ["stiffness \\ dt"] + [dt_label(d) for d in dts], body)
    if studies.get("long_run"):
        L += ["## Long runs", "", "Time reached of the planned end time; joint drift and energy gain "
              "are the largest over the run (energy gain: mechanical energy above the initial, "
              "over total mass · g · L).", ""]
        fr = sorted(studies["long_run"], key=lambda r: (r["family"], num(r, "dofs") or 0, -(num(r, "dt") or 0)))
        L += table(["family", "size", "method", "dt", "reached", "Newton its/step", "time/step",
                    "µs/link/step", "wall/simulated s", "joint drift [m]", "energy gain", "status"],
                   [long_run_row(r) for r in fr])
    if contact_rows(rows):
        L += ["## Contact", "", "The contact families' scaling and pattern-policy runs (CHOLMOD). "
              "Shares of the step time: detection = broad + narrow phase + CCD; contact "
              "assembly; the pattern's analysis. Active contacts and candidates at the last "
              "step; min gap and interpenetrations from the exact check; creep [µm/s] of the "
              "resting bodies from halfway to the end.", ""]
        cr = sorted(contact_rows(rows), key=lambda r: (r["family"], num(r, "dofs") or 0,
                                                       r["pattern_policy"], r["study"]))
        L += table(["family", "size", "dofs", "study", "pattern", "dt", "steps", "time/step",
                    "Newton its/step", "active", "candidates", "detection", "contact assembly",
                    "analysis", "contact pattern builds", "min gap [m]", "interpenetrations",
                    "creep [µm/s]", "status"], [contact_row(r) for r in cr])
    for name, title in (("bullet", "Bullet comparisons"), ("reference", "Reference runs")):
        if studies.get(name):
            L += [f"## {title}", ""] + table(
                ["family", "size", "dofs", "method", "integrator", "dt", "steps", "time/step",
                 "total", "error", "status"],
                [[r["family"], r["size"], fmt_count(num(r, "dofs")), r["method"], r["integrator"],
                  dt_label(num(r, "dt")), fmt_count(steps(r)), fmt_time(wall(r)),
                  fmt_time(num(r, "total_s")), fmt(num(r, "error")), status_text(r)]
                 for r in studies[name]])
    failed = [r for r in rows if not is_ok(r)]
    L += ["## Failed runs", ""] + ([
        "- " + " ".join(x for x in (r["study"], "/", r["family"], r["size"], "/", r["method"],
                                    r["integrator"]) if x)
        + (f" dt={dt_label(num(r, 'dt'))}" if pos(num(r, "dt")) else "")
        + (f" stiffness={r['stiffness_ratio']}" if r["stiffness_ratio"] else "")
        + f": {r['reason'] or r['status'] or '?'}" for r in failed] or ["none"]) + [""]
    with open(os.path.join(out, "summary.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(L))
    written.append("summary.md")


# ------------------------------------------------------------------- main ----
def main(argv):
    if len(argv) != 2:
        sys.exit("usage: plot.py OUT_DIR   (reads OUT_DIR/results.csv)")
    out = argv[1]
    path = os.path.join(out, "results.csv")
    if not os.path.isfile(path):
        sys.exit(f"plot.py: error: {path} not found")
    rows = read_rows(path)
    # One colour and marker per method, the same in every chart.
    methods = sorted({r["method"] for r in rows})
    cmap = plt.get_cmap("tab10" if len(methods) <= 10 else "tab20")
    styles = {m: (cmap(i % cmap.N), MARKERS[i % len(MARKERS)]) for i, m in enumerate(methods)}
    contact_families = sorted({r["family"] for r in contact_rows(rows)})
    family_styles = {f: (plt.get_cmap("tab10")(i % 10), MARKERS[i % len(MARKERS)])
                     for i, f in enumerate(contact_families)}
    studies = group(rows, lambda r: r["study"])
    wp, sc, st = (studies.get(k, []) for k in ("work_precision", "scaling", "stability"))
    written, broken = [], []
    charts = [lambda: chart_work_precision(wp, out, styles.get, written),
              lambda: chart_scaling(sc, out, styles.get, written),
              lambda: chart_stability(st, out, written),
              lambda: chart_phases(sc, out, written),
              lambda: chart_chain(rows, out, styles.get, written),
              lambda: chart_contact(rows, out, family_styles.get, written)]
    for name, chart in zip(("work_precision", "scaling", "stability", "phases", "chain", "contact"),
                           charts):
        try:
            chart()
        except Exception:  # one broken chart must not stop the others
            traceback.print_exc()
            broken.append(name)
            plt.close("all")
    summary(rows, out, written)
    print("wrote:\n" + "\n".join("  " + os.path.join(out, f) for f in written))
    if broken:
        sys.exit(f"plot.py: error: chart(s) failed: {', '.join(broken)}")


if __name__ == "__main__":
    main(sys.argv)
