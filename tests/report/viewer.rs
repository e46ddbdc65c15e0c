//! Viewer files: the extended XYZ that ASE reads with velocities, masses
//! and a species (and OVITO with its standard properties), the legacy VTK cell data on a grid
//! whose bounds are the box with undefined values as NaN, the initial snapshot and file names
//! by the run clock. Written files are read back by a parser here, by ASE and by meshio (both
//! installed by `.ci/run`; missing, the tests fail).

use crate::common::{BIN, granflow_ok, scratch};
use granflow::analysis::fields::{Fields, Grid};
use granflow::analysis::{AnalysisSettings, SnapshotNames, write_vtk_density, write_xyz};
use granflow::engine::{BoxGeometry, Clock, Content, Counters, Particles, Progress, Snapshot};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;
use std::path::Path;
use std::process::Command;

// ---------- a snapshot with empty, single and crowded cells ----------

/// 150 particles in the lower half of x (so the upper half's cells are empty) and one alone in
/// the upper half, with random velocities and spins.
fn snapshot(walls: bool) -> Snapshot {
    let g = BoxGeometry {
        length: 12.0,
        width: 10.0,
        height: 8.0,
        walls,
    };
    let mut rng = Pcg64::seed_from_u64(7);
    let mut positions: Vec<[f64; 3]> = (0..150)
        .map(|_| {
            [
                rng.random::<f64>() * 6.0,
                0.5 + rng.random::<f64>() * 9.0,
                rng.random::<f64>() * 8.0,
            ]
        })
        .collect();
    positions.push([9.5, 5.2, 3.1]);
    let n = positions.len();
    let mut v3 = || [0, 1, 2].map(|_| rng.random::<f64>() * 2.0 - 1.0);
    let velocities = (0..n).map(|_| v3()).collect();
    let angular_velocities = (0..n).map(|_| v3()).collect();
    Snapshot {
        progress: Progress {
            time: 3.25,
            collisions_per_particle: 40.0,
            steps: 0,
            events: 0,
        },
        counters: Counters::default(),
        content: Content::Particles(Particles {
            geometry: g,
            inertia_factor: 0.4,
            gravity: 1.0,
            positions,
            velocities,
            angular_velocities,
            diameters: Vec::new(),
            translational_energy: 0.0,
            rotational_energy: 0.0,
            wall_momentum: [[0.0; 3]; 2],
            energy_dissipated: 0.0,
            gravity_work: 0.0,
            suppressed_dissipation: 0.0,
        }),
    }
}

// ---------- a reader of legacy VTK (the subset granflow writes) ----------

/// A legacy VTK rectilinear grid: header lines, coordinates and cell arrays by name.
#[derive(Debug)]
struct Vtk {
    header: Vec<String>,
    dimensions: [usize; 3],
    coordinates: [Vec<f64>; 3],
    /// name -> (components, values)
    arrays: Vec<(String, usize, Vec<f64>)>,
}

impl Vtk {
    fn array(&self, name: &str) -> &[f64] {
        &self
            .arrays
            .iter()
            .find(|(n, _, _)| n == name)
            .unwrap_or_else(|| panic!("no array {name}"))
            .2
    }
}

/// Parse a BINARY legacy VTK RECTILINEAR_GRID with CELL_DATA as one FIELD, checking the
/// layout strictly (every block ends with a newline, counts match).
fn read_vtk(path: &Path) -> Vtk {
    let bytes = std::fs::read(path).unwrap();
    let mut at = 0;
    // the text line at `at`, moving `at` past it; (the line, where the next one starts)
    let line = |at: &mut usize| {
        let end = *at + bytes[*at..].iter().position(|&b| b == b'\n').unwrap();
        let text = String::from_utf8(bytes[*at..end].to_vec()).unwrap();
        *at = end + 1;
        (text, *at)
    };
    let header: Vec<String> = (0..5).map(|_| line(&mut at).0).collect();
    assert_eq!(header[0], "# vtk DataFile Version 3.0");
    assert_eq!(header[2], "BINARY");
    assert_eq!(header[3], "DATASET RECTILINEAR_GRID");
    let dims: Vec<usize> = header[4]
        .strip_prefix("DIMENSIONS ")
        .unwrap()
        .split(' ')
        .map(|t| t.parse().unwrap())
        .collect();
    let dimensions = [dims[0], dims[1], dims[2]];
    // binary data of `count` values of `size` bytes starting at `start`, then a newline
    let block = |start: usize, count: usize, size: usize| {
        let end = start + count * size;
        assert_eq!(bytes[end], b'\n', "a data block ends with a newline");
        (&bytes[start..end], end + 1)
    };
    let doubles = |b: &[u8]| -> Vec<f64> {
        b.chunks(8)
            .map(|c| f64::from_be_bytes(c.try_into().unwrap()))
            .collect()
    };
    let mut coordinates: [Vec<f64>; 3] = Default::default();
    for (axis, name) in ["X", "Y", "Z"].iter().enumerate() {
        let (text, start) = line(&mut at);
        assert_eq!(
            text,
            format!("{name}_COORDINATES {} double", dimensions[axis])
        );
        let (data, next) = block(start, dimensions[axis], 8);
        coordinates[axis] = doubles(data);
        at = next;
    }
    let cells = (dimensions[0] - 1) * (dimensions[1] - 1) * (dimensions[2] - 1);
    assert_eq!(line(&mut at).0, format!("CELL_DATA {cells}"));
    let field = line(&mut at).0;
    let arrays_in_field: usize = field
        .strip_prefix("FIELD cellwise ")
        .unwrap()
        .parse()
        .unwrap();
    let mut arrays = Vec::new();
    for _ in 0..arrays_in_field {
        let (text, start) = line(&mut at);
        let parts: Vec<&str> = text.split(' ').collect();
        let (name, components, tuples, kind) = (
            parts[0].to_string(),
            parts[1].parse::<usize>().unwrap(),
            parts[2].parse::<usize>().unwrap(),
            parts[3],
        );
        assert_eq!(tuples, cells, "{name}: one tuple per cell");
        let size = if kind == "int" { 4 } else { 8 };
        let (data, next) = block(start, tuples * components, size);
        let values = match kind {
            "int" => data
                .chunks(4)
                .map(|c| i32::from_be_bytes(c.try_into().unwrap()) as f64)
                .collect(),
            "double" => doubles(data),
            other => panic!("unexpected type {other}"),
        };
        arrays.push((name, components, values));
        at = next;
    }
    assert_eq!(at, bytes.len(), "nothing after the last array");
    Vtk {
        header,
        dimensions,
        coordinates,
        arrays,
    }
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

// ---------- VTK ----------

#[test]
fn vtk_cell_data_spans_the_box_and_marks_undefined_values() {
    let dir = scratch("viewer-vtk");
    let settings = AnalysisSettings {
        grid: Some([6, 5, 4]),
        ..AnalysisSettings::default()
    };
    for walls in [true, false] {
        let snap = snapshot(walls);
        let particles = snap.particles().unwrap();
        let path = dir.join(format!("walls-{walls}.vtk"));
        write_vtk_density(&path, &snap, &settings).unwrap();
        let vtk = read_vtk(&path);
        assert!(vtk.header[1].contains("t = 3.25"), "{}", vtk.header[1]);
        // the grid's bounds are the box; along y between walls the two layers that no centre
        // can enter (d/2 each) are cells of their own
        let grid = Grid::new(&particles.geometry, particles.len(), &settings);
        let layers = if walls { 2 } else { 0 };
        assert_eq!(vtk.dimensions, [7, 5 + 1 + layers, 5]);
        for (axis, extent) in [12.0, 10.0, 8.0].into_iter().enumerate() {
            let c = &vtk.coordinates[axis];
            assert_eq!((c[0], *c.last().unwrap()), (0.0, extent), "axis {axis}");
            assert!(c.windows(2).all(|w| w[1] > w[0]));
        }
        if walls {
            let y = &vtk.coordinates[1];
            assert_eq!((y[1], y[2]), (0.5, 0.5 + 9.0 / 5.0));
            assert!((y[6] - 9.5).abs() < 1e-12);
        }
        let fields = Fields::compute(particles, &grid);
        let (count, phi) = (vtk.array("count"), vtk.array("phi"));
        let (t, theta, velocity) = (vtk.array("T"), vtk.array("theta"), vtk.array("velocity"));
        let [nx, ny, nz] = vtk.dimensions.map(|d| d - 1);
        let (mut empty, mut single, mut crowded) = (0, 0, 0);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    // x varies fastest
                    let c = i + nx * (j + ny * k);
                    let wall_layer = walls && (j == 0 || j == ny - 1);
                    if wall_layer {
                        assert_eq!(count[c], 0.0);
                        assert!(phi[c].is_nan() && t[c].is_nan() && theta[c].is_nan());
                        assert!(velocity[3 * c..3 * c + 3].iter().all(|v| v.is_nan()));
                        continue;
                    }
                    let g = grid.linear([i, j - usize::from(walls), k]);
                    let n = fields.count[g];
                    assert_eq!(count[c], n as f64);
                    assert!(same(phi[c], fields.phi[g]));
                    match n {
                        0 => empty += 1,
                        1 => single += 1,
                        _ => crowded += 1,
                    }
                    // T and theta need two centres, the mean velocity one
                    let (t_expect, theta_expect) = if n >= 2 {
                        (fields.temperature[g], fields.rotational_temperature[g])
                    } else {
                        (f64::NAN, f64::NAN)
                    };
                    assert!(same(t[c], t_expect), "T at {c}: {} vs {t_expect}", t[c]);
                    assert!(same(theta[c], theta_expect));
                    for a in 0..3 {
                        let expect = if n >= 1 {
                            fields.velocity[g][a]
                        } else {
                            f64::NAN
                        };
                        assert!(same(velocity[3 * c + a], expect));
                    }
                    if n >= 2 {
                        assert!(t[c] > 0.0);
                    }
                }
            }
        }
        assert!(
            empty > 0 && single > 0 && crowded > 0,
            "{empty} {single} {crowded}"
        );
        assert_eq!(
            count.iter().sum::<f64>(),
            particles.len() as f64,
            "every centre is in one cell"
        );
    }
}

// ---------- XYZ ----------

#[test]
fn xyz_columns_carry_species_masses_momenta_and_velocities() {
    let dir = scratch("viewer-xyz");
    let snap = snapshot(true);
    let particles = snap.particles().unwrap();
    let path = dir.join("s.xyz");
    write_xyz(&path, &snap).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], particles.len().to_string());
    assert_eq!(lines.len(), particles.len() + 2);
    for expected in [
        "Lattice=\"12 0 0 0 10 0 0 0 8\"",
        "Properties=species:S:1:pos:R:3:masses:R:1:momenta:R:3:velo:R:3:omega:R:3:radius:R:1",
        "pbc=\"T F T\"",
        "Time=3.25",
        "collisions_per_particle=40",
    ] {
        assert!(lines[1].contains(expected), "{expected} in {}", lines[1]);
    }
    for (p, line) in lines[2..].iter().enumerate() {
        let fields: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(fields.len(), 15);
        assert_eq!(fields[0], "Ar");
        let v: Vec<f64> = fields[1..].iter().map(|t| t.parse().unwrap()).collect();
        assert_eq!(&v[0..3], &particles.positions[p]);
        assert_eq!(v[3], 1.0, "mass");
        assert_eq!(&v[4..7], &particles.velocities[p], "momenta = m v, m = 1");
        assert_eq!(&v[7..10], &particles.velocities[p]);
        assert_eq!(&v[10..13], &particles.angular_velocities[p]);
        assert_eq!(v[13], 0.5, "radius");
    }
    // a periodic box is periodic in y too
    write_xyz(&path, &snapshot(false)).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.lines().nth(1).unwrap().contains("pbc=\"T T T\""));
}

// ---------- file names ----------

#[test]
fn snapshot_names_follow_the_clock_and_sort_in_time_order() {
    let cpp = SnapshotNames::new(Clock::CollisionsPerParticle, 30000.0, 100.0);
    assert_eq!(cpp.name("snapshot", 0.0, "xyz"), "snapshot-cpp0000000.xyz");
    assert_eq!(
        cpp.name("snapshot", 100.0, "xyz"),
        "snapshot-cpp0000100.xyz"
    );
    let steps = SnapshotNames::new(Clock::Steps, 26214400.0, 10000.0);
    assert_eq!(
        steps.name("fields", 20000.0, "vtk"),
        "fields-steps00020000.vtk",
        "wider than 7 digits when the run is longer"
    );
    let time = SnapshotNames::new(Clock::Time, 400.0, 2.5);
    assert_eq!(
        time.name("snapshot", 12.5, "xyz"),
        "snapshot-t0000012.5.xyz"
    );
    assert_eq!(time.name("snapshot", 0.0, "xyz"), "snapshot-t0000000.0.xyz");
    // readings that accumulate round-off still get the cadence's decimals
    let fine = SnapshotNames::new(Clock::Time, 1.0, 0.1);
    assert_eq!(
        fine.name("snapshot", 0.1 + 0.2, "xyz"),
        "snapshot-t0000000.3.xyz"
    );
    // names sort as their readings do
    for names in [cpp, steps, time, fine] {
        let readings = [0.0, 0.1, 0.5, 2.5, 10.0, 99.9, 100.0, 12500.0, 400000.0];
        let mut sorted: Vec<String> = readings
            .iter()
            .map(|&r| names.name("s", r, "xyz"))
            .collect();
        let in_order = sorted.clone();
        sorted.sort();
        assert_eq!(sorted, in_order);
    }
}

// ---------- end to end: sim, ASE, meshio ----------

/// Run a Python snippet on `files` (its `sys.argv[1:]`) that prints JSON; fail (with what to
/// install) when Python or the module is missing.
fn python(module: &str, script: &str, files: &[std::path::PathBuf]) -> serde_json::Value {
    let out = Command::new("python3")
        .arg("-c")
        .arg(script)
        .args(files)
        .output()
        .unwrap_or_else(|e| panic!("python3 is needed for this test: {e}"));
    assert!(
        out.status.success(),
        "python3 with {module} (`pip install {module}`; .ci/run installs it): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A number that Python wrote as its repr (`nan` included).
fn number(repr: &serde_json::Value) -> f64 {
    repr.as_str().unwrap().parse().unwrap()
}

/// The numbers of the XYZ file's particle lines, per particle (the species left out).
fn xyz_numbers(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(2)
        .map(|l| {
            l.split_whitespace()
                .skip(1)
                .map(|t| t.parse().unwrap())
                .collect()
        })
        .collect()
}

#[test]
fn sim_writes_files_that_ase_and_meshio_read() {
    let dir = scratch("viewer-sim");
    let (xyz, vtk) = (dir.join("xyz"), dir.join("vtk"));
    granflow_ok(&[
        "sim",
        "--length-over-width",
        "2",
        "--width-over-diameter",
        "6",
        "--height-over-diameter",
        "5",
        "--volume-fraction",
        "0.1",
        "--collisions-per-particle",
        "20",
        "--report-every",
        "10",
        "--grid",
        "4,3,3",
        "--xyz",
        xyz.to_str().unwrap(),
        "--vtk",
        vtk.to_str().unwrap(),
    ]);
    // the initial snapshot (t = 0) and one per report, named by collisions per particle
    let listing = |d: &Path| {
        let mut names: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        names
    };
    assert_eq!(
        listing(&xyz),
        [
            "snapshot-cpp0000000.xyz",
            "snapshot-cpp0000010.xyz",
            "snapshot-cpp0000020.xyz"
        ]
    );
    assert_eq!(
        listing(&vtk),
        [
            "fields-cpp0000000.vtk",
            "fields-cpp0000010.vtk",
            "fields-cpp0000020.vtk"
        ]
    );
    let first = std::fs::read_to_string(xyz.join("snapshot-cpp0000000.xyz")).unwrap();
    assert!(first.lines().nth(1).unwrap().contains(" Time=0 "));

    // ASE: positions, velocities (= momenta / masses), masses, cell, pbc and species
    let files: Vec<_> = listing(&xyz).iter().map(|n| xyz.join(n)).collect();
    let read_by_ase = python(
        "ase",
        "import json, sys, ase.io\n\
         r = lambda x: [[repr(float(v)) for v in row] for row in x.reshape(len(x), -1)]\n\
         out = []\n\
         for path in sys.argv[1:]:\n\
         \x20   a = ase.io.read(path)\n\
         \x20   out.append(dict(symbols=sorted(set(a.get_chemical_symbols())),\n\
         \x20       positions=r(a.get_positions()), velocities=r(a.get_velocities()),\n\
         \x20       masses=r(a.get_masses()), cell=a.cell.tolist(), pbc=a.pbc.tolist(),\n\
         \x20       omega=r(a.arrays['omega']), radius=r(a.arrays['radius'])))\n\
         print(json.dumps(out))",
        &files,
    );
    assert_eq!(read_by_ase.as_array().unwrap().len(), files.len());
    for (path, ase) in files.iter().zip(read_by_ase.as_array().unwrap()) {
        let name = path.file_name().unwrap().to_str().unwrap();
        let numbers = xyz_numbers(path);
        // numbers travel as Python's repr, parsed here exactly
        let column = |key: &str| -> Vec<Vec<f64>> {
            ase[key]
                .as_array()
                .unwrap()
                .iter()
                .map(|r| r.as_array().unwrap().iter().map(number).collect())
                .collect()
        };
        assert_eq!(ase["symbols"], serde_json::json!(["Ar"]), "{name}");
        assert_eq!(ase["pbc"], serde_json::json!([true, false, true]));
        assert_eq!(
            ase["cell"],
            serde_json::json!([[12.0, 0.0, 0.0], [0.0, 6.0, 0.0], [0.0, 0.0, 5.0]])
        );
        let (positions, velocities) = (column("positions"), column("velocities"));
        let (masses, omega, radius) = (column("masses"), column("omega"), column("radius"));
        assert_eq!(positions.len(), numbers.len());
        let mut speed = 0.0f64;
        for (p, row) in numbers.iter().enumerate() {
            assert_eq!(positions[p], row[0..3], "{name} particle {p}");
            assert_eq!(masses[p], [1.0]);
            // what the file says the velocity is (the velo columns), exactly
            assert_eq!(velocities[p], row[7..10], "{name} particle {p}");
            assert_eq!(omega[p], row[10..13]);
            assert_eq!(radius[p], [0.5]);
            speed = speed.max(velocities[p].iter().map(|v| v.abs()).fold(0.0, f64::max));
        }
        assert!(speed > 0.0, "{name}: ASE reads non-zero velocities");
    }

    // meshio: the grid spans the box, the cell data are ours (NaN where undefined)
    let files: Vec<_> = listing(&vtk).iter().map(|n| vtk.join(n)).collect();
    let read_by_meshio = python(
        "meshio",
        "import json, sys, meshio\n\
         out = []\n\
         for path in sys.argv[1:]:\n\
         \x20   m = meshio.read(path)\n\
         \x20   d = {k: [repr(float(x)) for x in v[0].ravel()] for k, v in m.cell_data.items()}\n\
         \x20   out.append(dict(lo=m.points.min(0).tolist(), hi=m.points.max(0).tolist(),\n\
         \x20       cells=sum(len(c.data) for c in m.cells), data=d))\n\
         print(json.dumps(out))",
        &files,
    );
    assert_eq!(read_by_meshio.as_array().unwrap().len(), files.len());
    for (path, mesh) in files.iter().zip(read_by_meshio.as_array().unwrap()) {
        let name = path.file_name().unwrap().to_str().unwrap();
        let ours = read_vtk(path);
        assert_eq!(mesh["lo"], serde_json::json!([0.0, 0.0, 0.0]), "{name}");
        assert_eq!(mesh["hi"], serde_json::json!([12.0, 6.0, 5.0]), "{name}");
        assert_eq!(
            mesh["cells"],
            4 * 5 * 3,
            "{name}: 4 x (3 + 2 wall layers) x 3 cells"
        );
        let mut undefined = 0;
        for (key, components, values) in &ours.arrays {
            let read: Vec<f64> = mesh["data"][key]
                .as_array()
                .unwrap_or_else(|| panic!("{name}: meshio has no {key}"))
                .iter()
                .map(number)
                .collect();
            assert_eq!(
                read.len(),
                values.len(),
                "{name} {key} ({components} components)"
            );
            for (a, b) in read.iter().zip(values) {
                assert!(same(*a, *b), "{name} {key}: meshio {a}, ours {b}");
            }
            undefined += values.iter().filter(|v| v.is_nan()).count();
        }
        assert!(undefined > 0, "{name}: the wall layers are undefined");
    }
}

#[test]
fn sim_refuses_particle_files_for_engines_without_particles() {
    let dir = scratch("viewer-lga");
    let out = Command::new(BIN)
        .args(["sim", "--engine", "lga", "--steps", "10", "--xyz"])
        .arg(dir.join("x"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--xyz") && err.contains("edmd"), "{err}");
    assert!(
        !dir.join("x").exists(),
        "nothing written before the refusal"
    );
}
