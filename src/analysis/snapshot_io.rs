//! Snapshot files for viewers: particles as extended XYZ (ASE, OVITO, ParaView) and the
//! coarse-grained fields as a legacy VTK rectilinear grid of cell data (ParaView, VisIt,
//! meshio), named by the run's clock so that a directory of them sorts in time order.

use super::AnalysisSettings;
use super::fields::{Fields, Grid, PARTICLE_RADIUS};
use crate::engine::{Clock, Particles, Snapshot};
use std::io::{BufWriter, Write};
use std::path::Path;

/// The chemical symbol written as every particle's `species`. ASE needs a real element symbol
/// (else it reads the dummy "X"); argon, the textbook simple fluid of hard spheres, is a label
/// only: mass and radius come from the file's own `masses` and `radius` columns (m = d = 1).
pub const XYZ_SPECIES: &str = "Ar";

/// The per-particle columns of the XYZ files, in the `Properties=` syntax of extended XYZ.
/// ASE maps `species` to its symbols, `pos` to positions and `masses` and `momenta` to its
/// arrays of those names (so `get_velocities()` = momenta / masses = the velocities); OVITO
/// maps `velo` to its Velocity property and `radius` to Radius. `omega` (angular velocity) is
/// an extra property for both.
pub const XYZ_PROPERTIES: &str =
    "species:S:1:pos:R:3:masses:R:1:momenta:R:3:velo:R:3:omega:R:3:radius:R:1";

/// The particle mass m = 1 (the reduced unit of all engines with particles).
const PARTICLE_MASS: f64 = 1.0;

/// Write `snapshot` as extended XYZ: line 1 N, line 2 the box as `Lattice` with `Origin`, the
/// columns [`XYZ_PROPERTIES`], `pbc` (periodic along x and z, walls along y unless the box is
/// periodic), `Time` and `collisions_per_particle`; then one line per particle.
pub fn write_xyz(path: impl AsRef<Path>, snapshot: &Snapshot) -> std::io::Result<()> {
    let particles = particles_of(snapshot)?;
    let file = std::fs::File::create(path.as_ref())?;
    let mut out = BufWriter::new(file);
    let g = &particles.geometry;
    writeln!(out, "{}", particles.len())?;
    writeln!(
        out,
        "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Origin=\"0 0 0\" Properties={XYZ_PROPERTIES} \
         pbc=\"T {} T\" Time={} collisions_per_particle={}",
        g.length,
        g.width,
        g.height,
        if g.walls { "F" } else { "T" },
        snapshot.progress.time,
        snapshot.progress.collisions_per_particle
    )?;
    let m = PARTICLE_MASS;
    for p in 0..particles.len() {
        let [x, y, z] = particles.positions[p];
        let [u, v, w] = particles.velocities[p];
        let [a, b, c] = particles.spin(p);
        writeln!(
            out,
            "{XYZ_SPECIES} {x} {y} {z} {m} {} {} {} {u} {v} {w} {a} {b} {c} {PARTICLE_RADIUS}",
            m * u,
            m * v,
            m * w
        )?;
    }
    out.flush()
}

/// Write the coarse-grained fields of `snapshot` (grid of `settings`) as a legacy VTK file
/// (binary, big-endian, as the format prescribes): a RECTILINEAR_GRID whose bounds are the
/// box, with the analysis grid's cells as cells and the fields as CELL_DATA:
/// - `count` (int): particle centres in the cell;
/// - `phi` (volume fraction), `T` and `theta` (translational and rotational temperature) and
///   `velocity` (cell mean), as the analysis computes them.
///
/// Undefined values are NaN (ParaView draws them in its NaN colour): `velocity` in empty
/// cells, `T` and `theta` in cells with fewer than 2 centres, and every field in the two wall
/// layers y < d/2 and y > W - d/2, which the analysis grid leaves out because no centre can
/// enter them (they are there so that the grid spans the box; their `count` is 0).
/// Binary because VTK's legacy reader cannot read NaN from ASCII files. x varies fastest.
pub fn write_vtk_density(
    path: impl AsRef<Path>,
    snapshot: &Snapshot,
    settings: &AnalysisSettings,
) -> std::io::Result<()> {
    let particles = particles_of(snapshot)?;
    let grid = Grid::new(&particles.geometry, particles.len(), settings);
    let fields = Fields::compute(particles, &grid);
    let box_extent = particles.geometry.extents();
    let edges: [Vec<f64>; 3] = [0, 1, 2].map(|a| cell_edges(&grid, a, box_extent[a]));
    // the analysis cell index along y of a y-layer of the file (None: a wall layer)
    let wall_below = usize::from(edges[1][0] < grid.origin[1]);
    let grid_j = |j: usize| j.checked_sub(wall_below).filter(|&g| g < grid.n[1]);
    let dims = edges.clone().map(|e| e.len() - 1);
    // the analysis cell of each cell of the file, in VTK order (x fastest, then y, then z)
    let cells: Vec<Option<usize>> = (0..dims[2])
        .flat_map(|k| (0..dims[1]).flat_map(move |j| (0..dims[0]).map(move |i| (i, j, k))))
        .map(|(i, j, k)| grid_j(j).map(|j| grid.linear([i, j, k])))
        .collect();
    let file = std::fs::File::create(path.as_ref())?;
    let mut out = BufWriter::new(file);
    writeln!(out, "# vtk DataFile Version 3.0")?;
    writeln!(
        out,
        "granflow cellwise fields t = {} collisions/particle = {}",
        snapshot.progress.time, snapshot.progress.collisions_per_particle
    )?;
    writeln!(out, "BINARY")?;
    writeln!(out, "DATASET RECTILINEAR_GRID")?;
    writeln!(
        out,
        "DIMENSIONS {} {} {}",
        edges[0].len(),
        edges[1].len(),
        edges[2].len()
    )?;
    for (axis, e) in ["X", "Y", "Z"].iter().zip(&edges) {
        writeln!(out, "{axis}_COORDINATES {} double", e.len())?;
        write_doubles(&mut out, e.iter().copied())?;
    }
    // the arrays as one FIELD: VTK's legacy reader reads every array of a FIELD, while of
    // several SCALARS it reads only the first unless told otherwise
    let n = cells.len();
    writeln!(out, "CELL_DATA {n}")?;
    writeln!(out, "FIELD cellwise 5")?;
    writeln!(out, "count 1 {n} int")?;
    for c in &cells {
        let count = c.map_or(0, |c| fields.count[c]);
        out.write_all(&i32::try_from(count).unwrap_or(i32::MAX).to_be_bytes())?;
    }
    writeln!(out)?;
    let count = |c: usize| fields.count[c];
    let scalars: [(&str, &Vec<f64>, u32); 3] = [
        ("phi", &fields.phi, 0),
        ("T", &fields.temperature, 2),
        ("theta", &fields.rotational_temperature, 2),
    ];
    for (name, values, min_count) in scalars {
        writeln!(out, "{name} 1 {n} double")?;
        write_doubles(
            &mut out,
            cells.iter().map(|c| match c {
                Some(c) if count(*c) >= min_count => values[*c],
                _ => f64::NAN,
            }),
        )?;
    }
    writeln!(out, "velocity 3 {n} double")?;
    write_doubles(
        &mut out,
        cells.iter().flat_map(|c| match c {
            Some(c) if count(*c) >= 1 => fields.velocity[*c],
            _ => [f64::NAN; 3],
        }),
    )?;
    out.flush()
}

/// The cell edges of the file along `axis`: the analysis grid's, with a wall layer added
/// below and above where the grid does not reach the box's faces 0 and `extent`.
fn cell_edges(grid: &Grid, axis: usize, extent: f64) -> Vec<f64> {
    let (origin, n, h) = (grid.origin[axis], grid.n[axis], grid.spacing()[axis]);
    let end = origin + grid.extent[axis];
    let mut edges = Vec::with_capacity(n + 3);
    if origin > 0.0 {
        edges.push(0.0);
    }
    edges.extend((0..n).map(|i| origin + i as f64 * h));
    edges.push(end);
    if end < extent {
        edges.push(extent);
    }
    edges
}

/// Binary doubles (big-endian, as legacy VTK requires) followed by the newline that ends the
/// data block.
fn write_doubles(out: &mut impl Write, values: impl Iterator<Item = f64>) -> std::io::Result<()> {
    for v in values {
        out.write_all(&v.to_be_bytes())?;
    }
    writeln!(out)
}

/// The particles of a snapshot, or an error for engines whose snapshots carry none.
fn particles_of(snapshot: &Snapshot) -> std::io::Result<&Particles> {
    snapshot
        .particles()
        .ok_or_else(|| std::io::Error::other("this engine's snapshots carry no particles to write"))
}

/// File names of the snapshots of one run, by the reading of its clock:
/// `<prefix>-<unit><reading>.<ext>`, e.g. `snapshot-cpp0000100.xyz` (collisions per particle),
/// `fields-steps0020000.vtk` (time steps), `snapshot-t0000012.5.xyz` (simulated time). The
/// integer part is zero-padded to at least 7 digits (more when the run is longer), and the
/// reading has as many decimals as the cadence and run length need (none when both are whole
/// numbers, at most 9), so that the names of a run sort in time order and viewers (OVITO,
/// ParaView) group them into one series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapshotNames {
    unit: &'static str,
    digits: usize,
    decimals: usize,
}

impl SnapshotNames {
    /// Names for a run of `length` on `clock` with a snapshot every `every`.
    pub fn new(clock: Clock, length: f64, every: f64) -> SnapshotNames {
        let whole = |x: f64, d: i32| {
            let scaled = x * 10f64.powi(d);
            (scaled - scaled.round()).abs() <= 1e-6 * scaled.abs().max(1.0)
        };
        let decimals = (0..=9)
            .find(|&d| whole(every, d) && whole(length, d))
            .unwrap_or(9) as usize;
        let digits = format!("{:.0}", length.abs().floor()).len().max(7);
        SnapshotNames {
            unit: clock.unit(),
            digits,
            decimals,
        }
    }

    /// The file name of the snapshot at `reading` on the run's clock.
    pub fn name(&self, prefix: &str, reading: f64, extension: &str) -> String {
        let width = if self.decimals == 0 {
            self.digits
        } else {
            self.digits + 1 + self.decimals
        };
        format!(
            "{prefix}-{}{:0width$.prec$}.{extension}",
            self.unit,
            reading,
            prec = self.decimals
        )
    }
}
