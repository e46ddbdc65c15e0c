//! The parallel kernels of a step: pair forces (each listed pair once, by its owner, into its
//! slot, the owner summing its owned pairs on the way) and the particle pass (each particle
//! gathers the forces of the pairs owned by its lower-tag partners, in tag order, adds its
//! owned sum, its wall and floor contacts and gravity, and kicks and drifts), both in
//! parallel over blocks of particles. A pair's forces go to a slot of the other particle's
//! (its *incoming* slots, see [`super::neighbours`]), which the gather reads in one run.
//!
//! Integration is LAMMPS' velocity Verlet (`fix nve/sphere`), per particle:
//!
//! ```text
//! v += (dt/2) F / m;   x += dt v;   w += (dt/2) tau / I      (initial half step)
//! F, tau = forces(x(t + dt), v(t + dt/2), w(t + dt/2))        (damping and history see the
//!                                                              half-step velocities)
//! v += (dt/2) F / m;   w += (dt/2) tau / I                    (final half step)
//! ```
//!
//! Between two steps that need no full-step state (no sample, no stop) the final half step of
//! one and the initial half step of the next are done in the same pass, as the same
//! operations in the same order. Every sum (a particle's forces, a block's tallies) runs in
//! an order fixed by tags and blocks, never by threads: the same bits on any number of
//! threads.

use super::bodies::Bodies;
use super::contact::{self, ContactLaw, WallLaws};
use super::contact_lanes::ContactLanes;
use super::domain::Domain;
use super::neighbours::{NeighbourList, PairOut};
use super::scan_lanes::{self, Candidates, SCAN_BLOCK};
use super::simd::with_avx2;
use crate::engine::prefetch::prefetch_at;
use rayon::prelude::*;
use std::marker::PhantomData;

/// Particles per parallel task.
pub const PARTICLE_CHUNK: usize = 256;

/// The flat boundaries: walls at y = 0 and y = W, and the preparation's floor normal to x.
#[derive(Clone, Copy, Debug)]
pub struct Boundaries {
    /// W
    pub width: f64,
    /// the law of both walls, by particle size
    pub wall_laws: WallLaws,
    /// the floor's position along x (gravity pushes particles onto it), during preparation
    pub floor: Option<f64>,
    /// the floor's law, by particle size
    pub floor_laws: WallLaws,
    /// g, the gravitational acceleration
    pub gravity: [f64; 3],
}

/// What the particle pass does after the forces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pass {
    /// forces only (LAMMPS' setup: histories are not advanced, velocities unchanged)
    Setup,
    /// the final half kick
    Final,
    /// the final half kick, then the next step's initial half kick and drift
    FinalAndNext,
}

/// A block's sums of one pass, added in block order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tally {
    /// force of the particles on each wall (minus the walls' force on the particles)
    pub on_walls: [[f64; 3]; 2],
    /// force of the particles on the floor
    pub on_floor: [f64; 3],
    /// particles touching a wall (and the floor)
    pub wall_contacts: u64,
    /// smallest and largest component of the displacements x - x_build after a drift
    pub displacement_min: [f64; 3],
    pub displacement_max: [f64; 3],
    /// sum m g . v over the drifted particles (times dt: the work of gravity in the drift)
    pub gravity_power: f64,
}

impl Default for Tally {
    fn default() -> Self {
        Tally {
            on_walls: [[0.0; 3]; 2],
            on_floor: [0.0; 3],
            wall_contacts: 0,
            displacement_min: [f64::INFINITY; 3],
            displacement_max: [f64::NEG_INFINITY; 3],
            gravity_power: 0.0,
        }
    }
}

impl Tally {
    /// (2 x) the half-diagonal of the box holding every displacement since the list build:
    /// no pair's separation has changed by more than this (x_i - x_j moves by
    /// (d_i - c) - (d_j - c) for the box's centre c), whatever common motion the particles
    /// share. Squared; 0 before any drift.
    pub fn separation_change2(&self) -> f64 {
        (0..3)
            .map(|k| (self.displacement_max[k] - self.displacement_min[k]).max(0.0))
            .map(|w| w * w)
            .sum()
    }

    /// The sum of the blocks' tallies, in block order.
    pub fn sum(tallies: &[Tally]) -> Tally {
        let mut sum = Tally::default();
        for t in tallies {
            sum.add(t);
        }
        sum
    }

    /// Add a later block's tally.
    pub fn add(&mut self, o: &Tally) {
        for w in 0..2 {
            for k in 0..3 {
                self.on_walls[w][k] += o.on_walls[w][k];
            }
        }
        for k in 0..3 {
            self.on_floor[k] += o.on_floor[k];
        }
        self.wall_contacts += o.wall_contacts;
        for k in 0..3 {
            self.displacement_min[k] = self.displacement_min[k].min(o.displacement_min[k]);
            self.displacement_max[k] = self.displacement_max[k].max(o.displacement_max[k]);
        }
        self.gravity_power += o.gravity_power;
    }
}

/// What the pair kernel reads of the particles.
struct PairInput<'a> {
    law: &'a ContactLaw,
    domain: &'a Domain,
    x: &'a [[f64; 3]],
    v: &'a [[f64; 3]],
    w: &'a [[f64; 3]],
    radius: &'a [f64],
    mass: &'a [f64],
    pairs: &'a [[u32; 2]],
    pair_start: &'a [u32],
    in_slot: &'a [u32],
    update: bool,
}

/// The incoming slots while the pair kernel's tasks write them at scattered places (a pair's
/// slot belongs to the other particle, anywhere in the working order). Sound because a slot
/// is written only by the task evaluating its pair (the list gives every pair its own slot,
/// and every pair is in one task's range of owners) and nothing reads the slots meanwhile.
struct IncomingSlots<'a> {
    ptr: *mut PairOut,
    len: usize,
    _slots: PhantomData<&'a mut [PairOut]>,
}

// SAFETY: tasks write disjoint slots (see the type's doc) and never read them.
unsafe impl Sync for IncomingSlots<'_> {}

impl<'a> IncomingSlots<'a> {
    fn new(slots: &'a mut [PairOut]) -> Self {
        IncomingSlots {
            ptr: slots.as_mut_ptr(),
            len: slots.len(),
            _slots: PhantomData,
        }
    }

    #[inline(always)]
    fn set(&self, slot: usize, out: PairOut) {
        assert!(slot < self.len);
        // SAFETY: in bounds, and this task alone writes this slot during the kernel
        unsafe { self.ptr.add(slot).write(out) }
    }
}

/// What the pair kernel writes for a range of owners and their pairs.
struct PairOutput<'a> {
    incoming: &'a IncomingSlots<'a>,
    shear: &'a mut [[f64; 3]],
    touch: &'a mut [bool],
    owned_force: &'a mut [[f64; 3]],
    owned_torque: &'a mut [[f64; 3]],
}

impl<'a> PairOutput<'a> {
    /// Split after `particles` owners, whose pairs are the first `pairs`.
    fn split(self, particles: usize, pairs: usize) -> (PairOutput<'a>, PairOutput<'a>) {
        let (s1, s2) = self.shear.split_at_mut(pairs);
        let (t1, t2) = self.touch.split_at_mut(pairs);
        let (f1, f2) = self.owned_force.split_at_mut(particles);
        let (q1, q2) = self.owned_torque.split_at_mut(particles);
        (
            PairOutput {
                incoming: self.incoming,
                shear: s1,
                touch: t1,
                owned_force: f1,
                owned_torque: q1,
            },
            PairOutput {
                incoming: self.incoming,
                shear: s2,
                touch: t2,
                owned_force: f2,
                owned_torque: q2,
            },
        )
    }
}

/// Forces of all listed pairs at the current positions and velocities: each pair's force
/// and tor into the other's incoming slot, and each owner's sums over its owned pairs (tag
/// order) of F and of -R_owner tor. In parallel over ranges of owners (split in halves down
/// to [`PARTICLE_CHUNK`] owners), so that an owner's pairs are summed in one task, in order.
/// Returns the number of touching pairs. `update`: advance the histories.
pub fn pair_forces(
    law: &ContactLaw,
    domain: &Domain,
    bodies: &Bodies,
    list: &mut NeighbourList,
    update: bool,
) -> u64 {
    let input = PairInput {
        law,
        domain,
        x: &bodies.x,
        v: &bodies.v,
        w: &bodies.w,
        radius: &bodies.radius,
        mass: &bodies.mass,
        pairs: &list.pairs,
        pair_start: &list.pair_start,
        in_slot: &list.in_slot,
        update,
    };
    let incoming = IncomingSlots::new(&mut list.incoming);
    let output = PairOutput {
        incoming: &incoming,
        shear: &mut list.shear,
        touch: &mut list.touch,
        owned_force: &mut list.owned_force,
        owned_torque: &mut list.owned_torque,
    };
    owners(&input, 0, bodies.len(), output)
}

/// The pairs of owners lo .. hi (their slots start at pair_start[lo]), in blocks: first the
/// block's candidates, the pairs touching now (r^2 < (R_a + R_b)^2) or at the last evaluation,
/// collected with their separations into the lanes without a branch on the contact test
/// (most listed pairs do not touch, and which do is unpredictable); then the law in all
/// lanes at once ([`ContactLanes`]), and the results put in place in pair order: the
/// forces of a touching pair, or the end of a contact.
fn owners(input: &PairInput, lo: usize, hi: usize, output: PairOutput) -> u64 {
    if hi - lo > PARTICLE_CHUNK {
        let mid = lo + (hi - lo) / 2;
        let pairs = (input.pair_start[mid] - input.pair_start[lo]) as usize;
        let (first, second) = output.split(mid - lo, pairs);
        let (a, b) = rayon::join(
            || owners(input, lo, mid, first),
            || owners(input, mid, hi, second),
        );
        return a + b;
    }
    let PairInput {
        law,
        domain,
        x,
        v,
        w,
        radius,
        mass,
        pairs,
        pair_start,
        in_slot,
        update,
    } = *input;
    let (base, end) = (pair_start[lo] as usize, pair_start[hi] as usize);
    // the owners' sums over their pairs, in tag order: sum F, sum -R_a tor
    output.owned_force.fill([0.0; 3]);
    output.owned_torque.fill([0.0; 3]);
    let mut touching = 0u64;
    LANES.with_borrow_mut(|(lanes, found)| {
        for block in (base..end).step_by(SCAN_BLOCK) {
            let stop = end.min(block + SCAN_BLOCK);
            let touch = &output.touch[block - base..stop - base];
            let listed = scan_lanes::Listed {
                pairs: &pairs[block..stop],
                touch,
            };
            let n = scan_lanes::scan(domain, x, radius, listed, found, lanes);
            // the rest of the candidates' inputs
            for l in 0..n {
                // the partner's velocities are scattered in memory: ask for those of a
                // candidate further on while this one is filled
                let ahead = found.b[(l + PREFETCH_AHEAD).min(n - 1)] as usize;
                prefetch_at(v, ahead);
                prefetch_at(w, ahead);
                let q = block - base + found.place[l] as usize;
                let (a, b) = (found.a[l] as usize, found.b[l] as usize);
                let (ra, rb) = (lanes.radius[0][l], lanes.radius[1][l]);
                for k in 0..3 {
                    lanes.vr[k][l] = v[a][k] - v[b][k];
                    lanes.spin[k][l] = ra * w[a][k] + rb * w[b][k];
                    lanes.shear[k][l] = output.shear[q][k];
                }
                lanes.mass[0][l] = mass[a];
                lanes.mass[1][l] = mass[b];
            }
            if update {
                lanes.evaluate::<true>(law, n);
            } else {
                lanes.evaluate::<false>(law, n);
            }
            for l in 0..n {
                let p = block + found.place[l] as usize;
                let q = p - base;
                let a = found.a[l] as usize;
                let (ra, rb) = (lanes.radius[0][l], lanes.radius[1][l]);
                if lanes.rsq[l] < (ra + rb) * (ra + rb) {
                    let c = contact::ContactForce {
                        force: std::array::from_fn(|k| lanes.force[k][l]),
                        tor: std::array::from_fn(|k| lanes.tor[k][l]),
                    };
                    output.incoming.set(
                        in_slot[p] as usize,
                        PairOut {
                            force: c.force,
                            tor: c.tor,
                        },
                    );
                    output.shear[q] = std::array::from_fn(|k| lanes.shear[k][l]);
                    output.touch[q] = true;
                    touching += 1;
                    add_contact(
                        &mut output.owned_force[a - lo],
                        &mut output.owned_torque[a - lo],
                        ra,
                        &c,
                    );
                } else {
                    // the contact ended: its history is dropped
                    output.incoming.set(in_slot[p] as usize, PairOut::default());
                    output.shear[q] = [0.0; 3];
                    output.touch[q] = false;
                }
            }
        }
    });
    touching
}

thread_local! {
    /// Each thread's lanes of the pair kernel (a leaf of [`owners`] borrows them while it
    /// runs, and never yields to another task meanwhile).
    static LANES: std::cell::RefCell<(ContactLanes, Candidates)> =
        std::cell::RefCell::new((ContactLanes::default(), Candidates::default()));
}

/// How many candidates ahead the fill loop asks for a partner's velocities (4, 8 and 16
/// measured: 8 the fastest, docs/performance.md).
const PREFETCH_AHEAD: usize = 8;

/// A contact's part of the force and torque on the particle of radius `r` it was computed
/// for (the owner of a pair, or the particle at a wall or the floor): F += force,
/// tau -= r tor.
#[inline(always)]
fn add_contact(f: &mut [f64; 3], t: &mut [f64; 3], r: f64, c: &contact::ContactForce) {
    for d in 0..3 {
        f[d] += c.force[d];
        t[d] -= r * c.tor[d];
    }
}

/// The force of the nearer wall (LAMMPS fix wall/gran with yplane 0 W) on a particle at y,
/// if it touches: (wall index, del from the wall point, rsq).
#[inline(always)]
pub fn nearer_wall(y: f64, radius: f64, width: f64) -> (usize, [f64; 3], bool) {
    let del1 = y - 0.0;
    let del2 = width - y;
    let (wall, dy) = if del1 < del2 { (0, del1) } else { (1, -del2) };
    let rsq = dy * dy;
    (wall, [0.0, dy, 0.0], rsq <= radius * radius)
}

/// The particle pass: gather each particle's forces (pairs in its row's tag order, then the
/// nearer wall, the floor, gravity), store F and tau, then kick (and drift) as `pass` says.
/// `record_wall`: keep each particle's wall force (for sampling). Returns the blocks' tallies
/// in `tallies` and their sum.
///
/// A block of particles is done in two loops: first every particle's forces, turned into its
/// kicks (dt/2) F/m and (dt/2) tau/I; then the kicks and drifts of the whole block, lane by
/// lane over its coordinates (the same operations in the same order as one particle at a
/// time, so the same bits).
#[allow(clippy::too_many_arguments)]
pub fn particle_pass(
    pair_law: &ContactLaw,
    bounds: &Boundaries,
    domain: &Domain,
    bodies: &mut Bodies,
    list: &NeighbourList,
    pass: Pass,
    record_wall: bool,
    tallies: &mut Vec<Tally>,
) -> Tally {
    let update = pass != Pass::Setup;
    let dt = pair_law.dt;
    let Bodies {
        radius,
        mass,
        kick_v,
        kick_w,
        x,
        v,
        w,
        force,
        torque,
        x_build,
        wall_shear,
        floor_shear,
        wall_force,
        ..
    } = bodies;
    let (radius, mass, kick_v, kick_w, x_build) = (&*radius, &*mass, &*kick_v, &*kick_w, &*x_build);
    let (incoming, in_start) = (&list.incoming, &list.in_start);
    let (owned_force, owned_torque) = (&list.owned_force, &list.owned_torque);
    x.par_chunks_mut(PARTICLE_CHUNK)
        .zip(v.par_chunks_mut(PARTICLE_CHUNK))
        .zip(w.par_chunks_mut(PARTICLE_CHUNK))
        .zip(force.par_chunks_mut(PARTICLE_CHUNK))
        .zip(torque.par_chunks_mut(PARTICLE_CHUNK))
        .zip(wall_shear.par_chunks_mut(PARTICLE_CHUNK))
        .zip(floor_shear.par_chunks_mut(PARTICLE_CHUNK))
        .zip(wall_force.par_chunks_mut(PARTICLE_CHUNK))
        .enumerate()
        .map(|(c, (((((((xs, vs), ws), fs), ts), wss), fss), wfs))| {
            let mut tally = Tally::default();
            // the block's particles lo .. lo + n in every array (k indexes them all)
            let (lo, n) = (c * PARTICLE_CHUNK, xs.len());
            let (vs, ws, fs, ts) = (&mut vs[..n], &mut ws[..n], &mut fs[..n], &mut ts[..n]);
            let (wss, fss, wfs) = (&mut wss[..n], &mut fss[..n], &mut wfs[..n]);
            let (radius, mass) = (&radius[lo..lo + n], &mass[lo..lo + n]);
            let (kick_v, kick_w) = (&kick_v[lo..lo + n], &kick_w[lo..lo + n]);
            let x_build = &x_build[lo..lo + n];
            let (owned_force, owned_torque) = (&owned_force[lo..lo + n], &owned_torque[lo..lo + n]);
            let in_start = &in_start[lo..=lo + n];
            // each particle's half kicks of this pass: (dt/2) F/m and (dt/2) tau/I
            let mut kicks = Kicks::new(n);
            for k in 0..n {
                let (r, m) = (radius[k], mass[k]);
                // F = (sum over the lower part of the row, tag order, of -F_pair: the
                //   incoming slots) + (sum over the owned pairs, formed by the pair kernel);
                //   tau alike with -R_i tor
                let mut f = [0.0f64; 3];
                let mut t = [0.0f64; 3];
                for o in &incoming[in_start[k] as usize..in_start[k + 1] as usize] {
                    for d in 0..3 {
                        f[d] -= o.force[d];
                        t[d] -= r * o.tor[d];
                    }
                }
                let (of, ot) = (&owned_force[k], &owned_torque[k]);
                for d in 0..3 {
                    f[d] += of[d];
                    t[d] += ot[d];
                }
                // the nearer wall
                let (wall, del, touching) = nearer_wall(xs[k][1], r, bounds.width);
                if touching {
                    let cw = contact::wall(
                        bounds.wall_laws.of(r),
                        del,
                        del[1] * del[1],
                        r,
                        vs[k],
                        ws[k],
                        m,
                        &mut wss[k],
                        update,
                    );
                    add_contact(&mut f, &mut t, r, &cw);
                    for (on, fd) in tally.on_walls[wall].iter_mut().zip(cw.force) {
                        *on -= fd;
                    }
                    tally.wall_contacts += 1;
                    if record_wall {
                        wfs[k] = cw.force;
                    }
                } else {
                    if wss[k] != [0.0; 3] {
                        wss[k] = [0.0; 3];
                    }
                    if record_wall {
                        wfs[k] = [0.0; 3];
                    }
                }
                // the floor (preparation): a wall normal to x at x = floor
                if let Some(floor) = bounds.floor {
                    let dx = -(floor - xs[k][0]);
                    let rsq = dx * dx;
                    if rsq <= r * r {
                        let cf = contact::wall(
                            bounds.floor_laws.of(r),
                            [dx, 0.0, 0.0],
                            rsq,
                            r,
                            vs[k],
                            ws[k],
                            m,
                            &mut fss[k],
                            update,
                        );
                        add_contact(&mut f, &mut t, r, &cf);
                        for (on, fd) in tally.on_floor.iter_mut().zip(cf.force) {
                            *on -= fd;
                        }
                        tally.wall_contacts += 1;
                    } else if fss[k] != [0.0; 3] {
                        fss[k] = [0.0; 3];
                    }
                }
                // gravity, m g
                for d in 0..3 {
                    f[d] += m * bounds.gravity[d];
                }
                // F and tau are kept for the next step's initial half step, unless this pass
                // does that half step itself (they are then not needed again)
                if pass != Pass::FinalAndNext {
                    fs[k] = f;
                    ts[k] = t;
                }
                kicks.set(k, (kick_v[k], &f), (kick_w[k], &t));
            }
            match pass {
                Pass::Setup => {}
                // final half step: v += (dt/2) F/m, w += (dt/2) tau/I
                Pass::Final => kicks.apply(vs, ws),
                Pass::FinalAndNext => {
                    kicks.apply(vs, ws);
                    let block = Block {
                        x: xs,
                        v: vs,
                        w: ws,
                        mass,
                        x_build,
                    };
                    drift(domain, bounds, dt, block, &kicks, &mut tally);
                }
            }
            tally
        })
        .collect_into_vec(tallies);
    Tally::sum(tallies)
}

/// The half kicks of a block's particles: (dt/2) F/m and (dt/2) tau/I.
struct Kicks {
    dv: [[f64; 3]; PARTICLE_CHUNK],
    dw: [[f64; 3]; PARTICLE_CHUNK],
    n: usize,
}

impl Kicks {
    fn new(n: usize) -> Kicks {
        assert!(n <= PARTICLE_CHUNK);
        Kicks {
            dv: [[0.0; 3]; PARTICLE_CHUNK],
            dw: [[0.0; 3]; PARTICLE_CHUNK],
            n,
        }
    }

    /// Particle k's kicks from its kick factors and F, tau.
    #[inline(always)]
    fn set(&mut self, k: usize, (kv, f): (f64, &[f64; 3]), (kw, t): (f64, &[f64; 3])) {
        for d in 0..3 {
            self.dv[k][d] = kv * f[d];
            self.dw[k][d] = kw * t[d];
        }
    }

    /// v += (dt/2) F/m, w += (dt/2) tau/I, over the block's coordinates.
    fn apply(&self, v: &mut [[f64; 3]], w: &mut [[f64; 3]]) {
        with_avx2(
            #[inline(always)]
            || {
                add_all(v.as_flattened_mut(), self.dv[..self.n].as_flattened());
                add_all(w.as_flattened_mut(), self.dw[..self.n].as_flattened());
            },
        )
    }
}

/// a += b, coordinate by coordinate.
#[inline(always)]
fn add_all(a: &mut [f64], b: &[f64]) {
    for (a, b) in a.iter_mut().zip(b) {
        *a += b;
    }
}

/// A block of particles as the drift sees it.
struct Block<'a> {
    x: &'a mut [[f64; 3]],
    v: &'a mut [[f64; 3]],
    w: &'a mut [[f64; 3]],
    mass: &'a [f64],
    x_build: &'a [[f64; 3]],
}

/// The initial half step of a block: v += (dt/2) F/m, x += dt v (wrapped), w += (dt/2)
/// tau/I; tallies the displacement since the list build and the work rate of gravity.
fn drift(
    domain: &Domain,
    bounds: &Boundaries,
    dt: f64,
    b: Block,
    kicks: &Kicks,
    tally: &mut Tally,
) {
    let Block {
        x,
        v,
        w,
        mass,
        x_build,
    } = b;
    with_avx2(
        #[inline(always)]
        || {
            add_all(v.as_flattened_mut(), kicks.dv[..kicks.n].as_flattened());
            for (x, v) in x.as_flattened_mut().iter_mut().zip(v.as_flattened()) {
                *x += dt * v;
            }
            domain.wrap_all(x);
            add_all(w.as_flattened_mut(), kicks.dw[..kicks.n].as_flattened());
            let (lo, hi) = (&mut tally.displacement_min, &mut tally.displacement_max);
            domain.widen_displacement_box(x, x_build, lo, hi);
        },
    );
    // sum m g . v over the block in four interleaved partial sums (particle k into sum
    // k mod 4, then ((s0 + s1) + (s2 + s3))): four chains of additions instead of one, in
    // an order fixed by the block alone
    let g = &bounds.gravity;
    let power = |v: &[f64; 3], m: f64| m * (g[0] * v[0] + g[1] * v[1] + g[2] * v[2]);
    let mut sums = [0.0f64; 4];
    let (fours, fours_mass) = (v.chunks_exact(4), mass.chunks_exact(4));
    let rest = fours.remainder().iter().zip(fours_mass.remainder());
    for (v, m) in fours.zip(fours_mass) {
        for k in 0..4 {
            sums[k] += power(&v[k], m[k]);
        }
    }
    for (k, (v, &m)) in rest.enumerate() {
        sums[k] += power(v, m);
    }
    tally.gravity_power += (sums[0] + sums[1]) + (sums[2] + sums[3]);
}

/// The initial half step of every particle (when it could not be fused with the previous
/// step's final one).
pub fn kick_drift(
    domain: &Domain,
    bounds: &Boundaries,
    dt: f64,
    bodies: &mut Bodies,
    tallies: &mut Vec<Tally>,
) -> Tally {
    let Bodies {
        mass,
        kick_v,
        kick_w,
        x,
        v,
        w,
        force,
        torque,
        x_build,
        ..
    } = bodies;
    let (mass, kick_v, kick_w, force, torque, x_build) =
        (&*mass, &*kick_v, &*kick_w, &*force, &*torque, &*x_build);
    x.par_chunks_mut(PARTICLE_CHUNK)
        .zip(v.par_chunks_mut(PARTICLE_CHUNK))
        .zip(w.par_chunks_mut(PARTICLE_CHUNK))
        .enumerate()
        .map(|(c, ((xs, vs), ws))| {
            let mut tally = Tally::default();
            let (lo, n) = (c * PARTICLE_CHUNK, xs.len());
            let mut kicks = Kicks::new(n);
            for k in 0..n {
                let i = lo + k;
                kicks.set(k, (kick_v[i], &force[i]), (kick_w[i], &torque[i]));
            }
            let block = Block {
                x: xs,
                v: vs,
                w: ws,
                mass: &mass[lo..lo + n],
                x_build: &x_build[lo..lo + n],
            };
            drift(domain, bounds, dt, block, &kicks, &mut tally);
            tally
        })
        .collect_into_vec(tallies);
    Tally::sum(tallies)
}
