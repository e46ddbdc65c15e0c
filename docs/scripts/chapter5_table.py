#!/usr/bin/env python3
"""The chapter-5 table of docs/thesis-chapter5.md from a gathered thesis-chapter5 sweep.

    python3 docs/scripts/chapter5_table.py results/thesis-chapter5

Reads `jobs.parquet` and `evolution.parquet` with DuckDB (pip install duckdb) and prints one
Markdown row per point of the sweep: its parameters and N, the structure at each of the
thesis' milestones (label with humps and the probability of its candidate over the milestone's
window), the steady label (or why there is none), whether the collapse guard stayed valid, the
momentum and energy balances over the job's window, and the job's wall time. Points that have
not reached a milestone (or not finished) say so; nothing is filled in that was not measured.
Then the sweep's total wall time summed over its jobs.
"""
import sys

import duckdb

# the scripts' one reader of a gathered table (this directory is on the path of a script run
# from it)
from thesis_statements import table

MILESTONES = [4000, 8000, 10000, 11000, 14000]


def number(x):
    """A parameter as the thesis writes it: 3 rather than 3.0."""
    return f"{x:g}"


def milestone_cell(row):
    if row is None:
        return "not reached"
    structure, probability = row
    return f"{structure} ({probability:.2f})"


def steady_cell(job):
    if job["state"] != "done":
        return f"not finished ({job['state']})"
    if job["steady"]:
        return job["label"]
    return f"not steady by {job['final_collisions_per_particle']:.0f} cpp"


def balance_cell(job):
    if job["momentum_balance"] is None:
        return ""
    return (f"{job['momentum_balance']:.3f} +- {job['momentum_balance_error']:.3f}, "
            f"{job['energy_balance']:.3f} +- {job['energy_balance_error']:.3f}")


def hours(seconds):
    if seconds is None:
        return ""
    return f"{seconds / 3600:.2f} h" if seconds >= 360 else f"{seconds:.0f} s"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    results = sys.argv[1]
    con = duckdb.connect()
    jobs, evolution = table(results, "jobs"), table(results, "evolution")
    columns = [
        "job_id", "length_over_width", "width_over_diameter", "height_over_diameter",
        "restitution", "particles", "state", "label", "steady", "final_collisions_per_particle",
        "collapse_guard_valid", "momentum_balance", "momentum_balance_error", "energy_balance",
        "energy_balance_error", "wall_seconds",
    ]
    rows = con.execute(
        f"SELECT {', '.join(columns)} FROM {jobs} ORDER BY "
        "restitution, height_over_diameter != width_over_diameter, width_over_diameter, "
        "length_over_width, height_over_diameter").fetchall()
    print("| L/W | W/d | H/d | e | N | " + " | ".join(f"{m:,}".replace(",", " ") for m in MILESTONES)
          + " | steady | TC valid | balances (momentum, energy) | wall time |")
    print("|" + "---|" * (5 + len(MILESTONES) + 4))
    total = 0.0
    for values in rows:
        job = dict(zip(columns, values))
        cells = [number(job["length_over_width"]), number(job["width_over_diameter"]),
                 number(job["height_over_diameter"]), number(job["restitution"]),
                 str(job["particles"] or "")]
        for m in MILESTONES:
            found = con.execute(
                f"SELECT structure, probability FROM {evolution} WHERE job_id = ? "
                "AND milestone_clock = 'collisions_per_particle' AND milestone = ?",
                [job["job_id"], float(m)]).fetchone()
            cells.append(milestone_cell(found))
        valid = job["collapse_guard_valid"]
        cells += [steady_cell(job), "" if valid is None else ("yes" if valid else "no"),
                  balance_cell(job), hours(job["wall_seconds"])]
        total += job["wall_seconds"] or 0.0
        print("| " + " | ".join(cells) + " |")
    done = sum(1 for values in rows if dict(zip(columns, values))["state"] == "done")
    print(f"\n{done} of {len(rows)} jobs done; wall time summed over the jobs: {total / 3600:.2f} h "
          "(core-hours of a run on one thread per job)")


if __name__ == "__main__":
    main()
