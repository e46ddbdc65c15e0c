#!/usr/bin/env python3
"""Write SPARTA inputs for granflow's DSMC benchmark case (`granflow bench --workload dsmc-...`).

    python3 bench/peers/sparta/gen_input.py [DIR]     # default: bench/peers/sparta/inputs

The case is the one `dsmc_workloads()` in src/cli/bench.rs defines (the parameters are repeated
below, CASE; change both together): the thesis channel for a molecular gas between two diffuse
walls at T_w, forced along x, at Kn = 0.1 and Kn = 1, 6000 simulators in 200 layer cells,
dt = 0.1 mean collision times, 500 warm-up steps then 10 000 timed steps, sampled every step or
not at all; on that grid and on one of about 3 cells per mean free path (`-3mfp`). For each Kn,
grid and sampling this writes `in.kn{KN}[-3mfp]-{sampled,unsampled}` (the regular mover) and the same with `-optmove` (SPARTA's optimised mover), plus `gas.species` and
`gas.vss`; `in.kn{KN}-check` adds the mass-weighted mean velocity over the second half of the
run (run.py --check compares it with granflow's).

Units. granflow works in W = m = k_B = T_w = 1; SPARTA in SI. Any SI values give the same
dimensionless case; we take an argon-like gas (PHYS below) and derive everything else from
Kn, a-hat, dt/tau_c and N exactly as granflow does (src/engine/dsmc/params.rs).
"""

import math
import sys
from pathlib import Path

# granflow's case: src/cli/bench.rs, dsmc_workloads() (+ DsmcParams::default() for forcing,
# restitution, walls)
CASE = {
    "cells": 200,
    "particles_per_cell": 30.0,  # N = 6000
    "time_step": 0.1,  # dt in tau_c
    "forcing": 0.5,  # a-hat
    "warmup_steps": 500,
    "timed_moves": 6e7,  # `granflow bench --moves 6e7`: ceil(6e7 / 6000) = 10 000 steps
}
KNUDSEN = {"0.1": 0.1, "1": 1.0}
# The grids: granflow's 200 layer cells (20 and 200 cells per mean free path at Kn = 0.1 and 1),
# and the grid a SPARTA user would choose, about 3 cells per mean free path (`-3mfp` in the
# names: 30 and 3 cells; granflow's workloads `dsmc-kn{KN}-6000-3mfp-*`). Same 6000 simulators.
GRIDS = {"": lambda kn: CASE["cells"], "-3mfp": lambda kn: round(3.0 / kn)}

# SI values of the physical gas (any values give the same dimensionless case)
PHYS = {
    "k_B": 1.380649e-23,  # J/K, SPARTA's update->boltz in SI units
    "mass": 6.63e-26,  # kg (argon)
    "diameter": 4.17e-10,  # m (argon's VHS diameter at 273 K)
    "T_w": 273.15,  # K
    "W": 1.0e-3,  # m, channel width (y)
    "side": 100.0,  # periodic x and z sides of the box, in W
}


def derived(kn):
    """Every SPARTA number of the case at Knudsen number `kn`, from CASE and PHYS."""
    k, m, d, t, w = (PHYS[x] for x in ("k_B", "mass", "diameter", "T_w", "W"))
    n_sim = round(CASE["cells"] * CASE["particles_per_cell"])
    # Kn = lambda / W with lambda = 1 / (sqrt 2 pi n d^2) (thesis eqs. 3.20-3.21): the number
    # density n of the real gas
    mfp = kn * w
    nrho = 1.0 / (math.sqrt(2.0) * math.pi * d * d * mfp)
    # x and z are periodic and granflow does not store them; SPARTA needs a box. Its sides are
    # 100 W so that a simulator wraps around x or z rarely (granflow never does); the physics
    # does not depend on them: the weight fnum = n V / N keeps the density.
    lx = lz = PHYS["side"] * w
    volume = lx * w * lz
    fnum = nrho * volume / n_sim
    # tau_c = lambda / v-bar, v-bar = sqrt(8 k T_w / (pi m)) (params.rs, collision_time)
    mean_speed = math.sqrt(8.0 * k * t / (math.pi * m))
    dt = CASE["time_step"] * mfp / mean_speed
    # The body force. granflow: a-hat = a W / (2 k T_w / m) (thesis eq. 3.4, params.rs `forcing`),
    # so the acceleration is a = 2 a-hat k T_w / (m W) (params.rs `acceleration()`: 2 a-hat in
    # its units k T_w / (m W)); each step a simulator gets v_x += a dt, x += v dt + a dt^2 / 2.
    # SPARTA: `global field constant mag ex ey ez` is an acceleration (docs: "magnitude of field
    # acceleration (acceleration units)"); Update::field3d adds v += dt * field and
    # x += dt^2 / 2 * field after the straight flight, with field = mag * unit(ex, ey, ez).
    # So SPARTA's mag equals granflow's a = 2 a-hat k T_w / (m W), not a-hat k T_w / (m W)
    # nor a-hat u_c^2 / (2 W): the factor 2 is the one in u_c^2 = 2 k T_w / m. Checked by
    # run.py --check (2026-12-03): SPARTA's mean velocity / granflow's = 1.001 at Kn = 0.1 and
    # 0.969 at Kn = 1. The 3 % is SPARTA's integration, not the conversion: it adds the whole
    # a dt before the flight and nothing after a wall hit inside the step (the diffuse wall
    # erases what came before), granflow applies the force before and after the hit; 5.3 % of
    # SPARTA's moves hit a wall at Kn = 1, losing half a step of force each: 2.7 % of it.
    accel = 2.0 * CASE["forcing"] * k * t / (m * w)
    timed_steps = math.ceil(CASE["timed_moves"] / n_sim)
    return {
        "n_sim": n_sim,
        "nrho": nrho,
        "lx": lx,
        "lz": lz,
        "fnum": fnum,
        "dt": dt,
        "accel": accel,
        "u_c": math.sqrt(2.0 * k * t / m),
        "timed_steps": timed_steps,
    }


SPECIES = """# argon-like hard spheres for granflow's DSMC benchmark (written by gen_input.py)
# ID molwt mass rotdof rotrel vibdof vibrel vibtemp specwt charge
G 39.948 {mass:.6e} 0 0 0 0 0 0 0
"""

# VSS with omega = 0.5, alpha = 1: hard spheres (sigma = pi d^2 whatever tref, isotropic)
VSS = """# hard spheres: VSS with omega = 0.5, alpha = 1 (written by gen_input.py)
# ID diam omega tref alpha
G {diameter:.6e} 0.5 {T_w} 1.0
"""


def sparta_input(kn_name, sampled, optmove, check=False, grid=""):
    """The text of one SPARTA input."""
    kn = KNUDSEN[kn_name]
    p = derived(kn)
    cells = GRIDS[grid](kn)
    warm, timed = CASE["warmup_steps"], p["timed_steps"]
    total = warm + timed
    lines = [
        f"# granflow DSMC benchmark case at Kn = {kn_name}: written by bench/peers/sparta/gen_input.py",
        f"# {p['n_sim']} simulators, {cells} layer cells, dt = {CASE['time_step']} tau_c, "
        f"a-hat = {CASE['forcing']}, diffuse walls at T_w, e_n = 1 (SPARTA has no restitution)",
        f"# sampling: {'13 cell quantities every step' if sampled else 'none'}; "
        f"mover: {'optmove' if optmove else 'regular'}",
        "seed 12345",
        "dimension 3",
        "units si",
        "global gridcut 0.0",
        f"global fnum {p['fnum']:.10e}",
        f"global field constant {p['accel']:.10e} 1 0 0",
    ]
    if optmove:
        lines.append("global optmove yes")
    lines += [
        # x, z periodic; the two y faces are surfaces: diffuse walls at T_w, full accommodation
        "boundary p s p",
        f"create_box 0 {p['lx']:.10e} 0 {PHYS['W']:.10e} 0 {p['lz']:.10e}",
        f"create_grid 1 {cells} 1",
        f"surf_collide wall diffuse {PHYS['T_w']} 1.0",
        "bound_modify ylo yhi collide wall",
        "species gas.species G",
        f"mixture gas G vstream 0.0 0.0 0.0 temp {PHYS['T_w']}",
        "collide vss gas gas.vss",
        # uniform positions, Maxwellian at T_w at rest, as granflow starts
        f"create_particles gas n {p['n_sim']}",
        f"timestep {p['dt']:.10e}",
        "stats 0",
        "stats_style step cpu np nattempt ncoll",
    ]
    if sampled:
        # granflow samples 13 raw moments per cell every step (count, v_a, v_a v_b, v_a |v|^2);
        # SPARTA's nearest: n u v w, the 6 momentum fluxes, the 3 energy fluxes, averaged every
        # step of the run (the window [1, total] covers warm-up and timed steps, as granflow's
        # sample_every = 1 does)
        lines += [
            "compute g grid all gas n u v w",
            "compute p pflux/grid all gas momxx momyy momzz momxy momyz momxz",
            "compute e eflux/grid all gas heatx heaty heatz",
            f"fix s ave/grid all 1 {total} {total} c_g[*] c_p[*] c_e[*]",
        ]
    if check:
        # mass-weighted mean velocity <u_x> (one species) averaged over the second half
        half = total // 2
        lines += [
            "compute ux reduce ave vx",
            f"fix ux ave/time 1 {half} {total} c_ux",
            "stats_style step cpu np nattempt ncoll f_ux",
        ]
    lines += [f"run {warm}", f"run {timed}", ""]
    return "\n".join(lines)


def write_all(directory):
    """Write every input and the species files into `directory`; the list of input names."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    (directory / "gas.species").write_text(SPECIES.format(**PHYS))
    (directory / "gas.vss").write_text(VSS.format(**PHYS))
    names = []
    for kn in KNUDSEN:
        for grid in GRIDS:
            for sampled in (False, True):
                for optmove in (False, True):
                    name = f"in.kn{kn}{grid}-{'sampled' if sampled else 'unsampled'}"
                    name += "-optmove" if optmove else ""
                    (directory / name).write_text(sparta_input(kn, sampled, optmove, grid=grid))
                    names.append(name)
        (directory / f"in.kn{kn}-check").write_text(sparta_input(kn, False, True, check=True))
    return names


if __name__ == "__main__":
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parent / "inputs"
    for name in write_all(out):
        print(out / name)
