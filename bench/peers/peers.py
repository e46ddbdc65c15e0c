#!/usr/bin/env python3
"""Side-by-side speed comparisons of granflow with public peer codes, run as interleaved rounds
(peer, granflow, peer, granflow, ...; one process at a time), so that both see the same spells
of a noisy machine. Nothing is downloaded: each peer is built from a source tree whose path you
give, with the documented edits below applied to a copy (the tree itself is not touched).

    python3 bench/peers/peers.py edmd --source PATH/TO/FSmallenburg-EDMD [--rounds 7]
    python3 bench/peers/peers.py lammps-dem [--lmp /usr/bin/lmp] [--rounds 5] [--workload 4k]

Each prints one table row per workload: the peer's and granflow's rate (median and range over
the rounds), the median of the per-round ratios granflow / peer, and in how many rounds granflow
was ahead; `--json FILE` also writes every round. The granflow binary is `target/release/granflow`
(build it first) unless `--granflow` says otherwise. See bench/peers/README.md for what each
comparison holds equal (thermostat, warm-up, forcing) and docs/performance.md for the results.
"""

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def run(cmd, cwd=None, env=None):
    """Run a command, fail loudly with its output when it fails; its stdout."""
    out = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({out.returncode}):\n{out.stdout}\n{out.stderr}")
    return out.stdout


def granflow_bench(binary, workload, extra):
    """One `granflow bench --json` run of one workload: its JSON object."""
    text = run([binary, "bench", "--json", "--workload", workload] + extra)
    rows = [r for r in json.loads(text) if r["workload"] == workload]
    if len(rows) != 1:
        sys.exit(f"granflow bench: workload {workload} not found in {text}")
    return rows[0]


def summary(name, unit, peer, ours, results):
    ratios = [o / p for p, o in zip(peer, ours)]
    row = {
        "workload": name,
        "unit": unit,
        "rounds": len(ratios),
        "peer_median": statistics.median(peer),
        "peer_range": [min(peer), max(peer)],
        "granflow_median": statistics.median(ours),
        "granflow_range": [min(ours), max(ours)],
        "ratio_median": statistics.median(ratios),
        "ratio_range": [min(ratios), max(ratios)],
        "rounds_ahead": sum(r > 1 for r in ratios),
        "peer": peer,
        "granflow": ours,
    }
    results.append(row)
    m = lambda v: f"{v / 1e6:.3g} M"
    print(
        f"| {name} | {m(row['peer_median'])} ({m(min(peer))}-{m(max(peer))}) "
        f"| {m(row['granflow_median'])} ({m(min(ours))}-{m(max(ours))}) "
        f"| **{row['ratio_median']:.2f}** ({min(ratios):.2f}-{max(ratios):.2f}) "
        f"| {row['rounds_ahead']} / {len(ratios)} |",
        flush=True,
    )


# ---------------------------------------------------------------------------------------------
# FSmallenburg/EDMD (Smallenburg, EPJE 45, 22 (2022)): elastic hard spheres in a periodic box.

EDMD_TIMING = r"""
#include <stddef.h>
#include <sys/time.h>
static double bench_now(void) { struct timeval t; gettimeofday(&t, NULL); return t.tv_sec + 1e-6 * t.tv_usec; }
"""


def patch_edmd(text, n, phi, tmax):
    """The edits to the peer's source (a copy): start from an fcc crystal of N spheres at phi,
    no thermostat, run to tmax, and time the collisions after t = 2 (the crystal has melted by
    then); everything else is the peer's own code and Makefile flags."""
    subs = [
        (r"double maxtime = [0-9.e+-]+;", f"double maxtime = {tmax};"),
        (r"int initialconfig = 0;", "int initialconfig = 1;"),
        (r"double packfrac = [0-9.]+;", f"double packfrac = {phi};"),
        (r"int N = [0-9]+;", f"int N = {n};"),
        (r"const int usethermostat = 1;", "const int usethermostat = 0;"),
    ]
    for pattern, new in subs:
        text, k = re.subn(pattern, lambda _: new, text, count=1)
        if k == 0 and "usethermostat" not in pattern:
            sys.exit(f"EDMD source: `{pattern}` not found (another version of the code?)")
    loop = re.compile(r"while \(simtime <= maxtime\)\s*\{\s*step\(\);\s*\}")
    timed = (
        "double bench_t0 = 0; unsigned int bench_c0 = 0; int bench_on = 0;\n"
        "    while (simtime <= maxtime)\n    {\n      step();\n"
        "      if (!bench_on && simtime >= 2.0) { bench_on = 1; bench_c0 = colcounter; bench_t0 = bench_now(); }\n"
        "    }\n"
        '    printf("BENCH collisions %u seconds %.6f\\n", colcounter - bench_c0, bench_now() - bench_t0);'
    )
    text, k = loop.subn(lambda _: timed, text, count=1)
    if k != 1:
        sys.exit("EDMD source: the main loop `while (simtime <= maxtime) { step(); }` not found")
    return EDMD_TIMING + text


def build_edmd(source, variant, n, phi, tmax, work):
    """Copy one variant (Cell or Single), patch it, build it with its Makefile: the binary."""
    src = Path(source) / variant
    if not src.is_dir():
        sys.exit(f"{src}: no such directory (give --source the root of a FSmallenburg/EDMD checkout)")
    dest = Path(work) / f"{variant}-{n}-{phi}"
    shutil.copytree(src, dest)
    c = dest / f"md{variant}.c"
    c.write_text(patch_edmd(c.read_text(), n, phi, tmax))
    run(["make"], cwd=dest)
    return dest / "md"


def edmd_rate(binary):
    out = run([str(binary)], cwd=binary.parent)
    m = re.search(r"BENCH collisions (\d+) seconds ([0-9.]+)", out)
    if not m:
        sys.exit(f"{binary}: no BENCH line in its output")
    return int(m.group(1)) / float(m.group(2))


# Workloads: granflow's name, the peer's variant (its fastest at that density: cells at 0.15,
# neighbour lists "Single" at 0.40), N, phi, the peer's end time (about 1000 collisions per
# particle after t = 2 at kT = 1) and granflow's timed collisions per particle.
EDMD_WORKLOADS = [
    ("periodic-fcc-4k-phi0.15", "Cell", 4000, 0.15, 300, 1000),
    ("periodic-fcc-4k-phi0.40", "Single", 4000, 0.40, 52, 1000),
    ("periodic-fcc-32k-phi0.15", "Cell", 32000, 0.15, 60, 200),
    ("periodic-fcc-32k-phi0.40", "Single", 32000, 0.40, 12, 200),
]


def edmd(args, results):
    with tempfile.TemporaryDirectory() as work:
        chosen = [w for w in EDMD_WORKLOADS if not args.workload or args.workload in w[0]]
        built = {w[0]: build_edmd(args.source, w[1], w[2], w[3], w[4], work) for w in chosen}
        print("| workload | reference collisions/s (median, range) | granflow collisions/s | granflow / reference | rounds ahead |")
        print("|---|---|---|---|---|")
        for name, variant, n, phi, tmax, cpp in chosen:
            peer, ours = [], []
            for r in range(args.rounds):
                peer.append(edmd_rate(built[name]))
                row = granflow_bench(args.granflow, name, ["--collisions-per-particle", str(cpp)])
                ours.append(row["collisions_per_s"])
                print(f"  round {r + 1}: reference {peer[-1]:.4g}, granflow {ours[-1]:.4g}", file=sys.stderr, flush=True)
            summary(f"{name} ({variant})", "collisions/s", peer, ours, results)


# ---------------------------------------------------------------------------------------------
# LAMMPS (Debian's `lmp`, GRANULAR package): the DEM channel, same particles, same law.


def timed_child(cmd, cwd=None, env=None):
    """Run a command to its end; (stdout, peak resident bytes of that child). The peak comes
    from wait4's rusage of this one child (ru_maxrss, in KiB on Linux)."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        p = subprocess.Popen(cmd, cwd=cwd, env=env, stdout=out, stderr=err)
        _, status, usage = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read().decode(), err.read().decode()
    if p.returncode != 0:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({p.returncode}):\n{stdout}\n{stderr}")
    return stdout, usage.ru_maxrss * 1024


def one_core_env():
    env = dict(os.environ)
    env["OMP_NUM_THREADS"] = "1"
    return env


def granflow_dem(binary, workload, threads, steps, warmup, cache, extra=()):
    """One `granflow bench --json` DEM run: (particle-steps/s, peak RSS bytes, N, contacts per
    particle)."""
    cmd = [binary, "bench", "--json", "--workload", workload, "--threads", str(threads),
           "--dem-steps", str(steps), "--dem-warmup", str(warmup), *extra]
    if cache:
        cmd += ["--dem-cache", cache]
    text, rss = timed_child(cmd, env=one_core_env() if threads == 1 else None)
    rows = [r for r in json.loads(text) if r["workload"] == workload]
    if len(rows) != 1:
        sys.exit(f"granflow bench: workload {workload} not found in {text}")
    r = rows[0]
    return r["particle_steps_per_s"], rss, r["n"], r.get("contacts_per_particle")


def lammps_dem_rate(lmp, directory, ranks=1, mpirun=None):
    """One LAMMPS run of in.dem on `ranks` MPI processes (through `mpirun` when more than one):
    (particle-steps/s from its `Loop time`, peak RSS of the launched process)."""
    log = Path(directory) / f"log.{ranks}.lammps"
    cmd = [lmp, "-in", "in.dem", "-log", str(log), "-screen", "none", "-nocite"]
    env = one_core_env()
    if ranks > 1:
        cmd = [mpirun, "-np", str(ranks), *cmd]
        # Open MPI refuses to start as root unless told (a container's usual user)
        env["OMPI_ALLOW_RUN_AS_ROOT"] = env["OMPI_ALLOW_RUN_AS_ROOT_CONFIRM"] = "1"
    _, rss = timed_child(cmd, cwd=directory, env=env)
    text = log.read_text()
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    if not m:
        sys.exit(f"{log}: no `Loop time` line")
    secs, procs, steps, atoms = float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))
    if procs != ranks:
        sys.exit(f"{log}: LAMMPS ran on {procs} processes, not {ranks}")
    return atoms * steps / secs, rss, atoms


# granflow's DEM workloads (`granflow bench`): dense channels at phi-bar 0.6, the paper's law
LAMMPS_DEM_WORKLOADS = ["dem-channel-4k-phi0.60", "dem-channel-40k-phi0.60"]


def lammps_dem(args, results):
    if not Path(args.lmp).exists():
        sys.exit(f"{args.lmp}: no LAMMPS binary (Debian: apt-get install lammps; or --lmp PATH)")
    chosen = [w for w in LAMMPS_DEM_WORKLOADS if not args.workload or args.workload in w]
    # None: granflow bench's own cache ($GRANFLOW_BENCH_CACHE or ~/.cache/granflow/bench),
    # shared with plain `granflow bench` runs
    cache = args.dem_cache
    mpirun = shutil.which(args.mpirun) if args.mpirun else None
    if args.mpirun and not mpirun:
        sys.exit(f"{args.mpirun}: not found (Debian: apt-get install openmpi-bin; or --mpirun '' to skip LAMMPS on 2 ranks)")
    with tempfile.TemporaryDirectory() as work:
        print("| workload | LAMMPS particle-steps/s (median, range) | granflow 1 thread | granflow / LAMMPS | rounds ahead |")
        print("|---|---|---|---|---|")
        scaling = []
        for name in chosen:
            directory = Path(work) / name
            # the warmed state, written once by granflow (prepared and cached on first use)
            granflow_dem(args.granflow, name, 1, args.steps, args.warmup, cache,
                         ["--lammps-out", str(directory)])
            peer, ours, ours2, peer2 = [], [], [], []
            rss = {"lammps": [], "granflow-1": [], "granflow-2": []}
            n = None
            for r in range(args.rounds):
                g1, m1, n, contacts = granflow_dem(args.granflow, name, 1, args.steps, args.warmup, cache)
                l1, ml, atoms = lammps_dem_rate(args.lmp, directory)
                g2, m2, _, _ = granflow_dem(args.granflow, name, 2, args.steps, args.warmup, cache)
                if mpirun:
                    l2, _, _ = lammps_dem_rate(args.lmp, directory, 2, mpirun)
                    peer2.append(l2)
                if atoms != n:
                    sys.exit(f"{name}: LAMMPS has {atoms} atoms, granflow {n}")
                ours.append(g1)
                peer.append(l1)
                ours2.append(g2)
                rss["granflow-1"].append(m1)
                rss["lammps"].append(ml)
                rss["granflow-2"].append(m2)
                two_ranks = f", LAMMPS 2 ranks {peer2[-1]:.4g}" if mpirun else ""
                print(f"  round {r + 1}: LAMMPS {l1:.4g}, granflow 1 thread {g1:.4g}, 2 threads {g2:.4g}"
                      f"{two_ranks} particle-steps/s ({contacts:.2f} contacts per particle)",
                      file=sys.stderr, flush=True)
            summary(f"{name} (N = {n}, {args.steps} steps)", "particle-steps/s", peer, ours, results)
            ratios = [b / a for a, b in zip(ours, ours2)]
            per_particle = {k: statistics.median(v) / n for k, v in rss.items()}
            peer_ratios = [b / a for a, b in zip(peer, peer2)]
            scaling.append((name, ours, ours2, ratios, per_particle, peer_ratios))
            results[-1]["granflow_2_threads"] = ours2
            results[-1]["thread_scaling"] = ratios
            if mpirun:
                results[-1]["lammps_2_ranks"] = peer2
                results[-1]["lammps_rank_scaling"] = peer_ratios
            results[-1]["peak_rss_bytes_per_particle"] = per_particle
        print()
        print("| workload | granflow 1 thread | 2 threads | 2 / 1 threads (median, range) | LAMMPS 2 / 1 MPI ranks (median, range) | peak RSS / N: LAMMPS, granflow 1, 2 threads |")
        print("|---|---|---|---|---|---|")
        m = lambda v: f"{v / 1e6:.3g} M"
        spread = lambda v: f"**{statistics.median(v):.2f}** ({min(v):.2f}-{max(v):.2f})" if v else "not run"
        for name, one, two, ratios, mem, peer_ratios in scaling:
            print(f"| {name} | {m(statistics.median(one))} | {m(statistics.median(two))} "
                  f"| {spread(ratios)} | {spread(peer_ratios)} "
                  f"| {mem['lammps']:.0f}, {mem['granflow-1']:.0f}, {mem['granflow-2']:.0f} bytes |")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("peer", choices=["edmd", "lammps-dem"])
    p.add_argument("--source", help="the peer's source tree (edmd)")
    p.add_argument("--lmp", default="/usr/bin/lmp", help="the LAMMPS binary (lammps-dem)")
    p.add_argument("--mpirun", default="mpirun", help="MPI launcher for LAMMPS on 2 ranks, its scaling beside granflow's on 2 threads (lammps-dem; '' skips it)")
    p.add_argument("--steps", type=int, default=2000, help="timed steps (lammps-dem)")
    p.add_argument("--warmup", type=int, default=100000, help="granflow flow steps before the timed ones (lammps-dem; the state is cached)")
    p.add_argument("--dem-cache", help="granflow's cache of prepared states (lammps-dem; default: granflow bench's own, $GRANFLOW_BENCH_CACHE or ~/.cache/granflow/bench)")
    p.add_argument("--rounds", type=int, default=7)
    p.add_argument("--workload", help="only workloads whose name contains this text")
    p.add_argument("--granflow", default=str(ROOT / "target/release/granflow"))
    p.add_argument("--json", help="also write every round to this file")
    args = p.parse_args()
    if not Path(args.granflow).exists():
        sys.exit(f"{args.granflow}: not built (cargo build --release)")
    results = []
    if args.peer == "lammps-dem":
        lammps_dem(args, results)
    else:
        if not args.source:
            sys.exit("edmd: give --source PATH (a checkout of https://github.com/FSmallenburg/EDMD)")
        edmd(args, results)
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1))


if __name__ == "__main__":
    main()
