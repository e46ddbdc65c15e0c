//! Initial state: non-overlapping placement at volume fraction phi and Gaussian velocities,
//! all drawn from a seeded portable RNG (PCG-64) with platform-independent arithmetic, so the
//! same parameters and seed give bitwise the same start on every machine (the thermalised
//! start, [`super::start`], then runs a deterministic elastic stage on it).

use super::{EdmdParams, Placement};
use crate::engine::{BoxGeometry, EngineError};
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
        Placement::Thermalised { .. } => super::start::random_packing(params, &mut rng)
            .ok_or_else(|| unplaceable(params, "a random packing (thermalise > 0)"))?,
    };
    let n = positions.len();
    // equipartition: <c_a^2> = kT/m, <w_a^2> = kT/I with I = K m d^2 / 4
    let sigma_c = params.initial_temperature.sqrt();
    let sigma_w = (params.initial_temperature / (params.inertia_factor / 4.0)).sqrt();
    let velocities = zero_mean((0..n).map(|_| gaussian3(&mut rng, sigma_c)).collect());
    let angular_velocities = zero_mean((0..n).map(|_| gaussian3(&mut rng, sigma_w)).collect());
    let placed = InitialState {
        positions,
        velocities,
        angular_velocities,
    };
    match params.placement {
        Placement::Thermalised {
            collisions_per_particle,
        } => super::start::thermalise(params, placed, collisions_per_particle),
        _ => Ok(placed),
    }
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

pub(super) fn zero_mean(mut v: Vec<[f64; 3]>) -> Vec<[f64; 3]> {
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
pub(super) fn centre_ranges(g: &BoxGeometry) -> [(f64, f64); 3] {
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
    let ranges = centre_ranges(&params.geometry);
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

/// Lattice sites filling the box, and how far a sphere may be displaced from its site along
/// each axis without touching a neighbour.
struct Lattice {
    /// site positions, in the order their indices are drawn from
    sites: Vec<[f64; 3]>,
    /// largest displacement per axis
    jitter: f64,
}

/// N spheres on lattice sites taken in a random order, each displaced at random within its
/// share of the free space: the simple-cubic lattice where it leaves room between spheres,
/// else the checkerboard lattice (see [`checkerboard`]), which holds up to ~0.7 where the
/// simple-cubic one, at phi ~0.42-0.52 in a small channel, would make rows of spheres touch
/// (and the run stall at t = 0 in collisions at zero distance).
fn lattice_placement(params: &EdmdParams, rng: &mut Pcg64) -> Result<Vec<[f64; 3]>, EngineError> {
    let n = params.particles;
    let lattice = simple_cubic(params)
        .or_else(|| checkerboard(params))
        .ok_or_else(|| unplaceable(params, "a lattice"))?;
    let ranges = centre_ranges(&params.geometry);
    let periodic = periodic_axes(&params.geometry);
    let total = lattice.sites.len();
    let mut order: Vec<usize> = (0..total).collect();
    // Fisher-Yates with the seeded RNG
    for i in (1..total).rev() {
        let j = rng.random_range(0..=i);
        order.swap(i, j);
    }
    let mut positions = Vec::with_capacity(n);
    for &site in order.iter().take(n) {
        let mut p = [0.0; 3];
        for k in 0..3 {
            let jitter = lattice.jitter * (2.0 * rng.random::<f64>() - 1.0);
            p[k] = (lattice.sites[site][k] + jitter).clamp(ranges[k].0, ranges[k].1);
            if periodic[k] {
                p[k] = p[k].rem_euclid(ranges[k].1);
            }
        }
        positions.push(p);
    }
    Ok(positions)
}

/// Which axes are periodic: x and z always, y unless there are walls.
pub(super) fn periodic_axes(g: &BoxGeometry) -> [bool; 3] {
    [true, !g.walls, true]
}

/// Sites along one axis for the spacing `s` of a simple-cubic lattice: periodic axes hold
/// floor(extent / s), wall axes floor(span / s) + 1 (sites on both contact planes).
fn cubic_sites(span: f64, periodic: bool, s: f64) -> usize {
    if periodic {
        (span / s).floor() as usize
    } else {
        (span / s).floor() as usize + 1
    }
}

/// The rectangular lattice with the largest spacing s that holds N sites, if s > d (spheres
/// displaced by up to (s - d)/2 per axis never touch: its nearest sites are along the axes).
fn simple_cubic(params: &EdmdParams) -> Option<Lattice> {
    let n = params.particles;
    let ranges = centre_ranges(&params.geometry);
    let periodic = periodic_axes(&params.geometry);
    let sites = |k: usize, s: f64| cubic_sites(ranges[k].1 - ranges[k].0, periodic[k], s);
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
    if spacing <= 1.0 {
        return None;
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
    let sites = (0..total)
        .map(|site| {
            let idx = [
                site % counts[0],
                (site / counts[0]) % counts[1],
                site / (counts[0] * counts[1]),
            ];
            std::array::from_fn(|k| {
                ranges[k].0
                    + idx[k] as f64 * step[k]
                    + if periodic[k] { 0.5 * step[k] } else { 0.0 }
            })
        })
        .collect();
    Some(Lattice {
        sites,
        jitter: 0.5 * (spacing - 1.0) * (1.0 - 1e-9),
    })
}

/// The simple-cubic lattice's capacity with room between spheres: the sites at the smallest
/// spacing above d.
fn simple_cubic_capacity(g: &BoxGeometry) -> usize {
    let ranges = centre_ranges(g);
    let periodic = periodic_axes(g);
    let just_above_d = 1.0 + f64::EPSILON;
    (0..3)
        .map(|k| cubic_sites(ranges[k].1 - ranges[k].0, periodic[k], just_above_d))
        .product()
}

/// A grid of n points along one axis: periodic axes hold an even number at spacing
/// extent / n (so that the parity of the checkerboard continues across the boundary), wall
/// axes n points from contact plane to contact plane (one: in the middle).
#[derive(Clone, Copy, Debug)]
struct AxisGrid {
    count: usize,
    /// spacing h between neighbouring points (0 with a single point, which has none)
    step: f64,
    /// position of point 0
    first: f64,
    /// whether point i + 2 exists (or is point i's periodic image)
    has_second_neighbour: bool,
}

/// The grids along one axis: periodic axes hold an even number of points (so that the parity
/// of the checkerboard continues across the boundary), wall axes any number from contact
/// plane to contact plane; only spacings of at least d/2 (finer grids put same-parity points
/// closer than d).
#[derive(Clone, Copy, Debug)]
struct AxisChoices {
    /// centre range along the axis
    lo: f64,
    span: f64,
    periodic: bool,
}

impl AxisChoices {
    fn of(g: &BoxGeometry, k: usize) -> Self {
        let (lo, hi) = centre_ranges(g)[k];
        AxisChoices {
            lo,
            span: hi - lo,
            periodic: periodic_axes(g)[k],
        }
    }

    /// Number of grids; grid `index` (0: the coarsest) has more points than grid index - 1.
    fn len(&self) -> usize {
        if self.periodic {
            self.span.floor() as usize
        } else {
            (2.0 * self.span).floor() as usize + 1
        }
    }

    /// Grid `index` (below `len`).
    fn grid(&self, index: usize) -> AxisGrid {
        if self.periodic {
            let count = 2 * (index + 1);
            let step = self.span / count as f64;
            AxisGrid {
                count,
                step,
                first: self.lo + 0.5 * step,
                has_second_neighbour: true,
            }
        } else {
            let count = index + 1;
            AxisGrid {
                count,
                step: if count > 1 {
                    self.span / (count - 1) as f64
                } else {
                    0.0
                },
                first: if count > 1 {
                    self.lo
                } else {
                    self.lo + 0.5 * self.span
                },
                has_second_neighbour: count > 2,
            }
        }
    }

    /// The indices of the grids within `reach` grids of the one whose spacing is nearest
    /// `step` (all of them on short axes).
    fn around(&self, step: f64, reach: usize) -> std::ops::Range<usize> {
        let count = if self.periodic {
            self.span / step
        } else {
            self.span / step + 1.0
        };
        let index = if self.periodic {
            count / 2.0 - 1.0
        } else {
            count - 1.0
        };
        let index = (index.round().max(0.0) as usize).min(self.len().saturating_sub(1));
        index.saturating_sub(reach)..(index + reach + 1).min(self.len())
    }
}

/// Every grid along axis `k`, coarsest first.
#[cfg(test)]
fn axis_grids(g: &BoxGeometry, k: usize) -> Vec<AxisGrid> {
    let axis = AxisChoices::of(g, k);
    (0..axis.len()).map(|index| axis.grid(index)).collect()
}

/// The points (i, j, k) of three axis grids with i + j + k even. With equal spacings h this is
/// the face-centred cubic lattice (nearest distance h sqrt 2, phi up to 0.74); stretched to
/// fill a box, its nearest distances are the diagonals of the faces, hypot(h_a, h_b), and the
/// second neighbours along an axis, 2 h_a.
#[derive(Clone, Copy, Debug)]
struct Checkerboard([AxisGrid; 3]);

impl Checkerboard {
    /// Number of points with an even index sum.
    fn count(&self) -> usize {
        let all: usize = self.0.iter().map(|a| a.count).product();
        let odd_axes: usize = self.0.iter().map(|a| a.count % 2).product();
        (all + odd_axes) / 2
    }

    /// Distance between the nearest points.
    fn nearest_distance(&self) -> f64 {
        let mut nearest = f64::INFINITY;
        for a in 0..3 {
            if self.0[a].has_second_neighbour {
                nearest = nearest.min(2.0 * self.0[a].step);
            }
            for b in a + 1..3 {
                if self.0[a].count > 1 && self.0[b].count > 1 {
                    nearest = nearest.min(self.0[a].step.hypot(self.0[b].step));
                }
            }
        }
        nearest
    }

    fn sites(&self) -> Vec<[f64; 3]> {
        let [x, y, z] = self.0;
        let mut sites = Vec::with_capacity(self.count());
        for k in 0..z.count {
            for j in 0..y.count {
                for i in 0..x.count {
                    if (i + j + k) % 2 == 0 {
                        sites.push([
                            x.first + i as f64 * x.step,
                            y.first + j as f64 * y.step,
                            z.first + k as f64 * z.step,
                        ]);
                    }
                }
            }
        }
        sites
    }
}

/// Grids searched along x and z around a spacing: in boxes longer than this many grids the
/// best lie within it of the spacing of an even fcc lattice (all grids are searched in shorter
/// boxes), and the search stays short in any box.
const GRID_REACH: usize = 24;

/// The spacing h of an fcc lattice at contact, nearest distance h sqrt 2 = d.
const CONTACT_STEP: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The pairs of grids along x and z within `GRID_REACH` grids of each spacing in `steps`.
fn xz_grids(g: &BoxGeometry, steps: &[f64]) -> Vec<(AxisGrid, AxisGrid)> {
    let (x, z) = (AxisChoices::of(g, 0), AxisChoices::of(g, 2));
    let within = |axis: &AxisChoices| {
        let mut indices: Vec<usize> = steps
            .iter()
            .flat_map(|&step| axis.around(step, GRID_REACH))
            .collect();
        indices.sort_unstable();
        indices.dedup();
        indices
    };
    let (xs, zs) = (within(&x), within(&z));
    xs.iter()
        .flat_map(|&i| zs.iter().map(move |&k| (x.grid(i), z.grid(k))))
        .collect()
}

/// The checkerboard lattice (see [`Checkerboard`]) with the largest nearest distance that
/// holds N sites, if that distance exceeds d: for each pair of grids along x and z (around
/// the spacing of an even fcc lattice of N sites and around that at contact), the coarsest
/// grid along y that gives N sites. Spheres are displaced within a ball of half the free
/// space (per axis by up to that over sqrt 3), so none touch.
fn checkerboard(params: &EdmdParams) -> Option<Lattice> {
    let n = params.particles;
    let g = &params.geometry;
    let y = AxisChoices::of(g, 1);
    let ranges = centre_ranges(g);
    let volume: f64 = ranges.iter().map(|(lo, hi)| (hi - lo).max(1.0)).product();
    let even_step = (volume / (2.0 * n as f64)).cbrt();
    let mut best: Option<(f64, Checkerboard)> = None;
    for (gx, gz) in xz_grids(g, &[even_step, CONTACT_STEP]) {
        let board = |index: usize| Checkerboard([gx, y.grid(index), gz]);
        // counts grow along the y grids: the first with N sites
        let index = partition_point(y.len(), |k| board(k).count() < n);
        if index == y.len() {
            continue;
        }
        let nearest = board(index).nearest_distance();
        if best.is_none_or(|(d, _)| nearest > d) {
            best = Some((nearest, board(index)));
        }
    }
    let (nearest, grid) = best.filter(|&(d, _)| d > 1.0)?;
    Some(Lattice {
        sites: grid.sites(),
        jitter: 0.5 * (nearest - 1.0) * (1.0 - 1e-9) / 3f64.sqrt(),
    })
}

/// The first index in 0..len for which `pred` is false (`pred` holds on a prefix), by
/// bisection.
fn partition_point(len: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0, len);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if pred(mid) { lo = mid + 1 } else { hi = mid }
    }
    lo
}

/// The largest number of spheres the lattice placement can put in the box without contact:
/// the simple-cubic lattice with room, or for each pair of grids along x and z around the
/// contact spacing the finest grid along y whose checkerboard keeps the spheres apart.
pub fn placement_capacity(g: &BoxGeometry) -> usize {
    let y = AxisChoices::of(g, 1);
    let checkerboard = xz_grids(g, &[CONTACT_STEP])
        .into_iter()
        .map(|(gx, gz)| {
            let board = |index: usize| Checkerboard([gx, y.grid(index), gz]);
            // nearest distances shrink along the y grids: the last one above d
            let apart = partition_point(y.len(), |k| board(k).nearest_distance() > 1.0);
            if apart == 0 {
                0
            } else {
                board(apart - 1).count()
            }
        })
        .max()
        .unwrap_or(0);
    checkerboard.max(simple_cubic_capacity(g))
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

#[cfg(test)]
mod tests {
    use super::*;

    fn channel(length: f64, width: f64, height: f64, particles: usize) -> EdmdParams {
        let mut p = EdmdParams::channel(length, width, height, 0.0, 7);
        p.particles = particles;
        p
    }

    /// Smallest minimum-image distance between any two points (the plain all-pairs reference).
    fn nearest_pair(params: &EdmdParams, points: &[[f64; 3]]) -> f64 {
        let mut nearest = f64::INFINITY;
        for (a, p) in points.iter().enumerate() {
            for q in &points[a + 1..] {
                nearest = nearest.min(distance2(params, *p, *q).sqrt());
            }
        }
        nearest
    }

    /// The checkerboard's nearest distance (face diagonals and second neighbours) is that of
    /// its sites, measured pair by pair, on grids of every shape: coarse and fine, one or two
    /// planes between the walls, stretched along any axis.
    #[test]
    fn checkerboard_nearest_distance_agrees_with_all_pairs() {
        let params = channel(6.0, 5.0, 4.0, 1);
        let grids: [Vec<AxisGrid>; 3] = [0, 1, 2].map(|k| axis_grids(&params.geometry, k));
        let mut checked = 0;
        for x in &grids[0] {
            for y in &grids[1] {
                for z in &grids[2] {
                    let board = Checkerboard([*x, *y, *z]);
                    let sites = board.sites();
                    assert_eq!(sites.len(), board.count());
                    let want = nearest_pair(&params, &sites);
                    let got = board.nearest_distance();
                    assert!(
                        (got - want).abs() < 1e-12 * want.max(1.0)
                            || (got.is_infinite() && sites.len() < 2),
                        "grid {:?}: nearest {got}, all pairs {want}",
                        board.0.map(|a| a.count)
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked >= 200, "only {checked} grids checked");
    }

    /// Dense channels, up to the placement's capacity, are placed without contact and inside
    /// the walls; one sphere more is refused.
    #[test]
    fn dense_channels_are_placed_without_contact_up_to_the_capacity() {
        for (length, width, height) in [(10.0, 10.0, 10.0), (15.0, 7.5, 6.0), (4.5, 4.5, 4.5)] {
            let mut params = channel(length, width, height, 1);
            let capacity = placement_capacity(&params.geometry);
            let volume = length * width * height;
            let phi_max = capacity as f64 * std::f64::consts::PI / 6.0 / volume;
            assert!(
                phi_max > 0.55,
                "capacity {capacity} is only phi = {phi_max}"
            );
            for phi in [0.42, 0.45, 0.5, phi_max] {
                params.particles =
                    ((phi * volume / (std::f64::consts::PI / 6.0)).round() as usize).min(capacity);
                let mut rng = Pcg64::seed_from_u64(3);
                let positions = lattice_placement(&params, &mut rng).expect("placeable");
                assert_eq!(positions.len(), params.particles);
                let nearest = nearest_pair(&params, &positions);
                assert!(nearest > 1.0, "phi = {phi}: spheres {nearest} apart");
                let ranges = centre_ranges(&params.geometry);
                for p in &positions {
                    for k in 0..3 {
                        assert!(ranges[k].0 <= p[k] && p[k] <= ranges[k].1, "{p:?} outside");
                    }
                }
            }
            params.particles = capacity + 1;
            let mut rng = Pcg64::seed_from_u64(3);
            assert!(
                lattice_placement(&params, &mut rng).is_err(),
                "capacity + 1 placed"
            );
        }
    }
}
