//! The DEM engine as a job sees it: its declaration (the time-step rule, the damping
//! alternatives), `granflow sim`, and a short channel run whose walls carry the weight.

mod dem_support;

use granflow::engine::declare::Problem;
use granflow::engine::{ParamValue, Values, registry};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_granflow");

fn values(pairs: &[(&str, f64)]) -> Values {
    let mut v = Values::new();
    for (k, x) in [
        ("width_over_diameter", 10.0),
        ("span_over_diameter", 5.0),
        ("length_over_diameter", 10.0),
        ("volume_fraction", 0.5),
    ]
    .iter()
    .chain(pairs)
    {
        v.insert(k.to_string(), ParamValue::Number(*x));
    }
    v
}

fn resolve(pairs: &[(&str, f64)]) -> Result<Values, Problem> {
    registry::find("dem").unwrap().resolve_values(&values(pairs))
}

fn number(v: &Values, k: &str) -> f64 {
    v[k].as_f64().unwrap()
}

/// A time step that resolves the shortest contact time of any pair type or of the wall with
/// fewer than 10 steps is refused with a problem naming `time_step`; the default step (1.2e-4
/// at k_n = 1e6, scaled as k_n^-1/2) is accepted at every stiffness; the limit itself is
/// accepted and a step 1 % above it is not.
#[test]
fn a_coarse_time_step_is_refused_naming_the_key() {
    let p = resolve(&[("time_step", 2e-4)]).unwrap_err();
    assert_eq!(p.key, "time_step", "{p:?}");
    assert!(p.message.contains("0.90-0.90"), "{}", p.message);
    for kn in [1e5, 1e6, 1e7, 1e8] {
        let v = resolve(&[("normal_stiffness", kn)]).unwrap();
        let dt = number(&v, "time_step");
        assert!((dt / (1.2e-4 * (1e6 / kn).sqrt()) - 1.0).abs() < 1e-12);
        let p = resolve(&[("normal_stiffness", kn), ("time_step", 1.2e-4)]);
        assert_eq!(p.is_err(), kn > 1e6, "k_n = {kn}");
    }
    // the limit: the shortest contact (two 0.9 spheres) over 10
    let v = resolve(&[]).unwrap();
    let params = granflow::engine::dem::params_of(&v, 1);
    let t_min = params
        .contact_types()
        .iter()
        .map(|t| t.contact_time)
        .fold(f64::INFINITY, f64::min);
    assert!(resolve(&[("time_step", t_min / 10.0)]).is_ok());
    assert_eq!(
        resolve(&[("time_step", 1.01 * t_min / 10.0)]).unwrap_err().key,
        "time_step"
    );
    // and on the command line: exit 2 before anything runs, the key named
    let out = Command::new(BIN)
        .args(["sim", "--engine", "dem", "--set", "time_step=0.01"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr).contains("time_step"));
}

/// xi_n follows from e_n (0.82 by default) for the d_p pair, or e_n from a given xi_n (the
/// paper's literal 180 gives 0.865, dem.md A1.2), and which one was given is recorded; both
/// at once, or damping so strong that a contact never rebounds, are refused by key.
#[test]
fn the_damping_is_given_one_way_and_recorded() {
    let v = resolve(&[]).unwrap();
    assert_eq!(v["damping_from"].as_text(), Some("restitution"));
    assert_eq!(number(&v, "restitution"), 0.82);
    assert!((number(&v, "normal_damping") - 246.4).abs() < 0.05);
    let v = resolve(&[("normal_damping", 180.0)]).unwrap();
    assert_eq!(v["damping_from"].as_text(), Some("normal_damping"));
    assert!((number(&v, "restitution") - 0.865).abs() < 5e-4);
    assert_eq!(number(&v, "wall_friction"), number(&v, "friction"));
    let p = resolve(&[("normal_damping", 180.0), ("restitution", 0.8)]).unwrap_err();
    assert!(p.key == "restitution" || p.key == "normal_damping", "{p:?}");
    let p = resolve(&[("normal_damping", 5e3)]).unwrap_err();
    assert_eq!(p.key, "normal_damping", "{p:?}");
    assert!(p.message.contains("overdamps"), "{}", p.message);
}
