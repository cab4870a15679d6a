"""perf/peers: the markdown tables of a peers.csv (run.sh).

    /usr/bin/python3 perf/peers/table.py OUT_DIR/peers.csv > OUT_DIR/peers.md

One table per scene: a row per engine and dt (in the CSV's order), a column
per metric, then the wall time per simulated second. A failed run shows
"failed" and its reason under the table. The notes (each engine's settings)
are listed once at the end.
"""

import csv
import sys

SCENES = {
    "incline_stick": "Incline, tan θ = 0.49 (μ = 0.5: must stick); creep over t ∈ [1, 5] s, + = down the slope",
    "incline_slide": "Incline, tan θ = 0.51 (slides at g (sin θ − μ cos θ) = 0.0874 m/s²); fit over t ∈ [1, 3] s",
    "box_stack": "Stack of 5 boxes (0.2 m, 1 kg, μ = 0.5) on the ground, 10 s",
    "fast_box": "A 0.1 m box at 20 m/s onto a 5 mm plate, 0.5 s",
}


def rate(dt):
    """1/60 for 0.0166667."""
    value = float(dt)
    return f"1/{round(1 / value)}" if value > 0 else dt


def cell(metric, value):
    """A metric's value as the table shows it."""
    v = float(value)
    if metric in ("toppled", "tunnelled"):
        return "yes" if v else "no"
    if metric == "creep_um_per_s":
        return f"{v:.3g}"
    if metric == "acceleration_rel_error":
        # to 0.1 %, or its size where it is below that (an exact solver's)
        return f"{100 * v:+.1f} %" if abs(v) >= 1e-3 or v == 0 else f"{100 * v:+.0e} %"
    return f"{v:.3g}"


def main(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    notes = {}
    out = []
    for scene, title in SCENES.items():
        runs = {}  # (engine, dt) -> {metric: value}, in the CSV's order
        wall = {}
        failures = []
        metrics = []
        for r in rows:
            if r["scene"] != scene:
                continue
            key = (r["engine"], r["dt"])
            notes.setdefault(r["engine"], r["note"].split("; step ")[0])
            runs.setdefault(key, {})[r["metric"]] = r["value"]
            wall[key] = float(r["wall_per_sim_s"])
            if r["metric"] == "failed":
                failures.append(f"{r['engine']} at dt {rate(r['dt'])}: {r['note']}")
            elif r["metric"] not in metrics:
                metrics.append(r["metric"])
        if not runs:
            continue
        out.append(f"### {title}\n")
        out.append("| engine | dt | " + " | ".join(metrics) + " | wall s / sim s |")
        out.append("|---|---|" + "---:|" * (len(metrics) + 1))
        for (engine, dt), values in runs.items():
            if "failed" in values:
                cells = ["failed"] + [""] * (len(metrics) - 1)
            else:
                cells = [cell(m, values[m]) if m in values else "" for m in metrics]
            out.append(f"| {engine} | {rate(dt)} | " + " | ".join(cells) + f" | {wall[(engine, dt)]:.3g} |")
        out.append("")
        for failure in failures:
            out.append(f"- failed: {failure}")
        if failures:
            out.append("")
    out.append("### Settings\n")
    for engine, note in notes.items():
        out.append(f"- **{engine}**: {note}")
    print("\n".join(out))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
