//! Synthetic coarse-grained density fields of known structure with the shot noise of a real
//! box: Poisson counts in the cells of the grid the analysis uses (its default, 4 centres per
//! cell), drawn about a known relative density, at the N of W/d = 15, 30, 50 channels at
//! phi = 0.15 (the thesis' ch. 5 boxes). Seeded and deterministic; the records go through the
//! real analysis (`analyse_job`) as a run's would.
//!
//! The structures (density-waves vocabulary, thesis ch. 5; u = (y - d/2) / (W - d) across the
//! gridded width, xi = x / L, zeta = z / H; a dense band of peak 1 over a dilute base B):
//! - homogeneous: uniform;
//! - plug: a dense core about the centreline, uniform along x;
//! - S-wave with n humps: a band whose centre snakes as u_c = 1/2 + A sin(2 pi n xi + psi),
//!   optionally sharper, nearer the walls and with its thickness modulated along x;
//! - slug: a dense region localised along x spanning the width (symmetric about the centre);
//! - wavy slug: a slug whose x position shifts with y (an antisymmetric tilt);
//! - S-wave + slug: both at once;
//! - 3D waves: an S-wave whose density varies along z, and a slug whose x position varies
//!   along z (structure in every plane).
//!
//! The phases psi (and the slug's position) are random per snapshot: travelling structures,
//! which the power spectrum does not see.

use granflow::analysis::fields::Grid;
use granflow::analysis::{AnalysisSettings, SnapshotRecord};
use granflow::engine::BoxGeometry;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use std::f64::consts::PI;

/// Volume fraction of the thesis' ch. 5 boxes.
pub const PHI: f64 = 0.15;

/// Relative density of the dilute base (the band's peak is 1): a band at phi ~ 0.4 in a
/// gas at phi ~ 0.1, as in the thesis' contours.
const BASE: f64 = 0.2;

/// A channel box: L = `l_over_w` W, H = `h_over_w` W, walls along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SyntheticBox {
    pub l_over_w: f64,
    pub w: f64,
    pub h_over_w: f64,
}

impl SyntheticBox {
    pub fn geometry(&self) -> BoxGeometry {
        BoxGeometry {
            length: self.l_over_w * self.w,
            width: self.w,
            height: self.h_over_w * self.w,
            walls: true,
        }
    }

    /// N = round(phi L W H / (pi d^3 / 6)).
    pub fn particles(&self) -> usize {
        (PHI * self.geometry().volume() / (PI / 6.0)).round() as usize
    }
}

/// The thesis' L/W = 3 boxes at W/d = 15, 30 and 50 (H = W; N = 2901, 23 205, 107 430).
pub fn thesis_boxes() -> Vec<SyntheticBox> {
    [15.0, 30.0, 50.0]
        .map(|w| SyntheticBox {
            l_over_w: 3.0,
            w,
            h_over_w: 1.0,
        })
        .to_vec()
}

/// The tall box of the thesis' Fig. 5.20: L/W = 3, W/d = 50, H/d = 150 (N = 322 289).
pub fn tall_box() -> SyntheticBox {
    SyntheticBox {
        l_over_w: 3.0,
        w: 50.0,
        h_over_w: 3.0,
    }
}

/// A structure of known name.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Structure {
    Homogeneous,
    Plug,
    /// humps, thickness modulated along x
    SWave(u32, bool),
    Slug,
    WavySlug,
    /// humps of the S-wave
    SWaveSlug(u32),
    /// an S-wave with one hump whose density varies along z
    SWave3d,
    /// a slug whose x position varies along z
    Slug3d,
}

impl Structure {
    /// Every structure of the confusion table.
    pub fn all() -> Vec<Structure> {
        use Structure::*;
        vec![
            Homogeneous,
            Plug,
            SWave(1, false),
            SWave(2, false),
            SWave(3, false),
            SWave(1, true),
            SWave(2, true),
            SWave(3, true),
            Slug,
            WavySlug,
            SWaveSlug(1),
            SWaveSlug(2),
            SWave3d,
            Slug3d,
        ]
    }

    /// The row name of the confusion table.
    pub fn name(&self) -> String {
        use Structure::*;
        match *self {
            Homogeneous => "homogeneous".into(),
            Plug => "plug".into(),
            SWave(n, false) => format!("s-wave({n})"),
            SWave(n, true) => format!("s-wave({n}) thickness-modulated"),
            Slug => "slug".into(),
            WavySlug => "wavy-slug".into(),
            SWaveSlug(n) => format!("s-wave({n})+slug"),
            SWave3d => "s-wave(1) varying along z".into(),
            Slug3d => "slug varying along z".into(),
        }
    }

    /// The label the analysis must give (the label with its humps) and the 3D flag.
    pub fn expected(&self) -> (String, bool) {
        use Structure::*;
        match *self {
            Homogeneous => ("homogeneous".into(), false),
            Plug => ("plug".into(), false),
            SWave(n, _) => (format!("s-wave({n})"), false),
            Slug => ("slug".into(), false),
            WavySlug => ("wavy-slug".into(), false),
            SWaveSlug(n) => (format!("s-wave+slug({n})"), false),
            SWave3d => ("s-wave(1)".into(), true),
            Slug3d => ("slug".into(), true),
        }
    }

    /// Relative density at (xi, u, zeta) with phases `psi` (S-wave phase, slug position, z
    /// phase), each in [0, 1).
    /// `w` is the gridded width in d (the sharp band's width is in d).
    pub fn density(&self, xi: f64, u: f64, zeta: f64, psi: [f64; 3], w: f64) -> f64 {
        use Structure::*;
        let dense = match *self {
            Homogeneous => return 1.0,
            Plug => gauss(u - 0.5, 0.15),
            SWave(n, modulated) => band(xi, u, n, psi[0], modulated.then_some(w)),
            Slug => slug(xi, u, psi[1], 0.0),
            WavySlug => slug(xi, u, psi[1], 0.7),
            SWaveSlug(n) => (band(xi, u, n, psi[0], None) + slug(xi, u, psi[1], 0.0)).min(1.0),
            SWave3d => band(xi, u, 1, psi[0], None) * (0.6 + 0.4 * wave(zeta + psi[2])),
            Slug3d => slug(xi + 0.12 * wave(zeta + psi[2]), u, psi[1], 0.0),
        };
        BASE + (1.0 - BASE) * dense
    }
}

fn gauss(s: f64, sigma: f64) -> f64 {
    (-0.5 * (s / sigma).powi(2)).exp()
}

/// cos(2 pi t)
fn wave(t: f64) -> f64 {
    (2.0 * PI * t).cos()
}

/// Periodic distance on the unit circle.
fn circular(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(1.0);
    d.min(1.0 - d)
}

/// An S-shaped band with `n` humps: centre 1/2 + 0.3 sin(2 pi (n xi + psi)), width (standard
/// deviation) 0.06 of the channel. `modulated`: a sharper band reaching nearer the walls, as
/// in the W/d = 50 evolution figures (centre 1/2 + 0.34 sin, width 2.5 d, at least 0.05 of the
/// channel, varying by +-50 % along x, thinnest at the crests); `w` is the gridded width in d.
fn band(xi: f64, u: f64, n: u32, psi: f64, modulated: Option<f64>) -> f64 {
    let phase = 2.0 * PI * (n as f64 * xi + psi);
    let (amplitude, width) = if let Some(w) = modulated {
        let sharp = (2.5 / w).max(0.05);
        (0.34, sharp * (1.0 + 0.5 * (2.0 * phase).cos()))
    } else {
        (0.3, 0.06)
    };
    gauss(u - (0.5 + amplitude * phase.sin()), width)
}

/// A slug centred at xi0 (length: standard deviation L / 12 along x, W / 4 in a box of
/// L = 3 W), denser at the centreline; `tilt`: its position shifts by tilt (u - 1/2) / 3 of L
/// across the width (a wavy slug).
fn slug(xi: f64, u: f64, xi0: f64, tilt: f64) -> f64 {
    let centre = xi0 + tilt * (u - 0.5) / 3.0;
    gauss(circular(xi, centre), 1.0 / 12.0) * (1.0 - 0.5 * (2.0 * u - 1.0).powi(2))
}

/// A Poisson variate of mean `mean` (Knuth's product of uniforms, in pieces of mean <= 16).
fn poisson(mean: f64, rng: &mut Pcg64) -> u32 {
    let mut left = mean;
    let mut k = 0;
    while left > 0.0 {
        let piece = left.min(16.0);
        left -= piece;
        let limit = (-piece).exp();
        let mut p = rng.random::<f64>();
        while p > limit {
            k += 1;
            p *= rng.random::<f64>();
        }
    }
    k
}

/// One snapshot record of `structure` in `b`: Poisson counts in the default grid's cells
/// about the structure's density (scaled so the mean total is the box's N), phases drawn
/// from `rng`, at clock `cpp` (collisions per particle = time), with a flat energy trace
/// and exact balances (a steady run).
pub fn record(b: &SyntheticBox, structure: Structure, cpp: f64, rng: &mut Pcg64) -> SnapshotRecord {
    let g = b.geometry();
    let particles = b.particles();
    let grid = Grid::new(&g, particles, &AnalysisSettings::default());
    let [n1, n2, n3] = grid.n;
    let psi = [
        rng.random::<f64>(),
        rng.random::<f64>(),
        rng.random::<f64>(),
    ];
    let centre = |i: usize, n: usize| (i as f64 + 0.5) / n as f64;
    let mut density = vec![0.0; grid.cells()];
    for i in 0..n1 {
        for j in 0..n2 {
            for k in 0..n3 {
                density[grid.linear([i, j, k])] = structure.density(
                    centre(i, n1),
                    centre(j, n2),
                    centre(k, n3),
                    psi,
                    grid.extent[1],
                );
            }
        }
    }
    let scale = particles as f64 / density.iter().sum::<f64>();
    let counts: Vec<u32> = density.iter().map(|&r| poisson(scale * r, rng)).collect();
    let [xy, xz, yz] = granflow::analysis::fields::plane_counts(&counts, &grid);
    // the box's N (the Poisson total differs from it by ~sqrt(N): a fixed N keeps the
    // records on one common grid and the balances exact)
    let n = particles as u64;
    let nf = n as f64;
    SnapshotRecord {
        collisions_per_particle: cpp,
        time: cpp,
        translational_energy: 1.0,
        rotational_energy: 0.1,
        particles: n,
        box_extent: g.extents(),
        gravity: 1.0,
        inertia_factor: 0.4,
        grid: grid.n.map(|k| k as u32),
        grid_volume: grid.volume(),
        counts_xy: xy,
        counts_xz: xz,
        counts_yz: yz,
        profile: Vec::new(),
        wall_impulse_x: nf * cpp,
        momentum_x: 0.0,
        energy_dissipated: nf * cpp,
        gravity_work: nf * cpp,
        suppressed_dissipation: 0.0,
        pair_collisions: 0,
        tc_elastic_collisions: 0,
    }
}

/// `snapshots` records of `structure` in `b` (every 100 collisions per particle), seeded.
pub fn window(
    b: &SyntheticBox,
    structure: Structure,
    snapshots: usize,
    seed: u64,
) -> Vec<SnapshotRecord> {
    let mut rng = Pcg64::seed_from_u64(seed);
    (0..snapshots)
        .map(|s| record(b, structure, 100.0 * (s + 1) as f64, &mut rng))
        .collect()
}
