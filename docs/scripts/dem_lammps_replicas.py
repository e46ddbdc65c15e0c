#!/usr/bin/env python3
"""granflow and LAMMPS as two samples of one physics: replicas of a DEM channel run by both codes
from the same prepared states, their distributions compared (issue 46; docs/dem.md, "granflow
beside LAMMPS, replica by replica").

    python3 docs/scripts/dem_lammps_replicas.py sweeps/dem-lammps-replicas.ron --out results/46/replicas
        [--granflow target/release/granflow] [--lmp /usr/bin/lmp] [--threads 2]

For every job of the sweep (one per seed: each seed is its own preparation):
1. `granflow run` runs it as any job (prepared, then the run's length), its tables in
   OUT/granflow/<sweep>/jobs.parquet;
2. `granflow lammps --job i` writes the same prepared state (granflow's preparation is a
   deterministic function of the parameters and the seed) for LAMMPS, which runs the same
   number of steps, dumping a frame every snapshot interval; `granflow lammps-import` reads the
   dump into the same tables (OUT/lammps-<i>/jobs.parquet), analysed by the same analysis.
   LAMMPS starts without contact histories (a data file cannot hold them); granflow's job kept
   them when the floor was removed: a difference of the first steps only, which chaos forgets.

Then, per quantity (u_cm, u_max / u_slip, sigma_xx, the wall-force balance beta), the replicas of
each code: their mean and standard deviation s over the seeds, the paired differences
d_i = granflow_i - LAMMPS_i (the same prepared state i) with their mean and t = mean(d) /
(s_d / sqrt(n)), set beside the two-sided 0.1 % point of Student's t with n - 1 degrees of
freedom; and beside the mean block error of a single job, to show how far one job's error bar
is from the run-to-run spread. Prints Markdown; `--json FILE` also writes every number.
Steps already done are skipped (granflow's jobs are resumable, a LAMMPS directory with its
dump and tables is reused), so the script can be run again after a stop.
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

import duckdb

ROOT = Path(__file__).resolve().parents[2]

# (column of jobs.parquet, its error column, what it is)
QUANTITIES = [
    ("com_velocity", "com_velocity_error", "u_cm"),
    ("velocity_ratio", "velocity_ratio_error", "u_max / u_slip"),
    ("normal_stress", "normal_stress_error", "sigma_xx"),
    ("wall_force_balance", "wall_force_balance_error", "beta"),
]

# two-sided 0.1 % points of Student's t (0.9995 quantile) by degrees of freedom
T_9995 = {1: 636.62, 2: 31.599, 3: 12.924, 4: 8.610, 5: 6.869, 6: 5.959, 7: 5.408, 8: 5.041,
          9: 4.781, 10: 4.587, 11: 4.437, 12: 4.318, 14: 4.140, 19: 3.883, 29: 3.659}


def t_point(dof):
    known = [k for k in T_9995 if k <= dof]
    return T_9995[max(known)]  # conservative between tabulated values


def run(cmd, **kw):
    print("$", " ".join(map(str, cmd)), file=sys.stderr, flush=True)
    out = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if out.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({out.returncode}):\n{out.stdout}\n{out.stderr}")
    return out.stdout


def rows(path):
    con = duckdb.connect()
    cols = ["plan_index", "seed", "state", "time_step", "snapshot_interval", "run_length"] + [
        c for q in QUANTITIES for c in q[:2]]
    return [dict(zip(cols, r)) for r in con.execute(
        f"SELECT {', '.join(cols)} FROM read_parquet('{path}') ORDER BY plan_index").fetchall()]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("sweep")
    p.add_argument("--out", required=True)
    p.add_argument("--granflow", default=str(ROOT / "target/release/granflow"))
    p.add_argument("--lmp", default="/usr/bin/lmp")
    p.add_argument("--threads", type=int, default=1, help="granflow run's worker threads")
    p.add_argument("--json", help="also write every number to this file")
    args = p.parse_args()
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    g = args.granflow
    sweep = str(Path(args.sweep).resolve())

    run([g, "run", sweep, "--results", str(out / "granflow"), "--threads", str(args.threads)])
    ours_tables = list((out / "granflow").glob("*/jobs.parquet"))
    if len(ours_tables) != 1:
        sys.exit(f"{out / 'granflow'}: expected one sweep's jobs.parquet, found {ours_tables}")
    ours = rows(ours_tables[0])
    env = dict(os.environ, OMP_NUM_THREADS="1")
    theirs = []
    for job in ours:
        if job["state"] != "done":
            sys.exit(f"granflow job {job['plan_index']} is {job['state']}: see {out / 'granflow'}")
        i = job["plan_index"]
        d = out / f"lammps-{i}"
        table = d / "tables" / "jobs.parquet"
        if not table.exists():
            dt = job["time_step"]
            steps = round(job["run_length"] / dt)
            every = max(1, round(job["snapshot_interval"] / dt))
            run([g, "lammps", sweep, "--job", str(i), "--out", str(d), "--steps", str(steps),
                 "--dump-every", str(every)])
            run([args.lmp, "-in", "in.dem", "-log", "log.lammps", "-screen", "none", "-nocite"],
                cwd=d, env=env)
            run([g, "lammps-import", sweep, "--job", str(i), "--dump", str(d / "dump.dem"),
                 "--out", str(d / "tables")])
        theirs.append(rows(table)[0])

    n = len(ours)
    report = {"sweep": args.sweep, "replicas": n, "quantities": {}}
    print(f"{n} replicas (seeds {', '.join(str(j['seed']) for j in ours)}), both codes from the same "
          f"prepared states; paired t against the two-sided 0.1 % point {t_point(n - 1):.3g} "
          f"(Student, {n - 1} dof)\n")
    print("| quantity | granflow: mean, s over the seeds | LAMMPS: mean, s | mean block error of a job "
          "(granflow, LAMMPS) | mean difference +- its standard error | t | within |")
    print("|---|---|---|---|---|---|---|")
    for col, err, name in QUANTITIES:
        a = [j[col] for j in ours]
        b = [j[col] for j in theirs]
        if any(v is None or (isinstance(v, float) and math.isnan(v)) for v in a + b):
            print(f"| {name} | missing in some replica | | | | | |")
            continue
        d = [x - y for x, y in zip(a, b)]
        md, sd = statistics.mean(d), statistics.stdev(d)
        se = sd / math.sqrt(n)
        t = md / se if se > 0 else math.inf
        ea = statistics.mean(j[err] for j in ours)
        eb = statistics.mean(j[err] for j in theirs if j[err] is not None)
        ok = abs(t) <= t_point(n - 1)
        report["quantities"][name] = {"granflow": a, "lammps": b, "difference_mean": md,
                                      "difference_se": se, "t": t, "block_error": [ea, eb],
                                      "within": ok}
        print(f"| {name} | {statistics.mean(a):.4g}, {statistics.stdev(a):.2g} "
              f"| {statistics.mean(b):.4g}, {statistics.stdev(b):.2g} | {ea:.2g}, {eb:.2g} "
              f"| {md:+.3g} +- {se:.2g} | {t:+.2f} | {'yes' if ok else 'no'} |")
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
