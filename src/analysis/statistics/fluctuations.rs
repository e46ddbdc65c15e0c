//! The fluctuations every statistic of a snapshot starts from: each particle's slab across
//! the channel and its translational and rotational fluctuations C = c - <c>_k and
//! Omega = w - <w>_k about the mean of its fluctuation cell k (the slab cut into
//! `cells = [n_x, n_z]` columns along x and z; [1, 1]: the slab mean).
//!
//! Why the slab mean by default, where the thesis says "cellwise": a cell of N_k particles
//! pulls every fluctuation towards a Gaussian. For independent velocities, C_i = c_i - <c>_k
//! has the variance sigma^2 (1 - 1/N_k), which the factor sqrt(N_k / (N_k - 1)) restores
//! ([`Fluctuation::unbiased`]), but its excess kurtosis is multiplied by
//! [(1 - 1/N_k)^4 + (N_k - 1)/N_k^4] / (1 - 1/N_k)^2, 0.58 for N_k = 4 (the structure
//! analysis' cells) and 0.98 for N_k = 100; and two particles of one cell are anticorrelated,
//! <C_i C_j> / <C^2> = -1/(N_k - 1). So fluctuation cells must hold many particles: a slab of
//! the thesis' channels holds 110 (phi = 0.01) to 980 (phi = 0.1).

use crate::engine::Particles;

/// One particle's part in the statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fluctuation {
    /// slab across y (0 at y = 0)
    pub slab: usize,
    /// C = c - <c>_k
    pub c: [f64; 3],
    /// Omega = w - <w>_k (zero for spheres without spins)
    pub omega: [f64; 3],
    /// sqrt(N_k / (N_k - 1)): scales C and Omega to the unbiased variance; 0 when the particle
    /// is alone in its cell (no fluctuation is defined: it takes part in g(r) only)
    pub unbiased: f64,
}

impl Fluctuation {
    /// Whether the particle has a fluctuation (shares its cell with another).
    pub fn defined(&self) -> bool {
        self.unbiased > 0.0
    }
}

/// Slab of height `y` for `slabs` slabs over [0, width] (clamped: a centre on the boundary
/// belongs to the outermost slab).
pub fn slab_of(y: f64, width: f64, slabs: usize) -> usize {
    let u = y / width * slabs as f64;
    if u.is_nan() || u < 0.0 {
        0
    } else {
        (u as usize).min(slabs - 1)
    }
}

/// The fluctuations of every particle of a snapshot (in particle order).
pub fn fluctuations(p: &Particles, slabs: usize, cells: [usize; 2]) -> Vec<Fluctuation> {
    let [l, w, h] = p.geometry.extents();
    let (cx, cz) = (cells[0].max(1), cells[1].max(1));
    let column = |x: f64, extent: f64, n: usize| slab_of(x, extent, n);
    let cell_of: Vec<(usize, usize)> = p
        .positions
        .iter()
        .map(|r| {
            let slab = slab_of(r[1], w, slabs);
            let k = (column(r[0], l, cx) * slabs + slab) * cz + column(r[2], h, cz);
            (slab, k)
        })
        .collect();
    let cells = cx * slabs * cz;
    let mut count = vec![0u64; cells];
    let mut sum_c = vec![[0.0; 3]; cells];
    let mut sum_w = vec![[0.0; 3]; cells];
    for (i, &(_, k)) in cell_of.iter().enumerate() {
        count[k] += 1;
        let (c, s) = (p.velocities[i], p.spin(i));
        for a in 0..3 {
            sum_c[k][a] += c[a];
            sum_w[k][a] += s[a];
        }
    }
    cell_of
        .iter()
        .enumerate()
        .map(|(i, &(slab, k))| {
            let n = count[k] as f64;
            let (c, s) = (p.velocities[i], p.spin(i));
            Fluctuation {
                slab,
                c: [0, 1, 2].map(|a| c[a] - sum_c[k][a] / n),
                omega: [0, 1, 2].map(|a| s[a] - sum_w[k][a] / n),
                unbiased: if count[k] > 1 {
                    (n / (n - 1.0)).sqrt()
                } else {
                    0.0
                },
            }
        })
        .collect()
}
