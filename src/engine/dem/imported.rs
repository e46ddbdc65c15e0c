//! Records of a channel run that another code made: the frames of a LAMMPS dump
//! ([`super::lammps::read_dump`]) turned into the records granflow's DEM analysis reads, so
//! that a LAMMPS run (e.g. one written by `granflow lammps` and run on many nodes) gets the
//! same profiles, numbers and tables as a granflow run (docs/lammps.md).
//!
//! A dump holds positions, velocities and spins at some steps, nothing else. Each interval
//! between two consecutive frames becomes one record with one sample (the later frame):
//! - the kinetic sums (count, volume, mass, momentum, spin and their products per bin, the
//!   centre-of-mass velocity, the kinetic energies) as a granflow sample forms them
//!   ([`super::sampling::add_kinetic_sample`]), and the bond-orientational sums of the
//!   positions ([`super::bond_order`]): profiles of phi, u, spin, T, the shear rate, the
//!   zones, u_slip, u_max, delta_0.95 and Q6 follow;
//! - the walls' force along the flow from the exact momentum balance of the periodic
//!   channel: nothing but gravity and the two walls acts on the particles, so the impulse
//!   of the particles on both walls over the interval is J_x = M g_x T - (P_x(end) -
//!   P_x(start)) (velocity Verlet keeps this to round-off). It is booked as both walls' sum
//!   (wall 0 holds J_x, wall 1 zero), the per-step force as J_x / Delta t: the balance beta
//!   and the steady rule follow, with the resolution of the frames;
//! - the contact stress when the dump has each particle's pair virial (`c_pairstress[1..6]`,
//!   which `granflow lammps` scripts dump): LAMMPS' six entries r_a F_b / 2 (xx, yy, zz, xy,
//!   xz, yz) go to the bin of the particle's centre, as granflow's sampling splits each
//!   contact between its two particles; the other three entries of granflow's non-symmetric
//!   tensor are NaN. So sigma_xx, sigma_yy, sigma_zz and the paper's sigma_xy (granflow's
//!   F_y r_x) are there, hence mu and I in the interior bins; the wall bins lack the wall
//!   contacts' stress (NaN);
//! - not in a dump, so NaN (null in the tables): the dissipation, the contact counts, each
//!   wall's own forces (the wall normal stress, mu_wall), the sampled wall stresses, the work
//!   of gravity, and without the virial columns the contact stress and all made of it.

use super::bond_order;
use super::domain::Domain;
use super::engine::{Record, RunConstants};
use super::lammps::DumpFrame;
use super::params::{DemParams, sphere_mass};
use super::sampling::{Bins, IntervalSums, add_kinetic_sample};

/// Why frames cannot be read as a run of these parameters.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ImportError {
    #[error("the dump has {0} frame(s); a record needs two (an interval), so at least 2")]
    TooFewFrames(usize),
    #[error(
        "frame at step {step}: box {axis} is {got} long, the job's {name} is {want} (the dump \
         must be of this job's channel)"
    )]
    Box {
        step: u64,
        axis: char,
        name: &'static str,
        got: f64,
        want: f64,
    },
    #[error(
        "frame at step {step}: {what} differ from the first frame's (a dump of one run keeps \
         its particles)"
    )]
    Particles { step: u64, what: &'static str },
    #[error("frame at step {step} follows step {previous}: the frames must go forward in time")]
    Order { step: u64, previous: u64 },
    #[error(
        "frame at step {step}: a particle of diameter {diameter} is not of the job's size mix \
         {mix:?}"
    )]
    Size {
        step: u64,
        diameter: f64,
        mix: Vec<(f64, f64)>,
    },
}

/// Relative tolerance of the box check: the dump's bounds are printed numbers.
const BOX_TOLERANCE: f64 = 1e-9;

/// The records of the intervals between consecutive frames (see the module documentation),
/// with the constants of `params` and the frames' particles. Steps are the dump's.
pub fn records_from_frames(
    params: &DemParams,
    frames: &[DumpFrame],
) -> Result<Vec<Record>, ImportError> {
    check(params, frames)?;
    let first = &frames[0];
    let radius: Vec<f64> = first.states.iter().map(|s| 0.5 * s.diameter).collect();
    let mass: Vec<f64> = first
        .states
        .iter()
        .map(|s| sphere_mass(s.diameter))
        .collect();
    let bins = Bins::new(params.width);
    let domain = Domain::new(params.length, params.width, params.span, true);
    let constants = RunConstants::of(params, &radius, &mass, &bins);
    let (total_mass, g, dt) = (constants.total_mass, params.gravity, params.time_step);
    let momentum = |f: &DumpFrame| {
        let mut p = [0.0; 3];
        for (m, s) in mass.iter().zip(&f.states) {
            for (pk, vk) in p.iter_mut().zip(s.velocity) {
                *pk += m * vk;
            }
        }
        p
    };
    let nan3 = [f64::NAN; 3];
    let mut records = Vec::with_capacity(frames.len() - 1);
    let mut start_momentum = momentum(first);
    for pair in frames.windows(2) {
        let (from, to) = (&pair[0], &pair[1]);
        let end_momentum = momentum(to);
        let mut sums = IntervalSums::start(from.timestep, bins.len(), start_momentum);
        sums.end_step = to.timestep;
        let steps = to.timestep - from.timestep;
        sums.duration = steps as f64 * dt;
        sums.momentum[1] = end_momentum;
        let x: Vec<[f64; 3]> = to.states.iter().map(|s| s.position).collect();
        let v: Vec<[f64; 3]> = to.states.iter().map(|s| s.velocity).collect();
        let w: Vec<[f64; 3]> = to.states.iter().map(|s| s.spin).collect();
        add_kinetic_sample(&mut sums, &bins, &mass, &radius, &x, &v, &w);
        sums.samples = 1;
        for b in &mut sums.bins {
            b.dissipation = f64::NAN;
            b.contacts = f64::NAN;
        }
        set_contact_stress(&mut sums, &bins, &x, to.pair_virial.as_deref());
        // both walls' impulse along the flow from the momentum balance; their split and the
        // other components are unknown
        let impulse = total_mass * g[0] * sums.duration - (end_momentum[0] - start_momentum[0]);
        sums.force_steps = steps;
        sums.wall_impulse = [[impulse, f64::NAN, f64::NAN], [0.0, f64::NAN, f64::NAN]];
        sums.wall_force = [
            [impulse / dt, f64::NAN, f64::NAN],
            [0.0, f64::NAN, f64::NAN],
        ];
        sums.gravity_work = f64::NAN;
        sums.sampled_wall_force = [nan3; 2];
        sums.wall_stress = [[f64::NAN; 9]; 2];
        sums.wall_dissipation = [f64::NAN; 2];
        sums.contacts = f64::NAN;
        records.push(Record {
            constants: constants.clone(),
            sums,
            bonds: bond_order::bond_sums(&domain, &bins, &x, &radius),
        });
        start_momentum = end_momentum;
    }
    Ok(records)
}

/// Where each of LAMMPS' six pair-virial entries (xx, yy, zz, xy, xz, yz; ab = r_a F_b / 2)
/// sits in a bin's `contact_stress` (row-major, the force's component first: F_a r_b at
/// 3 a + b): r_x F_y is granflow's (y, x) entry, and so on. The other three entries (F_x r_y,
/// F_x r_z, F_y r_z) LAMMPS does not keep.
const FROM_LAMMPS: [usize; 6] = [0, 4, 8, 3, 6, 7];

/// The bins' contact stress from each particle's pair virial (its half of each of its
/// contacts' r F, the split granflow's sampling makes), summed into the bin of its centre; the
/// three entries LAMMPS does not keep, and every entry without a virial, are NaN.
fn set_contact_stress(
    sums: &mut IntervalSums,
    bins: &Bins,
    x: &[[f64; 3]],
    virial: Option<&[[f64; 6]]>,
) {
    for b in &mut sums.bins {
        b.contact_stress = [f64::NAN; 9];
    }
    let Some(virial) = virial else { return };
    for b in &mut sums.bins {
        for &k in &FROM_LAMMPS {
            b.contact_stress[k] = 0.0;
        }
    }
    for (x, w) in x.iter().zip(virial) {
        let b = &mut sums.bins[bins.of(x[1])];
        for (&k, w) in FROM_LAMMPS.iter().zip(w) {
            b.contact_stress[k] += w;
        }
    }
}

/// The frames are of one run of this channel: at least two, forward in time, the same
/// particles (ids and diameters, each of the size mix) in a box of the job's L x W x B.
fn check(params: &DemParams, frames: &[DumpFrame]) -> Result<(), ImportError> {
    if frames.len() < 2 {
        return Err(ImportError::TooFewFrames(frames.len()));
    }
    let first = &frames[0];
    for (k, f) in frames.iter().enumerate() {
        let step = f.timestep;
        for (axis, name, want) in [
            ('x', "length L", params.length),
            ('y', "width W", params.width),
            ('z', "span B", params.span),
        ] {
            let a = (axis as usize) - ('x' as usize);
            let got = f.bounds[a][1] - f.bounds[a][0];
            if (got - want).abs() > BOX_TOLERANCE * want {
                return Err(ImportError::Box {
                    step,
                    axis,
                    name,
                    got,
                    want,
                });
            }
        }
        if k > 0 {
            let previous = frames[k - 1].timestep;
            if step <= previous {
                return Err(ImportError::Order { step, previous });
            }
            if f.ids != first.ids {
                return Err(ImportError::Particles {
                    step,
                    what: "the atom ids",
                });
            }
            if f.states
                .iter()
                .zip(&first.states)
                .any(|(a, b)| a.diameter != b.diameter)
            {
                return Err(ImportError::Particles {
                    step,
                    what: "the diameters",
                });
            }
        }
        if let Some(s) = f
            .states
            .iter()
            .find(|s| !params.size_mix.has_diameter(s.diameter))
        {
            return Err(ImportError::Size {
                step,
                diameter: s.diameter,
                mix: params.size_mix.components().to_vec(),
            });
        }
    }
    Ok(())
}
