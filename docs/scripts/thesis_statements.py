#!/usr/bin/env python3
"""The thesis' statements of chapters 3-4 (docs/statistics.md) checked against a gathered sweep.

    python3 docs/scripts/thesis_statements.py results/thesis-ch3
    python3 docs/scripts/thesis_statements.py results/thesis-ch4-dilute --dilute
    python3 docs/scripts/thesis_statements.py results/thesis-ch4-dense --dense
    python3 docs/scripts/thesis_statements.py results/thesis-ch4-dense --grid
    python3 docs/scripts/thesis_statements.py sweeps/thesis-ch3.ron --readings [--dilute]

Reads the sweep's Parquet tables with DuckDB (pip install duckdb) and prints, per statement of
the thesis' chapter 3 (default) or 4.1 (`--dilute`), a Markdown row: section, the thesis'
words, the literal reading as a test on the tables, the averaging it uses, what granflow
measured and the verdict (yes, partly, no, not measured), then the summary line (rows, yes,
partly, no, not measured). The readings and their tolerances are in `statements/`
(`readings.py` states the tolerances); only jobs that are results (statistics taken, steady,
collapse guard valid) count. `--readings` prints the rows' readings for a sweep file, without
results (the skeleton of docs/statistics.md's table). `--dense` prints the chapter 4.2 row, `--grid` the dense sweep's
grid. A sweep still running is read as far as it got.
"""
import sys
from pathlib import Path

import duckdb

from statements import chapter3, chapter41
from statements.readings import summary
from statements.sweep import Sweep


def table(results, name):
    path = Path(results) / f"{name}.parquet"
    if not path.exists():
        sys.exit(f"{path}: missing (run `granflow gather {results}` first)")
    return f"read_parquet('{path}')"


def statements(results, chapter, readings=False):
    """The rows of a chapter's statements (`chapter3` or `chapter41`) on a results directory
    (or, with `readings`, on a sweep file without results)."""
    if readings:
        sweep = Sweep.planned(results)
    else:
        table(results, "jobs")
        sweep = Sweep(results)
    return [statement(sweep) for statement in chapter.STATEMENTS]


def chapter4_dense(results):
    con = duckdb.connect()
    jobs, g, c = (table(results, n) for n in ("jobs", "pair_correlation", "velocity_correlation"))
    done = f"(SELECT * FROM {jobs} WHERE statistics_snapshots > 0 AND restitution = 0.9 AND roughness = 0.9)"
    # local maxima of the all-slab g(r)
    peaks = con.execute(
        f"WITH s AS (SELECT job_id, r, g, lag(g) OVER w AS gl, lead(g) OVER w AS gr FROM {g} "
        f"WHERE g_bin IS NULL AND job_id IN (SELECT job_id FROM {done}) WINDOW w AS (PARTITION BY job_id ORDER BY r)) "
        "SELECT r, g FROM s WHERE g > gl AND g >= gr AND g > 1.02 ORDER BY r").fetchall()
    centre = con.execute(
        f"SELECT c_pair, avg(c) FROM {c} WHERE job_id IN (SELECT job_id FROM {done}) "
        f"AND c_bin = (SELECT max(c_bin) / 2 FROM {c}) AND c_r BETWEEN 1.0 AND 2.0 "
        "AND c_pair IN ('xx', 'yy', 'zz') GROUP BY c_pair ORDER BY c_pair").fetchall()
    # a number is a result only where the method was valid: steady, and the collapse guard
    # (the TC model) did not change the physics
    validity = con.execute(
        f"SELECT steady, collapse_guard_valid, momentum_balance, momentum_balance_error, "
        f"energy_balance, energy_balance_error, window_tc_elastic_fraction, "
        f"window_suppressed_dissipation FROM {done}").fetchall()
    measured = ("g(r) maxima at r/d = " + ", ".join(f"{r:.2f} ({v:.2f})" for r, v in peaks[:6]) +
                "; centre slab, 1 <= r/d <= 2: " + ", ".join(f"C_{p} = {v:.3g}" for p, v in centre))
    invalid = [v for v in validity if not (v[0] and v[1])]
    if not validity:
        verdict = "not run yet"
    elif invalid:
        st, guard, mb, mbe, eb, ebe, tc, sup = invalid[0]
        verdict = (f"not a result: the run is {'steady' if st else 'not steady'} (momentum balance "
                   f"{mb:.3f} +- {mbe:.3f}, energy balance {eb:.3f} +- {ebe:.3f}) and its collapse "
                   f"guard {'held' if guard else 'changed the physics'} ({100 * tc:.0f} % of the "
                   f"pair collisions made elastic, {100 * sup:.1f} % of the dissipation suppressed)")
    else:
        verdict = "see the numbers"
    return [("phi = 0.5: g(r) peaks near integer r/d, C_xx ~ 0 while C_yy, C_zz significant at the centre",
             measured, verdict)]


def grid(results):
    """One row per done job of a sweep: is it a result (steady, collapse guard valid), and the
    statistics a reader looks at first (contact value, Lambda at the centre, the centre slab's
    kurtosis of the six components, mean over them), with the job's cost."""
    con = duckdb.connect()
    jobs, moments = (table(results, n) for n in ("jobs", "vdf_moments"))
    rows = con.execute(
        f"SELECT j.restitution, j.roughness, j.label, j.steady, j.momentum_balance, "
        f"j.momentum_balance_error, j.window_tc_elastic_fraction, j.collapse_guard_valid, "
        f"j.contact_value, j.lambda_centre, j.lambda_centre_error, "
        f"(SELECT avg(m.kurtosis) FROM {moments} m WHERE m.job_id = j.job_id "
        f" AND m.moment_bin = (SELECT max(moment_bin) / 2 FROM {moments})), "
        f"j.wall_seconds, j.pair_collisions "
        f"FROM {jobs} j WHERE j.statistics_snapshots > 0 ORDER BY j.restitution, j.roughness DESC"
    ).fetchall()
    print("| e | beta | label | momentum balance | TC-elastic collisions | result? | g(d+) "
          "| Lambda centre | centre kurtosis (mean of 6) | wall time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for e, b, label, steady, mb, mbe, tc, guard, g, lam, lame, kurt, wall, coll in rows:
        valid = "yes" if steady and guard else (
            "no: " + " and ".join(w for w, bad in (("not steady", not steady),
                                                   ("guard changed the physics", not guard)) if bad))
        print(f"| {e:g} | {b:g} | {label} | {mb:.3f} +- {mbe:.3f} | {100 * tc:.0f} % | {valid} "
              f"| {g:.3g} | {lam:.4f} +- {lame:.4f} | {kurt:.2f} | {wall / 60:.0f} min |")
    if rows:
        print(f"\n{len(rows)} jobs, {sum(r[-1] for r in rows):.3g} pair collisions, "
              f"{sum(r[-2] for r in rows) / 3600:.1f} core-hours of job wall time")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    if "--grid" in sys.argv:
        grid(sys.argv[1])
        return
    if "--dense" in sys.argv:
        for statement, measured, agrees in chapter4_dense(sys.argv[1]):
            print(f"| {statement} | {measured} | {agrees} |")
        return
    readings = "--readings" in sys.argv
    rows = statements(sys.argv[1], chapter41 if "--dilute" in sys.argv else chapter3, readings)
    print("| section | thesis | literal reading | averaging | measured | agrees |")
    print("|---|---|---|---|---|---|")
    for row in rows:
        cells = list(row.cells())
        if readings:
            cells[4:] = ["to be measured", "to be measured" if not row.missing else row.missing]
        print("| " + " | ".join(cell.replace("|", "/") for cell in cells) + " |")
    print()
    print(summary(rows))


if __name__ == "__main__":
    main()
