//! The EDMD engine's declaration: its sweep parameters (the thesis channel),
//! N from phi, the placeability check, clocks, estimates and counters.

use super::{EdmdEngine, EdmdParams, Placement, particles_for_volume_fraction};
use crate::engine::declare::{
    CounterDef, InId, ParamDefault, ParamKind, Problem, RatioDef, ranges,
};
use crate::engine::{
    BoxGeometry, Clock, Engine, EngineDef, EngineError, ParamDef, ParamValue, Values,
};

/// The declaration of the `edmd` engine.
pub static DECLARATION: EngineDef = EngineDef {
    name: "edmd",
    title: "event-driven rough inelastic hard spheres between flat rough walls (Malik 2008, ch. 2)",
    version: 1,
    params: PARAMS,
    alternatives: &[&["volume_fraction", "particles"]],
    clocks: &[Clock::CollisionsPerParticle, Clock::Time],
    resolve,
    build,
    restore,
    size_name: "N",
    size: |v| number(v, "particles"),
    work,
    work_unit: "collisions",
    // the thesis channel (W/d = 30, L/W = 3, with its slug) runs 0.31-0.42 M collisions/s on
    // one core of the CI machine kind (`granflow bench --workload channel`); `plan` uses the
    // sweep's own finished jobs once there are any
    work_rate: |_| 3.5e5,
    memory,
    counters: &[
        CounterDef {
            name: "pair_collisions",
            doc: "particle-particle collisions (including TC-elastic ones)",
        },
        CounterDef {
            name: "wall_collisions",
            doc: "particle-wall collisions",
        },
        CounterDef {
            name: "cell_crossings",
            doc: "cell crossings (bookkeeping events)",
        },
        CounterDef {
            name: "tc_elastic_collisions",
            doc: "pair collisions made elastic in the normal direction by the TC model",
        },
        CounterDef {
            name: "events",
            doc: "all events taken from the queue, including invalidated ones",
        },
    ],
    ratios: &[RatioDef {
        name: "tc_elastic_fraction",
        numerator: "tc_elastic_collisions",
        denominator: "pair_collisions",
        doc: "fraction of pair collisions made elastic by the TC model",
    }],
    example: &[
        ("length_over_width", "3"),
        ("width_over_diameter", "15"),
        ("height_over_diameter", "15"),
        ("volume_fraction", "0.15"),
    ],
    example_run: (Clock::CollisionsPerParticle, 1000.0, 100.0),
};

/// Largest box side, in diameters: far beyond any channel one machine can fill, and small
/// enough that counts of lattice sites along it stay exact.
const LONGEST_SIDE: f64 = 1e7;
/// Largest wall-to-wall width or spanwise height, in diameters.
const WIDEST_SIDE: f64 = 1e5;
/// Largest number of spheres, the bound of [`count`].
const MOST_PARTICLES: f64 = 1e9;

fn side(v: f64) -> bool {
    (3.0..=WIDEST_SIDE).contains(&v)
}
/// Below the densest packing of spheres, pi / (3 sqrt 2) (fcc); what a given box can hold is
/// checked against the placement's capacity ([`lattice_capacity`]).
fn fraction(v: f64) -> bool {
    v > 0.0 && v < std::f64::consts::PI / (3.0 * std::f64::consts::SQRT_2)
}
fn inertia(v: f64) -> bool {
    v > 0.0 && v <= 1.0
}
fn count(v: f64) -> bool {
    (1.0..=MOST_PARTICLES).contains(&v)
}
/// Longest thermalisation, in collisions per particle (a stored whole number).
const LONGEST_THERMALISATION: f64 = 1e6;
fn thermalisation(v: f64) -> bool {
    (0.0..=LONGEST_THERMALISATION).contains(&v)
}

const fn real(
    name: &'static str,
    symbol: &'static str,
    unit: &'static str,
    default: ParamDefault,
    allowed: &'static str,
    check: fn(f64) -> bool,
    doc: &'static str,
) -> ParamDef {
    ParamDef {
        name,
        symbol,
        unit,
        kind: ParamKind::Real,
        default,
        allowed,
        check,
        doc,
        in_id: InId::Always,
    }
}

/// The sweepable parameters, in expansion order (the last swept one varies fastest). All of
/// them but `volume_fraction` (which follows from N and the box) and `thermalise` (added
/// later: in a job's id only when not 0) are in the first id scheme.
const PARAMS: &[ParamDef] = &[
    real(
        "length_over_width",
        "L/W",
        "1",
        ParamDefault::Required,
        "a finite value > 0 with 3 <= L = (L/W)(W/d) <= 1e7",
        ranges::positive,
        "channel length (periodic, along gravity) over width",
    ),
    real(
        "width_over_diameter",
        "W/d",
        "1",
        ParamDefault::Required,
        "a finite value 3 <= W/d <= 1e5 (channel width in particle diameters)",
        side,
        "channel width, wall to wall",
    ),
    real(
        "height_over_diameter",
        "H/d",
        "1",
        ParamDefault::Required,
        "a finite value 3 <= H/d <= 1e5 (spanwise extent in particle diameters)",
        side,
        "spanwise extent (periodic)",
    ),
    ParamDef {
        in_id: InId::Never,
        ..real(
            "volume_fraction",
            "phi",
            "1",
            ParamDefault::Derived,
            "0 < phi < 0.74 (and placeable in the box: up to ~0.6-0.7)",
            fraction,
            "solid volume fraction N (pi d^3/6) / (L W H); give it or `particles`",
        )
    },
    ParamDef {
        kind: ParamKind::Integer,
        ..real(
            "particles",
            "N",
            "1",
            ParamDefault::Derived,
            "a whole number >= 1 (default: from volume_fraction)",
            count,
            "number of spheres, round(phi L W H / (pi d^3/6)) unless given",
        )
    },
    real(
        "restitution",
        "e",
        "1",
        ParamDefault::Number(0.7),
        "[0, 1]",
        ranges::unit,
        "normal restitution of particle-particle collisions",
    ),
    real(
        "roughness",
        "beta",
        "1",
        ParamDefault::Number(0.1),
        "[-1, 1]",
        ranges::signed_unit,
        "tangential restitution of particle-particle collisions (-1 smooth, 1 perfectly rough)",
    ),
    real(
        "wall_restitution",
        "e_w",
        "1",
        ParamDefault::Number(0.99),
        "[0, 1]",
        ranges::unit,
        "normal restitution of particle-wall collisions",
    ),
    real(
        "wall_roughness",
        "beta_w",
        "1",
        ParamDefault::Number(0.99),
        "[-1, 1]",
        ranges::signed_unit,
        "tangential restitution of particle-wall collisions",
    ),
    real(
        "inertia_factor",
        "K",
        "1",
        ParamDefault::Number(0.4),
        "(0, 1] (2/5 solid sphere, 2/3 thin shell)",
        inertia,
        "reduced moment of inertia 4 I / (m d^2)",
    ),
    real(
        "gravity",
        "g",
        "g",
        ParamDefault::Number(1.0),
        "a finite value >= 0",
        ranges::non_negative,
        "gravitational acceleration along the flow (units: d = m = g = 1)",
    ),
    real(
        "tc",
        "t_c",
        "sqrt(d/g)",
        ParamDefault::Number(EdmdParams::DEFAULT_TC),
        "a finite time >= 0 (0 switches the TC model off)",
        ranges::non_negative,
        "TC model: a pair collision within t_c of a partner's last collision is elastic (normal part)",
    ),
    real(
        "initial_temperature",
        "T_0",
        "m g d",
        ParamDefault::Number(0.01),
        "a finite value > 0",
        ranges::positive,
        "kT of the initial Gaussian translational and rotational velocities",
    ),
    ParamDef {
        kind: ParamKind::Integer,
        in_id: InId::AwayFromDefault,
        ..real(
            "thermalise",
            "n_th",
            "collisions per particle",
            ParamDefault::Number(0.0),
            "a whole number 0 <= n_th <= 1e6 (0: start from the placement)",
            thermalisation,
            "the start: 0 places the spheres (a lattice above phi = 0.3); n_th > 0 packs them at random and runs n_th collisions per particle elastic, smooth and without gravity first, so that a dense channel starts as a fluid (docs/dense-flows.md)",
        )
    },
];

fn number(values: &Values, name: &str) -> f64 {
    values
        .get(name)
        .and_then(ParamValue::as_f64)
        .unwrap_or(f64::NAN)
}

/// The channel box: L = (L/W) W, W, H, walls at y = 0, W.
pub fn geometry(values: &Values) -> BoxGeometry {
    let w = number(values, "width_over_diameter");
    BoxGeometry {
        length: number(values, "length_over_width") * w,
        width: w,
        height: number(values, "height_over_diameter"),
        walls: true,
    }
}

/// How many spheres the engine's lattice placement can put in the channel without contact
/// (see [`super::setup::placement_capacity`]).
pub fn lattice_capacity(geometry: &BoxGeometry) -> f64 {
    super::setup::placement_capacity(geometry) as f64
}

/// N from phi when N is not given, phi from N; L >= 3; N placeable in the box.
fn resolve(values: &mut Values) -> Result<(), Problem> {
    let has = |v: &Values, k: &str| v.contains_key(k);
    if !has(values, "particles") && !has(values, "volume_fraction") {
        return Err(Problem::new(
            "volume_fraction",
            "neither `volume_fraction` nor `particles` is given: N follows from phi unless given",
        ));
    }
    let requested_phi = has(values, "volume_fraction") && !has(values, "particles");
    let g = geometry(values);
    if !(3.0..=LONGEST_SIDE).contains(&g.length) {
        return Err(Problem::new(
            "length_over_width",
            format!(
                "L = (L/W)(W/d) = {} particle diameters: allowed 3 <= L <= {LONGEST_SIDE:e}",
                g.length
            ),
        ));
    }
    if requested_phi {
        let phi = number(values, "volume_fraction");
        let n = phi * g.volume() / (std::f64::consts::PI / 6.0);
        if n > MOST_PARTICLES {
            return Err(Problem::new(
                "volume_fraction",
                format!(
                    "phi = {phi} in the {} x {} x {} channel makes N = {n:.3e} spheres: allowed \
                     N <= {MOST_PARTICLES:e} (lower phi or shrink the box)",
                    g.length, g.width, g.height
                ),
            ));
        }
        values.insert(
            "particles".into(),
            ParamValue::Number(particles_for_volume_fraction(&g, phi) as f64),
        );
    }
    let n = number(values, "particles");
    values.insert(
        "volume_fraction".into(),
        ParamValue::Number(n * std::f64::consts::PI / 6.0 / g.volume()),
    );
    let capacity = lattice_capacity(&g);
    if n < 1.0 || n > capacity {
        return Err(Problem::new(
            if requested_phi {
                "volume_fraction"
            } else {
                "particles"
            },
            format!(
                "phi = {:.4} (N = {n}) cannot be placed in the {} x {} x {} channel: allowed 1 <= N <= {capacity} \
                 (phi <= {:.4}, the densest lattice placement without contact)",
                number(values, "volume_fraction"),
                g.length,
                g.width,
                g.height,
                capacity * std::f64::consts::PI / 6.0 / g.volume()
            ),
        ));
    }
    Ok(())
}

/// The engine parameters of resolved sweep values.
pub fn params_of(values: &Values, seed: u64) -> EdmdParams {
    let mut p = EdmdParams::channel(1.0, 1.0, 1.0, 0.0, seed);
    p.geometry = geometry(values);
    p.particles = number(values, "particles") as usize;
    p.restitution = number(values, "restitution");
    p.roughness = number(values, "roughness");
    p.wall_restitution = number(values, "wall_restitution");
    p.wall_roughness = number(values, "wall_roughness");
    p.inertia_factor = number(values, "inertia_factor");
    p.gravity = number(values, "gravity");
    p.tc = number(values, "tc");
    p.initial_temperature = number(values, "initial_temperature");
    // jobs stored before the parameter existed read NaN here: the placement, as they ran
    let thermalise = number(values, "thermalise");
    if thermalise > 0.0 {
        p.placement = Placement::Thermalised {
            collisions_per_particle: thermalise as u32,
        };
    }
    p
}

fn build(values: &Values, seed: u64) -> Result<Box<dyn Engine>, EngineError> {
    Ok(Box::new(EdmdEngine::new(params_of(values, seed))?))
}

fn restore(version: u32, payload: &[u8]) -> Result<Box<dyn Engine>, EngineError> {
    Ok(Box::new(EdmdEngine::restore_payload(version, payload)?))
}

/// Collisions per particle per unit of simulated time assumed by the work estimate of a run
/// measured in time, at the thesis' phi = 0.15: its channels measured there ran 10-25
/// (W/d = 15-30) and up to 80 in dense slugs. Only `plan`'s estimate (before a job of the
/// sweep has run) and the pool's order depend on it.
const ASSUMED_CPP_PER_TIME: f64 = 25.0;

/// The density factor of the Enskog collision frequency, phi g0(phi) with the
/// Carnahan-Starling contact value g0 = (1 - phi/2) / (1 - phi)^3: at a given temperature
/// a sphere collides in proportion to it.
fn enskog_density_factor(phi: f64) -> f64 {
    phi * (1.0 - 0.5 * phi) / (1.0 - phi).powi(3)
}

/// Collisions per particle per time unit assumed at volume fraction `phi`: the phi = 0.15
/// value scaled by the Enskog density factor (x 14.6 at the thesis' dense phi = 0.513). The
/// temperature is taken as at phi = 0.15, so a dense flow that heats as it accelerates
/// collides more still: measured on ch. 4.2's dense case 1150 per time unit over t = 10-25,
/// 3000 at t = 30 and 5800 at t = 60 against the 366 assumed (docs/dense-flows.md).
fn assumed_cpp_per_time(phi: f64) -> f64 {
    ASSUMED_CPP_PER_TIME * enskog_density_factor(phi) / enskog_density_factor(0.15)
}

/// Estimated pair collisions of a run.
fn work(values: &Values, clock: Clock, length: f64) -> f64 {
    let n = number(values, "particles");
    let phi = values
        .get("volume_fraction")
        .and_then(|v| v.as_f64())
        .unwrap_or(0.15);
    let cpp = match clock {
        Clock::CollisionsPerParticle => length,
        Clock::Time => length * assumed_cpp_per_time(phi),
        Clock::Steps => f64::NAN,
    };
    n * cpp / 2.0
}

/// Bytes a job needs: about 600 per sphere (records, calendar, lists, snapshot copies; the
/// process grows by 370-560 bytes per sphere, measured) plus at most 16 per cell of side >= d.
fn memory(values: &Values) -> f64 {
    let g = geometry(values);
    600.0 * number(values, "particles") + 16.0 * g.length.ceil() * g.width.ceil() * g.height.ceil()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_assumed_collision_rate_follows_enskog_density_scaling() {
        // Carnahan-Starling: g0(1/2) = (3/4) / (1/8) = 6, so phi g0 = 3 at phi = 1/2
        assert!((enskog_density_factor(0.5) - 3.0).abs() < 1e-12);
        // the thesis' phi = 0.15 keeps the measured 25 per time unit
        assert!((assumed_cpp_per_time(0.15) - ASSUMED_CPP_PER_TIME).abs() < 1e-12);
        // denser collides more, by the ratio of the factors
        let ratio = assumed_cpp_per_time(0.5) / assumed_cpp_per_time(0.15);
        let g0 = |phi: f64| (1.0 - phi / 2.0) / (1.0 - phi).powi(3);
        assert!((ratio - 0.5 * g0(0.5) / (0.15 * g0(0.15))).abs() < 1e-12);
    }
}
