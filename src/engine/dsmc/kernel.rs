//! The collision kernel both DSMC solvers share: the contact direction of a hard-sphere
//! collision given the relative velocity, smooth inelastic hard-sphere collisions (thesis
//! eqs. 2.26-2.27 and 5.4-5.5), and portable random deviates (open unit interval, normal
//! pairs) from `libm`, so that a seed gives bitwise the same run on every machine.

use nalgebra::Vector3;
use rand::{Rng, RngExt};

/// Unit vector k from sphere i to sphere j at contact, given the direction u of their relative
/// velocity: among approaching contacts (u . k > 0) the rate is proportional to u . k, so
/// cos(theta) = u . k has density 2 cos(theta) on [0, 1] (drawn as sqrt of a uniform deviate)
/// and the azimuth is uniform.
///
/// Drawing a pair with probability |g| / g_max and then k from this density samples the same
/// collisions as drawing k uniformly on the sphere and accepting with
/// Theta(g . k) |g . k| / g_max (thesis eq. 2.19): integrated over k the latter accepts with
/// |g| / (4 g_max), and its accepted k have density proportional to Theta(g . k) (g . k).
pub fn contact_direction<R: Rng + ?Sized>(rng: &mut R, u: &Vector3<f64>) -> Vector3<f64> {
    let cos_theta = rng.random::<f64>().sqrt();
    let sin_theta = (1.0 - cos_theta * cos_theta).sqrt();
    let phi = 2.0 * std::f64::consts::PI * rng.random::<f64>();
    // an orthonormal pair perpendicular to u
    let helper = if u.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = u.cross(&helper).normalize();
    let e2 = u.cross(&e1);
    cos_theta * u + sin_theta * (libm::cos(phi) * e1 + libm::sin(phi) * e2)
}

/// Smooth inelastic hard spheres i and j collide along the unit vector `k` from i to j
/// (thesis eqs. 2.26-2.27, and 5.4-5.5 for unequal masses):
/// v_i' = v_i - mu_ji (1 + e) (k . v_ij) k, v_j' = v_j + mu_ij (1 + e) (k . v_ij) k,
/// with v_ij = v_i - v_j, mu_ji = m_j / (m_i + m_j), mu_ij = m_i / (m_i + m_j).
/// Returns the kinetic energy dissipated, (1 - e^2) m_i m_j / (2 (m_i + m_j)) (k . v_ij)^2.
pub fn smooth_collision(
    vi: &mut Vector3<f64>,
    vj: &mut Vector3<f64>,
    k: &Vector3<f64>,
    restitution: f64,
    masses: (f64, f64),
) -> f64 {
    let (mi, mj) = masses;
    let approach = k.dot(&(*vi - *vj)); // k . v_ij
    let total = mi + mj;
    let kick = (1.0 + restitution) * approach;
    *vi -= (mj / total * kick) * k;
    *vj += (mi / total * kick) * k;
    0.5 * (1.0 - restitution * restitution) * mi * mj / total * approach * approach
}

/// A uniform deviate on the open interval (0, 1): the top 53 bits of a 64-bit word, centred
/// in their bin, so that logarithms and divisions never see 0 or 1.
pub fn open_unit<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    ((rng.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64)
}

/// Two independent standard normal deviates (Box-Muller with both outputs, `libm` trig).
pub fn normal_pair<R: Rng + ?Sized>(rng: &mut R) -> (f64, f64) {
    let radius = (-2.0 * libm::log(open_unit(rng))).sqrt();
    let angle = 2.0 * std::f64::consts::PI * rng.random::<f64>();
    (radius * libm::cos(angle), radius * libm::sin(angle))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_pcg::Pcg64Mcg;

    /// Contact directions lie on the approaching hemisphere with <u . k> = 2/3 (density
    /// 2 cos theta) and no preferred azimuth; sampling error of the means ~ 1e-3 for 1e5 draws.
    #[test]
    fn contact_directions_are_weighted_by_the_approach_speed() {
        let mut rng = Pcg64Mcg::seed_from_u64(3);
        let u = Vector3::new(0.3, -0.5, 0.8).normalize();
        let draws = 100_000;
        let mut mean_cos = 0.0;
        let mut mean_k = Vector3::zeros();
        for _ in 0..draws {
            let k = contact_direction(&mut rng, &u);
            assert!((k.norm() - 1.0).abs() < 1e-12);
            let c = u.dot(&k);
            assert!(c >= 0.0);
            mean_cos += c / draws as f64;
            mean_k += (k - c * u) / draws as f64;
        }
        assert!((mean_cos - 2.0 / 3.0).abs() < 5e-3, "<cos> = {mean_cos}");
        assert!(mean_k.norm() < 1e-2, "azimuthal mean {mean_k:?}");
    }

    /// Unequal masses: momentum is conserved, the normal relative velocity becomes
    /// -e (k . v_ij), the tangential one is kept and the energy loss is the returned one, for
    /// 10^4 random collisions (relative error < 1e-12).
    #[test]
    fn smooth_collisions_obey_the_collision_rule() {
        let mut rng = Pcg64Mcg::seed_from_u64(11);
        for _ in 0..10_000 {
            let (a, b) = normal_pair(&mut rng);
            let (c, d) = normal_pair(&mut rng);
            let (f, h) = normal_pair(&mut rng);
            let mut vi = Vector3::new(a, b, c);
            let mut vj = Vector3::new(d, f, h);
            let g = vi - vj;
            let k = contact_direction(&mut rng, &g.normalize());
            let e = rng.random::<f64>();
            let (mi, mj) = (1.0, 0.1 + 10.0 * rng.random::<f64>());
            let (vi0, vj0) = (vi, vj);
            let energy = |x: &Vector3<f64>, y: &Vector3<f64>| {
                0.5 * mi * x.norm_squared() + 0.5 * mj * y.norm_squared()
            };
            let lost = smooth_collision(&mut vi, &mut vj, &k, e, (mi, mj));
            let scale = g.norm() * (mi + mj);
            assert!((mi * (vi - vi0) + mj * (vj - vj0)).norm() < 1e-12 * scale);
            let g1 = vi - vj;
            assert!((g1.dot(&k) + e * g.dot(&k)).abs() < 1e-12 * g.norm());
            assert!(((g1 - g1.dot(&k) * k) - (g - g.dot(&k) * k)).norm() < 1e-12 * g.norm());
            let drop = energy(&vi0, &vj0) - energy(&vi, &vj);
            assert!(
                (drop - lost).abs() < 1e-12 * energy(&vi0, &vj0),
                "{drop} vs {lost}"
            );
            assert!(lost >= 0.0);
        }
    }

    /// The deviates are what they claim: (0, 1) never hits an end; normal pairs have mean 0,
    /// variance 1, kurtosis 3 and no correlation (10^5 pairs, errors ~ 0.5 %).
    #[test]
    fn deviates_have_their_distributions() {
        let mut rng = Pcg64Mcg::seed_from_u64(5);
        let n = 100_000;
        let (mut m1, mut m2, mut m4, mut cross) = (0.0, 0.0, 0.0, 0.0);
        for _ in 0..n {
            let u = open_unit(&mut rng);
            assert!(u > 0.0 && u < 1.0);
            let (a, b) = normal_pair(&mut rng);
            m1 += (a + b) / (2.0 * n as f64);
            m2 += (a * a + b * b) / (2.0 * n as f64);
            m4 += (a.powi(4) + b.powi(4)) / (2.0 * n as f64);
            cross += a * b / n as f64;
        }
        assert!(m1.abs() < 0.01, "mean {m1}");
        assert!((m2 - 1.0).abs() < 0.015, "variance {m2}");
        assert!(
            (m4 / (m2 * m2) - 3.0).abs() < 0.1,
            "kurtosis {}",
            m4 / (m2 * m2)
        );
        assert!(cross.abs() < 0.015, "correlation {cross}");
    }
}
