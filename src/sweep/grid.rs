//! Grid expansion: a validated sweep spec becomes the ordered list of jobs (the plan).
//!
//! Plan order (relied on by `--job-range`): the grid first, as the cartesian product of the
//! axes in the order of the parameter table ([`super::job::PARAMS`]) with the last axis varying
//! fastest and seeds innermost; then the extra points in file order, each once per seed.

use super::job::{JobId, JobParams, PARAMS, lattice_capacity, resolve_particles};
use super::spec::{Source, SpecError, SweepSpec};
use std::collections::{BTreeMap, HashMap};

/// One job of a plan.
#[derive(Clone, Debug, PartialEq)]
pub struct PlannedJob {
    /// position in the plan order (0-based)
    pub index: usize,
    /// the job id (hash of the canonical parameters)
    pub id: JobId,
    /// resolved parameters
    pub params: JobParams,
}

/// Where a set of values came from, for error messages.
enum From {
    Grid,
    Point(usize),
}

/// Expand a validated spec into the plan.
pub(crate) fn expand(spec: &SweepSpec, src: &Source) -> Result<Vec<PlannedJob>, SpecError> {
    let fixed = spec.fixed.to_map();
    let axes_map = spec.axes.to_map();
    let axes: Vec<(&str, &Vec<f64>)> = PARAMS
        .iter()
        .filter_map(|d| axes_map.get(d.name).map(|v| (d.name, v)))
        .collect();
    let mut points: Vec<(From, BTreeMap<String, f64>)> = Vec::new();
    let combos: usize = axes.iter().map(|(_, v)| v.len()).product();
    for mut i in 0..combos {
        let mut values = fixed.clone();
        let mut picks = vec![0.0; axes.len()];
        for (k, (_, vals)) in axes.iter().enumerate().rev() {
            picks[k] = vals[i % vals.len()];
            i /= vals.len();
        }
        for (k, (name, _)) in axes.iter().enumerate() {
            values.insert(name.to_string(), picks[k]);
        }
        points.push((From::Grid, values));
    }
    for (i, point) in spec.points.iter().enumerate() {
        let mut values = fixed.clone();
        values.extend(point.to_map());
        points.push((From::Point(i), values));
    }
    let mut plan = Vec::new();
    let mut seen: HashMap<JobId, usize> = HashMap::new();
    for (from, mut values) in points {
        let axes_keys = spec.axes.to_map();
        let fixed_keys = spec.fixed.to_map();
        let at = |key: &str, message: String| match from {
            From::Grid => {
                let section = if axes_keys.contains_key(key) {
                    Some("axes")
                } else if fixed_keys.contains_key(key) {
                    Some("fixed")
                } else if spec.linked.iter().any(|l| l.param == key) {
                    Some("linked")
                } else {
                    None
                };
                src.error_at(section, key, 0, message)
            }
            From::Point(i) => {
                src.error_at(None, "points", 0, format!("point {}: {message}", i + 1))
            }
        };
        for link in &spec.linked {
            let explicit =
                matches!(from, From::Point(i) if spec.points[i].to_map().contains_key(&link.param));
            if !explicit && let Some(&followed) = values.get(&link.follows) {
                values.insert(link.param.clone(), link.factor * followed);
            }
        }
        for def in PARAMS {
            if !values.contains_key(def.name)
                && let Some(d) = def.default
            {
                values.insert(def.name.into(), d);
            }
        }
        for required in [
            "length_over_width",
            "width_over_diameter",
            "height_over_diameter",
        ] {
            if !values.contains_key(required) {
                return Err(src.error_at(
                    None,
                    "fixed",
                    0,
                    format!("`{required}` is not given: set it in `fixed`, `axes`, `linked` or every point"),
                ));
            }
        }
        if !values.contains_key("particles") && !values.contains_key("volume_fraction") {
            return Err(src.error_at(
                None,
                "fixed",
                0,
                "neither `volume_fraction` nor `particles` is given: N follows from phi unless given".into(),
            ));
        }
        for def in PARAMS {
            if let Some(&v) = values.get(def.name)
                && !(def.check)(v)
            {
                return Err(at(
                    def.name,
                    format!(
                        "{} ({}) = {v} is out of range: allowed {}",
                        def.name, def.symbol, def.allowed
                    ),
                ));
            }
        }
        let requested_phi = values.get("volume_fraction").copied();
        resolve_particles(&mut values);
        let probe = JobParams {
            engine: spec.engine.clone(),
            values: values.clone(),
            seed: 0,
            run: spec.run.clone(),
            analysis: spec.analysis.clone(),
        };
        let g = probe.geometry();
        if g.length < 3.0 {
            return Err(at(
                "length_over_width",
                format!(
                    "L = (L/W)(W/d) = {} is too short: allowed L >= 3 particle diameters",
                    g.length
                ),
            ));
        }
        let n = probe.particles() as f64;
        let capacity = lattice_capacity(&g);
        if n < 1.0 || n > capacity {
            let key = if requested_phi.is_some() && spec.fixed.particles.is_none() {
                "volume_fraction"
            } else {
                "particles"
            };
            return Err(at(
                key,
                format!(
                    "phi = {:.4} (N = {n}) cannot be placed in the {} x {} x {} channel: allowed 1 <= N <= {capacity} \
                     (phi <= {:.4}, a lattice of spacing d)",
                    probe.get("volume_fraction"),
                    g.length,
                    g.width,
                    g.height,
                    capacity * std::f64::consts::PI / 6.0 / g.volume()
                ),
            ));
        }
        for &seed in &spec.seeds {
            let params = JobParams {
                seed,
                ..probe.clone()
            };
            let id = params.id();
            if let Some(&other) = seen.get(&id) {
                return Err(at(
                    "length_over_width",
                    format!(
                        "duplicate point: it resolves to the same job ({id}, seed {seed}) as job {} of the plan; \
                         each point may appear once",
                        other
                    ),
                ));
            }
            seen.insert(id.clone(), plan.len());
            plan.push(PlannedJob {
                index: plan.len(),
                id,
                params,
            });
        }
    }
    Ok(plan)
}
