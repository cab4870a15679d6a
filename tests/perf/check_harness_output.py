"""Checks a perf harness output folder after `superdex_perf --suite tiny` and
`plot.py`: the CSV has exactly the documented columns in order, at least one
row per study and a scaling row per family, every run of the tiny suite
succeeded (except stability cells, whose failures are data), the JSON has one
object per CSV row, and every chart is a non-empty PNG.

usage: check_harness_output.py OUT_DIR
"""
import csv
import json
import sys
from pathlib import Path

COLUMNS = (
    "suite study family size dofs material stiffness_ratio method solver preconditioner rtol "
    "newton_tol constraint_hessian near_rigid integrator dt steps end_time newton_iterations linear_iterations "
    "linear_solves truncated_solves factorizations reused_solves near_rigid_capped pattern_builds symbolic_analyses solver_object_builds nnz_h nnz_l factor_flops analysis_s "
    "ordering_s pattern_s slot_tables_s symbolic_s assembly_s factorization_s solve_s line_search_s other_s wall_per_step_s steady_per_step_s total_s "
    "ranks owned_dofs peak_rss_mb scene_rss_mb error reference joint_drift energy_gain state_hash "
    "contact_candidates active_contacts min_contact_distance contact_pattern_builds pattern_policy broad_phase_s narrow_phase_s "
    "ccd_s contact_assembly_s penetration_checks interpenetrations min_gap creep_um_per_s status reason"
).split()
STUDIES = ("scaling", "work_precision", "stability", "bullet", "reference", "long_run", "pattern_policy")
# every family of the harness (perf/harness/families.cc) has scaling runs in the tiny suite
FAMILIES = ("cantilever", "cloth", "chain", "rods", "chain-articulated", "chain-articulated-dense",
            "contact-cloth", "contact-solids", "contact-rigid", "contact-rods", "contact-grasp")
CONTACT_FAMILIES = tuple(f for f in FAMILIES if f.startswith("contact-"))
CONTACT_TIMES = ("broad_phase_s", "narrow_phase_s", "ccd_s", "contact_assembly_s")
CHARTS = ("scaling.png", "phases.png", "work_precision_cantilever.png", "stability_cantilever.png",
          "chain.png", "contact.png")
# joint drift [m]: the articulated chain's joints are exact (drift at round-off
# of the 0.1 m links); the rigid chain's compliant joints (1e6 N/m, ~1e-3 N·s²
# links) give way by ~1e-5 m and more under their own weight
EXACT_JOINT_DRIFT_MAX = 1e-12
COMPLIANT_JOINT_DRIFT_MIN = 1e-7
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def fail(message):
    print(f"check_harness_output: FAILED: {message}")
    sys.exit(1)


def main():
    if len(sys.argv) != 2:
        fail("usage: check_harness_output.py OUT_DIR")
    out = Path(sys.argv[1])

    # the CSV: exact columns, rows of every study, every non-stability run ok
    with open(out / "results.csv", newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [dict(zip(header, r)) for r in reader]
    if header != COLUMNS:
        missing = [c for c in COLUMNS if c not in header]
        extra = [c for c in header if c not in COLUMNS]
        fail(f"CSV columns differ: missing {missing}, extra {extra}, order {header}")
    for study in STUDIES:
        if not any(r["study"] == study for r in rows):
            fail(f"no row of study '{study}'")
    for family in FAMILIES:
        if not any(r["study"] == "scaling" and r["family"] == family for r in rows):
            fail(f"no scaling row of family '{family}'")
    for r in rows:
        # (stability maps chart where methods fail; every other run must succeed,
        # the 3-s long runs included)
        if r["study"] != "stability" and r["status"] != "ok":
            fail(f"run failed: {r['family']} {r['size']} {r['method']}: {r['reason']}")
        if r["status"] == "ok" and not float(r["wall_per_step_s"]) > 0:
            fail(f"run without a time: {r}")
        # the steady cost leaves out only the one-time analysis
        if r["status"] == "ok" and not (
                0 < float(r["steady_per_step_s"]) <= float(r["wall_per_step_s"])
                and abs(float(r["steady_per_step_s"]) * float(r["steps"]) + float(r["analysis_s"])
                        - float(r["wall_per_step_s"]) * float(r["steps"]))
                <= 1e-4 * float(r["total_s"]) + 1e-6 * float(r["steps"])):
            fail(f"steady_per_step_s is not the step time without the analysis: {r}")
    # the chain families carry the mechanism columns: exact joints stay at
    # round-off, compliant ones drift, and neither gains energy
    for r in rows:
        if r["family"] not in ("chain", "chain-articulated", "chain-articulated-dense") or r["status"] != "ok":
            continue
        drift, gain = float(r["joint_drift"]), float(r["energy_gain"])
        if r["family"].startswith("chain-articulated") and not drift <= EXACT_JOINT_DRIFT_MAX:
            fail(f"articulated chain joint drift {drift} m in {r['study']} {r['size']}")
        if r["family"] == "chain" and not drift >= COMPLIANT_JOINT_DRIFT_MIN:
            fail(f"rigid chain joint drift {drift} m in {r['study']} {r['size']}: implausibly small")
        if not gain <= 1e-6:
            fail(f"{r['family']} {r['size']} gained energy: {gain}")
    # the contact families carry the contact columns: the exact test ran
    # (at the last step at least) and found nothing, the phase times are
    # parts of the step, and a scene with bodies at rest reports its creep
    for r in rows:
        if r["family"] not in CONTACT_FAMILIES or r["status"] != "ok":
            continue
        if not (int(r["penetration_checks"]) >= 1 and int(r["interpenetrations"]) == 0):
            fail(f"{r['family']} {r['size']}: exact interpenetration test not run or failed: {r}")
        times = [float(r[c]) for c in CONTACT_TIMES]
        if not all(t >= 0 for t in times) or not sum(times) <= float(r["wall_per_step_s"]) * int(r["steps"]):
            fail(f"{r['family']} {r['size']}: contact phase times {times} not within the steps' time")
        if not int(r["contact_candidates"]) >= 0 or (r["family"] in ("contact-rigid", "contact-solids", "contact-grasp")
                                                     and r["creep_um_per_s"] == ""):
            fail(f"{r['family']} {r['size']}: contact figures missing: {r}")
    # the pattern policies: one run of each per family and size in the
    # pattern_policy study, every other run with the default
    for r in rows:
        if r["pattern_policy"] not in ("reserve", "rebuild") or (
                r["study"] != "pattern_policy" and r["pattern_policy"] != "reserve"):
            fail(f"{r['family']} {r['size']}: pattern policy '{r['pattern_policy']}' in study {r['study']}")
    policy_runs = {}
    for r in rows:
        if r["study"] == "pattern_policy":
            policy_runs.setdefault((r["family"], r["size"]), set()).add(r["pattern_policy"])
    if not policy_runs or any(p != {"reserve", "rebuild"} for p in policy_runs.values()):
        fail(f"the pattern_policy study does not run both policies per scene: {policy_runs}")
    for r in rows:
        if r["family"] not in CONTACT_FAMILIES and any(r[c] for c in CONTACT_TIMES):
            fail(f"{r['family']} {r['size']} has contact columns")
    for family in ("chain", "chain-articulated"):
        if not any(r["study"] == "long_run" and r["family"] == family for r in rows):
            fail(f"no long_run row of family '{family}'")
    # work-precision rows carry an error against their reference
    for r in rows:
        if r["study"] == "work_precision" and not float(r["error"]) > 0:
            fail(f"work-precision run without an error: {r['method']} dt {r['dt']}")

    # the JSON: the same runs
    runs = json.loads((out / "results.json").read_text())
    if len(runs) != len(rows) or set(runs[0]) != set(COLUMNS):
        fail(f"results.json has {len(runs)} runs for {len(rows)} CSV rows, or other keys")

    # the charts and the summary
    for chart in CHARTS:
        path = out / chart
        if not path.is_file():
            fail(f"{chart} was not written")
        data = path.read_bytes()
        if not data.startswith(PNG_SIGNATURE) or len(data) < 5000:
            fail(f"{chart} is not a non-empty PNG ({len(data)} bytes)")
    summary = (out / "summary.md").read_text()
    if "|" not in summary:
        fail("summary.md has no table")
    print(f"check_harness_output: {len(rows)} runs, {len(CHARTS)} charts and summary.md ok")


if __name__ == "__main__":
    main()
