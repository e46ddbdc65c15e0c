//! Slip, temperatures and gradients at the walls (thesis 3.1.1, Figs. 3.10-3.11), from the
//! window-averaged cross-channel profiles of the structure analysis (phi, U_x, omega_z, T,
//! theta over its `profile_bins` bins and its window, the steady window or else the final
//! third; reused, not recomputed): "all the quantities at the walls are average values of two
//! bins adjacent to the left and right walls".
//!
//! Sign folding: a quantity even under the reflection y -> W - y (U_x, T, theta) is averaged
//! over the two wall bins; an odd one (omega_z, < 0 at y = 0 and > 0 at y = W in the thesis'
//! flows) is averaged with the sign it has at the wall y = W: (q(W) - q(0)) / 2, so the
//! rotational slip is positive in the thesis' convention and a plain average cannot cancel
//! it. Gradients at the wall are one-sided first differences between the wall bin and its
//! neighbour, d q / d y' with y' the distance from the wall into the channel, folded the same
//! way: (s q'(0) + q'(W)) / 2, s = -1 for odd quantities. The wall bins are the outermost bins
//! holding centres (bins narrower than d/2 next to a wall hold none). The thesis' temperature
//! jump T_w - T_s needs a wall temperature T_s that a fixed wall does not have; we report T_w
//! and theta_w, as its Figs. 3.10(c, d) do.

use crate::analysis::ProfileRow;

/// The wall values of a job's profiles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallValues {
    /// omega_z at the walls, sign-folded, sqrt(g/d)
    pub slip_rotational: f64,
    /// T at the walls, g d
    pub temperature: f64,
    /// theta at the walls, g d
    pub rotational_temperature: f64,
    /// dU_x/dy', sqrt(g/d)
    pub gradient_u_x: f64,
    /// d omega_z/dy', sign-folded, sqrt(g/d)/d
    pub gradient_omega_z: f64,
    /// dT/dy', g
    pub gradient_temperature: f64,
    /// d theta/dy', g
    pub gradient_rotational_temperature: f64,
}

/// (value at the walls, gradient at the walls) of one quantity, folded with parity `sign`.
fn folded(profiles: &[ProfileRow], quantity: &str, sign: f64) -> (f64, f64) {
    let points: Vec<(f64, f64)> = profiles
        .iter()
        .filter(|p| p.quantity == quantity && p.value.is_finite())
        .map(|p| (p.y, p.value))
        .collect();
    let k = points.len();
    if k < 2 {
        return (f64::NAN, f64::NAN);
    }
    let (lo, lo_next, hi, hi_next) = (points[0], points[1], points[k - 1], points[k - 2]);
    let value = 0.5 * (sign * lo.1 + hi.1);
    let lower = (lo_next.1 - lo.1) / (lo_next.0 - lo.0);
    let upper = (hi_next.1 - hi.1) / (hi.0 - hi_next.0);
    (value, 0.5 * (sign * lower + upper))
}

/// The wall values of window-averaged profiles (NaN where a profile is missing).
pub fn wall_values(profiles: &[ProfileRow]) -> WallValues {
    let (_, gradient_u_x) = folded(profiles, "u_x", 1.0);
    let (slip_rotational, gradient_omega_z) = folded(profiles, "omega_z", -1.0);
    let (temperature, gradient_temperature) = folded(profiles, "T", 1.0);
    let (rotational_temperature, gradient_rotational_temperature) = folded(profiles, "theta", 1.0);
    WallValues {
        slip_rotational,
        temperature,
        rotational_temperature,
        gradient_u_x,
        gradient_omega_z,
        gradient_temperature,
        gradient_rotational_temperature,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile(q: &str, f: impl Fn(f64) -> f64) -> Vec<ProfileRow> {
        (0..10)
            .map(|b| {
                let y = 0.5 + b as f64;
                ProfileRow {
                    quantity: q.into(),
                    bin: b,
                    y,
                    value: f(y),
                }
            })
            .collect()
    }

    #[test]
    fn odd_quantities_keep_the_upper_walls_sign() {
        // omega_z = y - 5 on [0, 10]: -4.5 and 4.5 at the wall bins, slope 1 everywhere
        let mut rows = profile("omega_z", |y| y - 5.0);
        // U_x = 1 + y (10 - y): 5.75 at both walls, inward slope 10 - 2 y: 8 (mean of 9 and 7)
        rows.extend(profile("u_x", |y| 1.0 + y * (10.0 - y)));
        let w = wall_values(&rows);
        assert!((w.slip_rotational - 4.5).abs() < 1e-12);
        assert!(
            (w.gradient_omega_z + 1.0).abs() < 1e-12,
            "{}",
            w.gradient_omega_z
        );
        assert!((w.gradient_u_x - 8.0).abs() < 1e-12, "{}", w.gradient_u_x);
        assert!(w.temperature.is_nan());
    }
}
