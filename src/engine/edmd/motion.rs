//! Free flight under uniform gravity g along +x, and the times at which it meets a plane or
//! another sphere. Pure functions: *when* things meet, not *what* happens then.
//!
//! Between events: x(t) = x0 + c_x t + g t^2 / 2, y and z straight, angular velocity constant.
//! Because gravity is uniform, the relative motion of two spheres is a straight line, so pair
//! collision times are roots of a quadratic (thesis eq. 2.19).

/// Position and velocity after free flight over `dt` under gravity `g` along +x.
#[inline(always)]
pub fn fly(position: [f64; 3], velocity: [f64; 3], g: f64, dt: f64) -> ([f64; 3], [f64; 3]) {
    (
        [
            position[0] + velocity[0] * dt + 0.5 * g * dt * dt,
            position[1] + velocity[1] * dt,
            position[2] + velocity[2] * dt,
        ],
        [velocity[0] + g * dt, velocity[1], velocity[2]],
    )
}

/// Time until a straight flight x0 + v t reaches the plane at `lower` (moving down) or `upper`
/// (moving up); `None` when the velocity is zero. A position already past the plane it moves
/// towards gives 0 (round-off never makes a crossing be lost).
#[inline(always)]
pub fn linear_exit_time(x0: f64, v: f64, lower: f64, upper: f64) -> Option<(f64, bool)> {
    if v > 0.0 {
        Some((((upper - x0) / v).max(0.0), true))
    } else if v < 0.0 {
        Some((((lower - x0) / v).max(0.0), false))
    } else {
        None
    }
}

/// As [`linear_exit_time`] (the same arithmetic, so the same bits), without branches: which
/// face a particle leaves by is random, so the face is chosen by a select. Infinite time (and
/// `false`) when the velocity is zero.
#[inline(always)]
pub fn linear_exit_time_within(x0: f64, v: f64, lower: f64, upper: f64) -> (f64, bool) {
    let up = v > 0.0;
    let face = if up { upper } else { lower };
    let t = ((face - x0) / v).max(0.0);
    (if v != 0.0 { t } else { f64::INFINITY }, up)
}

/// Time until the parabola x(t) = x0 + v t + g t^2 / 2 (g > 0) leaves [lower, upper], with
/// `true` when it leaves through `upper`. Roots are taken in their cancellation-free forms.
#[inline(always)]
pub fn parabolic_exit_time(x0: f64, v: f64, g: f64, lower: f64, upper: f64) -> (f64, bool) {
    debug_assert!(g > 0.0);
    if v < 0.0 {
        // moving down: it reaches `lower` if v^2 >= 2 g (x0 - lower); the first root is
        // t_- = 2 (x0 - lower) / (-v + sqrt(disc))
        let c = x0 - lower;
        let disc = v * v - 2.0 * g * c;
        if disc >= 0.0 {
            return ((2.0 * c / (-v + disc.sqrt())).max(0.0), false);
        }
        // turns around below... above `lower`: reaches `upper` at t_+ = (-v + sqrt(disc')) / g
        let disc_up = v * v - 2.0 * g * (x0 - upper);
        ((-v + disc_up.sqrt()) / g, true)
    } else {
        // moving up (or at rest): t_+ = 2 (upper - x0) / (v + sqrt(v^2 + 2 g (upper - x0)))
        let c = upper - x0;
        if c <= 0.0 {
            return (0.0, true);
        }
        let disc = v * v + 2.0 * g * c;
        (2.0 * c / (v + disc.sqrt()), true)
    }
}

/// Time until two unit-diameter spheres with relative position `r` = r_i - r_j and relative
/// velocity `v` touch, if they approach and meet: the smaller root of
/// |r + v t|^2 = d^2 (thesis eq. 2.20), written as t = (r^2 - d^2) / (-b + sqrt(b^2 - v^2 (r^2 - d^2)))
/// with b = r . v. Overlapping approaching spheres (round-off) collide at once (t = 0).
#[inline(always)]
pub fn pair_contact_time(r: [f64; 3], v: [f64; 3]) -> Option<f64> {
    let b = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    if b >= 0.0 {
        return None;
    }
    let gap = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - 1.0;
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let disc = b * b - v2 * gap;
    if disc < 0.0 {
        return None;
    }
    Some((gap / (-b + disc.sqrt())).max(0.0))
}

/// As [`pair_contact_time`], but only if the contact comes before `horizon`; avoids the square
/// root for pairs that cannot beat it (the root satisfies t >= gap / (-2 b)). The plain,
/// branching form: the reference that the engine's [`pair_contact_time_within`] is tested
/// against.
#[inline(always)]
pub fn pair_contact_time_before(r: [f64; 3], v: [f64; 3], horizon: f64) -> Option<f64> {
    let b = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    if b >= 0.0 {
        return None;
    }
    let gap = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - 1.0;
    if gap > -2.0 * b * horizon {
        return None;
    }
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let disc = b * b - v2 * gap;
    if disc < 0.0 {
        return None;
    }
    let t = (gap / (-b + disc.sqrt())).max(0.0);
    (t < horizon).then_some(t)
}

/// As [`pair_contact_time_before`] (the same arithmetic, so the same decisions bit for bit),
/// but without branches: the square root is always taken and the tests are combined into one
/// select, so that a neighbour search's random approach/recede outcomes cost no mispredicted
/// branches. Infinite when the pair does not touch before `horizon`.
#[inline(always)]
pub fn pair_contact_time_within(r: [f64; 3], v: [f64; 3], horizon: f64) -> f64 {
    PairApproach::new(r, v).contact_time_within(horizon)
}

/// The coefficients of a pair's contact equation |r + v t|^2 = d^2 (d = 1): b = r.v, the gap
/// |r|^2 - 1 and |v|^2. Split from the root so that a search can first keep, without a
/// branch, the pairs that may touch and take square roots only for those.
#[derive(Clone, Copy, Debug, Default)]
pub struct PairApproach {
    /// b = r.v (negative while approaching)
    b: f64,
    /// |r|^2 - d^2
    gap: f64,
    /// |v|^2
    v2: f64,
}

// the tests are written as negations (`!(b >= 0.0)`) on purpose: they decide NaN exactly as
// the branching `pair_contact_time_before` does
#[allow(clippy::neg_cmp_op_on_partial_ord)]
impl PairApproach {
    #[inline(always)]
    pub fn new(r: [f64; 3], v: [f64; 3]) -> Self {
        PairApproach {
            b: r[0] * v[0] + r[1] * v[1] + r[2] * v[2],
            gap: r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - 1.0,
            v2: v[0] * v[0] + v[1] * v[1] + v[2] * v[2],
        }
    }

    /// The coefficients as computed elsewhere (the two-lane first pass).
    #[inline(always)]
    pub(crate) fn from_parts(b: f64, gap: f64, v2: f64) -> Self {
        PairApproach { b, gap, v2 }
    }

    /// (b, gap, |v|^2).
    pub fn parts(self) -> [f64; 3] {
        [self.b, self.gap, self.v2]
    }

    /// Approaching, meeting at all (discriminant b^2 - |v|^2 (|r|^2 - d^2) >= 0), and close
    /// enough to touch before `horizon` (the gap closes no faster than -2 b per unit time):
    /// the square-root-free part of the test.
    #[inline(always)]
    pub fn may_touch_within(self, horizon: f64) -> bool {
        let approaching = !(self.b >= 0.0);
        let meets = !(self.discriminant() < 0.0);
        let soon_enough = !(self.gap > -2.0 * self.b * horizon);
        approaching & meets & soon_enough
    }

    /// b^2 - |v|^2 (|r|^2 - d^2): negative when the spheres pass each other.
    #[inline(always)]
    fn discriminant(self) -> f64 {
        self.b * self.b - self.v2 * self.gap
    }

    /// Time of contact if before `horizon`, else infinite; without branches.
    #[inline(always)]
    pub fn contact_time_within(self, horizon: f64) -> f64 {
        let PairApproach { b, gap, .. } = self;
        let disc = self.discriminant();
        let t = (gap / (-b + disc.max(0.0).sqrt())).max(0.0);
        let hit = self.may_touch_within(horizon) & (t < horizon);
        if hit { t } else { f64::INFINITY }
    }
}

/// Time until a straight flight from displacement `d` (|d| <= `radius`) with velocity `v`
/// leaves the ball of radius `radius` about the origin: the larger root of
/// |d + v t|^2 = radius^2, in a cancellation-free form. A start on or outside the surface gives
/// 0; `None` when at rest.
#[inline(always)]
pub fn ball_exit_time(d: [f64; 3], v: [f64; 3], radius: f64) -> Option<f64> {
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    if v2 == 0.0 {
        return None;
    }
    let room = radius * radius - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if room <= 0.0 {
        return Some(0.0);
    }
    let b = d[0] * v[0] + d[1] * v[1] + d[2] * v[2];
    let root = (b * b + v2 * room).sqrt();
    Some(if b < 0.0 {
        (root - b) / v2
    } else {
        room / (b + root)
    })
}

/// A lower bound on the time until the parabola d + v t + g t^2 / 2 (gravity along +x) leaves
/// the ball of radius `radius` about the origin: |d(t)| <= |d| + |v| t + g t^2 / 2, so the ball
/// is not left before that bound reaches `radius` (the exact time is a quartic's root).
#[inline(always)]
pub fn ball_exit_time_bound(d: [f64; 3], v: [f64; 3], g: f64, radius: f64) -> f64 {
    let room = radius - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if room <= 0.0 {
        return 0.0;
    }
    let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    // smaller positive root of g t^2 / 2 + speed t - room = 0, cancellation-free
    2.0 * room / (speed + (speed * speed + 2.0 * g * room).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_pcg::Pcg64;

    fn norm(a: [f64; 3]) -> f64 {
        (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
    }

    fn random_vector(rng: &mut Pcg64, scale: f64) -> [f64; 3] {
        [0; 3].map(|_| scale * (2.0 * rng.random::<f64>() - 1.0))
    }

    /// The branch-free contact time makes the same decision, and returns the same bits, as
    /// the plain one, over pairs that approach, recede, miss, graze, overlap, and contacts just
    /// before, at and just after the horizon.
    #[test]
    fn branch_free_contact_time_equals_the_plain_one() {
        let mut rng = Pcg64::seed_from_u64(17);
        let mut hits = 0;
        for case in 0..200_000 {
            let r = random_vector(&mut rng, 1.5);
            let v = random_vector(&mut rng, 2.0);
            let horizon = match case % 4 {
                0 => f64::INFINITY,
                1 => rng.random::<f64>() * 2.0,
                // an ulp before, exactly at and an ulp after the plain contact time (when there
                // is one): the strict `<` decides
                _ => {
                    let nudge = [1.0 - f64::EPSILON / 2.0, 1.0, 1.0 + f64::EPSILON][case % 3];
                    pair_contact_time(r, v).unwrap_or(1.0) * nudge
                }
            };
            let plain = pair_contact_time_before(r, v, horizon);
            let branch_free = pair_contact_time_within(r, v, horizon);
            match plain {
                Some(t) => {
                    hits += 1;
                    assert_eq!(t.to_bits(), branch_free.to_bits(), "{r:?} {v:?} {horizon}");
                }
                None => assert_eq!(branch_free, f64::INFINITY, "{r:?} {v:?} {horizon}"),
            }
        }
        assert!(hits > 10_000, "the cases exercise contacts: {hits}");
    }

    /// The square-root-free filter of a search's first pass keeps every pair that touches
    /// before any shorter horizon: a search that filtered with its horizon at the start of a
    /// chunk and tests with a later, shorter one loses no contact.
    #[test]
    fn filter_keeps_every_pair_that_touches_within_a_shorter_horizon() {
        let mut rng = Pcg64::seed_from_u64(29);
        let mut hits = 0;
        let mut dropped = 0;
        for _ in 0..200_000 {
            let pair =
                PairApproach::new(random_vector(&mut rng, 1.5), random_vector(&mut rng, 2.0));
            let horizon = 2.0 * rng.random::<f64>();
            let shorter = horizon * rng.random::<f64>();
            if pair.contact_time_within(shorter).is_finite() {
                hits += 1;
                assert!(
                    pair.may_touch_within(horizon),
                    "{pair:?} {horizon} {shorter}"
                );
            }
            dropped += !pair.may_touch_within(horizon) as usize;
        }
        assert!(hits > 10_000, "the cases exercise contacts: {hits}");
        assert!(dropped > 50_000, "the filter drops pairs: {dropped}");
    }

    /// The branch-free face exit equals the plain one bit for bit: moving up, down, at rest,
    /// on a face and already past it.
    #[test]
    fn branch_free_face_exit_equals_the_plain_one() {
        let mut rng = Pcg64::seed_from_u64(23);
        for case in 0..100_000 {
            let (lower, upper) = (1.0, 2.0 + rng.random::<f64>());
            let x0 = match case % 5 {
                0 => lower,
                1 => upper,
                _ => 0.5 + 3.0 * rng.random::<f64>(),
            };
            let v = if case % 7 == 0 {
                0.0
            } else {
                4.0 * rng.random::<f64>() - 2.0
            };
            let (t, up) = linear_exit_time_within(x0, v, lower, upper);
            match linear_exit_time(x0, v, lower, upper) {
                Some((plain, plain_up)) => {
                    assert_eq!((t.to_bits(), up), (plain.to_bits(), plain_up), "{x0} {v}");
                }
                None => assert_eq!(t, f64::INFINITY, "{x0} {v}"),
            }
        }
    }

    /// The straight exit is on the surface, and inside until then.
    #[test]
    fn ball_exit_lands_on_the_surface() {
        let mut rng = Pcg64::seed_from_u64(3);
        for _ in 0..10_000 {
            let radius = 0.25;
            let d = random_vector(&mut rng, 0.14);
            let v = random_vector(&mut rng, 2.0);
            let t = ball_exit_time(d, v, radius).unwrap();
            let (at_exit, _) = fly(d, v, 0.0, t);
            assert!((norm(at_exit) - radius).abs() < 1e-12, "{d:?} {v:?} {t}");
            let (halfway, _) = fly(d, v, 0.0, 0.5 * t);
            assert!(norm(halfway) < radius);
        }
        assert_eq!(
            ball_exit_time([0.3, 0.0, 0.0], [1.0, 0.0, 0.0], 0.25),
            Some(0.0)
        );
        assert_eq!(ball_exit_time([0.1, 0.0, 0.0], [0.0; 3], 0.25), None);
    }

    /// Under gravity the bound never comes after the true exit (checked on a fine time grid),
    /// and is exact when the flight starts at the centre straight along gravity.
    #[test]
    fn ball_exit_bound_under_gravity_is_never_late() {
        let mut rng = Pcg64::seed_from_u64(4);
        for _ in 0..2_000 {
            let radius = 0.25;
            let d = random_vector(&mut rng, 0.14);
            let v = random_vector(&mut rng, 2.0);
            let g = rng.random::<f64>() * 5.0;
            let bound = ball_exit_time_bound(d, v, g, radius);
            for k in 0..=1000 {
                let (r, _) = fly(d, v, g, bound * k as f64 / 1000.0);
                assert!(
                    norm(r) <= radius * (1.0 + 1e-12),
                    "left at {k}/1000 of the bound"
                );
            }
        }
        let t = ball_exit_time_bound([0.0; 3], [0.5, 0.0, 0.0], 1.0, 0.25);
        let (r, _) = fly([0.0; 3], [0.5, 0.0, 0.0], 1.0, t);
        assert!((r[0] - 0.25).abs() < 1e-15);
    }
}
