//! The refine stage: the rounds of a sweep's `refine` section, replayed from the job results
//! on disk. A round's points follow from the classes of the points before it
//! ([`super::refine::next_round`]), so the sweep with its refined points is a function of the
//! results alone: a rerun after a kill, `status`, `gather` and `report` all see the same
//! points, and a point's jobs have ordinary ids (the refined points are expanded as extra
//! points of the sweep, after the file's own).

use super::phase::{Cell, CellJob};
use super::refine::{Class, Lattice, Quantity, RefineSpec, Site, Slice};
use super::spec::{ParamValues, SpecError};
use super::store::JobState;
use super::{JobId, PlannedJob, Sweep, SweepDirs};
use crate::engine::ParamValue;
use std::collections::BTreeMap;

/// A refined sweep: the sweep whose plan holds the points of every round whose predecessors
/// are finished, and how many points each round added.
#[derive(Clone, Debug)]
pub struct Refined {
    pub sweep: Sweep,
    /// points added per round (round 1 first); empty without refinement
    pub rounds: Vec<usize>,
    /// no further round will come (every job finished, and the levels, the budget or the
    /// classes end the refinement)
    pub complete: bool,
}

/// One refined point: its slice, site and jobs (one per seed).
struct Point {
    slice: usize,
    site: Site,
    jobs: Vec<JobId>,
}

/// The base grid's points of a sweep with a `refine` section, with the lattice and each
/// slice's values of the other swept axes.
struct Grid {
    lattice: Lattice,
    points: Vec<Point>,
    /// per slice: the swept axes' values that are not refined
    slices: Vec<Vec<(String, ParamValue)>>,
}

/// The sweep with its refined points so far (the sweep itself without a `refine` section).
pub fn replay(sweep: &Sweep, dirs: &SweepDirs) -> Result<Refined, SpecError> {
    replay_with(sweep, &|job| outcome(dirs, job))
}

/// A finished job's label and summary, read from its directory: Some(None) for a failed or
/// damaged job, None while it is not finished.
type Outcome = Option<Option<(String, serde_json::Map<String, serde_json::Value>)>>;

fn outcome(dirs: &SweepDirs, job: &PlannedJob) -> Outcome {
    let dir = dirs.job(&job.id);
    match dir.state(false) {
        JobState::Done => Some(
            dir.result()
                .ok()
                .map(|r| (r.analysis.label().0.to_string(), r.analysis.summary())),
        ),
        JobState::Failed(_) | JobState::Damaged { .. } => Some(None),
        _ => None,
    }
}

/// [`replay`] with the jobs' outcomes from `outcome_of`.
pub fn replay_with(
    sweep: &Sweep,
    outcome_of: &dyn Fn(&PlannedJob) -> Outcome,
) -> Result<Refined, SpecError> {
    let Some(spec) = &sweep.spec.refine else {
        return Ok(Refined {
            sweep: sweep.clone(),
            rounds: Vec::new(),
            complete: true,
        });
    };
    let Grid {
        lattice,
        mut points,
        slices,
    } = grid(sweep, spec);
    let seeds = sweep.spec.seeds.len().max(1);
    let base_jobs = (sweep.spec.points.len()
        + sweep.spec.axes.0.values().map(Vec::len).product::<usize>())
        * seeds;
    let mut current = sweep.clone();
    let mut classes: BTreeMap<JobId, Class> = BTreeMap::new();
    let mut rounds = Vec::new();
    let mut extra: Vec<ParamValues> = Vec::new();
    loop {
        let mut known: Vec<Slice> = vec![Slice::new(); slices.len()];
        let by_id: std::collections::HashMap<&JobId, &PlannedJob> =
            current.plan.iter().map(|j| (&j.id, j)).collect();
        for p in &points {
            let class = match classes.get(&p.jobs[0]) {
                Some(c) => c.clone(),
                None => {
                    let Some(outcomes) = p
                        .jobs
                        .iter()
                        .map(|id| outcome_of(by_id[id]))
                        .collect::<Option<Vec<_>>>()
                    else {
                        // a job of this round is not finished: the next round waits
                        return Ok(Refined {
                            sweep: current,
                            rounds,
                            complete: false,
                        });
                    };
                    let c = class_of(&spec.quantity, &outcomes);
                    classes.insert(p.jobs[0].clone(), c.clone());
                    c
                }
            };
            known[p.slice].insert(p.site, class);
        }
        // the budget counts the whole sweep's jobs (also under `--where`)
        let room = spec.budget.saturating_sub(base_jobs + extra.len() * seeds) / seeds;
        let new = super::refine::next_round(&lattice, &spec.quantity, &known, room);
        if new.is_empty() {
            return Ok(Refined {
                sweep: current,
                rounds,
                complete: true,
            });
        }
        rounds.push(new.len());
        for &(slice, site) in &new {
            let mut values: BTreeMap<String, ParamValue> = slices[slice].iter().cloned().collect();
            for (a, name) in spec.axes.iter().enumerate() {
                values.insert(name.clone(), ParamValue::Number(lattice.value(a, site[a])));
            }
            extra.push(ParamValues(values.into_iter().collect()));
        }
        let before = extra.len() - new.len();
        let (next, added) = with_points(sweep, &extra)?;
        current = next;
        for (k, &(slice, site)) in new.iter().enumerate() {
            let jobs = &added[(before + k) * seeds..(before + k + 1) * seeds];
            points.push(Point {
                slice,
                site,
                jobs: jobs.to_vec(),
            });
        }
        // every refined job's level (the plan was expanded anew)
        let level: std::collections::HashMap<&JobId, u32> = points
            .iter()
            .flat_map(|p| {
                let level = lattice.level(p.site);
                p.jobs.iter().map(move |id| (id, level))
            })
            .collect();
        for job in &mut current.plan {
            job.level = level.get(&job.id).copied().unwrap_or(0);
        }
    }
}

/// A point's class from its seeds' outcomes (module doc of [`super::refine`]): a label that
/// is `not-steady` counts as not steady.
fn class_of(
    quantity: &Quantity,
    outcomes: &[Option<(String, serde_json::Map<String, serde_json::Value>)>],
) -> Class {
    let steady = |o: &&(String, serde_json::Map<String, serde_json::Value>)| o.0 != "not-steady";
    match quantity {
        Quantity::Label => {
            let jobs: Vec<CellJob> = outcomes
                .iter()
                .flatten()
                .filter(steady)
                .map(|(label, summary)| {
                    let humps = summary.get("humps").and_then(serde_json::Value::as_u64);
                    CellJob::from_summary(label, humps.unwrap_or(0) as u32, summary)
                })
                .collect();
            class_of_seeds(jobs, outcomes.len())
        }
        Quantity::Change { column, .. } | Quantity::Minimum { column } => Class::of_values(
            &outcomes
                .iter()
                .map(|o| {
                    o.as_ref()
                        .filter(steady)
                        .and_then(|o| o.1.get(column))
                        .and_then(serde_json::Value::as_f64)
                })
                .collect::<Vec<_>>(),
        ),
    }
}

/// A labelled point's class from its steady seeds (of `seeds` in all): the label its
/// phase-diagram cell shows for them ([`Cell::verdict`]: pooled by window snapshots, the modal
/// label with two thirds, else `mixed`), by the rule of [`Class::of_cell`].
fn class_of_seeds(steady: Vec<CellJob>, seeds: usize) -> Class {
    let count = steady.len();
    let cell = Cell {
        jobs: steady,
        not_done: 0,
    };
    let verdict = cell.verdict();
    Class::of_cell(verdict.as_ref().map(|v| v.label.as_str()), count, seeds)
}

/// The sweep with `extra` as further extra points (after the file's), expanded: ordinary jobs
/// with ordinary ids and plan indices after the file's points; the resolved spec (what
/// `sweep.ron` holds) stays the file's, and of the base plan only the sweep's jobs stay (a
/// plan cut by `--where` stays cut). The ids of the extra points' jobs, in order.
fn with_points(sweep: &Sweep, extra: &[ParamValues]) -> Result<(Sweep, Vec<JobId>), SpecError> {
    let mut spec = sweep.spec.clone();
    let base =
        sweep.spec.points.len() + sweep.spec.axes.0.values().map(Vec::len).product::<usize>();
    let base_jobs = base * sweep.spec.seeds.len();
    spec.points.extend(extra.iter().cloned());
    let src = super::spec::Source {
        path: std::path::Path::new(super::RESOLVED_SWEEP_FILE),
        text: "",
    };
    let mut plan = super::grid::expand(&spec, &src)?;
    let swept = sweep
        .plan
        .first()
        .map(|j| j.swept.clone())
        .unwrap_or_default();
    for job in &mut plan {
        job.swept = swept.clone();
    }
    let added: Vec<JobId> = plan[base_jobs..].iter().map(|j| j.id.clone()).collect();
    let kept: std::collections::HashSet<&JobId> = sweep.plan.iter().map(|j| &j.id).collect();
    plan.retain(|j| j.index >= base_jobs || kept.contains(&j.id));
    Ok((
        Sweep {
            name: sweep.name.clone(),
            spec: sweep.spec.clone(),
            plan,
        },
        added,
    ))
}

/// The lattice of the refined axes and the base grid's points on it, sliced by the values of
/// the other swept axes (in plan order).
fn grid(sweep: &Sweep, spec: &RefineSpec) -> Grid {
    let axes: Vec<Vec<f64>> = spec
        .axes
        .iter()
        .map(|name| {
            let mut v: Vec<f64> = sweep.spec.axes.0[name]
                .iter()
                .filter_map(ParamValue::as_f64)
                .collect();
            v.sort_by(f64::total_cmp);
            v
        })
        .collect();
    let lattice = Lattice {
        axes,
        levels: spec.levels,
    };
    let s = lattice.scale();
    let grid_jobs: usize =
        sweep.spec.axes.0.values().map(Vec::len).product::<usize>() * sweep.spec.seeds.len();
    let mut slices: Vec<Vec<(String, ParamValue)>> = Vec::new();
    let mut points: Vec<Point> = Vec::new();
    let mut at: std::collections::HashMap<(usize, Site), usize> = Default::default();
    for job in sweep.plan.iter().filter(|j| j.index < grid_jobs) {
        let values = &job.params.values;
        let mut site = [0u32; 2];
        for (a, name) in spec.axes.iter().enumerate() {
            let v = values
                .get(name)
                .and_then(ParamValue::as_f64)
                .unwrap_or(f64::NAN);
            let i = lattice.axes[a].iter().position(|&x| x == v).unwrap_or(0);
            site[a] = i as u32 * s;
        }
        let others: Vec<(String, ParamValue)> = sweep
            .spec
            .axes
            .0
            .keys()
            .filter(|k| !spec.axes.contains(k))
            .filter_map(|k| values.get(k).map(|v| (k.clone(), v.clone())))
            .collect();
        let slice = match slices.iter().position(|o| *o == others) {
            Some(k) => k,
            None => {
                slices.push(others);
                slices.len() - 1
            }
        };
        match at.get(&(slice, site)) {
            Some(&k) => points[k].jobs.push(job.id.clone()),
            None => {
                at.insert((slice, site), points.len());
                points.push(Point {
                    slice,
                    site,
                    jobs: vec![job.id.clone()],
                })
            }
        }
    }
    Grid {
        lattice,
        points,
        slices,
    }
}

/// What `plan` says of a sweep's refinement: the base plan's jobs, the most the rounds may
/// add (the budget, or the whole lattice at the finest spacing when that is less), and the
/// jobs of the regular grid of that spacing. None without a `refine` section.
pub fn bound(sweep: &Sweep) -> Option<String> {
    let r = sweep.spec.refine.as_ref()?;
    let seeds = sweep.spec.seeds.len();
    let per_slice: usize = sweep.spec.axes.0.values().map(Vec::len).product();
    let base = (per_slice + sweep.spec.points.len()) * seeds;
    let refined: usize = r.axes.iter().map(|a| sweep.spec.axes.0[a].len()).product();
    let slices = per_slice / refined.max(1);
    let fine: usize = r
        .axes
        .iter()
        .map(|a| (sweep.spec.axes.0[a].len() - 1) * (1usize << r.levels) + 1)
        .product();
    let regular = fine * slices * seeds;
    let most = r.budget.min(regular + sweep.spec.points.len() * seeds);
    Some(format!(
        "refinement of {} ({} levels, budget {}): base plan {base} jobs, the rounds add at most \
         {} more; a regular grid of the finest spacing has {regular} jobs",
        r.axes.join(" x "),
        r.levels,
        r.budget,
        most.saturating_sub(base)
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::phase::parse_probabilities;

    /// A steady seed's entry: its label probabilities ("plug 0.6; slug 0.4") over `weight`
    /// window snapshots, labelled by the first.
    fn seed(probabilities: &str, weight: f64) -> CellJob {
        let probabilities = parse_probabilities(probabilities);
        CellJob {
            label: probabilities[0].0.clone(),
            humps: 0,
            probabilities,
            weight,
            steady: true,
            guard_valid: true,
            three_dimensional: false,
        }
    }

    fn label(l: &str) -> Class {
        Class::Label(l.to_string())
    }

    #[test]
    fn a_point_is_classed_as_its_diagram_cell() {
        // seeds that agree: their label
        let plug = || seed("plug 1", 30.0);
        assert_eq!(class_of_seeds(vec![plug(), plug()], 2), label("plug"));
        // two of three seeds plug, one slug: the pooled snapshots are two thirds plug
        let three = vec![plug(), plug(), seed("slug 1", 30.0)];
        assert_eq!(class_of_seeds(three, 3), label("plug"));
        // two seeds of two thirds plug and one that alternates: 59 % plug pooled, so the cell
        // shows `mixed`, and so does the class (Fig. 5.25's L/W = 1.4, W/d = 15 over three
        // seeds), even though two seeds of three are labelled plug
        let alternating = vec![
            seed("plug 0.7; slug 0.3", 30.0),
            seed("plug 0.67; slug 0.33", 30.0),
            seed("slug 0.6; plug 0.4", 30.0),
        ];
        assert_eq!(class_of_seeds(alternating, 3), label("mixed"));
        let split = vec![plug(), seed("slug 1", 30.0)];
        assert_eq!(class_of_seeds(split, 2), label("mixed"));
        // the snapshots weigh: a long plug window outweighs a short slug one
        let weighed = vec![seed("plug 1", 90.0), seed("slug 1", 10.0)];
        assert_eq!(class_of_seeds(weighed, 2), label("plug"));
        // failed or not steady: one seed of three is tolerated, two are not
        assert_eq!(class_of_seeds(vec![plug(), plug()], 3), label("plug"));
        assert_eq!(class_of_seeds(vec![plug()], 3), Class::Other);
        assert_eq!(class_of_seeds(Vec::new(), 1), Class::Other);
    }
}
