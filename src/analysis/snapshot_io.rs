//! Snapshot files for viewing: particles as extended XYZ (OVITO and ParaView open it directly)
//! and the coarse-grained fields as a legacy VTK STRUCTURED_POINTS volume (ParaView).

use super::AnalysisSettings;
use super::fields::{Fields, Grid, PARTICLE_RADIUS};
use crate::engine::{Particles, Snapshot};
use std::io::{BufWriter, Write};
use std::path::Path;

/// Write `snapshot` as extended XYZ: line 1 N, line 2 the box as `Lattice` (periodic along x
/// and z, walls along y unless the box is periodic) and the columns
/// `Properties=pos:R:3:velo:R:3:omega:R:3:radius:R:1`, then one line per particle.
pub fn write_xyz(path: impl AsRef<Path>, snapshot: &Snapshot) -> std::io::Result<()> {
    let particles = particles_of(snapshot)?;
    let file = std::fs::File::create(path.as_ref())?;
    let mut out = BufWriter::new(file);
    let g = &particles.geometry;
    writeln!(out, "{}", particles.len())?;
    writeln!(
        out,
        "Lattice=\"{} 0 0 0 {} 0 0 0 {}\" Origin=\"0 0 0\" \
         Properties=pos:R:3:velo:R:3:omega:R:3:radius:R:1 pbc=\"T {} T\" \
         Time={} collisions_per_particle={}",
        g.length,
        g.width,
        g.height,
        if g.walls { "F" } else { "T" },
        snapshot.progress.time,
        snapshot.progress.collisions_per_particle
    )?;
    for p in 0..particles.len() {
        let [x, y, z] = particles.positions[p];
        let [u, v, w] = particles.velocities[p];
        let [a, b, c] = particles.spin(p);
        writeln!(out, "{x} {y} {z} {u} {v} {w} {a} {b} {c} {PARTICLE_RADIUS}")?;
    }
    out.flush()
}

/// Write the coarse-grained fields of `snapshot` (grid of `settings`) as a legacy VTK
/// STRUCTURED_POINTS file: point data at the cell centres, scalars `phi` (volume fraction),
/// `T` and `theta` (temperatures, 0 in cells with fewer than 2 particles) and vectors
/// `velocity` (cell mean, 0 in empty cells). x varies fastest, as VTK expects.
pub fn write_vtk_density(
    path: impl AsRef<Path>,
    snapshot: &Snapshot,
    settings: &AnalysisSettings,
) -> std::io::Result<()> {
    let particles = particles_of(snapshot)?;
    let grid = Grid::new(&particles.geometry, particles.len(), settings);
    let fields = Fields::compute(particles, &grid);
    let file = std::fs::File::create(path.as_ref())?;
    let mut out = BufWriter::new(file);
    let [n1, n2, n3] = grid.n;
    let h = grid.spacing();
    writeln!(out, "# vtk DataFile Version 3.0")?;
    writeln!(
        out,
        "granflow cellwise fields t = {} collisions/particle = {}",
        snapshot.progress.time, snapshot.progress.collisions_per_particle
    )?;
    writeln!(out, "ASCII")?;
    writeln!(out, "DATASET STRUCTURED_POINTS")?;
    writeln!(out, "DIMENSIONS {n1} {n2} {n3}")?;
    writeln!(
        out,
        "ORIGIN {} {} {}",
        grid.origin[0] + 0.5 * h[0],
        grid.origin[1] + 0.5 * h[1],
        grid.origin[2] + 0.5 * h[2]
    )?;
    writeln!(out, "SPACING {} {} {}", h[0], h[1], h[2])?;
    writeln!(out, "POINT_DATA {}", grid.cells())?;
    let vtk_order =
        || (0..n3).flat_map(move |k| (0..n2).flat_map(move |j| (0..n1).map(move |i| [i, j, k])));
    for (name, values) in [
        ("phi", &fields.phi),
        ("T", &fields.temperature),
        ("theta", &fields.rotational_temperature),
    ] {
        writeln!(out, "SCALARS {name} double 1")?;
        writeln!(out, "LOOKUP_TABLE default")?;
        for c in vtk_order() {
            writeln!(out, "{}", values[grid.linear(c)])?;
        }
    }
    writeln!(out, "VECTORS velocity double")?;
    for c in vtk_order() {
        let [u, v, w] = fields.velocity[grid.linear(c)];
        writeln!(out, "{u} {v} {w}")?;
    }
    out.flush()
}

/// The particles of a snapshot, or an error for engines whose snapshots carry none.
fn particles_of(snapshot: &Snapshot) -> std::io::Result<&Particles> {
    snapshot
        .particles()
        .ok_or_else(|| std::io::Error::other("this engine's snapshots carry no particles to write"))
}
