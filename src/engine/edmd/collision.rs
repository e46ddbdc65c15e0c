//! Collision rules of rough inelastic spheres (thesis eqs. 2.5-2.16): pure functions from
//! pre-collisional to post-collisional velocities, with the energy dissipated.
//!
//! Notation: k is the unit vector from the centre of particle i to the contact point (for a
//! pair, towards particle j); a = d/2 is the radius; K = 4 I / (m d^2), so I = K m a^2.

use nalgebra::Vector3;

/// Material constants of one kind of contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactLaw {
    /// e, normal restitution
    pub restitution: f64,
    /// beta, tangential restitution
    pub roughness: f64,
    /// K = 4 I / (m d^2)
    pub inertia_factor: f64,
}

/// Translational and angular velocity of one sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereVelocity {
    /// c, translational velocity
    pub linear: Vector3<f64>,
    /// w, angular velocity
    pub angular: Vector3<f64>,
}

/// Radius a = d/2 of the unit-diameter spheres.
pub const RADIUS: f64 = 0.5;

/// Outcome of a pair collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairOutcome {
    pub first: SphereVelocity,
    pub second: SphereVelocity,
    /// J, impulse transferred from particle i to particle j (m (c_i - c_i'))
    pub impulse: Vector3<f64>,
    /// kinetic energy dissipated, -dE >= 0
    pub dissipated: f64,
}

/// Outcome of a wall collision.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallOutcome {
    pub sphere: SphereVelocity,
    /// J_w, impulse delivered to the wall (m (c - c'))
    pub impulse: Vector3<f64>,
    /// kinetic energy dissipated, -dE >= 0
    pub dissipated: f64,
}

/// Relative velocity of the contact points, g = c_i - c_j - a k x (w_i + w_j) (eq. 2.5).
pub fn contact_velocity(i: &SphereVelocity, j: &SphereVelocity, k: &Vector3<f64>) -> Vector3<f64> {
    i.linear - j.linear - RADIUS * k.cross(&(i.angular + j.angular))
}

/// Pair collision (eqs. 2.6-2.11), unit masses. `k` is the unit vector from i to j.
///
/// J = m eta2 g + m (eta1 - eta2) k (k . g), eta1 = (1 + e)/2, eta2 = (1 + beta) K / (2 (1 + K));
/// c_i' = c_i - J/m, c_j' = c_j + J/m, w_i' - w_i = w_j' - w_j = -(a/I) k x J.
pub fn pair_collision(
    i: &SphereVelocity,
    j: &SphereVelocity,
    k: &Vector3<f64>,
    law: &ContactLaw,
) -> PairOutcome {
    let kk = law.inertia_factor;
    let g = contact_velocity(i, j, k);
    let g_n = k.dot(&g);
    let g_t = g - g_n * k;
    let eta1 = 0.5 * (1.0 + law.restitution);
    let eta2 = 0.5 * (1.0 + law.roughness) * kk / (1.0 + kk);
    let impulse = eta2 * g + (eta1 - eta2) * g_n * k;
    // I = K m a^2, so (a / I) = 1 / (K a) for m = 1
    let spin_change = -k.cross(&impulse) / (kk * RADIUS);
    let dissipated = 0.25
        * ((1.0 - law.restitution * law.restitution) * g_n * g_n
            + kk / (1.0 + kk) * (1.0 - law.roughness * law.roughness) * g_t.norm_squared());
    PairOutcome {
        first: SphereVelocity {
            linear: i.linear - impulse,
            angular: i.angular + spin_change,
        },
        second: SphereVelocity {
            linear: j.linear + impulse,
            angular: j.angular + spin_change,
        },
        impulse,
        dissipated,
    }
}

/// Wall collision (eqs. 2.12-2.16): the wall is a rough body of infinite mass at rest. `k` is
/// the unit vector from the sphere's centre to the contact point (the outward wall normal).
///
/// g = c - a k x w; J_w = 2 m eta2w g + 2 m (eta1w - eta2w) k (k . g);
/// c' = c - J_w/m, w' = w - (a/I) k x J_w.
pub fn wall_collision(s: &SphereVelocity, k: &Vector3<f64>, law: &ContactLaw) -> WallOutcome {
    let kk = law.inertia_factor;
    let g = s.linear - RADIUS * k.cross(&s.angular);
    let g_n = k.dot(&g);
    let g_t = g - g_n * k;
    let eta1 = 0.5 * (1.0 + law.restitution);
    let eta2 = 0.5 * (1.0 + law.roughness) * kk / (1.0 + kk);
    let impulse = 2.0 * eta2 * g + 2.0 * (eta1 - eta2) * g_n * k;
    let dissipated = 0.5
        * ((1.0 - law.restitution * law.restitution) * g_n * g_n
            + kk / (1.0 + kk) * (1.0 - law.roughness * law.roughness) * g_t.norm_squared());
    WallOutcome {
        sphere: SphereVelocity {
            linear: s.linear - impulse,
            angular: s.angular - k.cross(&impulse) / (kk * RADIUS),
        },
        impulse,
        dissipated,
    }
}
