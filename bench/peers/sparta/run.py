#!/usr/bin/env python3
"""granflow's DSMC against SPARTA on the same case, in interleaved rounds.

    python3 bench/peers/sparta/run.py --spa PATH/spa_serial [--rounds N] [--json FILE]
    python3 bench/peers/sparta/run.py --spa PATH/spa_serial --check   # same physics?

Each round runs, one process at a time and for each case (Kn = 0.1 and 1, on granflow's 200-cell
grid and on one of about 3 cells per mean free path, `-3mfp`, sampled and not):
SPARTA with its regular mover, SPARTA with `global optmove yes` (if the binary knows it), and
`granflow bench --json --workload dsmc-kn{KN}-6000[-3mfp]-{sampled,unsampled} --moves 6e7`. The SPARTA
inputs are written by gen_input.py (same directory) into a temporary directory.

Method: each process's CPU time (user + sys, from getrusage(RUSAGE_CHILDREN) deltas around
it) over all its simulator moves, warm-up included on both sides (500 + 10 000 steps of 6000
simulators; set-up and start-up are in the CPU time too). Moves: SPARTA's own "Particle
moves" counts; granflow's n x (500 + ceil(6e7 / n)) steps. Collisions per move of the timed
10 000 steps: SPARTA's "Collide occurs / Particle moves" of its second `run`, granflow's
collisions_per_s / moves_per_s. The table: medians over rounds (range), the median of the
per-round ratios granflow / SPARTA, and in how many rounds granflow was ahead. --json also
keeps each run's timed_moves_per_loop_s: the in-process wall-clock rate of the 10 000 timed
steps (SPARTA's "Loop time", granflow's moves_per_s), which a loaded machine spoils.

--check instead runs each Kn once with the mean velocity tallied (SPARTA: mass-weighted <v_x>
over the second half; granflow: `granflow sim --analyse`, its steady window), both in
u_c = sqrt(2 k T_w / m): equal within a few per cent if the body force is converted right.
"""

import argparse
import json
import math
import re
import resource
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
sys.dont_write_bytecode = True  # keep the tree clean
sys.path.insert(0, str(HERE))
import gen_input  # noqa: E402

CASES = [(kn, g, s) for g in gen_input.GRIDS for kn in gen_input.KNUDSEN for s in ("unsampled", "sampled")]


def timed(cmd, cwd=None):
    """Run cmd; (stdout, CPU seconds user + sys of the child). Fails loudly."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if out.returncode != 0 or "ERROR" in out.stdout:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({out.returncode}):\n{out.stdout[-3000:]}\n{out.stderr[-3000:]}")
    return out.stdout, cpu


def spa_counts(text):
    """Per `run` of a SPARTA screen output: (steps, moves, collisions, loop seconds)."""
    loops = re.findall(r"Loop time of (\S+) on \d+ procs for (\d+) steps", text)
    moves = re.findall(r"Particle moves\s*=\s*(\d+)", text)
    colls = re.findall(r"Collide occurs\s*=\s*(\d+)", text)
    if not (len(loops) == len(moves) == len(colls) == 2):
        sys.exit(f"unexpected SPARTA output:\n{text[-3000:]}")
    return [(int(s), int(m), int(c), float(t)) for (t, s), m, c in zip(loops, moves, colls)]


def run_sparta(spa, directory, name):
    """One SPARTA run: moves/s over CPU time, collisions per timed move, SPARTA's own rate."""
    text, cpu = timed([spa, "-in", name, "-log", "none", "-echo", "none"], cwd=directory)
    (_, m0, _, _), (steps, m1, c1, loop) = spa_counts(text)
    return {"moves_per_cpu_s": (m0 + m1) / cpu, "cpu_s": cpu, "moves": m0 + m1,
            "collisions_per_move": c1 / m1, "timed_moves_per_loop_s": m1 / loop}


def run_granflow(binary, kn, grid, sampling):
    """One `granflow bench` run of the same case, measured as run_sparta does."""
    workload = f"dsmc-kn{kn}-6000{grid}-{sampling}"
    moves = gen_input.CASE["timed_moves"]
    text, cpu = timed([binary, "bench", "--json", "--workload", workload, "--moves", f"{moves:g}"])
    rows = [r for r in json.loads(text) if r["workload"] == workload]
    if len(rows) != 1:
        sys.exit(f"granflow bench: workload {workload} not in {text}")
    r = rows[0]
    n = r["n"]
    total = n * (gen_input.CASE["warmup_steps"] + math.ceil(moves / n))
    return {"moves_per_cpu_s": total / cpu, "cpu_s": cpu, "moves": total,
            "collisions_per_move": r["collisions_per_s"] / r["moves_per_s"],
            "timed_moves_per_loop_s": r["moves_per_s"]}


def has_optmove(spa, directory):
    """Does this SPARTA know `global optmove`?"""
    probe = Path(directory) / "in.probe"
    probe.write_text("global optmove yes\n")
    out = subprocess.run([spa, "-in", "in.probe", "-log", "none", "-echo", "none"],
                         cwd=directory, capture_output=True, text=True)
    return out.returncode == 0 and "ERROR" not in out.stdout


def fmt(x):
    return f"{x / 1e6:.1f} M"


def column(values):
    return f"{fmt(statistics.median(values))} ({fmt(min(values))}-{fmt(max(values))})"


def table(results, sides):
    """The markdown table of the rounds."""
    names = {"spa": "SPARTA", "opt": "SPARTA `optmove`", "gf": "granflow"}
    head = ["case"] + [f"{names[s]} moves/s" for s in sides]
    head += [f"granflow / {names[s]}" for s in sides if s != "gf"]
    head += ["rounds ahead", "collisions per move (" + ", ".join(names[s] for s in sides) + ")"]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for (kn, grid, sampling), rounds in results.items():
        rate = {s: [r[s]["moves_per_cpu_s"] for r in rounds] for s in sides}
        cells = gen_input.GRIDS[grid](gen_input.KNUDSEN[kn])
        row = [f"Kn = {kn}, {cells} cells, "
               f"{'13 quantities sampled every step' if sampling == 'sampled' else 'no sampling'}"]
        row += [column(rate[s]) for s in sides]
        ahead = []
        for s in sides:
            if s == "gf":
                continue
            ratios = [g / p for g, p in zip(rate["gf"], rate[s])]
            row.append(f"**{statistics.median(ratios):.1f}x** ({min(ratios):.1f}-{max(ratios):.1f})")
            ahead.append(f"{sum(r > 1 for r in ratios)}/{len(ratios)}")
        row.append(", ".join(ahead))
        cpm = [statistics.median(r[s]["collisions_per_move"] for r in rounds) for s in sides]
        row.append(", ".join(f"{c:.4f}" for c in cpm))
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines)


def check(spa, binary, directory):
    """Mean velocity of both codes at each Kn, in u_c."""
    print("| Kn | SPARTA <u_x> / u_c | granflow <u_x> / u_c | SPARTA / granflow |")
    print("|---|---|---|---|")
    for kn in gen_input.KNUDSEN:
        p = gen_input.derived(gen_input.KNUDSEN[kn])
        text, _ = timed([spa, "-in", f"in.kn{kn}-check", "-log", "none", "-echo", "none"], cwd=directory)
        # the last stats line of the second run: step cpu np nattempt ncoll f_ux
        rows = [ln.split() for ln in text.splitlines() if re.match(r"^\s*\d+\s+\S+\s+\d+\s+\d+\s+\d+\s+\S+\s*$", ln)]
        spa_u = float(rows[-1][-1]) / p["u_c"]
        steps = gen_input.CASE["warmup_steps"] + p["timed_steps"]
        text, _ = timed([binary, "sim", "--engine", "dsmc", "--knudsen-number", kn, "--cells",
                         str(gen_input.CASE["cells"]), "--particles-per-cell",
                         str(gen_input.CASE["particles_per_cell"]), "--steps", str(steps), "--analyse"])
        gf = re.search(r"^\s*mean_velocity:\s*(\S+)", text, re.M)
        err = re.search(r"^\s*mean_velocity_error:\s*(\S+)", text, re.M)
        gf_u = float(gf.group(1))
        print(f"| {kn} | {spa_u:.4f} | {gf_u:.4f} +- {float(err.group(1)):.4f} | {spa_u / gf_u:.3f} |")


def build_sparta(source):
    """spa_serial of the checkout at `source`, built with SPARTA's own serial makefile."""
    src = source.resolve() / "src"
    binary = src / "spa_serial"
    if not (src / "Makefile").exists():
        sys.exit(f"--source {source}: no src/Makefile there (expected a SPARTA checkout)")
    if not binary.exists():
        print(f"building {binary} (make -j2 serial) ...", file=sys.stderr, flush=True)
        subprocess.run(["make", "-j2", "serial"], cwd=src, check=True)
    return str(binary)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    which = ap.add_mutually_exclusive_group(required=True)
    which.add_argument("--spa", help="SPARTA's spa_serial binary")
    which.add_argument("--source", help="a SPARTA checkout (https://github.com/sparta/sparta): "
                       "spa_serial is built there with its own Makefile.serial (make serial, -O3), unpatched, "
                       "unless it is there already")
    ap.add_argument("--granflow", default=str(ROOT / "target/release/granflow"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--case", action="append", help="only this case, e.g. kn1-sampled or kn1-3mfp-sampled (repeatable)")
    ap.add_argument("--no-optmove", action="store_true", help="skip SPARTA's optmove runs")
    ap.add_argument("--json", help="write every round to this file")
    ap.add_argument("--check", action="store_true", help="compare the mean velocities instead")
    args = ap.parse_args()
    spa = str(Path(args.spa).resolve()) if args.spa else build_sparta(Path(args.source))
    with tempfile.TemporaryDirectory(prefix="granflow-sparta-") as directory:
        gen_input.write_all(directory)
        if args.check:
            check(spa, args.granflow, directory)
            return
        sides = ["spa"] + (["opt"] if not args.no_optmove and has_optmove(spa, directory) else []) + ["gf"]
        cases = [c for c in CASES if not args.case or f"kn{c[0]}{c[1]}-{c[2]}" in args.case]
        results = {c: [] for c in cases}
        for i in range(args.rounds):
            for kn, grid, sampling in cases:
                r = {}
                for s in sides:
                    if s == "gf":
                        r[s] = run_granflow(args.granflow, kn, grid, sampling)
                    else:
                        name = f"in.kn{kn}{grid}-{sampling}" + ("-optmove" if s == "opt" else "")
                        r[s] = run_sparta(spa, directory, name)
                    print(f"round {i + 1}/{args.rounds} kn{kn}{grid}-{sampling} {s}: "
                          f"{fmt(r[s]['moves_per_cpu_s'])} moves/CPU-s, "
                          f"{r[s]['collisions_per_move']:.4f} collisions/move", file=sys.stderr, flush=True)
                results[(kn, grid, sampling)].append(r)
    if args.json:
        Path(args.json).write_text(json.dumps(
            [{"case": f"kn{kn}{g}-{s}", "rounds": rounds} for (kn, g, s), rounds in results.items()], indent=1))
    print(f"{args.rounds} interleaved rounds; moves per process CPU second (user + sys), "
          "warm-up included; median (range)\n")
    print(table(results, sides))


if __name__ == "__main__":
    main()
