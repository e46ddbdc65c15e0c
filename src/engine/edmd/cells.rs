//! Cell lists: the box divided into cells of side >= d, each holding the particles whose
//! centres it contains, so that a particle's collision partners lie in its own and the 26
//! adjacent cells. Each cell is a singly linked list threaded through one per-particle array
//! (no allocation per event; 4 bytes per cell, so the heads of a neighbourhood share a few
//! cache lines even at low density, where most cells are empty). The grid does not store
//! which cell a particle is in: its owner keeps that beside the particle's other data (one
//! cache line per particle instead of four in a large system), and names it when it moves or
//! takes out a particle. Removal walks the cell's list to the particle (cells hold about one
//! particle at phi = 0.15 and a few in dense flows), which costs less than keeping the
//! back links up to date.
//!
//! Along a wall axis (y in the channel) the cells cover only the reachable centre positions
//! [a, W - a]: leaving an edge cell through its outer face is a wall collision.

use super::huge::HugeArray;
use super::images::Image;
use crate::engine::prefetch::prefetch_at;
use std::mem::MaybeUninit;
use strength_reduce::StrengthReducedU32;

/// Geometry of the grid along one axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisCells {
    /// number of cells
    pub count: usize,
    /// cell side (>= d)
    pub side: f64,
    /// coordinate of the lower face of cell 0
    pub origin: f64,
    /// box extent along the axis (period for periodic axes)
    pub extent: f64,
    /// periodic (true) or bounded by walls (false)
    pub periodic: bool,
}

impl AxisCells {
    /// Cells at least `min_side` wide over `[origin, origin + span]`.
    pub fn new(origin: f64, span: f64, extent: f64, periodic: bool, min_side: f64) -> Self {
        let count = ((span / min_side).floor() as usize).max(1);
        AxisCells {
            count,
            side: span / count as f64,
            origin,
            extent,
            periodic,
        }
    }

    /// Cell containing coordinate `x` (clamped into the grid).
    #[inline(always)]
    pub fn cell_of(&self, x: f64) -> usize {
        // `as` truncates towards zero and saturates (negative and NaN give 0): the floor for
        // x >= origin, the clamp below it, without a call to floor
        (((x - self.origin) / self.side) as usize).min(self.count - 1)
    }

    /// Lower and upper face of cell `c`.
    #[inline(always)]
    pub fn faces(&self, c: usize) -> (f64, f64) {
        let lo = self.origin + c as f64 * self.side;
        (
            lo,
            if c + 1 == self.count {
                self.origin + self.count as f64 * self.side
            } else {
                lo + self.side
            },
        )
    }

    /// Neighbour of cell `c` at offset `dc` in {-1, 0, 1}, with the shift to add to a
    /// position in that cell to bring it next to cell `c` (periodic image); None past a wall.
    #[inline(always)]
    pub fn neighbour(&self, c: usize, dc: isize) -> Option<(usize, f64)> {
        let n = c as isize + dc;
        if n < 0 {
            self.periodic.then(|| (self.count - 1, -self.extent))
        } else if n as usize >= self.count {
            self.periodic.then_some((0, self.extent))
        } else {
            Some((n as usize, 0.0))
        }
    }
}

/// End of a cell's list.
const EMPTY: u32 = u32::MAX;

/// Cells around a particle, each with the periodic image in which its members are near: the
/// 27 of a full search, or the 9 that become adjacent when the particle crosses a face. Kept
/// as up to three options per axis, each a part of the flat index and of the image code, so
/// visiting a cell costs two additions.
#[derive(Clone, Copy, Debug)]
pub struct Neighbourhood {
    /// per axis: (flat-index part, image-code part) of each option
    parts: [[(u32, u8); 3]; 3],
    counts: [usize; 3],
}

impl Neighbourhood {
    /// Call `visit(flat cell, image)` for every cell.
    #[inline(always)]
    pub fn for_each(&self, mut visit: impl FnMut(usize, Image)) {
        self.for_each_option(|cell, image, _| visit(cell, image));
    }

    /// Call `visit(flat cell, image, option per axis)` for every cell; the options index the
    /// cells along each axis in the order of `AxisSteps::around`.
    #[inline(always)]
    fn for_each_option(&self, mut visit: impl FnMut(usize, Image, [usize; 3])) {
        for (oz, &(z, kz)) in self.parts[2][..self.counts[2]].iter().enumerate() {
            for (oy, &(y, ky)) in self.parts[1][..self.counts[1]].iter().enumerate() {
                for (ox, &(x, kx)) in self.parts[0][..self.counts[0]].iter().enumerate() {
                    visit(
                        (z + y + x) as usize,
                        Image::from_code(kz + ky + kx),
                        [ox, oy, oz],
                    );
                }
            }
        }
    }
}

/// Squared distances, per axis and option of a neighbourhood (see
/// [`CellGrid::slab_distances`]), from a point to the slab of cells of that option.
pub type SlabDistances = [[f64; 3]; 3];

/// The cells next to one cell along one axis, precomputed as (flat-index part, image-code part)
/// so that a search only adds them up.
#[derive(Clone, Copy, Debug)]
struct AxisSteps {
    /// the cells at offsets -1, 0, +1 that exist (fewer past a wall), in that order
    around: [(u32, u8); 3],
    around_count: u8,
    /// the cell at offset -1 and at +1, if it exists
    lower: Option<(u32, u8)>,
    upper: Option<(u32, u8)>,
}

impl AxisSteps {
    /// The steps from cell `c` of `axis`, whose flat index has stride `stride` and whose image
    /// code has stride `image_stride`.
    fn new(axis: &AxisCells, c: usize, stride: usize, image_stride: u8) -> Self {
        let part = |dc: isize| {
            axis.neighbour(c, dc).map(|(n, shift)| {
                let k = 1 + (shift > 0.0) as u8 - (shift < 0.0) as u8;
                ((n * stride) as u32, k * image_stride)
            })
        };
        let mut steps = AxisSteps {
            around: [(0, 0); 3],
            around_count: 0,
            lower: part(-1),
            upper: part(1),
        };
        for option in [steps.lower, part(0), steps.upper].into_iter().flatten() {
            steps.around[steps.around_count as usize] = option;
            steps.around_count += 1;
        }
        steps
    }
}

/// Cell membership of all particles.
#[derive(Clone, Debug)]
pub struct CellGrid {
    pub axes: [AxisCells; 3],
    /// per axis and cell coordinate: the neighbouring cells along that axis
    steps: [Vec<AxisSteps>; 3],
    /// first particle of each cell, or EMPTY
    head: HugeArray<u32>,
    /// next particle in the same cell, or EMPTY
    next: HugeArray<u32>,
    /// per axis and cell coordinate: the cell's lower and upper face (`AxisCells::faces`)
    faces: [Vec<(f64, f64)>; 3],
    /// whether a walk prefetches the heads before reading them: only for grids whose heads
    /// do not fit in a first-level cache, where the pass hides latency (at 32 000 particles
    /// and phi = 0.15); for smaller grids it costs more instructions than it hides
    prefetch_heads: bool,
    /// the cell counts along x and y as divisors by multiplication (a crossing turns a flat
    /// index into coordinates; a hardware division would cost more than the rest of it)
    count_x: StrengthReducedU32,
    count_y: StrengthReducedU32,
}

/// The particles of one cell, in list order.
pub struct CellMembers<'a> {
    next: &'a [u32],
    current: u32,
}

impl Iterator for CellMembers<'_> {
    type Item = u32;

    #[inline(always)]
    fn next(&mut self) -> Option<u32> {
        if self.current == EMPTY {
            return None;
        }
        let id = self.current;
        self.current = self.next[id as usize];
        Some(id)
    }
}

impl CellGrid {
    /// Bytes of list heads that a first-level data cache holds (64 KiB on the machines
    /// measured; smaller caches only make the prefetch pass start later).
    const HEADS_IN_CACHE: usize = 64 * 1024;

    /// An empty grid for `particles` particles.
    pub fn new(axes: [AxisCells; 3], particles: usize) -> Self {
        let cells = axes.iter().map(|a| a.count).product::<usize>();
        assert!(
            cells < u32::MAX as usize,
            "{cells} cells: flat cell indices are 32-bit"
        );
        let strides = [1, axes[0].count, axes[0].count * axes[1].count];
        let image_strides = [1, 3, 9];
        let steps = std::array::from_fn(|a| {
            (0..axes[a].count)
                .map(|c| AxisSteps::new(&axes[a], c, strides[a], image_strides[a]))
                .collect()
        });
        CellGrid {
            axes,
            steps,
            head: HugeArray::new(cells, EMPTY),
            next: HugeArray::new(particles, EMPTY),
            faces: std::array::from_fn(|a| (0..axes[a].count).map(|c| axes[a].faces(c)).collect()),
            prefetch_heads: cells * std::mem::size_of::<u32>() > Self::HEADS_IN_CACHE,
            count_x: StrengthReducedU32::new(axes[0].count as u32),
            count_y: StrengthReducedU32::new(axes[1].count as u32),
        }
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.head.len()
    }

    /// Flat index of cell (cx, cy, cz).
    #[inline(always)]
    pub fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.axes[1].count + c[1]) * self.axes[0].count + c[0]
    }

    /// Cell coordinates of flat index `cell`.
    #[inline(always)]
    pub fn coords(&self, cell: usize) -> [usize; 3] {
        let (row, x) = StrengthReducedU32::div_rem(cell as u32, self.count_x);
        let (z, y) = StrengthReducedU32::div_rem(row, self.count_y);
        [x as usize, y as usize, z as usize]
    }

    /// Cell coordinates containing position `p`.
    #[inline(always)]
    pub fn locate(&self, p: [f64; 3]) -> [usize; 3] {
        [
            self.axes[0].cell_of(p[0]),
            self.axes[1].cell_of(p[1]),
            self.axes[2].cell_of(p[2]),
        ]
    }

    /// The 27 cells around flat cell `cell` (fewer past a wall).
    #[inline(always)]
    pub fn around(&self, cell: usize) -> Neighbourhood {
        self.around_coords(self.coords(cell))
    }

    /// The 27 cells around the cell at `coords` (fewer past a wall).
    #[inline(always)]
    pub fn around_coords(&self, coords: [usize; 3]) -> Neighbourhood {
        let mut hood = Neighbourhood {
            parts: [[(0, 0); 3]; 3],
            counts: [0; 3],
        };
        for a in 0..3 {
            let steps = &self.steps[a][coords[a]];
            hood.parts[a] = steps.around;
            hood.counts[a] = steps.around_count as usize;
        }
        hood
    }

    /// The 9 cells that became adjacent when a particle entered flat cell `cell` across its
    /// upper (true) or lower face along `axis` (fewer past a wall).
    #[inline(always)]
    pub fn entered(&self, cell: usize, axis: usize, upper: bool) -> Neighbourhood {
        self.entered_at(self.coords(cell), axis, upper)
    }

    /// `entered` for the cell at `coords`.
    #[inline(always)]
    pub fn entered_at(&self, coords: [usize; 3], axis: usize, upper: bool) -> Neighbourhood {
        let mut hood = self.around_coords(coords);
        let steps = &self.steps[axis][coords[axis]];
        match if upper { steps.upper } else { steps.lower } {
            Some(part) => {
                hood.parts[axis][0] = part;
                hood.counts[axis] = 1;
            }
            None => hood.counts[axis] = 0,
        }
        hood
    }

    /// Lower and upper face along `axis` of the cells at coordinate `c` (as
    /// `AxisCells::faces`, from a table).
    #[inline(always)]
    pub fn faces(&self, axis: usize, c: usize) -> (f64, f64) {
        self.faces[axis][c]
    }

    /// Particles in flat cell `cell` (the most recently inserted first).
    #[inline(always)]
    pub fn members(&self, cell: usize) -> CellMembers<'_> {
        CellMembers {
            next: &self.next,
            current: self.head[cell],
        }
    }

    /// Squared distances from point `p`, in the cell at `coords`, to the slabs of the cells
    /// around it (`around_coords`): per axis, the options' slabs are at distance p - lo below,
    /// 0 in the cell's own and hi - p above (0 for a point outside its cell on that side).
    #[inline(always)]
    pub fn slab_distances(&self, coords: [usize; 3], p: [f64; 3]) -> SlabDistances {
        std::array::from_fn(|a| {
            let steps = &self.steps[a][coords[a]];
            let (lo, hi) = self.faces[a][coords[a]];
            let below = (p[a] - lo).max(0.0);
            let above = (hi - p[a]).max(0.0);
            let mut d2 = [0.0; 3];
            let mut option = 0;
            if steps.lower.is_some() {
                d2[0] = below * below;
                option = 1;
            }
            // the own cell (0), then the upper one
            if steps.upper.is_some() {
                d2[option + 1] = above * above;
            }
            d2
        })
    }

    /// Visit every member `j` of the cells of `hood`, with the image of its cell, in cell and
    /// list order, issuing the loads before any waits on another: read the cells' heads,
    /// keeping the occupied cells; prefetch each first member's link and, through
    /// `prefetch_record`, its record; then walk the lists (later members' records are the
    /// caller's to prefetch). Large grids prefetch the heads first (`prefetch_heads`).
    #[inline(always)]
    pub fn walk(
        &self,
        hood: &Neighbourhood,
        prefetch_record: impl Fn(u32),
        visit: impl FnMut(u32, Image),
    ) {
        self.walk_where(hood, |_| true, prefetch_record, visit);
    }

    /// As [`CellGrid::walk`], over the cells of `hood` within reach: the cells whose slabs
    /// (`distances`, from [`CellGrid::slab_distances`]) add up to less than `reach2`; the
    /// others are dropped with the empty ones (their heads are read, their members never).
    #[inline(always)]
    pub fn walk_within(
        &self,
        hood: &Neighbourhood,
        distances: &SlabDistances,
        reach2: f64,
        prefetch_record: impl Fn(u32),
        visit: impl FnMut(u32, Image),
    ) {
        self.walk_where(
            hood,
            |[ox, oy, oz]| distances[2][oz] + distances[1][oy] + distances[0][ox] < reach2,
            prefetch_record,
            visit,
        );
    }

    /// The walk over the cells of `hood` for which `wanted(options)` holds (decided without
    /// a branch, as whether a cell is empty).
    #[inline(always)]
    fn walk_where(
        &self,
        hood: &Neighbourhood,
        wanted: impl Fn([usize; 3]) -> bool,
        prefetch_record: impl Fn(u32),
        mut visit: impl FnMut(u32, Image),
    ) {
        if self.prefetch_heads {
            hood.for_each(|cell, _| prefetch_at(&self.head, cell));
        }
        // the occupied cells, gathered without a branch (whether a cell is empty is random)
        let mut occupied = [const { MaybeUninit::<(u32, Image)>::uninit() }; 27];
        let mut count = 0;
        hood.for_each_option(|cell, image, options| {
            // SAFETY: the neighbourhood tables hold only cells of this grid
            let first = unsafe { *self.head.get_unchecked(cell) };
            // SAFETY: `for_each` visits at most 27 cells and `count` grows by at most one per
            // cell, so it is below 27 here
            unsafe { occupied.get_unchecked_mut(count) }.write((first, image));
            count += ((first != EMPTY) & wanted(options)) as usize;
        });
        // SAFETY: entries 0..count were written above
        let occupied =
            unsafe { std::slice::from_raw_parts(occupied.as_ptr().cast::<(u32, Image)>(), count) };
        for &(first, _) in occupied {
            prefetch_at(&self.next, first as usize);
            prefetch_record(first);
        }
        for &(first, image) in occupied {
            let mut j = first;
            while j != EMPTY {
                visit(j, image);
                // SAFETY: every id in a cell list went in through `insert`, which indexes
                // `next` with it
                j = unsafe { *self.next.get_unchecked(j as usize) };
            }
        }
    }

    /// Put particle `id` (in no cell) at the front of flat cell `cell`.
    #[inline]
    pub fn insert(&mut self, id: u32, cell: usize) {
        self.next[id as usize] = std::mem::replace(&mut self.head[cell], id);
    }

    /// Take particle `id` out of flat cell `cell`, which holds it.
    #[inline]
    pub fn remove(&mut self, id: u32, cell: usize) {
        let after = self.next[id as usize];
        let mut link = &mut self.head[cell];
        while *link != id {
            assert!(*link != EMPTY, "particle {id} is not in cell {cell}");
            let j = *link as usize;
            link = &mut self.next[j];
        }
        *link = after;
    }

    /// Move particle `id` from flat cell `from` to flat cell `to`.
    #[inline]
    pub fn relocate(&mut self, id: u32, from: usize, to: usize) {
        self.remove(id, from);
        self.insert(id, to);
    }

    /// Memory used, in bytes.
    pub fn bytes(&self) -> usize {
        let faces: usize = self.faces.iter().map(Vec::len).sum();
        4 * (self.head.len() + self.next.len()) + std::mem::size_of::<(f64, f64)>() * faces
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;

    /// The cells at the given offsets per axis from `coords`, each with its image, computed
    /// directly from `AxisCells::neighbour` (the reference for the precomputed tables).
    fn block_directly(
        grid: &CellGrid,
        coords: [usize; 3],
        offsets: [&[isize]; 3],
    ) -> Vec<(usize, Image)> {
        let mut cells = Vec::new();
        for &dz in offsets[2] {
            for &dy in offsets[1] {
                for &dx in offsets[0] {
                    let steps = [(0, dx), (1, dy), (2, dz)]
                        .map(|(a, d)| grid.axes[a].neighbour(coords[a], d));
                    if let [Some(x), Some(y), Some(z)] = steps {
                        let k =
                            [x.1, y.1, z.1].map(|shift| (shift > 0.0) as i8 - (shift < 0.0) as i8);
                        cells.push((grid.index([x.0, y.0, z.0]), Image::new(k)));
                    }
                }
            }
        }
        cells
    }

    /// The neighbourhoods built from the per-axis tables, in their visiting order, are the
    /// cells and images computed directly, for periodic and wall axes of 1 to 4 cells.
    #[test]
    fn neighbourhood_tables_agree_with_direct_offsets() {
        for (counts, periodic) in [
            ([4, 3, 2], [true, true, true]),
            ([1, 4, 3], [true, false, true]),
            ([2, 1, 4], [true, false, true]),
        ] {
            let axes = std::array::from_fn(|a| {
                let span = counts[a] as f64;
                AxisCells::new(0.0, span, span, periodic[a], 1.0)
            });
            let grid = CellGrid::new(axes, 1);
            for (a, axis) in axes.iter().enumerate() {
                for c in 0..axis.count {
                    assert_eq!(grid.faces(a, c), axis.faces(c), "face table, axis {a}");
                }
            }
            for cell in 0..grid.cell_count() {
                let coords = grid.coords(cell);
                let mut got = Vec::new();
                grid.around(cell).for_each(|c, image| got.push((c, image)));
                assert_eq!(
                    got,
                    block_directly(&grid, coords, [&[-1, 0, 1]; 3]),
                    "around {coords:?}"
                );
                for axis in 0..3 {
                    for (upper, side) in [(true, [1]), (false, [-1])] {
                        let mut offsets: [&[isize]; 3] = [&[-1, 0, 1]; 3];
                        offsets[axis] = &side;
                        let mut got = Vec::new();
                        grid.entered(cell, axis, upper)
                            .for_each(|c, image| got.push((c, image)));
                        assert_eq!(
                            got,
                            block_directly(&grid, coords, offsets),
                            "entered {coords:?} {axis} {upper}"
                        );
                    }
                }
            }
        }
    }

    /// Walking only the cells within reach of a point visits every member within reach that
    /// the whole walk visits, in the same order, and skips cells: random points in grids with
    /// periodic and wall axes of 1 to 5 cells of side 1.2-2, reaches from 0.5 to 2.
    #[test]
    fn walk_within_reach_skips_only_cells_out_of_reach() {
        let mut rng = Pcg64::seed_from_u64(9);
        let mut skipped = 0;
        for (counts, periodic) in [
            ([5, 4, 3], [true, true, true]),
            ([1, 5, 2], [true, false, true]),
            ([4, 2, 5], [true, false, true]),
        ] {
            let side = 1.2 + 0.8 * rng.random::<f64>();
            let axes: [AxisCells; 3] = std::array::from_fn(|a| {
                let span = counts[a] as f64 * side;
                AxisCells::new(0.0, span, span, periodic[a], side)
            });
            let n = 300;
            let mut grid = CellGrid::new(axes, n);
            let points: Vec<[f64; 3]> = (0..n)
                .map(|_| std::array::from_fn(|a| axes[a].extent * rng.random::<f64>()))
                .collect();
            for (id, p) in points.iter().enumerate() {
                grid.insert(id as u32, grid.index(grid.locate(*p)));
            }
            let shift = |image: Image, a: usize| {
                image.offsets()[a] as f64
                    * if axes[a].periodic {
                        axes[a].extent
                    } else {
                        0.0
                    }
            };
            for round in 0..400 {
                let id = rng.random_range(0..n);
                let p = points[id];
                let reach = 0.5 + 1.5 * rng.random::<f64>();
                let near = |j: u32, image: Image| {
                    let q = points[j as usize];
                    let d2: f64 = (0..3)
                        .map(|a| (p[a] - (q[a] + shift(image, a))).powi(2))
                        .sum();
                    d2 < reach * reach
                };
                let coords = grid.locate(p);
                let hood = grid.around_coords(coords);
                let (mut all, mut within) = (Vec::new(), Vec::new());
                grid.walk(&hood, |_| {}, |j, image| all.push((j, image)));
                let slabs = grid.slab_distances(coords, p);
                grid.walk_within(
                    &hood,
                    &slabs,
                    reach * reach,
                    |_| {},
                    |j, image| within.push((j, image)),
                );
                let near_all: Vec<_> = all.iter().copied().filter(|&(j, k)| near(j, k)).collect();
                let near_within: Vec<_> = within
                    .iter()
                    .copied()
                    .filter(|&(j, k)| near(j, k))
                    .collect();
                assert_eq!(near_within, near_all, "round {round}: reach {reach}");
                skipped += all.len() - within.len();
            }
        }
        assert!(
            skipped > 1000,
            "only {skipped} members skipped: the pruning never acted"
        );
    }

    /// The linked lists hold exactly what a plain vector of member lists holds, through a
    /// random sequence of inserts, moves and removals.
    #[test]
    fn linked_cells_agree_with_plain_member_lists() {
        let axis = AxisCells::new(0.0, 4.0, 4.0, true, 1.0);
        let mut grid = CellGrid::new([axis; 3], 200);
        let cells = grid.cell_count();
        let mut reference: Vec<Vec<u32>> = vec![Vec::new(); cells];
        let mut located: Vec<Option<usize>> = vec![None; 200];
        let mut rng = Pcg64::seed_from_u64(5);
        for _ in 0..20_000 {
            let id = rng.random_range(0..200u32);
            let cell = rng.random_range(0..cells);
            match located[id as usize] {
                None => {
                    grid.insert(id, cell);
                    reference[cell].push(id);
                    located[id as usize] = Some(cell);
                }
                Some(old) => {
                    reference[old].retain(|&m| m != id);
                    if rng.random::<f64>() < 0.3 {
                        grid.remove(id, old);
                        located[id as usize] = None;
                    } else {
                        grid.relocate(id, old, cell);
                        reference[cell].push(id);
                        located[id as usize] = Some(cell);
                    }
                }
            }
            // the prefetching walk visits what the plain member lists of its cells hold
            let hood = grid.around(cell);
            let mut walked = Vec::new();
            grid.walk(&hood, |_| {}, |j, image| walked.push((j, image)));
            let mut listed = Vec::new();
            hood.for_each(|c, image| listed.extend(reference[c].iter().map(|&j| (j, image))));
            walked.sort_unstable();
            listed.sort_unstable();
            assert_eq!(walked, listed, "walk around cell {cell}");
            for c in [cell, rng.random_range(0..cells)] {
                let mut got: Vec<u32> = grid.members(c).collect();
                let mut want = reference[c].clone();
                got.sort_unstable();
                want.sort_unstable();
                assert_eq!(got, want, "cell {c}");
            }
        }
    }
}
