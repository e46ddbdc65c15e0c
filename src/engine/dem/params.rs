//! Validated parameters of one DEM channel run (Debnath, Rao & Kumaran 2022, §2 and App. A) and
//! what follows from them: the particle count, the size mix, the contact laws and the
//! contact time and restitution of every pair type and of the wall.
//!
//! Units: d_p = 1 (the reference diameter), rho_p = 1, g = 1; a sphere of diameter d has mass
//! m = (pi/6) d^3 and moment of inertia I = m d^2 / 10; time in sqrt(d_p / g).

use super::contact::{ContactLaw, WallLaws};
use crate::engine::declare::Problem;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The reference time step at k_n = 1e6 (the paper's 1.2e-4 sqrt(d_p/g), App. A); the default
/// is scaled as (1e6 / k_n)^(1/2).
pub const REFERENCE_TIME_STEP: f64 = 1.2e-4;
/// Fewest time steps per contact time t_c of any pair type (walls included) that a run may
/// use; a coarser step is refused.
pub const MIN_STEPS_PER_CONTACT: f64 = 10.0;
/// The paper's particle-particle restitution (App. A), the default.
pub const DEFAULT_RESTITUTION: f64 = 0.82;
/// m_eff of two reference spheres (d = d_p = 1, rho = 1): (pi/6) / 2 = pi/12; the restitution
/// parameter fixes xi_n through this pair.
pub const REFERENCE_PAIR_MASS: f64 = PI / 12.0;

/// The sizes of the particles: diameters with their number fractions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SizeMix {
    /// the paper's mix (§2): 30 % of 0.9 d_p, 40 % of d_p, 30 % of 1.1 d_p (number fractions)
    #[default]
    Debnath,
    /// all of diameter d_p
    Mono,
}

impl SizeMix {
    /// Names in sweep files, in declaration order.
    pub const NAMES: &'static [&'static str] = &["debnath", "mono"];

    /// The mix of a name.
    pub fn from_name(name: &str) -> Option<SizeMix> {
        match name {
            "debnath" => Some(SizeMix::Debnath),
            "mono" => Some(SizeMix::Mono),
            _ => None,
        }
    }

    /// (diameter, number fraction) of each size, smallest first.
    pub fn components(self) -> &'static [(f64, f64)] {
        match self {
            SizeMix::Debnath => &[(0.9, 0.3), (1.0, 0.4), (1.1, 0.3)],
            SizeMix::Mono => &[(1.0, 1.0)],
        }
    }

    /// Whether d is one of the mix's diameters (exactly).
    pub fn has_diameter(self, d: f64) -> bool {
        self.components().iter().any(|c| c.0 == d)
    }

    /// <pi d^3 / 6>, the mean particle volume.
    pub fn mean_volume(self) -> f64 {
        self.components()
            .iter()
            .map(|&(d, f)| f * PI / 6.0 * d * d * d)
            .sum()
    }

    /// The largest diameter.
    pub fn max_diameter(self) -> f64 {
        self.components().iter().map(|c| c.0).fold(0.0, f64::max)
    }

    /// Exact particle counts of each size for N particles: round(N f_k) with the remainder
    /// (largest fractional parts first, ties to the smaller size) so that they sum to N.
    pub fn counts(self, n: usize) -> Vec<usize> {
        let comps = self.components();
        let exact: Vec<f64> = comps.iter().map(|c| c.1 * n as f64).collect();
        let mut counts: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
        let mut left = n - counts.iter().sum::<usize>();
        let mut order: Vec<usize> = (0..comps.len()).collect();
        order.sort_by(|&a, &b| {
            let fa = exact[a] - exact[a].floor();
            let fb = exact[b] - exact[b].floor();
            fb.total_cmp(&fa).then(a.cmp(&b))
        });
        for k in order.into_iter().cycle() {
            if left == 0 {
                break;
            }
            counts[k] += 1;
            left -= 1;
        }
        counts
    }
}

/// Mass of a sphere of diameter `d` at density 1, computed as LAMMPS computes `rmass` from a
/// data file's diameter and density (4 pi / 3 r^3 rho, r = d / 2), so that both hold the same
/// bits.
#[inline]
pub fn sphere_mass(d: f64) -> f64 {
    let r = 0.5 * d;
    4.0 * PI / 3.0 * r * r * r
}

/// How xi_n was fixed (the paper's e_n = 0.82 and xi_n = 180 disagree, dem.md A1.2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DampingFrom {
    /// from e_n of the d_p-d_p pair: xi_n = 2 L w0 / sqrt(pi^2 + L^2), L = -ln e_n,
    /// w0 = sqrt(k_n / (pi/12))
    Restitution,
    /// xi_n given (the paper's literal 180)
    NormalDamping,
}

impl DampingFrom {
    pub const NAMES: &'static [&'static str] = &["restitution", "normal_damping"];

    pub fn name(self) -> &'static str {
        match self {
            DampingFrom::Restitution => "restitution",
            DampingFrom::NormalDamping => "normal_damping",
        }
    }
}

/// How the walls damp a contact. The paper: "the restitution and friction coefficients for
/// particle-wall collisions are the same as those for particle-particle collisions" (App. A);
/// a wall is a particle of infinite mass and no radius, so its contact with a sphere of mass
/// m has m_eff = m (LAMMPS' `fix wall/gran`), twice the m_eff of a pair of such spheres.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WallDamping {
    /// the pair's xi_n and xi_t (LAMMPS' `fix wall/gran` given the pair's gamma_n, gamma_t):
    /// with m_eff = m the wall's e_n depends on the size, 0.72-0.79 for the paper's mix at a
    /// pair e_n of 0.82 (0.755 for a d_p sphere). The default, because jobs of granflow
    /// before this parameter existed ran this way and their ids do not name it
    #[default]
    PairRate,
    /// per size d, xi_n,w(d) = 2 L w0 / sqrt(pi^2 + L^2) with w0 = sqrt(k_n / m_d) and
    /// L = -ln e_n, e_n the d_p pair's; xi_t,w = (xi_t / xi_n) xi_n,w: every size rebounds
    /// from a wall with the pair's e_n (the paper)
    PairRestitution,
}

impl WallDamping {
    /// Names in sweep files, in declaration order.
    pub const NAMES: &'static [&'static str] = &["pair_rate", "pair_restitution"];

    pub fn name(self) -> &'static str {
        match self {
            WallDamping::PairRate => "pair_rate",
            WallDamping::PairRestitution => "pair_restitution",
        }
    }

    pub fn from_name(name: &str) -> Option<WallDamping> {
        match name {
            "pair_rate" => Some(WallDamping::PairRate),
            "pair_restitution" => Some(WallDamping::PairRestitution),
            _ => None,
        }
    }
}

/// Everything that defines one DEM channel run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DemParams {
    /// W, wall-to-wall width (walls at y = 0 and y = W), in d_p
    pub width: f64,
    /// B, spanwise extent (periodic z), in d_p
    pub span: f64,
    /// L, length along the flow and gravity (periodic x), in d_p
    pub length: f64,
    /// phi-bar, mean volume fraction: N = round(phi L W B / <pi d^3 / 6>)
    pub volume_fraction: f64,
    /// the particle sizes
    pub size_mix: SizeMix,
    /// k_n, normal stiffness (units rho_p g d_p^2)
    pub normal_stiffness: f64,
    /// k_t / k_n
    pub stiffness_ratio: f64,
    /// xi_n, normal damping rate (LAMMPS gamma_n): F_n = k_n delta n - m_eff xi_n v_n
    pub normal_damping: f64,
    /// how xi_n was fixed
    pub damping_from: DampingFrom,
    /// xi_t / xi_n
    pub tangential_damping_ratio: f64,
    /// mu_p, particle-particle friction coefficient
    pub friction: f64,
    /// mu_w, particle-wall friction coefficient
    pub wall_friction: f64,
    /// the walls' damping. Not in this struct's serialised form: the checkpoint payload of
    /// version 1 (before it existed) is this struct's serialisation, and version 2 appends
    /// the wall damping after the whole payload (`engine.rs`), so that both decode
    #[serde(skip)]
    pub wall_damping: WallDamping,
    /// mu during the preparation (pairs, walls and the temporary floor)
    pub settle_friction: f64,
    /// gravitational acceleration (the channel: (g, 0, 0), along the flow)
    pub gravity: [f64; 3],
    /// Delta t
    pub time_step: f64,
    /// neighbour-list skin (in d_p): pairs closer than (d_i + d_j)/2 + skin are listed, the
    /// list is rebuilt before any pair's separation can have changed by the skin
    pub skin: f64,
    /// steps between two samples of the bin sums
    pub sample_every: u64,
    /// seed of the preparation (sizes, initial velocities)
    pub seed: u64,
}

impl DemParams {
    /// The paper's parameters (k_n = 1e6, k_t = 2/7 k_n, e_n = 0.82, xi_t = xi_n/2, mu = 0.5
    /// for particles and walls, its size mix) in a channel W x B x L at phi-bar, with the
    /// registry's default wall damping ([`WallDamping::PairRate`]; the paper's is
    /// [`WallDamping::PairRestitution`]).
    pub fn channel(width: f64, span: f64, length: f64, volume_fraction: f64, seed: u64) -> Self {
        let normal_stiffness = 1e6;
        DemParams {
            width,
            span,
            length,
            volume_fraction,
            size_mix: SizeMix::Debnath,
            normal_stiffness,
            stiffness_ratio: 2.0 / 7.0,
            normal_damping: damping_for_restitution(DEFAULT_RESTITUTION, normal_stiffness),
            damping_from: DampingFrom::Restitution,
            tangential_damping_ratio: 0.5,
            friction: 0.5,
            wall_friction: 0.5,
            wall_damping: WallDamping::default(),
            settle_friction: 0.0,
            gravity: [1.0, 0.0, 0.0],
            time_step: default_time_step(normal_stiffness),
            skin: 0.1,
            sample_every: 100,
            seed,
        }
    }

    /// N, the number of particles.
    pub fn particle_count(&self) -> usize {
        particle_count(
            self.volume_fraction,
            self.length * self.width * self.span,
            self.size_mix,
        )
    }

    /// k_t
    pub fn tangential_stiffness(&self) -> f64 {
        self.stiffness_ratio * self.normal_stiffness
    }

    /// xi_t
    pub fn tangential_damping(&self) -> f64 {
        self.tangential_damping_ratio * self.normal_damping
    }

    /// The particle-particle law (friction mu_p).
    pub fn pair_law(&self) -> ContactLaw {
        self.law(self.friction)
    }

    /// The particle-wall laws of each size (friction mu_w).
    pub fn wall_laws(&self) -> WallLaws {
        self.wall_laws_with(self.wall_friction)
    }

    /// The particle-wall laws of each size with friction `mu`: the same k_n, k_t; the pair's
    /// xi_n, xi_t or, with [`WallDamping::PairRestitution`], each size's own.
    pub fn wall_laws_with(&self, mu: f64) -> WallLaws {
        let sizes: Vec<(f64, ContactLaw)> = self
            .size_mix
            .components()
            .iter()
            .map(|&(d, _)| {
                let xi_n = self.wall_damping_rate(d);
                let law = ContactLaw {
                    gamma_n: xi_n,
                    gamma_t: self.tangential_damping_ratio * xi_n,
                    ..self.law(mu)
                };
                (0.5 * d, law)
            })
            .collect();
        WallLaws::new(&sizes)
    }

    /// xi_n,w of a sphere of diameter d against a wall: the pair's xi_n, or with
    /// [`WallDamping::PairRestitution`] the rate that gives it the d_p pair's e_n at
    /// m_eff = m_d.
    pub fn wall_damping_rate(&self, d: f64) -> f64 {
        match self.wall_damping {
            WallDamping::PairRate => self.normal_damping,
            WallDamping::PairRestitution => damping_for(
                self.pair_restitution(),
                self.normal_stiffness,
                sphere_mass(d),
            ),
        }
    }

    /// e_n of the d_p-d_p pair under the run's k_n and xi_n (0 when overdamped): the pair
    /// value the walls match under [`WallDamping::PairRestitution`].
    pub fn pair_restitution(&self) -> f64 {
        ContactType::new(
            1.0,
            Some(1.0),
            REFERENCE_PAIR_MASS,
            self.normal_stiffness,
            self.normal_damping,
        )
        .restitution
    }

    /// A law with the run's stiffnesses, damping and time step and friction `mu`.
    pub fn law(&self, mu: f64) -> ContactLaw {
        ContactLaw {
            kn: self.normal_stiffness,
            kt: self.tangential_stiffness(),
            gamma_n: self.normal_damping,
            gamma_t: self.tangential_damping(),
            mu,
            dt: self.time_step,
        }
    }

    /// The largest diameter.
    pub fn max_diameter(&self) -> f64 {
        self.size_mix.max_diameter()
    }

    /// e_n and t_c of every pair type of the mix and of each size against a wall.
    pub fn contact_types(&self) -> Vec<ContactType> {
        let comps = self.size_mix.components();
        let mut out = Vec::new();
        for (a, &(da, _)) in comps.iter().enumerate() {
            for &(db, _) in &comps[a..] {
                let (ma, mb) = (sphere_mass(da), sphere_mass(db));
                out.push(ContactType::new(
                    da,
                    Some(db),
                    ma * mb / (ma + mb),
                    self.normal_stiffness,
                    self.normal_damping,
                ));
            }
        }
        for &(d, _) in comps {
            out.push(ContactType::new(
                d,
                None,
                sphere_mass(d),
                self.normal_stiffness,
                self.wall_damping_rate(d),
            ));
        }
        out
    }

    /// Check every value and what depends on several of them; a [`Problem`] names the key.
    pub fn validate(&self) -> Result<(), Problem> {
        let bad = |key: &str, msg: String| Err(Problem::new(key, msg));
        if !(self.volume_fraction > 0.0 && self.volume_fraction < 0.7) {
            return bad(
                "volume_fraction",
                format!(
                    "volume_fraction = {} is out of range: allowed 0 < phi < 0.7",
                    self.volume_fraction
                ),
            );
        }
        self.validate_box_and_law()?;
        if self.particle_count() < 2 {
            return bad(
                "volume_fraction",
                format!(
                    "volume_fraction = {} gives N = {} particles: at least 2 are needed",
                    self.volume_fraction,
                    self.particle_count()
                ),
            );
        }
        Ok(())
    }

    /// The checks that do not involve phi-bar (a run from a given state, whose N is its own),
    /// in this order: the box, the contact law, the neighbour reach, the time stepping.
    pub fn validate_box_and_law(&self) -> Result<(), Problem> {
        self.check_box()?;
        self.check_contact_law()?;
        self.check_reach()?;
        self.check_stepping()
    }

    /// The box: every extent >= 3 d_p, the width >= 4 d_p (two wall bins and one inside).
    fn check_box(&self) -> Result<(), Problem> {
        let bad = |key: &str, msg: String| Err(Problem::new(key, msg));
        for (key, v) in [
            ("width_over_diameter", self.width),
            ("span_over_diameter", self.span),
            ("length_over_diameter", self.length),
        ] {
            if !(v.is_finite() && v >= 3.0) {
                return bad(
                    key,
                    format!("{key} = {v} is out of range: allowed a finite value >= 3"),
                );
            }
        }
        if self.width < 4.0 {
            return bad(
                "width_over_diameter",
                format!(
                    "width_over_diameter = {} is out of range: allowed >= 4 (the two 1.5 d_p wall \
                     bins and at least one interior bin)",
                    self.width
                ),
            );
        }
        Ok(())
    }

    /// The contact law: stiffness, damping, friction and gravity.
    fn check_contact_law(&self) -> Result<(), Problem> {
        let bad = |key: &str, msg: String| Err(Problem::new(key, msg));
        let finite_positive = |v: f64| v.is_finite() && v > 0.0;
        if !finite_positive(self.normal_stiffness) {
            return bad(
                "normal_stiffness",
                format!(
                    "normal_stiffness = {} is out of range: allowed a finite value > 0",
                    self.normal_stiffness
                ),
            );
        }
        if !(self.stiffness_ratio.is_finite() && self.stiffness_ratio >= 0.0) {
            return bad(
                "stiffness_ratio",
                format!(
                    "stiffness_ratio = {} is out of range: allowed a finite value >= 0",
                    self.stiffness_ratio
                ),
            );
        }
        if !(self.normal_damping.is_finite() && self.normal_damping >= 0.0) {
            return bad(
                "normal_damping",
                format!(
                    "normal_damping = {} is out of range: allowed a finite value >= 0",
                    self.normal_damping
                ),
            );
        }
        if !(self.tangential_damping_ratio.is_finite() && self.tangential_damping_ratio >= 0.0) {
            return bad(
                "tangential_damping_ratio",
                format!(
                    "tangential_damping_ratio = {} is out of range: allowed a finite value >= 0",
                    self.tangential_damping_ratio
                ),
            );
        }
        for (key, v) in [
            ("friction", self.friction),
            ("wall_friction", self.wall_friction),
            ("settle_friction", self.settle_friction),
        ] {
            if !(v.is_finite() && (0.0..=1e4).contains(&v)) {
                return bad(
                    key,
                    format!("{key} = {v} is out of range: allowed 0 <= mu <= 1e4"),
                );
            }
        }
        if self.gravity.iter().any(|g| !g.is_finite()) {
            return bad(
                "gravity",
                format!("gravity = {:?} is not finite", self.gravity),
            );
        }
        Ok(())
    }

    /// The neighbour skin, and the box against the minimum image of the largest reach.
    fn check_reach(&self) -> Result<(), Problem> {
        let bad = |key: &str, msg: String| Err(Problem::new(key, msg));
        let d_max = self.max_diameter();
        if !(self.skin.is_finite() && self.skin > 0.0 && self.skin <= 1.0) {
            return bad(
                "skin",
                format!(
                    "skin = {} is out of range: allowed 0 < skin <= 1 d_p",
                    self.skin
                ),
            );
        }
        let reach = d_max + self.skin;
        for (key, v) in [
            ("span_over_diameter", self.span),
            ("length_over_diameter", self.length),
        ] {
            if v <= 2.0 * reach {
                return bad(
                    key,
                    format!(
                        "{key} = {v} is too small for the minimum image: allowed > 2 (d_max + \
                         skin) = {}",
                        2.0 * reach
                    ),
                );
            }
        }
        Ok(())
    }

    /// Sampling and the time step: no overdamped contact, each contact resolved by enough steps.
    fn check_stepping(&self) -> Result<(), Problem> {
        let bad = |key: &str, msg: String| Err(Problem::new(key, msg));
        if self.sample_every == 0 {
            return bad(
                "sample_every",
                "sample_every = 0: allowed a whole number >= 1".into(),
            );
        }
        let damping_key = self.damping_from.name();
        for t in self.contact_types() {
            if !t.contact_time.is_finite() {
                return bad(
                    damping_key,
                    format!(
                        "xi_n = {} overdamps the {} contact (xi_n^2 / 4 >= k_n / m_eff = {:.4e}): \
                         it never rebounds; allowed xi_n < {:.4e}",
                        match t.other {
                            Some(_) => self.normal_damping,
                            None => self.wall_damping_rate(t.diameter),
                        },
                        t.name(),
                        self.normal_stiffness / t.effective_mass,
                        2.0 * (self.normal_stiffness / t.effective_mass).sqrt()
                    ),
                );
            }
        }
        if !(self.time_step.is_finite() && self.time_step > 0.0) {
            return bad(
                "time_step",
                format!(
                    "time_step = {} is out of range: allowed a finite value > 0",
                    self.time_step
                ),
            );
        }
        let shortest = self
            .contact_types()
            .into_iter()
            .min_by(|a, b| a.contact_time.total_cmp(&b.contact_time))
            .expect("at least one contact type");
        if shortest.contact_time < MIN_STEPS_PER_CONTACT * self.time_step {
            return bad(
                "time_step",
                format!(
                    "time_step = {} resolves the shortest contact ({}: t_c = {:.4e}) with {:.2} \
                     steps: allowed time_step <= t_c / {MIN_STEPS_PER_CONTACT} = {:.4e}",
                    self.time_step,
                    shortest.name(),
                    shortest.contact_time,
                    shortest.contact_time / self.time_step,
                    shortest.contact_time / MIN_STEPS_PER_CONTACT
                ),
            );
        }
        Ok(())
    }
}

/// N = round(phi V / <pi d^3/6>) for a box of volume V.
pub fn particle_count(volume_fraction: f64, volume: f64, mix: SizeMix) -> usize {
    (volume_fraction * volume / mix.mean_volume()).round() as usize
}

/// The default time step at stiffness k_n: 1.2e-4 (1e6 / k_n)^(1/2).
pub fn default_time_step(normal_stiffness: f64) -> f64 {
    REFERENCE_TIME_STEP * (1e6 / normal_stiffness).sqrt()
}

/// xi_n that gives restitution `e` to the d_p-d_p pair (m_eff = pi/12) at stiffness k_n.
pub fn damping_for_restitution(e: f64, normal_stiffness: f64) -> f64 {
    damping_for(e, normal_stiffness, REFERENCE_PAIR_MASS)
}

/// xi_n that gives restitution `e` to a contact of effective mass m_eff at stiffness k_n:
/// xi_n = 2 L w0 / sqrt(pi^2 + L^2), L = -ln e, w0 = sqrt(k_n / m_eff) (inverting
/// e = exp(-xi_n t_c / 2), t_c = pi / sqrt(k_n/m_eff - xi_n^2/4)).
pub fn damping_for(e: f64, normal_stiffness: f64, effective_mass: f64) -> f64 {
    let l = -e.ln();
    let w0 = (normal_stiffness / effective_mass).sqrt();
    2.0 * l * w0 / (PI * PI + l * l).sqrt()
}

/// A contact type: two sizes, or one size against a wall; its effective mass, contact time
/// and restitution under the linear law.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ContactType {
    /// d_i
    pub diameter: f64,
    /// d_j, or None for the wall
    pub other: Option<f64>,
    /// m_eff = m_i m_j / (m_i + m_j), or m_i against the wall (LAMMPS fix wall/gran)
    pub effective_mass: f64,
    /// t_c = pi / sqrt(k_n / m_eff - xi_n^2 / 4) (infinite when overdamped)
    pub contact_time: f64,
    /// e_n = exp(-xi_n t_c / 2)
    pub restitution: f64,
}

impl ContactType {
    fn new(d: f64, other: Option<f64>, meff: f64, kn: f64, xi_n: f64) -> Self {
        let w2 = kn / meff - 0.25 * xi_n * xi_n;
        let contact_time = if w2 > 0.0 {
            PI / w2.sqrt()
        } else {
            f64::INFINITY
        };
        ContactType {
            diameter: d,
            other,
            effective_mass: meff,
            contact_time,
            restitution: (-0.5 * xi_n * contact_time).exp(),
        }
    }

    /// xi_n of the contact, from e_n = exp(-xi_n t_c / 2) (NaN when overdamped).
    pub fn damping_rate(&self) -> f64 {
        -2.0 * self.restitution.ln() / self.contact_time
    }

    /// "0.9-1.1" or "1.0-wall".
    pub fn name(&self) -> String {
        match self.other {
            Some(o) => format!("{:.2}-{:.2}", self.diameter, o),
            None => format!("{:.2}-wall", self.diameter),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damping_from_restitution_inverts_the_restitution() {
        for e in [0.3, 0.82, 0.99] {
            let p = DemParams {
                normal_damping: damping_for_restitution(e, 1e6),
                size_mix: SizeMix::Mono,
                ..DemParams::channel(10.0, 5.0, 10.0, 0.6, 1)
            };
            let pair = p.contact_types()[0];
            assert!((pair.restitution - e).abs() < 1e-12, "{pair:?}");
        }
    }

    /// dem.md A1.2: xi_n = 180 at k_n = 1e6 gives e_n = 0.865 for the d_p pair, 0.884 for
    /// 0.9-0.9, 0.846 for 1.1-1.1, 0.869 for 0.9-1.1; e_n = 0.82 needs xi_n = 246.4.
    #[test]
    fn the_papers_damping_numbers() {
        let p = DemParams {
            normal_damping: 180.0,
            ..DemParams::channel(10.0, 5.0, 10.0, 0.6, 1)
        };
        let e = |a: f64, b: f64| {
            p.contact_types()
                .into_iter()
                .find(|t| t.diameter == a && t.other == Some(b))
                .unwrap()
                .restitution
        };
        assert!((e(1.0, 1.0) - 0.865).abs() < 5e-4);
        assert!((e(0.9, 0.9) - 0.884).abs() < 5e-4);
        assert!((e(1.1, 1.1) - 0.846).abs() < 5e-4);
        assert!((e(0.9, 1.1) - 0.869).abs() < 5e-4);
        assert!((damping_for_restitution(0.82, 1e6) - 246.4).abs() < 0.05);
    }

    #[test]
    fn counts_sum_to_n_and_follow_the_fractions() {
        for n in [1, 2, 3, 10, 563, 1001] {
            let c = SizeMix::Debnath.counts(n);
            assert_eq!(c.iter().sum::<usize>(), n);
            for (k, &(_, f)) in SizeMix::Debnath.components().iter().enumerate() {
                assert!((c[k] as f64 - f * n as f64).abs() <= 1.0, "{n}: {c:?}");
            }
        }
        // <d^3> = 1.018 (dem.md A1.3)
        let d3 = SizeMix::Debnath.mean_volume() * 6.0 / PI;
        assert!((d3 - 1.018).abs() < 1e-12);
    }

    #[test]
    fn the_default_step_resolves_the_papers_contacts() {
        let p = DemParams::channel(10.0, 5.0, 10.0, 0.6, 1);
        p.validate().unwrap();
        let coarse = DemParams {
            time_step: 2e-4,
            ..p.clone()
        };
        assert_eq!(coarse.validate().unwrap_err().key, "time_step");
    }
}
