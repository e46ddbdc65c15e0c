//! Coarse-grained fields by cellwise averaging on an N1 x N2 x N3 grid (thesis 2.4 and 5.1.1):
//! cell counts, volume fraction phi, mean velocity U, translational temperature T and rotational
//! temperature theta, and the plane fields (xy, xz, yz) as averages over the third axis.
//!
//! The grid covers the region open to particle centres: along y, with walls, that is
//! [d/2, W - d/2] (a centre cannot come closer than d/2 to a wall). A random arrangement is then
//! uniform on the grid; a grid over [0, W] would show the excluded wall layers as a spurious
//! plug. Along x and z (periodic) the grid covers the whole box.

use super::AnalysisSettings;
use crate::engine::{BoxGeometry, Particles};

/// Particle radius d/2 in units of d (the engine's spheres have d = 1).
pub const PARTICLE_RADIUS: f64 = 0.5;

/// pi/6, the volume of a sphere of diameter d = 1.
pub const SPHERE_VOLUME: f64 = std::f64::consts::PI / 6.0;

/// The coarse-graining grid: `n` cells along x, y, z over the box `[origin, origin + extent]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    pub n: [usize; 3],
    pub origin: [f64; 3],
    pub extent: [f64; 3],
}

impl Grid {
    /// The grid of `settings` (or the default size) for a box holding `particles` spheres.
    ///
    /// Default: cubic-ish cells of edge a = (n_c / n)^(1/3), n = N / V_grid the number density
    /// and n_c = `settings.cell_particles` the mean number of centres per cell, rounded to whole
    /// cells per axis, at least [`MIN_CELLS`] per axis (so that k = 1 and k = 2 are resolved).
    pub fn new(geometry: &BoxGeometry, particles: usize, settings: &AnalysisSettings) -> Grid {
        let [l, w, h] = geometry.extents();
        let (y0, wy) = if geometry.walls && w > 2.0 * PARTICLE_RADIUS {
            (PARTICLE_RADIUS, w - 2.0 * PARTICLE_RADIUS)
        } else {
            (0.0, w)
        };
        let extent = [l, wy, h];
        let n = match settings.grid {
            Some(n) => n.map(|k| k.clamp(1, MAX_CELLS)),
            None => {
                let volume = l * wy * h;
                let density = particles.max(1) as f64 / volume;
                let edge = (settings.cell_particles / density).cbrt();
                extent.map(|e| {
                    let k = (e / edge).round();
                    if k.is_finite() {
                        (k as usize).clamp(MIN_CELLS, MAX_CELLS)
                    } else {
                        MIN_CELLS
                    }
                })
            }
        };
        Grid {
            n,
            origin: [0.0, y0, 0.0],
            extent,
        }
    }

    /// Number of cells N1 N2 N3.
    pub fn cells(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    /// Cell edges [dx, dy, dz].
    pub fn spacing(&self) -> [f64; 3] {
        [0, 1, 2].map(|a| self.extent[a] / self.n[a] as f64)
    }

    /// Volume of the gridded region.
    pub fn volume(&self) -> f64 {
        self.extent[0] * self.extent[1] * self.extent[2]
    }

    /// Index of the cell along `axis` holding coordinate `x` (clamped into the grid).
    pub fn index(&self, axis: usize, x: f64) -> usize {
        let u = (x - self.origin[axis]) / self.extent[axis] * self.n[axis] as f64;
        if u.is_nan() || u < 0.0 {
            0
        } else {
            (u as usize).min(self.n[axis] - 1)
        }
    }

    /// [i, j, k] of the cell holding position `r`.
    pub fn cell_of(&self, r: [f64; 3]) -> [usize; 3] {
        [
            self.index(0, r[0]),
            self.index(1, r[1]),
            self.index(2, r[2]),
        ]
    }

    /// Linear index of cell [i, j, k] (x slowest, z fastest).
    pub fn linear(&self, c: [usize; 3]) -> usize {
        (c[0] * self.n[1] + c[1]) * self.n[2] + c[2]
    }
}

/// Fewest cells per axis of a default grid.
pub const MIN_CELLS: usize = 4;

/// Most cells per axis of any grid (guards against degenerate boxes and settings).
pub const MAX_CELLS: usize = 4096;

/// Number of particle centres in each cell (linear index [`Grid::linear`]).
pub fn cell_counts(positions: &[[f64; 3]], grid: &Grid) -> Vec<u32> {
    let mut counts = vec![0u32; grid.cells()];
    for r in positions {
        counts[grid.linear(grid.cell_of(*r))] += 1;
    }
    counts
}

/// Column counts of the three planes from cell counts: xy (summed over z, index i n2 + j),
/// xz (summed over y, index i n3 + k), yz (summed over x, index j n3 + k).
pub fn plane_counts(counts: &[u32], grid: &Grid) -> [Vec<u32>; 3] {
    let [n1, n2, n3] = grid.n;
    let mut xy = vec![0u32; n1 * n2];
    let mut xz = vec![0u32; n1 * n3];
    let mut yz = vec![0u32; n2 * n3];
    for i in 0..n1 {
        for j in 0..n2 {
            for k in 0..n3 {
                let c = counts[grid.linear([i, j, k])];
                xy[i * n2 + j] += c;
                xz[i * n3 + k] += c;
                yz[j * n3 + k] += c;
            }
        }
    }
    [xy, xz, yz]
}

/// Cellwise averages of one snapshot.
#[derive(Clone, Debug, PartialEq)]
pub struct Fields {
    pub grid: Grid,
    /// centres per cell
    pub count: Vec<u32>,
    /// phi_c = (pi d^3 / 6) N_c / V_c
    pub phi: Vec<f64>,
    /// mean velocity U_c = (1/N_c) sum c_j (zero in empty cells)
    pub velocity: Vec<[f64; 3]>,
    /// T_c = sum |c_j - U_c|^2 / (3 (N_c - 1)) (zero for N_c < 2)
    pub temperature: Vec<f64>,
    /// theta_c = (I/m) sum |w_j - w_c|^2 / (3 (N_c - 1)), I/m = K d^2 / 4 (zero for N_c < 2)
    pub rotational_temperature: Vec<f64>,
}

impl Fields {
    /// Cellwise averages of `snapshot` on `grid`.
    pub fn compute(snapshot: &Particles, grid: &Grid) -> Fields {
        let m = grid.cells();
        let cells: Vec<usize> = snapshot
            .positions
            .iter()
            .map(|r| grid.linear(grid.cell_of(*r)))
            .collect();
        let CellMoments {
            count,
            mean_velocity: velocity,
            fluctuation_c2: sq_c,
            fluctuation_w2: sq_w,
            ..
        } = CellMoments::compute(snapshot, &cells, m);
        let inertia = snapshot.inertia_factor / 4.0;
        let pooled = |s: f64, n: u64| {
            if n < 2 {
                0.0
            } else {
                s / (3.0 * (n - 1) as f64)
            }
        };
        let cell_volume = grid.volume() / m as f64;
        Fields {
            grid: *grid,
            phi: count
                .iter()
                .map(|&n| SPHERE_VOLUME * n as f64 / cell_volume)
                .collect(),
            velocity,
            temperature: (0..m).map(|c| pooled(sq_c[c], count[c])).collect(),
            rotational_temperature: (0..m)
                .map(|c| inertia * pooled(sq_w[c], count[c]))
                .collect(),
            count: count.iter().map(|&n| n as u32).collect(),
        }
    }

    /// Plane field of phi: the average over the third axis (`plane` 0 = xy, 1 = xz, 2 = yz),
    /// laid out as [`plane_counts`].
    pub fn plane_phi(&self, plane: usize) -> Vec<f64> {
        let [xy, xz, yz] = plane_counts(&self.count, &self.grid);
        let m = self.grid.cells() as f64;
        let cell = SPHERE_VOLUME * m / self.grid.volume();
        let (counts, depth) = match plane {
            0 => (xy, self.grid.n[2]),
            1 => (xz, self.grid.n[1]),
            _ => (yz, self.grid.n[0]),
        };
        counts
            .iter()
            .map(|&c| cell * c as f64 / depth as f64)
            .collect()
    }
}

/// Velocity and angular-velocity moments of the particles in each cell, for any assignment
/// of particles to cells (the grid cells of [`Fields`], the fluctuation cells of profiles).
pub struct CellMoments {
    /// N_k, particles in cell k
    pub count: Vec<u64>,
    /// sum of c over cell k
    pub sum_velocity: Vec<[f64; 3]>,
    /// sum of w over cell k
    pub sum_spin: Vec<[f64; 3]>,
    /// <c>_k (0 in an empty cell)
    pub mean_velocity: Vec<[f64; 3]>,
    /// sum over cell k of |c - <c>_k|^2
    pub fluctuation_c2: Vec<f64>,
    /// sum over cell k of |w - <w>_k|^2
    pub fluctuation_w2: Vec<f64>,
}

impl CellMoments {
    /// Moments over `cells` cells; `cell_of[p]` is the cell of particle p.
    pub fn compute(snapshot: &Particles, cell_of: &[usize], cells: usize) -> CellMoments {
        let mut count = vec![0u64; cells];
        let mut sum_velocity = vec![[0.0; 3]; cells];
        let mut sum_spin = vec![[0.0; 3]; cells];
        for (p, &k) in cell_of.iter().enumerate() {
            count[k] += 1;
            for a in 0..3 {
                sum_velocity[k][a] += snapshot.velocities[p][a];
                sum_spin[k][a] += snapshot.spin(p)[a];
            }
        }
        let mean = |s: &[f64; 3], n: u64| s.map(|v| v / n.max(1) as f64);
        let mean_velocity: Vec<[f64; 3]> = (0..cells)
            .map(|k| mean(&sum_velocity[k], count[k]))
            .collect();
        let mean_spin: Vec<[f64; 3]> = (0..cells).map(|k| mean(&sum_spin[k], count[k])).collect();
        let mut fluctuation_c2 = vec![0.0; cells];
        let mut fluctuation_w2 = vec![0.0; cells];
        for (p, &k) in cell_of.iter().enumerate() {
            fluctuation_c2[k] += dist2(snapshot.velocities[p], mean_velocity[k]);
            fluctuation_w2[k] += dist2(snapshot.spin(p), mean_spin[k]);
        }
        CellMoments {
            count,
            sum_velocity,
            sum_spin,
            mean_velocity,
            fluctuation_c2,
            fluctuation_w2,
        }
    }
}

/// |a - b|^2.
pub fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}
