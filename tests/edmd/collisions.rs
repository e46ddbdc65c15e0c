//! Oracle 1 (docs/oracles.md section 1): single collisions against the exact rules of thesis eqs. 2.5-2.16,
//! checked on many random collisions to relative error ~1e-12.

use granflow::engine::edmd::collision::{
    ContactLaw, RADIUS, SphereVelocity, contact_velocity, pair_collision, wall_collision,
};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64;

const TOL: f64 = 1e-12;

fn random_vec(rng: &mut Pcg64, scale: f64) -> Vector3<f64> {
    Vector3::new(
        rng.random::<f64>() - 0.5,
        rng.random::<f64>() - 0.5,
        rng.random::<f64>() - 0.5,
    ) * 2.0
        * scale
}

fn random_sphere(rng: &mut Pcg64) -> SphereVelocity {
    SphereVelocity {
        linear: random_vec(rng, 3.0),
        angular: random_vec(rng, 5.0),
    }
}

fn random_law(rng: &mut Pcg64) -> ContactLaw {
    ContactLaw {
        restitution: rng.random::<f64>(),
        roughness: 2.0 * rng.random::<f64>() - 1.0,
        inertia_factor: if rng.random::<bool>() { 0.4 } else { 2.0 / 3.0 },
    }
}

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= TOL * scale.max(1.0)
}

fn assert_vec_close(a: Vector3<f64>, b: Vector3<f64>, scale: f64, what: &str) {
    for k in 0..3 {
        assert!(close(a[k], b[k], scale), "{what}: {a:?} vs {b:?}");
    }
}

/// Kinetic energy m c^2/2 + I w^2/2 with m = 1, I = K/4.
fn energy(s: &SphereVelocity, k: f64) -> f64 {
    0.5 * s.linear.norm_squared() + 0.5 * (k / 4.0) * s.angular.norm_squared()
}

#[test]
fn pair_collision_obeys_restitution_conservation_and_energy_loss() {
    let mut rng = Pcg64::seed_from_u64(11);
    for _ in 0..100_000 {
        let (a, b) = (random_sphere(&mut rng), random_sphere(&mut rng));
        let k = random_vec(&mut rng, 1.0).normalize();
        let law = random_law(&mut rng);
        let kk = law.inertia_factor;
        let out = pair_collision(&a, &b, &k, &law);
        let scale = 50.0;

        // g_n' = -e g_n and g_t' = -beta g_t
        let g = contact_velocity(&a, &b, &k);
        let g2 = contact_velocity(&out.first, &out.second, &k);
        let (gn, gn2) = (k.dot(&g), k.dot(&g2));
        assert!(
            close(gn2, -law.restitution * gn, scale),
            "normal restitution: {gn2} vs {}",
            -law.restitution * gn
        );
        assert_vec_close(
            g2 - gn2 * k,
            -law.roughness * (g - gn * k),
            scale,
            "tangential restitution",
        );

        // linear momentum
        assert_vec_close(
            out.first.linear + out.second.linear,
            a.linear + b.linear,
            scale,
            "linear momentum",
        );
        // angular momentum of each sphere about the contact point: I w + (a k_to_contact) x ... ;
        // for sphere 1 the contact is at +a k: L = I w1 + m (r_c - r_1) x c1 taken about the
        // contact, i.e. I w1 - a k x c1 (unit mass); likewise sphere 2 with -a k
        let i_mom = kk / 4.0;
        let l1 = |s: &SphereVelocity| i_mom * s.angular - RADIUS * k.cross(&s.linear);
        let l2 = |s: &SphereVelocity| i_mom * s.angular + RADIUS * k.cross(&s.linear);
        assert_vec_close(
            l1(&out.first),
            l1(&a),
            scale,
            "angular momentum of sphere 1 about contact",
        );
        assert_vec_close(
            l2(&out.second),
            l2(&b),
            scale,
            "angular momentum of sphere 2 about contact",
        );
        // spin along the normal is untouched
        assert!(close(k.dot(&out.first.angular), k.dot(&a.angular), scale));
        assert!(close(k.dot(&out.second.angular), k.dot(&b.angular), scale));

        // energy loss formula of docs/oracles.md section 1
        let gt2 = (g - gn * k).norm_squared();
        let loss = 0.25
            * ((1.0 - law.restitution.powi(2)) * gn * gn
                + kk / (1.0 + kk) * (1.0 - law.roughness.powi(2)) * gt2);
        let de = energy(&out.first, kk) + energy(&out.second, kk) - energy(&a, kk) - energy(&b, kk);
        assert!(close(de, -loss, 1000.0), "energy change {de} vs {}", -loss);
        assert!(close(out.dissipated, loss, 1000.0));
        // oracle's explicit form: dv1 = -(1+e)/2 g_n - eta g_t, dw1 = (k x dv1)/(K a)
        let eta = kk * (1.0 + law.roughness) / (2.0 * (1.0 + kk));
        let dv1 = -(1.0 + law.restitution) / 2.0 * gn * k - eta * (g - gn * k);
        assert_vec_close(out.first.linear - a.linear, dv1, scale, "dv1");
        assert_vec_close(
            out.first.angular - a.angular,
            k.cross(&dv1) / (kk * RADIUS),
            scale,
            "dw1",
        );
        assert_vec_close(
            out.second.angular - b.angular,
            k.cross(&dv1) / (kk * RADIUS),
            scale,
            "dw2",
        );
    }
}

#[test]
fn wall_collision_obeys_restitution_and_energy_loss() {
    let mut rng = Pcg64::seed_from_u64(12);
    for _ in 0..100_000 {
        let s = random_sphere(&mut rng);
        let upper = rng.random::<bool>();
        let k = Vector3::new(0.0, if upper { 1.0 } else { -1.0 }, 0.0);
        let law = random_law(&mut rng);
        let kk = law.inertia_factor;
        let out = wall_collision(&s, &k, &law);
        let scale = 50.0;
        let contact = |v: &SphereVelocity| v.linear - RADIUS * k.cross(&v.angular);
        let (g, g2) = (contact(&s), contact(&out.sphere));
        let (gn, gn2) = (k.dot(&g), k.dot(&g2));
        assert!(close(gn2, -law.restitution * gn, scale));
        assert_vec_close(
            g2 - gn2 * k,
            -law.roughness * (g - gn * k),
            scale,
            "wall tangential restitution",
        );
        // angular momentum about the contact point is conserved (the wall's force acts there)
        let l = |v: &SphereVelocity| (kk / 4.0) * v.angular - RADIUS * k.cross(&v.linear);
        assert_vec_close(
            l(&out.sphere),
            l(&s),
            scale,
            "angular momentum about the wall contact",
        );
        // impulse delivered to the wall is the sphere's momentum loss
        assert_vec_close(
            out.impulse,
            s.linear - out.sphere.linear,
            scale,
            "wall impulse",
        );
        let gt2 = (g - gn * k).norm_squared();
        let loss = 0.5
            * ((1.0 - law.restitution.powi(2)) * gn * gn
                + kk / (1.0 + kk) * (1.0 - law.roughness.powi(2)) * gt2);
        let de = energy(&out.sphere, kk) - energy(&s, kk);
        assert!(
            close(de, -loss, 1000.0),
            "wall energy change {de} vs {}",
            -loss
        );
        assert!(close(out.dissipated, loss, 1000.0));
    }
}

#[test]
fn smooth_elastic_limits() {
    // e = 1, beta = -1: no dissipation and spins untouched
    let mut rng = Pcg64::seed_from_u64(13);
    let law = ContactLaw {
        restitution: 1.0,
        roughness: -1.0,
        inertia_factor: 0.4,
    };
    for _ in 0..1000 {
        let (a, b) = (random_sphere(&mut rng), random_sphere(&mut rng));
        let k = random_vec(&mut rng, 1.0).normalize();
        let out = pair_collision(&a, &b, &k, &law);
        assert!(
            (out.first.angular - a.angular).norm() < 1e-14,
            "smooth spheres keep their spin"
        );
        assert!(out.dissipated.abs() < 1e-15);
    }
}
