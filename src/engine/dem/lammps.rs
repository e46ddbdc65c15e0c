//! LAMMPS files of a DEM channel run, both ways: the data file and input script that make
//! LAMMPS (`pair_style gran/hooke/history`, `fix wall/gran hooke/history`, `fix nve/sphere`)
//! run the same channel from the same particles, and the reader of `dump custom` text files
//! back into particle states. The one module that knows these formats (docs/lammps.md).
//!
//! **Mapping** (granflow -> LAMMPS, `units lj`, `atom_style sphere`, `boundary p f p`):
//! - box: x in [0, L) (flow and gravity, periodic), y in [0, W] (wall to wall, fixed, the
//!   walls `fix wall/gran ... yplane 0 W`), z in [0, B) (span, periodic);
//! - particle with canonical index (tag) k -> atom id k + 1, atom type 1 + the index of its
//!   size in the mix (smallest first), diameter d, density 1 (LAMMPS forms
//!   m = 4 pi / 3 (d/2)^3, the bits of [`super::params::sphere_mass`]);
//! - v -> vx vy vz, w (spin) -> omegax omegay omegaz, both in the `Velocities` section;
//! - k_n, k_t, xi_n (gamma_n), xi_t (gamma_t), mu_p -> `pair_style gran/hooke/history` with
//!   dampflag 1 (tangential damping on); the walls get the same k_n, k_t with mu_w and their
//!   own xi_n, xi_t (LAMMPS' wall has m_eff = m_i, as granflow's): one `fix wall/gran` on all
//!   particles when every size has the same wall law (`wall_damping: "pair_rate"`, the pair's
//!   xi_n, xi_t), else one per size group (`group size<k> type <k>`) with that size's
//!   damping (`"pair_restitution"`);
//! - g -> `fix gravity |g| vector gx gy gz` (force m g), defined after the walls (the order
//!   in which granflow adds them too);
//! - Delta t -> `timestep`, skin -> `neighbor skin bin` with a check every step.
//!
//! Numbers are written in Rust's shortest round-trip form (`{:e}`), so LAMMPS reads the same
//! bits. Contact histories (the tangential springs s of touching pairs and walls) cannot be
//! given to LAMMPS in a data file: it starts every contact with s = 0, so a state written
//! here continues in LAMMPS as granflow's [`super::DemEngine::from_state`] continues it with
//! no kept contacts, not as the run it came from.

use super::bodies::BodyState;
use super::contact::ContactLaw;
use super::params::{DemParams, SizeMix};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// File name of the data file in an exported directory.
pub const DATA_FILE: &str = "data.dem";
/// File name of the input script in an exported directory.
pub const INPUT_FILE: &str = "in.dem";
/// File name of the dump the input script writes.
pub const DUMP_FILE: &str = "dump.dem";

/// The columns the input script dumps (what [`read_dump`] needs, in this order).
pub const DUMP_COLUMNS: &str = "id type diameter x y z vx vy vz omegax omegay omegaz";

/// The compute of each particle's pair virial the input script defines (`compute pairstress
/// all stress/atom NULL pair`: the pair forces only, no kinetic, wall or gravity terms) and
/// dumps as `c_pairstress[1]` .. `c_pairstress[6]`; [`read_dump`] reads these columns when a
/// dump has them ([`DumpFrame::pair_virial`]).
pub const STRESS_COMPUTE: &str = "pairstress";

/// What the input script does besides setting up the channel.
#[derive(Clone, Debug, PartialEq)]
pub struct ScriptOptions {
    /// steps to run (`run N`)
    pub steps: u64,
    /// steps between dump frames (`dump ... custom N`); 0 for no dump
    pub dump_every: u64,
    /// steps between thermo lines
    pub thermo_every: u64,
    /// the data file's name as the script reads it (relative to LAMMPS' working directory)
    pub data_file: String,
    /// the dump's name as the script writes it
    pub dump_file: String,
}

impl ScriptOptions {
    /// `steps` steps, a dump frame at the start and at the end, the files of the directory.
    pub fn new(steps: u64) -> Self {
        ScriptOptions {
            steps,
            dump_every: steps.max(1),
            thermo_every: (steps / 10).max(1),
            data_file: DATA_FILE.into(),
            dump_file: DUMP_FILE.into(),
        }
    }
}

/// The `read_data` file of the particles `states` (canonical order: atom id = index + 1) in
/// the channel of `params`: box, diameters, density 1, positions, velocities and spins.
pub fn data_file(params: &DemParams, states: &[BodyState]) -> String {
    let mut d = String::new();
    let _ = writeln!(
        d,
        "LAMMPS data file written by granflow {}: DEM channel W = {:e}, B = {:e}, L = {:e}, \
         N = {} (atom id = granflow index + 1)\n",
        env!("CARGO_PKG_VERSION"),
        params.width,
        params.span,
        params.length,
        states.len()
    );
    let _ = writeln!(d, "{} atoms", states.len());
    let types = params.size_mix.components().len();
    let _ = writeln!(d, "{types} atom types\n");
    let _ = writeln!(d, "0 {:e} xlo xhi", params.length);
    let _ = writeln!(d, "0 {:e} ylo yhi", params.width);
    let _ = writeln!(d, "0 {:e} zlo zhi\n", params.span);
    let _ = writeln!(d, "Atoms # sphere\n");
    for (k, s) in states.iter().enumerate() {
        let [x, y, z] = s.position;
        let t = atom_type(params.size_mix, s.diameter);
        let _ = writeln!(d, "{} {t} {:e} 1 {x:e} {y:e} {z:e}", k + 1, s.diameter);
    }
    let _ = writeln!(d, "\nVelocities\n");
    for (k, s) in states.iter().enumerate() {
        let [vx, vy, vz] = s.velocity;
        let [wx, wy, wz] = s.spin;
        let _ = writeln!(d, "{} {vx:e} {vy:e} {vz:e} {wx:e} {wy:e} {wz:e}", k + 1);
    }
    d
}

/// The atom type of a particle of diameter d: 1 + the index of its size in the mix (1 for a
/// diameter of none: the data file of a state not of the mix, which a run refuses anyway).
pub fn atom_type(mix: SizeMix, d: f64) -> usize {
    1 + mix.components().iter().position(|c| c.0 == d).unwrap_or(0)
}

/// The input script that runs the channel of `params` from the data file in LAMMPS with
/// granflow's contact law, walls, gravity, integrator, step and skin.
pub fn input_script(params: &DemParams, opts: &ScriptOptions) -> String {
    let p = params;
    let (kn, kt, gn, gt) = (
        p.normal_stiffness,
        p.tangential_stiffness(),
        p.normal_damping,
        p.tangential_damping(),
    );
    let g = p.gravity;
    let g_len = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# granflow DEM channel (Debnath, Rao & Kumaran 2022) written by granflow {}: see \
         docs/lammps.md",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        s,
        "# x: flow and gravity, periodic; y: wall to wall (walls at 0 and W); z: span, periodic"
    );
    let _ = writeln!(
        s,
        "units lj\natom_style sphere\ndimension 3\nboundary p f p"
    );
    let _ = writeln!(s, "comm_modify vel yes");
    let _ = writeln!(s, "read_data {}", opts.data_file);
    let _ = writeln!(
        s,
        "# the skin; the list is checked every step (granflow: likewise)"
    );
    let _ = writeln!(s, "neighbor {:e} bin", p.skin);
    let _ = writeln!(s, "neigh_modify delay 0 every 1 check yes");
    let _ = writeln!(
        s,
        "# k_n k_t xi_n xi_t mu_p dampflag (1: tangential damping on)"
    );
    let _ = writeln!(
        s,
        "pair_style gran/hooke/history {kn:e} {kt:e} {gn:e} {gt:e} {:e} 1",
        p.friction
    );
    let _ = writeln!(s, "pair_coeff * *");
    let walls = p.wall_laws();
    let laws: Vec<(f64, ContactLaw)> = walls.sizes().map(|(r, law)| (r, *law)).collect();
    let mu_w = p.wall_friction;
    if laws.iter().all(|l| l.1 == laws[0].1) {
        let (gn, gt) = (laws[0].1.gamma_n, laws[0].1.gamma_t);
        let _ = writeln!(
            s,
            "# flat walls at y = 0 and y = W: m_eff = m_i, k_n k_t xi_n xi_t ({}), mu_w",
            if gn == p.normal_damping {
                "the pair's"
            } else {
                "the walls' own"
            }
        );
        let _ = writeln!(
            s,
            "fix walls all wall/gran hooke/history {kn:e} {kt:e} {gn:e} {gt:e} {mu_w:e} 1 yplane \
             0 {:e}",
            p.width
        );
    } else {
        let _ = writeln!(
            s,
            "# flat walls at y = 0 and y = W: m_eff = m_i, k_n k_t, each size's own xi_n xi_t \
             (e_n against a wall {:e} for every size, as the pair's), mu_w",
            p.pair_restitution()
        );
        for (k, (r, law)) in laws.iter().enumerate() {
            let _ = writeln!(s, "group size{} type {} # d = {:e}", k + 1, k + 1, 2.0 * r);
            let _ = writeln!(
                s,
                "fix walls{} size{} wall/gran hooke/history {kn:e} {kt:e} {:e} {:e} {mu_w:e} 1 \
                 yplane 0 {:e}",
                k + 1,
                k + 1,
                law.gamma_n,
                law.gamma_t,
                p.width
            );
        }
    }
    if g_len > 0.0 {
        let _ = writeln!(
            s,
            "fix gravity all gravity {g_len:e} vector {:e} {:e} {:e}",
            g[0], g[1], g[2]
        );
    }
    let _ = writeln!(s, "fix integrate all nve/sphere");
    let _ = writeln!(s, "timestep {:e}", p.time_step);
    let _ = writeln!(s, "thermo {}", opts.thermo_every.max(1));
    if opts.dump_every > 0 {
        let _ = writeln!(
            s,
            "# each particle's half of its pair contacts' r F (LAMMPS: minus it), for \
             `granflow lammps-import`'s contact stress (evaluated on dump steps only)"
        );
        let _ = writeln!(s, "compute {STRESS_COMPUTE} all stress/atom NULL pair");
        let stress: Vec<String> = (1..=6)
            .map(|k| format!("c_{STRESS_COMPUTE}[{k}]"))
            .collect();
        let _ = writeln!(
            s,
            "dump frames all custom {} {} {DUMP_COLUMNS} {}",
            opts.dump_every,
            opts.dump_file,
            stress.join(" ")
        );
        let _ = writeln!(s, "dump_modify frames format float %.17g sort id");
    }
    let _ = writeln!(s, "run {}", opts.steps);
    s
}

/// Write `data.dem` and `in.dem` into `dir` (created if missing); the two paths.
pub fn write(
    dir: &Path,
    params: &DemParams,
    states: &[BodyState],
    opts: &ScriptOptions,
) -> anyhow::Result<(PathBuf, PathBuf)> {
    use anyhow::Context;
    std::fs::create_dir_all(dir).with_context(|| format!("{}: cannot create", dir.display()))?;
    let data = dir.join(DATA_FILE);
    let input = dir.join(INPUT_FILE);
    std::fs::write(&data, data_file(params, states))
        .with_context(|| format!("{}: cannot write", data.display()))?;
    std::fs::write(&input, input_script(params, opts))
        .with_context(|| format!("{}: cannot write", input.display()))?;
    Ok((data, input))
}

/// One frame of a dump: its step, box and particles.
#[derive(Clone, Debug, PartialEq)]
pub struct DumpFrame {
    /// the LAMMPS time step of the frame
    pub timestep: u64,
    /// the box bounds (lo, hi) in x, y, z
    pub bounds: [[f64; 2]; 3],
    /// the atom ids, ascending
    pub ids: Vec<u64>,
    /// the particles in ascending id order (ids 1..N from [`data_file`] are granflow's
    /// canonical order); positions shifted so the box starts at 0 and wrapped into [0, L) and
    /// [0, B) in the periodic x and z; force, torque, histories zero
    pub states: Vec<BodyState>,
    /// when the dump has the columns `c_pairstress[1..6]` ([`STRESS_COMPUTE`]): each
    /// particle's (ascending id order) pair virial, minus LAMMPS' stress/atom: in LAMMPS'
    /// order xx, yy, zz, xy, xz, yz, where the ab entry is the sum over the particle's pair
    /// contacts of r_a F_b / 2 (r = x_i - x_j, F the force on i from j). LAMMPS keeps only
    /// these six of the nine r_a F_b
    pub pair_virial: Option<Vec<[f64; 6]>>,
}

/// What is wrong with a dump (line numbers from 1).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DumpError {
    #[error("line {line}: {message}")]
    Line { line: usize, message: String },
    #[error("no frame: not a LAMMPS dump (no `ITEM: TIMESTEP`)")]
    Empty,
}

fn bad(line: usize, message: impl Into<String>) -> DumpError {
    DumpError::Line {
        line,
        message: message.into(),
    }
}

/// Where each needed quantity sits among a frame's columns.
struct Columns {
    id: usize,
    /// diameter column, or radius column (true)
    size: (usize, bool),
    /// x y z, and whether they are scaled (xs ys zs)
    position: ([usize; 3], bool),
    velocity: [usize; 3],
    spin: [usize; 3],
    /// the six `c_pairstress[k]` columns, when all are there
    stress: Option<[usize; 6]>,
    count: usize,
}

impl Columns {
    fn parse(header: &str, line: usize) -> Result<Columns, DumpError> {
        let names: Vec<&str> = header.split_whitespace().collect();
        let find = |alts: &[&str]| alts.iter().find_map(|a| names.iter().position(|n| n == a));
        let need = |alts: &[&str]| {
            find(alts).ok_or_else(|| {
                bad(
                    line,
                    format!(
                        "the ATOMS columns lack `{}` (needed: id, diameter or radius, x y z, vx \
                         vy vz, omegax omegay omegaz; found: {header})",
                        alts.join("` or `")
                    ),
                )
            })
        };
        let id = need(&["id"])?;
        let size = match find(&["diameter"]) {
            Some(c) => (c, false),
            None => (need(&["diameter", "radius"])?, true),
        };
        let scaled = find(&["x", "xu"]).is_none() && find(&["xs", "xsu"]).is_some();
        let position = if scaled {
            [
                need(&["xs", "xsu"])?,
                need(&["ys", "ysu"])?,
                need(&["zs", "zsu"])?,
            ]
        } else {
            [
                need(&["x", "xu"])?,
                need(&["y", "yu"])?,
                need(&["z", "zu"])?,
            ]
        };
        Ok(Columns {
            id,
            size,
            position: (position, scaled),
            velocity: [need(&["vx"])?, need(&["vy"])?, need(&["vz"])?],
            spin: [need(&["omegax"])?, need(&["omegay"])?, need(&["omegaz"])?],
            stress: {
                let at: Vec<Option<usize>> = (1..=6)
                    .map(|k| find(&[format!("c_{STRESS_COMPUTE}[{k}]").as_str()]))
                    .collect();
                match at.iter().filter(|c| c.is_some()).count() {
                    0 => None,
                    6 => Some(std::array::from_fn(|k| at[k].expect("all six"))),
                    found => {
                        return Err(bad(
                            line,
                            format!(
                                "{found} of the six columns c_{STRESS_COMPUTE}[1] .. [6]: all \
                                 or none"
                            ),
                        ));
                    }
                }
            },
            count: names.len(),
        })
    }
}

/// Every frame of a `dump custom` text file (LAMMPS' default layout: `ITEM: TIMESTEP`,
/// `ITEM: NUMBER OF ATOMS`, `ITEM: BOX BOUNDS`, `ITEM: ATOMS <columns>`), with the columns
/// id, diameter (or radius), x y z (or xu yu zu, or scaled xs ys zs), vx vy vz, omegax
/// omegay omegaz in any order, other columns ignored.
pub fn read_dump(text: &str) -> Result<Vec<DumpFrame>, DumpError> {
    let mut lines = text.lines().enumerate().map(|(k, l)| (k + 1, l.trim()));
    let mut frames = Vec::new();
    let mut next = |what: &str, after: usize| {
        lines.next().ok_or_else(|| {
            bad(
                after + 1,
                format!("the file ends where {what} was expected"),
            )
        })
    };
    let mut last = 0;
    loop {
        let (line, item) = match next("ITEM: TIMESTEP", last) {
            Ok(l) => l,
            Err(_) if !frames.is_empty() => break,
            Err(_) => return Err(DumpError::Empty),
        };
        if item.is_empty() {
            last = line;
            continue;
        }
        if item != "ITEM: TIMESTEP" {
            return Err(bad(
                line,
                format!("expected `ITEM: TIMESTEP`, found `{item}`"),
            ));
        }
        let (line, v) = next("the time step", line)?;
        let timestep: u64 = v
            .parse()
            .map_err(|_| bad(line, format!("time step `{v}` is not a whole number")))?;
        let (line, item) = next("ITEM: NUMBER OF ATOMS", line)?;
        if item != "ITEM: NUMBER OF ATOMS" {
            return Err(bad(
                line,
                format!("expected `ITEM: NUMBER OF ATOMS`, found `{item}`"),
            ));
        }
        let (line, v) = next("the number of atoms", line)?;
        let n: usize = v
            .parse()
            .map_err(|_| bad(line, format!("number of atoms `{v}` is not a whole number")))?;
        let (mut line, item) = next("ITEM: BOX BOUNDS", line)?;
        if !item.starts_with("ITEM: BOX BOUNDS") {
            return Err(bad(
                line,
                format!("expected `ITEM: BOX BOUNDS`, found `{item}`"),
            ));
        }
        let mut bounds = [[0.0; 2]; 3];
        for b in &mut bounds {
            let (l, v) = next("a line of box bounds", line)?;
            line = l;
            let nums: Vec<f64> = v
                .split_whitespace()
                .take(2)
                .map(str::parse)
                .collect::<Result<_, _>>()
                .map_err(|_| bad(l, format!("box bounds `{v}` are not two numbers")))?;
            if nums.len() != 2 || nums.iter().any(|b| !b.is_finite()) || nums[1] <= nums[0] {
                return Err(bad(
                    l,
                    format!("box bounds `{v}`: expected lo hi with hi > lo"),
                ));
            }
            *b = [nums[0], nums[1]];
        }
        let (line, item) = next("ITEM: ATOMS", line)?;
        let Some(header) = item.strip_prefix("ITEM: ATOMS") else {
            return Err(bad(
                line,
                format!("expected `ITEM: ATOMS ...`, found `{item}`"),
            ));
        };
        let cols = Columns::parse(header, line)?;
        let mut atoms: Vec<(u64, BodyState, [f64; 6])> = Vec::with_capacity(n);
        let mut at = line;
        for _ in 0..n {
            let (l, v) = next("an atom line", at)?;
            at = l;
            let f: Vec<&str> = v.split_whitespace().collect();
            if f.len() != cols.count {
                return Err(bad(
                    l,
                    format!("{} columns, the ATOMS header names {}", f.len(), cols.count),
                ));
            }
            let num = |c: usize| {
                f[c].parse::<f64>()
                    .map_err(|_| bad(l, format!("column {} `{}` is not a number", c + 1, f[c])))
            };
            let id: u64 = f[cols.id]
                .parse()
                .map_err(|_| bad(l, format!("atom id `{}` is not a whole number", f[cols.id])))?;
            let size = num(cols.size.0)?;
            let diameter = if cols.size.1 { 2.0 * size } else { size };
            let mut position = [0.0; 3];
            for k in 0..3 {
                let v = num(cols.position.0[k])?;
                let [lo, hi] = bounds[k];
                // shift so that the box starts at 0 (granflow's box is [0, L) x [0, W] x [0, B))
                position[k] = if cols.position.1 {
                    v * (hi - lo)
                } else {
                    v - lo
                };
                if k != 1 {
                    position[k] = position[k].rem_euclid(hi - lo);
                }
            }
            let three = |c: [usize; 3]| -> Result<[f64; 3], DumpError> {
                Ok([num(c[0])?, num(c[1])?, num(c[2])?])
            };
            let mut virial = [0.0; 6];
            if let Some(c) = cols.stress {
                for (v, &c) in virial.iter_mut().zip(&c) {
                    // LAMMPS' stress/atom is minus the virial (pressure x volume)
                    *v = -num(c)?;
                }
            }
            atoms.push((
                id,
                BodyState::fresh(diameter, position, three(cols.velocity)?, three(cols.spin)?),
                virial,
            ));
        }
        atoms.sort_by_key(|a| a.0);
        if let Some(w) = atoms.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(bad(
                line,
                format!("atom id {} appears twice in the frame", w[0].0),
            ));
        }
        last = at;
        frames.push(DumpFrame {
            timestep,
            bounds,
            ids: atoms.iter().map(|a| a.0).collect(),
            pair_virial: cols.stress.map(|_| atoms.iter().map(|a| a.2).collect()),
            states: atoms.into_iter().map(|a| a.1).collect(),
        });
    }
    Ok(frames)
}

/// [`read_dump`] of a file; errors name the file.
pub fn read_dump_file(path: &Path) -> anyhow::Result<Vec<DumpFrame>> {
    read_dump_file_with_digest(path).map(|(frames, _)| frames)
}

/// [`read_dump_file`] and the SHA-256 of the file's bytes (hex, 64 digits): what a result
/// made from the dump names as its input.
pub fn read_dump_file_with_digest(path: &Path) -> anyhow::Result<(Vec<DumpFrame>, String)> {
    use anyhow::Context;
    use sha2::{Digest, Sha256};
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read the LAMMPS dump", path.display()))?;
    let digest = crate::provenance::hex(&Sha256::digest(text.as_bytes()));
    let frames = read_dump(&text)
        .with_context(|| format!("{}: not a readable LAMMPS dump", path.display()))?;
    Ok((frames, digest))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The data file carries every bit of the state: parsed back as LAMMPS does (strtod),
    /// its numbers are the state's.
    #[test]
    fn the_data_file_round_trips_every_bit() {
        let p = DemParams::channel(10.0, 5.0, 12.0, 0.6, 1);
        let s = vec![
            BodyState::fresh(
                0.9,
                [0.1 + 1e-17, 3.3333333333333335, 4.9],
                [1.0 / 3.0, -2e-300, 0.0],
                [7.0, -1.0 / 7.0, 1e-5],
            ),
            BodyState::fresh(
                1.1,
                [11.999999999999998, 0.55, 0.0],
                [0.0; 3],
                [0.0, 0.0, 3.0],
            ),
        ];
        let text = data_file(&p, &s);
        let atoms: Vec<Vec<f64>> = text
            .split("Atoms # sphere")
            .nth(1)
            .unwrap()
            .split("Velocities")
            .next()
            .unwrap()
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
            .collect();
        let vels: Vec<Vec<f64>> = text
            .split("Velocities")
            .nth(1)
            .unwrap()
            .lines()
            .filter(|l| !l.trim().is_empty())
            .map(|l| l.split_whitespace().map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(atoms.len(), 2);
        for (k, st) in s.iter().enumerate() {
            assert_eq!(atoms[k][0], (k + 1) as f64);
            assert_eq!(atoms[k][2].to_bits(), st.diameter.to_bits());
            assert_eq!(atoms[k][3], 1.0, "density");
            for c in 0..3 {
                assert_eq!(atoms[k][4 + c].to_bits(), st.position[c].to_bits());
                assert_eq!(vels[k][1 + c].to_bits(), st.velocity[c].to_bits());
                assert_eq!(vels[k][4 + c].to_bits(), st.spin[c].to_bits());
            }
        }
        assert!(text.contains("0 1.2e1 xlo xhi"));
        assert!(text.contains("0 1e1 ylo yhi"));
    }

    #[test]
    fn the_script_names_the_law_walls_gravity_and_step() {
        let p = DemParams::channel(10.0, 5.0, 12.0, 0.6, 1);
        let s = input_script(&p, &ScriptOptions::new(500));
        let law = format!(
            "{:e} {:e} {:e} {:e}",
            p.normal_stiffness,
            p.tangential_stiffness(),
            p.normal_damping,
            p.tangential_damping()
        );
        assert!(
            s.contains(&format!("pair_style gran/hooke/history {law} 5e-1 1\n")),
            "{s}"
        );
        assert!(s.contains(&format!(
            "wall/gran hooke/history {law} 5e-1 1 yplane 0 1e1\n"
        )));
        assert!(s.contains("boundary p f p\n"));
        assert!(s.contains("fix gravity all gravity 1e0 vector 1e0 0e0 0e0\n"));
        assert!(s.contains("timestep 1.2e-4\n"));
        assert!(s.contains("neighbor 1e-1 bin\n"));
        assert!(s.contains("run 500\n"));
        // walls before gravity: the order in which granflow adds the forces
        assert!(s.find("fix walls").unwrap() < s.find("fix gravity").unwrap());
    }

    /// With the paper's wall damping each size is a type and a group with its own `fix
    /// wall/gran`, whose gamma_n gives that size the pair's e_n at m_eff = m.
    #[test]
    fn the_papers_walls_are_one_fix_per_size() {
        use crate::engine::dem::params::{WallDamping, sphere_mass};
        let p = DemParams {
            wall_damping: WallDamping::PairRestitution,
            ..DemParams::channel(10.0, 5.0, 12.0, 0.6, 1)
        };
        let s = input_script(&p, &ScriptOptions::new(500));
        let fixes: Vec<&str> = s.lines().filter(|l| l.contains("wall/gran")).collect();
        assert_eq!(fixes.len(), 3, "{s}");
        for (k, &(d, _)) in p.size_mix.components().iter().enumerate() {
            assert!(
                s.contains(&format!("group size{} type {}", k + 1, k + 1)),
                "{s}"
            );
            let words: Vec<&str> = fixes[k].split(' ').collect();
            assert_eq!(words[2], format!("size{}", k + 1));
            let gamma_n: f64 = words[7].parse().unwrap();
            assert_eq!(words[8].parse::<f64>().unwrap(), 0.5 * gamma_n);
            // e_n = exp(-xi t_c / 2), t_c = pi / sqrt(k_n / m - xi^2 / 4)
            let m = sphere_mass(d);
            let t_c =
                std::f64::consts::PI / (p.normal_stiffness / m - 0.25 * gamma_n * gamma_n).sqrt();
            assert!(
                ((-0.5 * gamma_n * t_c).exp() - 0.82).abs() < 1e-12,
                "{}",
                fixes[k]
            );
        }
        let states = vec![
            BodyState::fresh(1.1, [1.0; 3], [0.0; 3], [0.0; 3]),
            BodyState::fresh(0.9, [3.0; 3], [0.0; 3], [0.0; 3]),
        ];
        let data = data_file(&p, &states);
        assert!(data.contains("3 atom types"), "{data}");
        assert!(data.contains("\n1 3 1.1e0 1 "), "{data}");
        assert!(data.contains("\n2 1 9e-1 1 "), "{data}");
    }

    const DUMP: &str = "ITEM: TIMESTEP
0
ITEM: NUMBER OF ATOMS
2
ITEM: BOX BOUNDS pp ff pp
0 12
0 10
0 5
ITEM: ATOMS id type diameter x y z vx vy vz omegax omegay omegaz
2 1 1.1 12.5 0.55 -0.25 1 2 3 4 5 6
1 1 0.9 0.1 3.3 4.9 -1 -2 -3 -4 -5 -6
ITEM: TIMESTEP
100
ITEM: NUMBER OF ATOMS
1
ITEM: BOX BOUNDS pp ff pp
-1 11
0 10
0 5
ITEM: ATOMS id radius omegax omegay omegaz vx vy vz xs ys zs
7 0.5 1 2 3 4 5 6 0.5 0.25 0.1
";

    #[test]
    fn a_dump_reads_into_states_by_id_wrapped_into_the_box() {
        let f = read_dump(DUMP).unwrap();
        assert_eq!(f.len(), 2);
        assert_eq!(f[0].timestep, 0);
        assert_eq!(f[0].ids, vec![1, 2]);
        assert_eq!(f[0].states[0].diameter, 0.9);
        assert_eq!(f[0].states[0].velocity, [-1.0, -2.0, -3.0]);
        assert_eq!(f[0].states[0].spin, [-4.0, -5.0, -6.0]);
        // x and z wrapped into the periodic box, y as it is
        assert_eq!(f[0].states[1].position, [0.5, 0.55, 4.75]);
        assert_eq!(f[0].bounds, [[0.0, 12.0], [0.0, 10.0], [0.0, 5.0]]);
        // radius doubled, scaled positions, any column order
        let s = f[1].states[0];
        assert_eq!(s.diameter, 1.0);
        assert_eq!(s.position, [6.0, 2.5, 0.5]);
        assert_eq!(s.velocity, [4.0, 5.0, 6.0]);
        assert_eq!(s.spin, [1.0, 2.0, 3.0]);
    }

    #[test]
    fn a_bad_dump_names_the_line_and_the_column() {
        let no_spin = DUMP.replace("omegax omegay omegaz\n2", "a b c\n2");
        let e = read_dump(&no_spin).unwrap_err();
        assert!(e.to_string().starts_with("line 9:"), "{e}");
        assert!(e.to_string().contains("`omegax`"), "{e}");
        let bad_number = DUMP.replace("0.1 3.3", "0.1 3.x");
        let e = read_dump(&bad_number).unwrap_err();
        assert!(e.to_string().starts_with("line 11:"), "{e}");
        assert!(e.to_string().contains("`3.x`"), "{e}");
        let short = DUMP.lines().take(10).collect::<Vec<_>>().join("\n");
        let e = read_dump(&short).unwrap_err();
        assert!(e.to_string().contains("ends where an atom line"), "{e}");
        assert_eq!(read_dump("").unwrap_err(), DumpError::Empty);
    }

    /// The virial columns, in any order, are read by id as minus LAMMPS' stress/atom; a
    /// frame without them has none; some of the six but not all is an error.
    #[test]
    fn the_pair_virial_columns_are_read_when_all_six_are_there() {
        let header = "ITEM: ATOMS id type diameter x y z vx vy vz omegax omegay omegaz";
        let stress = "c_pairstress[6] c_pairstress[1] c_pairstress[2] c_pairstress[3] \
                      c_pairstress[4] c_pairstress[5]";
        let with = DUMP
            .replacen(header, &format!("{header} {stress}"), 1)
            .replacen("4 5 6\n1", "4 5 6 -6 -1 -2 -3 -4 -5\n1", 1)
            .replacen("-4 -5 -6\n", "-4 -5 -6 6 1 2 3 4 5\n", 1);
        let f = read_dump(&with).unwrap();
        assert_eq!(
            f[0].pair_virial,
            Some(vec![
                [-1.0, -2.0, -3.0, -4.0, -5.0, -6.0],
                [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
            ])
        );
        assert_eq!(f[1].pair_virial, None);
        let five = DUMP.replacen(header, &format!("{header} c_pairstress[1] c_pairstress[2] c_pairstress[3] c_pairstress[4] c_pairstress[5]"), 1);
        let e = read_dump(&five).unwrap_err();
        assert!(e.to_string().contains("5 of the six columns"), "{e}");
    }
}
