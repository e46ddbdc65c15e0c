//! Cell lists: the box divided into cells of side >= d, each holding the particles whose
//! centres it contains, so that a particle's collision partners lie in its own and the 26
//! adjacent cells. Members are stored in fixed-capacity slots (no allocation per event).
//!
//! Along a wall axis (y in the channel) the cells cover only the reachable centre positions
//! [a, W - a]: leaving an edge cell through its outer face is a wall collision.

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
        let c = ((x - self.origin) / self.side).floor();
        (c.max(0.0) as usize).min(self.count - 1)
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
            self.periodic.then(|| (0, self.extent))
        } else {
            Some((n as usize, 0.0))
        }
    }
}

/// Cell membership of all particles.
#[derive(Clone, Debug)]
pub struct CellGrid {
    pub axes: [AxisCells; 3],
    capacity: usize,
    /// members of cell c in members[c * capacity .. c * capacity + fill[c]]
    members: Vec<u32>,
    fill: Vec<u32>,
    /// cell and slot of each particle
    cell_of_particle: Vec<u32>,
    slot_of_particle: Vec<u32>,
}

impl CellGrid {
    /// An empty grid for `particles` particles.
    pub fn new(axes: [AxisCells; 3], particles: usize) -> Self {
        let cells = axes.iter().map(|a| a.count).product::<usize>();
        // no more centres fit in a cell than spheres of radius 1/2 in a box one diameter larger
        // at the densest packing (0.7405); the margin covers round-off at the faces
        let box_volume: f64 = axes.iter().map(|a| a.side + 1.0).product();
        let capacity = (0.7405 * box_volume / (std::f64::consts::PI / 6.0)).ceil() as usize + 2;
        CellGrid {
            axes,
            capacity,
            members: vec![0; cells * capacity],
            fill: vec![0; cells],
            cell_of_particle: vec![u32::MAX; particles],
            slot_of_particle: vec![0; particles],
        }
    }

    /// Number of cells.
    pub fn cell_count(&self) -> usize {
        self.fill.len()
    }

    /// Flat index of cell (cx, cy, cz).
    #[inline(always)]
    pub fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.axes[1].count + c[1]) * self.axes[0].count + c[0]
    }

    /// Cell coordinates of flat index `cell`.
    #[inline(always)]
    pub fn coords(&self, cell: usize) -> [usize; 3] {
        let (nx, ny) = (self.axes[0].count, self.axes[1].count);
        [cell % nx, (cell / nx) % ny, cell / (nx * ny)]
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

    /// Flat cell of particle `id`.
    #[inline(always)]
    pub fn cell_of(&self, id: u32) -> usize {
        self.cell_of_particle[id as usize] as usize
    }

    /// Particles in flat cell `cell`.
    #[inline(always)]
    pub fn members(&self, cell: usize) -> &[u32] {
        let start = cell * self.capacity;
        &self.members[start..start + self.fill[cell] as usize]
    }

    /// Put particle `id` into flat cell `cell`.
    pub fn insert(&mut self, id: u32, cell: usize) {
        if self.fill[cell] as usize == self.capacity {
            self.grow();
        }
        let slot = self.fill[cell];
        self.members[cell * self.capacity + slot as usize] = id;
        self.fill[cell] += 1;
        self.cell_of_particle[id as usize] = cell as u32;
        self.slot_of_particle[id as usize] = slot;
    }

    /// Take particle `id` out of its cell.
    pub fn remove(&mut self, id: u32) {
        let cell = self.cell_of_particle[id as usize] as usize;
        let slot = self.slot_of_particle[id as usize] as usize;
        let last = self.fill[cell] as usize - 1;
        let moved = self.members[cell * self.capacity + last];
        self.members[cell * self.capacity + slot] = moved;
        self.slot_of_particle[moved as usize] = slot as u32;
        self.fill[cell] -= 1;
        self.cell_of_particle[id as usize] = u32::MAX;
    }

    /// Move particle `id` to flat cell `cell`.
    #[inline]
    pub fn relocate(&mut self, id: u32, cell: usize) {
        self.remove(id);
        self.insert(id, cell);
    }

    /// Double the slots per cell (only if round-off ever packs more centres than expected).
    fn grow(&mut self) {
        let new_capacity = self.capacity * 2;
        let mut members = vec![0; self.fill.len() * new_capacity];
        for (cell, &fill) in self.fill.iter().enumerate() {
            let old = &self.members[cell * self.capacity..cell * self.capacity + fill as usize];
            members[cell * new_capacity..cell * new_capacity + fill as usize].copy_from_slice(old);
        }
        self.members = members;
        self.capacity = new_capacity;
    }

    /// Memory used, in bytes.
    pub fn bytes(&self) -> usize {
        4 * (self.members.len() + self.fill.len() + 2 * self.cell_of_particle.len())
    }
}
