//! Initial state: non-overlapping placement at volume fraction phi and Gaussian velocities,
//! all drawn from a seeded portable RNG (PCG-64) with platform-independent arithmetic, so the
//! same parameters and seed give bitwise the same start on every machine.

use super::{EdmdParams, Placement};
use crate::engine::EngineError;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

/// Positions, velocities and angular velocities of a fresh run.
pub struct InitialState {
    pub positions: Vec<[f64; 3]>,
    pub velocities: Vec<[f64; 3]>,
    pub angular_velocities: Vec<[f64; 3]>,
}

/// Random sequential placement gives up above this volume fraction (its jamming limit is
/// about 0.38; it slows down well before).
const RANDOM_PLACEMENT_MAX_PHI: f64 = 0.30;

/// Place the spheres and draw velocities.
pub fn initial_state(params: &EdmdParams) -> Result<InitialState, EngineError> {
    let mut rng = Pcg64::seed_from_u64(params.seed);
    let phi = params.volume_fraction();
    let positions = match params.placement {
        Placement::Random => random_placement(params, &mut rng)
            .ok_or_else(|| unplaceable(params, "random placement"))?,
        Placement::Lattice => lattice_placement(params, &mut rng)?,
        Placement::Fcc => fcc_placement(params)?,
        Placement::Auto if phi <= RANDOM_PLACEMENT_MAX_PHI => {
            match random_placement(params, &mut rng) {
                Some(p) => p,
                None => lattice_placement(params, &mut rng)?,
            }
        }
        Placement::Auto => lattice_placement(params, &mut rng)?,
    };
    let n = positions.len();
    // equipartition: <c_a^2> = kT/m, <w_a^2> = kT/I with I = K m d^2 / 4
    let sigma_c = params.initial_temperature.sqrt();
    let sigma_w = (params.initial_temperature / (params.inertia_factor / 4.0)).sqrt();
    let velocities = zero_mean((0..n).map(|_| gaussian3(&mut rng, sigma_c)).collect());
    let angular_velocities = zero_mean((0..n).map(|_| gaussian3(&mut rng, sigma_w)).collect());
    Ok(InitialState {
        positions,
        velocities,
        angular_velocities,
    })
}

fn unplaceable(params: &EdmdParams, how: &str) -> EngineError {
    EngineError::InvalidParams(format!(
        "volume fraction {:.4} ({} spheres in a {} x {} x {} box{}) cannot be placed without overlap by {how}; \
         lower volume_fraction or the number of particles",
        params.volume_fraction(),
        params.particles,
        params.geometry.length,
        params.geometry.width,
        params.geometry.height,
        if params.geometry.walls {
            " between walls"
        } else {
            ""
        }
    ))
}

/// Standard normal deviates by the Box-Muller transform, with libm's portable log and cos.
pub(crate) fn gaussian3(rng: &mut Pcg64, sigma: f64) -> [f64; 3] {
    let mut normal = || {
        let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
        let u2: f64 = rng.random::<f64>();
        (-2.0 * libm::log(u1)).sqrt() * libm::cos(2.0 * std::f64::consts::PI * u2)
    };
    [sigma * normal(), sigma * normal(), sigma * normal()]
}

fn zero_mean(mut v: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
    let n = v.len().max(1) as f64;
    let mut mean = [0.0; 3];
    for x in &v {
        for a in 0..3 {
            mean[a] += x[a] / n;
        }
    }
    for x in &mut v {
        for a in 0..3 {
            x[a] -= mean[a];
        }
    }
    v
}

/// Range of centre coordinates along each axis: [0, extent) periodic, [a, extent - a] walls.
fn centre_ranges(params: &EdmdParams) -> [(f64, f64); 3] {
    let g = &params.geometry;
    let y = if g.walls {
        (0.5, g.width - 0.5)
    } else {
        (0.0, g.width)
    };
    [(0.0, g.length), y, (0.0, g.height)]
}

/// Minimum-image squared distance in the box.
fn distance2(params: &EdmdParams, a: [f64; 3], b: [f64; 3]) -> f64 {
    let g = &params.geometry;
    let ext = g.extents();
    let mut d2 = 0.0;
    for k in 0..3 {
        let mut d = a[k] - b[k];
        if k != 1 || !g.walls {
            d -= ext[k] * (d / ext[k]).round();
        }
        d2 += d * d;
    }
    d2
}

/// Random sequential addition with a coarse grid for overlap checks; None if it stalls.
fn random_placement(params: &EdmdParams, rng: &mut Pcg64) -> Option<Vec<[f64; 3]>> {
    let n = params.particles;
    let ranges = centre_ranges(params);
    let ext = params.geometry.extents();
    let dims: [usize; 3] = std::array::from_fn(|k| ((ext[k]).floor() as usize).max(1));
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); dims.iter().product()];
    let cell = |p: [f64; 3]| -> [usize; 3] {
        std::array::from_fn(|k| (((p[k] / ext[k]) * dims[k] as f64) as usize).min(dims[k] - 1))
    };
    let flat = |c: [usize; 3]| (c[2] * dims[1] + c[1]) * dims[0] + c[0];
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(n);
    let max_attempts = 2000 * n as u64 + 10_000;
    let mut attempts = 0u64;
    while positions.len() < n {
        attempts += 1;
        if attempts > max_attempts {
            return None;
        }
        let p: [f64; 3] = std::array::from_fn(|k| {
            ranges[k].0 + (ranges[k].1 - ranges[k].0) * rng.random::<f64>()
        });
        let c = cell(p);
        let mut free = true;
        'search: for dz in -1isize..=1 {
            for dy in -1isize..=1 {
                for dx in -1isize..=1 {
                    let d = [dx, dy, dz];
                    let nc: [usize; 3] = std::array::from_fn(|k| {
                        (c[k] as isize + d[k]).rem_euclid(dims[k] as isize) as usize
                    });
                    for &j in &grid[flat(nc)] {
                        if distance2(params, p, positions[j as usize]) < 1.0 {
                            free = false;
                            break 'search;
                        }
                    }
                }
            }
        }
        if free {
            grid[flat(c)].push(positions.len() as u32);
            positions.push(p);
        }
    }
    Some(positions)
}

/// A rectangular lattice with the largest spacing that holds N sites, sites taken in a random
/// order and displaced at random by up to half the free space, so no two spheres overlap.
fn lattice_placement(params: &EdmdParams, rng: &mut Pcg64) -> Result<Vec<[f64; 3]>, EngineError> {
    let n = params.particles;
    let ranges = centre_ranges(params);
    let periodic = [true, !params.geometry.walls, true];
    // sites along an axis for spacing s: periodic axes hold floor(extent / s), wall axes
    // floor(span / s) + 1 (sites on both contact planes)
    let sites = |k: usize, s: f64| -> usize {
        let span = ranges[k].1 - ranges[k].0;
        if periodic[k] {
            (span / s).floor() as usize
        } else {
            (span / s).floor() as usize + 1
        }
    };
    // bisect for the largest spacing with enough sites
    let (mut lo, mut hi) = (
        0.0f64,
        params
            .geometry
            .extents()
            .into_iter()
            .fold(f64::MAX, f64::min),
    );
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (0..3).map(|k| sites(k, mid)).product::<usize>() >= n {
            lo = mid
        } else {
            hi = mid
        }
    }
    let spacing = lo;
    if spacing < 1.0 {
        return Err(unplaceable(params, "a lattice"));
    }
    let counts: [usize; 3] = std::array::from_fn(|k| sites(k, spacing));
    let step: [f64; 3] = std::array::from_fn(|k| {
        let span = ranges[k].1 - ranges[k].0;
        if periodic[k] {
            span / counts[k] as f64
        } else if counts[k] > 1 {
            span / (counts[k] - 1) as f64
        } else {
            0.0
        }
    });
    let total = counts.iter().product::<usize>();
    let mut order: Vec<usize> = (0..total).collect();
    // Fisher-Yates with the seeded RNG
    for i in (1..total).rev() {
        let j = rng.random_range(0..=i);
        order.swap(i, j);
    }
    let slack = 0.5 * (spacing - 1.0) * (1.0 - 1e-9);
    let mut positions = Vec::with_capacity(n);
    for &site in order.iter().take(n) {
        let idx = [
            site % counts[0],
            (site / counts[0]) % counts[1],
            site / (counts[0] * counts[1]),
        ];
        let mut p = [0.0; 3];
        for k in 0..3 {
            let base = ranges[k].0
                + idx[k] as f64 * step[k]
                + if periodic[k] { 0.5 * step[k] } else { 0.0 };
            let jitter = slack * (2.0 * rng.random::<f64>() - 1.0);
            p[k] = (base + jitter).clamp(ranges[k].0, ranges[k].1);
            if periodic[k] {
                p[k] = p[k].rem_euclid(ranges[k].1);
            }
        }
        positions.push(p);
    }
    Ok(positions)
}

/// A perfect fcc crystal: the periodic box must be a cube holding N = 4 m^3 sites.
fn fcc_placement(params: &EdmdParams) -> Result<Vec<[f64; 3]>, EngineError> {
    let g = &params.geometry;
    let m = ((params.particles / 4) as f64).cbrt().round() as usize;
    if g.walls || 4 * m * m * m != params.particles || g.length != g.width || g.width != g.height {
        return Err(EngineError::InvalidParams(format!(
            "fcc placement needs a periodic cube and N = 4 m^3 particles (got N = {})",
            params.particles
        )));
    }
    let a = g.length / m as f64;
    if a / std::f64::consts::SQRT_2 < 1.0 {
        return Err(unplaceable(params, "an fcc lattice"));
    }
    let basis = [
        [0.25, 0.25, 0.25],
        [0.75, 0.75, 0.25],
        [0.75, 0.25, 0.75],
        [0.25, 0.75, 0.75],
    ];
    let mut positions = Vec::with_capacity(params.particles);
    for iz in 0..m {
        for iy in 0..m {
            for ix in 0..m {
                for b in &basis {
                    positions.push([
                        (ix as f64 + b[0]) * a,
                        (iy as f64 + b[1]) * a,
                        (iz as f64 + b[2]) * a,
                    ]);
                }
            }
        }
    }
    Ok(positions)
}
