//! Cell list and Verlet neighbour list with a skin, and the contact histories that survive its
//! rebuilds.
//!
//! A build (from the positions x_build, the positions at the build):
//! 1. the touching pairs of the old list are kept as (tag_a, tag_b, s), keyed by the tags
//!    (tag_a < tag_b), grouped by tag_a;
//! 2. a cell grid of cells at least (d_max + skin) wide; the particles are sorted by cell,
//!    by tag within a cell (a counting sort: the working order is a function of the
//!    positions alone, not of the order before), which keeps neighbours close in memory;
//! 3. every particle's *row*: all particles j with |x_i - x_j| < R_i + R_j + skin (minimum
//!    image), sorted by tag. A pair is *owned* by its lower tag, so a row is its *lower*
//!    part (partners of lower tag, whose pairs it does not own) followed by its owned part;
//!    owned pairs are numbered row by row (particle i owns pair_start[i] .. pair_start[i+1],
//!    in tag order), and each row entry holds the number of its pair;
//! 4. every particle's *incoming slots*, one per entry of its lower part, in tag order, all
//!    rows end to end: the pair kernel writes a pair's forces into the other's slot, so that
//!    the particle pass reads its lower part's forces in one contiguous run;
//! 5. the pair state (forces, history, touching) starts empty, with the kept histories put
//!    back by their tags.
//!
//! A particle's force is then (sum over its lower part, in tag order, of minus the pair
//! forces) + (sum over its owned pairs, in tag order, of the pair forces): the pair kernel
//! forms the second sum while it evaluates the owned pairs, the particle pass the first.
//!
//! The list is valid while no pair's separation can have changed by the skin since x_build:
//! the engine rebuilds when the box holding every particle's displacement x - x_build has a
//! diagonal longer than the skin (two displacements in it differ by at most that), which
//! lets a plug flow translate without rebuilds. Forces are summed in every row in tag order, so a
//! particle's force does not depend on the working order, the cell size, the skin or when
//! the list was built: only on the physical state (see [`super::reference`]).

use super::bodies::{Bodies, PermuteBuffers};
use super::domain::Domain;
use rayon::prelude::*;

/// Particles per parallel task in the list build.
const BUILD_CHUNK: usize = 256;
/// Pairs per parallel task when histories are put back.
const CARRY_CHUNK: usize = 4096;

/// What a pair's last evaluation gave its particles (zero when not touching).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PairOut {
    /// F on the owner (lower tag); the other receives -F
    pub force: [f64; 3],
    /// n x F_t: the owner's torque is -R_owner tor, the other's -R_other tor
    pub tor: [f64; 3],
}

/// A contact history kept across a rebuild or a checkpoint: (tag of the owner, tag of the
/// other, s).
pub type KeptContact = (u32, u32, [f64; 3]);

/// The cell grid of one build (also the bond search's, [`super::bond_order`]): cells at
/// least `reach` wide, x and z periodic when the domain is, y over [0, W].
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Grid {
    lo: [f64; 3],
    inv_width: [f64; 3],
    n: [usize; 3],
    periodic: [bool; 3],
}

impl Grid {
    pub(super) fn new(domain: &Domain, positions: &[[f64; 3]], reach: f64) -> Grid {
        let mut g = Grid::default();
        for k in 0..3 {
            let periodic = k == 2 || (k == 0 && domain.periodic_x);
            let (lo, hi) = if k == 0 && !domain.periodic_x {
                positions
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                        (a.min(x[0]), b.max(x[0]))
                    })
            } else {
                (0.0, domain.extent[k])
            };
            let span = (hi - lo).max(0.0);
            let n = ((span / reach).floor() as usize).clamp(1, 1 << 20);
            g.lo[k] = lo;
            g.n[k] = n;
            g.inv_width[k] = if span > 0.0 { n as f64 / span } else { 0.0 };
            g.periodic[k] = periodic;
        }
        g
    }

    pub(super) fn cells(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    #[inline]
    pub(super) fn coord(&self, x: &[f64; 3]) -> [usize; 3] {
        let mut c = [0; 3];
        for k in 0..3 {
            let f = ((x[k] - self.lo[k]) * self.inv_width[k]).floor();
            c[k] = if f.is_nan() || f < 0.0 {
                0
            } else {
                (f as usize).min(self.n[k] - 1)
            };
        }
        c
    }

    #[inline]
    pub(super) fn index(&self, c: [usize; 3]) -> usize {
        (c[0] * self.n[1] + c[1]) * self.n[2] + c[2]
    }

    /// The distinct neighbour coordinates of `c` along dimension k (itself included).
    #[inline]
    pub(super) fn around(&self, k: usize, c: usize) -> ([usize; 3], usize) {
        let n = self.n[k];
        let mut out = [0; 3];
        let mut len = 0;
        for o in [-1isize, 0, 1] {
            let t = c as isize + o;
            let t = if self.periodic[k] {
                t.rem_euclid(n as isize) as usize
            } else if t < 0 || t >= n as isize {
                continue;
            } else {
                t as usize
            };
            if !out[..len].contains(&t) {
                out[len] = t;
                len += 1;
            }
        }
        (out, len)
    }

    /// The neighbour cells of `c` along z (itself included) as at most two runs of
    /// consecutive coordinates (lo, hi), inclusive: cells consecutive in z are consecutive in
    /// [`Grid::index`], so a run is one range of the cell-sorted particles.
    #[inline]
    pub(super) fn z_runs(&self, c: usize) -> ([(usize, usize); 3], usize) {
        let (mut z, len) = self.around(2, c);
        z[..len].sort_unstable();
        let mut runs = [(0, 0); 3];
        let mut count = 0;
        for &t in &z[..len] {
            if count > 0 && runs[count - 1].1 + 1 == t {
                runs[count - 1].1 = t;
            } else {
                runs[count] = (t, t);
                count += 1;
            }
        }
        (runs, count)
    }
}

/// Counts of a build, for the statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BuildStats {
    pub pairs: usize,
    pub stride: usize,
    pub cells: usize,
}

/// The neighbour list with its pair slots and reused buffers.
#[derive(Clone, Debug, Default)]
pub struct NeighbourList {
    /// entries per row in `partners` and `entries` (the longest row of the build)
    pub stride: usize,
    /// length of each row
    pub row_len: Vec<u32>,
    /// row i: its partners (working indices) sorted by tag, at [i * stride, i * stride + len)
    pub partners: Vec<u32>,
    /// row i: the pair number of each partner
    pub entries: Vec<u32>,
    /// length of each row's lower part (partners of lower tag)
    pub lower: Vec<u32>,
    /// the pairs owned by particle i are pair_start[i] .. pair_start[i + 1]
    pub pair_start: Vec<u32>,
    /// the listed pairs (owner, other), working indices
    pub pairs: Vec<[u32; 2]>,
    /// per particle: the sums over its owned pairs of F and of -R tor (the pair kernel's
    /// part of its force and torque)
    pub owned_force: Vec<[f64; 3]>,
    pub owned_torque: Vec<[f64; 3]>,
    /// the incoming slots of particle i (one per entry of its lower row, in tag order) are
    /// in_start[i] .. in_start[i + 1]
    pub in_start: Vec<u32>,
    /// per pair: its slot among the other's incoming slots
    pub in_slot: Vec<u32>,
    /// per incoming slot: the forces of its pair's last evaluation (zero when not touching),
    /// written by the pair kernel, read in order by the other's gather
    pub incoming: Vec<PairOut>,
    /// per pair, parallel to `pairs`: the history s oriented from the owner, and whether it
    /// touched (kept apart: the pair kernel reads `touch` of every pair, `shear` only of the
    /// touching ones)
    pub shear: Vec<[f64; 3]>,
    pub touch: Vec<bool>,
    pub stats: BuildStats,
    // reused buffers
    kept: Vec<KeptContact>,
    kept_start: Vec<u32>,
    kept_sorted: Vec<(u32, [f64; 3])>,
    cell_of: Vec<u32>,
    cell_start: Vec<u32>,
    order: Vec<u32>,
    chunk_rows: Vec<Vec<u32>>,
    cursor: Vec<u32>,
    by_tag: Vec<u32>,
    permute: PermuteBuffers,
}

impl NeighbourList {
    /// The touching pairs of the current list as (owner tag, other tag, s).
    pub fn touching(&self, bodies: &Bodies) -> Vec<KeptContact> {
        let mut out = Vec::new();
        self.collect_touching(bodies, &mut out);
        out.sort_unstable_by_key(|c| (c.0, c.1));
        out
    }

    fn collect_touching(&self, bodies: &Bodies, out: &mut Vec<KeptContact>) {
        out.clear();
        for (p, &touch) in self.touch.iter().enumerate() {
            if touch {
                let [a, b] = self.pairs[p];
                out.push((
                    bodies.tag[a as usize],
                    bodies.tag[b as usize],
                    self.shear[p],
                ));
            }
        }
    }

    /// Rebuild at the current positions: keep the touching histories, x_build = x, sort the
    /// particles by cell, list, put the histories back.
    pub fn rebuild(&mut self, bodies: &mut Bodies, domain: &Domain, reach: f64, skin: f64) {
        let mut kept = std::mem::take(&mut self.kept);
        self.collect_touching(bodies, &mut kept);
        bodies.x_build.copy_from_slice(&bodies.x);
        self.build(bodies, domain, reach, skin, &kept);
        self.kept = kept;
    }

    /// Build from x_build (already set) with the given histories (a restore, or the start).
    pub fn build(
        &mut self,
        bodies: &mut Bodies,
        domain: &Domain,
        reach: f64,
        skin: f64,
        kept: &[KeptContact],
    ) {
        let n = bodies.len();
        self.group_kept(kept, n);
        let grid = Grid::new(domain, &bodies.x_build, reach);
        self.sort_by_cell(bodies, &grid);
        self.list_rows(bodies, domain, &grid, skin);
        self.number_pairs(bodies);
        self.number_incoming();
        self.put_back(bodies);
        self.stats = BuildStats {
            pairs: self.pairs.len(),
            stride: self.stride,
            cells: grid.cells(),
        };
    }

    /// Histories grouped by owner tag: those of tag t at kept_sorted[kept_start[t] ..
    /// kept_start[t + 1]].
    fn group_kept(&mut self, kept: &[KeptContact], n: usize) {
        self.kept_start.clear();
        self.kept_start.resize(n + 1, 0);
        for c in kept {
            self.kept_start[c.0 as usize + 1] += 1;
        }
        for t in 0..n {
            self.kept_start[t + 1] += self.kept_start[t];
        }
        self.kept_sorted.clear();
        self.kept_sorted.resize(kept.len(), (0, [0.0; 3]));
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.kept_start);
        for c in kept {
            let at = &mut self.cursor[c.0 as usize];
            self.kept_sorted[*at as usize] = (c.1, c.2);
            *at += 1;
        }
    }

    /// Stable counting sort of the particles by cell; `cell_start` indexes the cells.
    fn sort_by_cell(&mut self, bodies: &mut Bodies, grid: &Grid) {
        let n = bodies.len();
        let cells = grid.cells();
        self.cell_of.clear();
        self.cell_of.extend(
            bodies
                .x_build
                .iter()
                .map(|x| grid.index(grid.coord(x)) as u32),
        );
        self.cell_start.clear();
        self.cell_start.resize(cells + 1, 0);
        for &c in &self.cell_of {
            self.cell_start[c as usize + 1] += 1;
        }
        for c in 0..cells {
            self.cell_start[c + 1] += self.cell_start[c];
        }
        self.order.clear();
        self.order.resize(n, 0);
        self.cursor.clear();
        self.cursor.extend_from_slice(&self.cell_start[..cells]);
        // each cell's particles in tag order: the working order is a function of x_build
        // alone (not of the order before), so that order-dependent sums (the tallies, the
        // samples) are the same after a restore
        self.by_tag.clear();
        self.by_tag.resize(n, 0);
        for (i, &t) in bodies.tag.iter().enumerate() {
            self.by_tag[t as usize] = i as u32;
        }
        for &i in &self.by_tag {
            let at = &mut self.cursor[self.cell_of[i as usize] as usize];
            self.order[*at as usize] = i;
            *at += 1;
        }
        bodies.permute(&self.order, &mut self.permute);
    }

    /// Every particle's row: partners within R_i + R_j + skin, sorted by tag.
    fn list_rows(&mut self, bodies: &Bodies, domain: &Domain, grid: &Grid, skin: f64) {
        let n = bodies.len();
        let chunks = n.div_ceil(BUILD_CHUNK);
        self.chunk_rows.resize_with(chunks, Vec::new);
        self.row_len.clear();
        self.row_len.resize(n, 0);
        let cell_start = &self.cell_start;
        let xb = &bodies.x_build;
        let radius = &bodies.radius;
        let tag = &bodies.tag;
        self.row_len
            .par_chunks_mut(BUILD_CHUNK)
            .zip(self.chunk_rows.par_iter_mut())
            .enumerate()
            .for_each(|(c, (lens, rows))| {
                rows.clear();
                for (k, len) in lens.iter_mut().enumerate() {
                    let i = c * BUILD_CHUNK + k;
                    let start = rows.len();
                    let cc = grid.coord(&xb[i]);
                    let (ax, nx) = grid.around(0, cc[0]);
                    let (ay, ny) = grid.around(1, cc[1]);
                    let (zr, nz) = grid.z_runs(cc[2]);
                    for &cx in &ax[..nx] {
                        for &cy in &ay[..ny] {
                            for &(z_lo, z_hi) in &zr[..nz] {
                                // the run's cells are one range of particles; each is
                                // written at the row's end, which only a partner keeps
                                let lo = cell_start[grid.index([cx, cy, z_lo])] as usize;
                                let hi = cell_start[grid.index([cx, cy, z_hi]) + 1] as usize;
                                let mut at = rows.len();
                                rows.resize(at + (hi - lo), 0);
                                for j in lo..hi {
                                    let d = domain.min_image([
                                        xb[i][0] - xb[j][0],
                                        xb[i][1] - xb[j][1],
                                        xb[i][2] - xb[j][2],
                                    ]);
                                    let rsq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                                    let cut = radius[i] + radius[j] + skin;
                                    rows[at] = j as u32;
                                    at += ((rsq < cut * cut) & (j != i)) as usize;
                                }
                                rows.truncate(at);
                            }
                        }
                    }
                    rows[start..].sort_unstable_by_key(|&j| tag[j as usize]);
                    *len = (rows.len() - start) as u32;
                }
            });
        self.stride = self.row_len.iter().copied().max().unwrap_or(0) as usize;
        let stride = self.stride.max(1);
        self.partners.clear();
        self.partners.resize(n * stride, 0);
        let row_len = &self.row_len;
        self.partners
            .par_chunks_mut(BUILD_CHUNK * stride)
            .zip(self.chunk_rows.par_iter())
            .enumerate()
            .for_each(|(c, (out, rows))| {
                let mut at = 0;
                for k in 0..out.len() / stride {
                    let len = row_len[c * BUILD_CHUNK + k] as usize;
                    out[k * stride..k * stride + len].copy_from_slice(&rows[at..at + len]);
                    at += len;
                }
            });
    }

    /// Number the owned pairs row by row and point every row entry at its pair.
    fn number_pairs(&mut self, bodies: &Bodies) {
        let n = bodies.len();
        let stride = self.stride.max(1);
        let tag = &bodies.tag;
        // owned entries are the tail of each (tag-sorted) row
        self.lower.clear();
        self.lower.extend((0..n).map(|i| {
            let row = &self.partners[i * stride..i * stride + self.row_len[i] as usize];
            row.partition_point(|&j| tag[j as usize] < tag[i]) as u32
        }));
        self.pair_start.clear();
        self.pair_start.reserve(n + 1);
        let mut total = 0u32;
        for i in 0..n {
            self.pair_start.push(total);
            total += self.row_len[i] - self.lower[i];
        }
        self.pair_start.push(total);
        self.pairs.clear();
        for i in 0..n {
            let row = &self.partners[i * stride..i * stride + self.row_len[i] as usize];
            for &j in &row[self.lower[i] as usize..] {
                self.pairs.push([i as u32, j]);
            }
        }
        self.entries.clear();
        self.entries.resize(n * stride, 0);
        let (partners, row_len, lower, pair_start) =
            (&self.partners, &self.row_len, &self.lower, &self.pair_start);
        self.entries
            .par_chunks_mut(stride)
            .enumerate()
            .for_each(|(i, out)| {
                let row = &partners[i * stride..i * stride + row_len[i] as usize];
                let own = lower[i] as usize;
                for (k, &j) in row.iter().enumerate() {
                    out[k] = if k >= own {
                        pair_start[i] + (k - own) as u32
                    } else {
                        // the pair is j's: find i in j's row
                        let j = j as usize;
                        let rj = &partners[j * stride..j * stride + row_len[j] as usize];
                        let q = rj.partition_point(|&m| tag[m as usize] < tag[i]);
                        debug_assert_eq!(rj[q] as usize, i, "rows are symmetric");
                        pair_start[j] + (q - lower[j] as usize) as u32
                    };
                }
            });
    }

    /// Lay the lower rows end to end as the incoming slots, and give every pair its slot.
    fn number_incoming(&mut self) {
        let n = self.lower.len();
        self.in_start.clear();
        self.in_start.reserve(n + 1);
        let mut total = 0u32;
        for &l in &self.lower {
            self.in_start.push(total);
            total += l;
        }
        self.in_start.push(total);
        // every pair gets exactly one slot (the pair kernel's parallel writes rely on it)
        assert_eq!(total as usize, self.pairs.len(), "rows are symmetric");
        self.in_slot.clear();
        self.in_slot.resize(self.pairs.len(), u32::MAX);
        for i in 0..n {
            let row = &self.entries[i * self.stride..i * self.stride + self.lower[i] as usize];
            for (k, &p) in row.iter().enumerate() {
                let slot = &mut self.in_slot[p as usize];
                assert_eq!(*slot, u32::MAX, "one slot per pair");
                *slot = self.in_start[i] + k as u32;
            }
        }
    }

    /// Empty pair state, with the kept histories put back by tags.
    fn put_back(&mut self, bodies: &Bodies) {
        let np = self.pairs.len();
        self.incoming.clear();
        self.incoming.resize(np, PairOut::default());
        self.shear.clear();
        self.shear.resize(np, [0.0; 3]);
        self.touch.clear();
        self.touch.resize(np, false);
        let n = bodies.len();
        self.owned_force.clear();
        self.owned_force.resize(n, [0.0; 3]);
        self.owned_torque.clear();
        self.owned_torque.resize(n, [0.0; 3]);
        let (kept_start, kept_sorted, tag) = (&self.kept_start, &self.kept_sorted, &bodies.tag);
        self.shear
            .par_chunks_mut(CARRY_CHUNK)
            .zip(self.touch.par_chunks_mut(CARRY_CHUNK))
            .zip(self.pairs.par_chunks(CARRY_CHUNK))
            .for_each(|((shear, touch), pairs)| {
                for ((s, t), &[a, b]) in shear.iter_mut().zip(touch).zip(pairs) {
                    let (ta, tb) = (tag[a as usize], tag[b as usize]);
                    let group = &kept_sorted
                        [kept_start[ta as usize] as usize..kept_start[ta as usize + 1] as usize];
                    if let Some(&(_, kept)) = group.iter().find(|c| c.0 == tb) {
                        *s = kept;
                        *t = true;
                    }
                }
            });
    }

    /// Row i: the pair number of each partner, in tag order.
    #[inline]
    pub fn row(&self, i: usize) -> &[u32] {
        &self.entries[i * self.stride..i * self.stride + self.row_len[i] as usize]
    }

    /// The forces of pair p's last evaluation (zero when not touching).
    #[inline]
    pub fn pair_out(&self, p: usize) -> &PairOut {
        &self.incoming[self.in_slot[p] as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::super::bodies::BodyState;
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64Mcg;

    fn bodies(n: usize, domain: &Domain, seed: u64) -> Bodies {
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let states: Vec<BodyState> = (0..n)
            .map(|_| {
                let d = [0.9, 1.0, 1.1][rng.random_range(0..3usize)];
                let mut x = [0.0; 3];
                for (k, xk) in x.iter_mut().enumerate() {
                    let lo = if k == 0 && !domain.periodic_x {
                        -3.0
                    } else {
                        0.0
                    };
                    *xk = lo + rng.random::<f64>() * (domain.extent[k] - lo);
                }
                BodyState::fresh(d, x, [0.0; 3], [0.0; 3])
            })
            .collect();
        Bodies::from_states(&states, 1e-4)
    }

    /// The list holds exactly the pairs within R_i + R_j + skin found by trying all pairs
    /// (the simple reference), each once, owned by the lower tag, and every row entry points
    /// at its pair with the right sign; small periodic boxes (one or two cells along a
    /// direction) and a non-periodic x included.
    #[test]
    fn the_list_is_the_all_pairs_list() {
        for (domain, n, skin) in [
            (Domain::new(7.0, 6.0, 5.0, true), 150, 0.1),
            (Domain::new(2.5, 6.0, 2.5, true), 20, 0.15),
            (Domain::new(3.7, 5.0, 3.3, true), 40, 0.3),
            (Domain::new(6.0, 6.0, 4.0, false), 120, 0.2),
        ] {
            let mut b = bodies(n, &domain, n as u64);
            let mut list = NeighbourList::default();
            list.build(&mut b, &domain, 1.1 + skin, skin, &[]);
            let mut expected = Vec::new();
            for i in 0..n {
                for j in 0..n {
                    if b.tag[i] >= b.tag[j] {
                        continue;
                    }
                    let d = domain.min_image([
                        b.x[i][0] - b.x[j][0],
                        b.x[i][1] - b.x[j][1],
                        b.x[i][2] - b.x[j][2],
                    ]);
                    let cut = b.radius[i] + b.radius[j] + skin;
                    if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < cut * cut {
                        expected.push((b.tag[i], b.tag[j]));
                    }
                }
            }
            expected.sort();
            let mut got: Vec<(u32, u32)> = list
                .pairs
                .iter()
                .map(|&[a, c]| (b.tag[a as usize], b.tag[c as usize]))
                .collect();
            got.sort();
            assert_eq!(got, expected);
            assert!(!expected.is_empty());
            for i in 0..n {
                let row = list.row(i);
                let mut last = None;
                for (k, &e) in row.iter().enumerate() {
                    let [a, c] = list.pairs[e as usize];
                    let lower = k < list.lower[i] as usize;
                    let (me, other) = if lower { (c, a) } else { (a, c) };
                    assert_eq!(me as usize, i);
                    let t = b.tag[other as usize];
                    assert_eq!(lower, t < b.tag[i]);
                    assert!(last.is_none_or(|l| l < t), "rows sorted by tag");
                    last = Some(t);
                    if lower {
                        let slot = list.in_start[i] as usize + k;
                        assert_eq!(list.in_slot[e as usize] as usize, slot);
                    } else {
                        let p = e as usize;
                        assert!(
                            (list.pair_start[i] as usize..list.pair_start[i + 1] as usize)
                                .contains(&p)
                        );
                    }
                }
            }
        }
    }

    /// Histories kept by tags come back on the same pairs after a rebuild that reorders.
    #[test]
    fn histories_survive_a_rebuild() {
        let domain = Domain::new(7.0, 6.0, 5.0, true);
        let mut b = bodies(150, &domain, 3);
        let mut list = NeighbourList::default();
        list.build(&mut b, &domain, 1.2, 0.1, &[]);
        for p in 0..list.pairs.len() {
            if p % 3 == 0 {
                list.touch[p] = true;
                list.shear[p] = [p as f64, 1.0, -2.0];
            }
        }
        let before = list.touching(&b);
        assert!(!before.is_empty());
        for x in &mut b.x {
            x[1] = (x[1] + 0.01).min(6.0);
        }
        list.rebuild(&mut b, &domain, 1.2, 0.1);
        assert_eq!(list.touching(&b), before);
    }
}
