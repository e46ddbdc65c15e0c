//! Adaptive refinement of a sweep (the `refine` section, docs/sweeps.md): the rules that choose
//! a round's new points from the classes of the points done so far. Pure functions of their
//! input, so that a rerun after a kill computes the same rounds from the same results.
//!
//! Points live on a dyadic lattice over the refined axes' *index* space: the base value `i` of
//! an axis sits at `u = i·2^L` (`L` = `levels`), and a point between base values `i` and
//! `i + 1` at `u = i·2^L + k` is the value interpolated linearly between them
//! ([`Lattice::value`]). Midpoints of lattice points at distance `2^m` (`m ≥ 1`) are lattice
//! points again: refined coordinates are exact integers, whatever the axes' values.
//!
//! A round, for a boundary ([`Quantity::Label`], [`Quantity::Change`]): the cells of the
//! current partition (base intervals, 1D, or base rectangles, 2D, each split in two, or four,
//! where its midpoint, or centre, is a point) whose corners are not all of one class get their
//! midpoints: in 1D the interval's midpoint, in 2D the four edge midpoints and the centre (a
//! 2D refinement bisects edges and cells). A cell of size 1 (level `L`) is not split. For an
//! interior minimum ([`Quantity::Minimum`], 1D) a round adds the midpoint of the longer of the
//! two intervals beside the lowest point (it halves the longer side of the bracket), until
//! both are at the finest spacing.
//!
//! Classes ([`Class`]): a point's label, the one its phase-diagram cell shows (its seeds'
//! label probabilities merged, weighted by their window snapshots: the modal label with at
//! least two thirds, else `mixed`; the phase module's `Cell::verdict`, applied by
//! [`super::rounds`]), so that every boundary
//! the diagram draws is one the refinement bisects; its value (the mean over its seeds); or
//! [`Class::Other`] when more than a third of its seeds failed or did not reach a steady state
//! (with `Change` and `Minimum`, when any did): `Other` is a class of its own, different from
//! every label and value and equal to itself (so a boundary between a steady region and a
//! failing one is found, and two failing points are not bisected).

use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};

/// What marks a boundary (or the minimum) in the `refine` section.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Quantity {
    /// the structure label (the default)
    #[default]
    Label,
    /// a numeric jobs.parquet column; neighbours differ when `|a - b| > relative·max(|a|, |b|)`
    Change { column: String, relative: f64 },
    /// a numeric jobs.parquet column with an interior minimum along one axis: bracketing
    /// bisection of the minimum
    Minimum { column: String },
}

/// The `refine` section of a sweep file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RefineSpec {
    /// the swept axes to refine (one or two)
    pub axes: Vec<String>,
    /// what marks a boundary
    #[serde(default)]
    pub quantity: Quantity,
    /// bisection levels: the finest spacing is the base spacing / 2^levels
    pub levels: u32,
    /// the most jobs of the sweep, base grid included
    pub budget: usize,
}

/// Most bisection levels (a lattice coordinate is a u32).
pub const MAX_LEVELS: u32 = 16;

/// A point's class for the rules.
#[derive(Clone, Debug, PartialEq)]
pub enum Class {
    /// the label of the point's phase-diagram cell (a clear majority, or `mixed`)
    Label(String),
    /// the mean of the quantity over the point's seeds
    Value(f64),
    /// failed or not steady
    Other,
}

impl Class {
    /// The class of a point from its seeds' label: `label` is the one its phase-diagram cell
    /// shows for its `steady` seeds (of `seeds` in all; None without steady seeds), taken when
    /// at least two thirds of all seeds are steady; else [`Class::Other`].
    pub fn of_cell(label: Option<&str>, steady: usize, seeds: usize) -> Class {
        match label {
            Some(l) if l != "not-steady" && steady > 0 && 3 * steady >= 2 * seeds => {
                Class::Label(l.to_string())
            }
            _ => Class::Other,
        }
    }

    /// The class of a point from its seeds' values (None: failed, not steady or not finite):
    /// their mean, or [`Class::Other`] when any is missing.
    pub fn of_values(values: &[Option<f64>]) -> Class {
        let v: Option<Vec<f64>> = values.iter().map(|v| v.filter(|x| x.is_finite())).collect();
        match v {
            Some(v) if !v.is_empty() => Class::Value(v.iter().sum::<f64>() / v.len() as f64),
            _ => Class::Other,
        }
    }
}

/// A refined value as the researcher would write it: the interpolation's rounding noise
/// removed (12 significant digits), so that 1 + 3 (1.4 - 1) / 4 is the parameter 1.3 and not
/// 1.2999999999999998 (a job's id and its tables hold the value itself).
fn decimal(x: f64) -> f64 {
    format!("{x:.11e}").parse().unwrap_or(x)
}

/// Whether two points lie on two sides of a boundary under `quantity`.
pub fn differ(quantity: &Quantity, a: &Class, b: &Class) -> bool {
    match (a, b) {
        (Class::Other, Class::Other) => false,
        (Class::Label(x), Class::Label(y)) => x != y,
        (Class::Value(x), Class::Value(y)) => match quantity {
            Quantity::Change { relative, .. } => (x - y).abs() > relative * x.abs().max(y.abs()),
            _ => x != y,
        },
        _ => true,
    }
}

/// A point's place: lattice coordinates along the refined axes (the second is 0 in 1D).
pub type Site = [u32; 2];

/// The refinement lattice of one or two axes.
#[derive(Clone, Debug, PartialEq)]
pub struct Lattice {
    /// base values per refined axis (one or two), as in the sweep file (sorted ascending)
    pub axes: Vec<Vec<f64>>,
    /// bisection levels L
    pub levels: u32,
}

impl Lattice {
    /// 2^L: the lattice distance between neighbouring base values.
    pub fn scale(&self) -> u32 {
        1 << self.levels
    }

    /// The base grid's sites (row-major, the last axis fastest).
    pub fn base_sites(&self) -> Vec<Site> {
        let s = self.scale();
        let n0 = self.axes[0].len() as u32;
        let n1 = self.axes.get(1).map_or(1, |a| a.len() as u32);
        (0..n0)
            .flat_map(|i| (0..n1).map(move |j| [i * s, j * s]))
            .collect()
    }

    /// The value of axis `a` at lattice coordinate `u`: linear between the base values
    /// around it.
    pub fn value(&self, a: usize, u: u32) -> f64 {
        let vals = &self.axes[a];
        let s = self.scale();
        let i = (u / s) as usize;
        let k = u % s;
        if k == 0 || i + 1 >= vals.len() {
            return vals[i.min(vals.len() - 1)];
        }
        let t = k as f64 / s as f64;
        decimal(vals[i] + t * (vals[i + 1] - vals[i]))
    }

    /// The refinement level of a site: 0 on the base grid, `L` at the finest spacing.
    pub fn level(&self, site: Site) -> u32 {
        site[..self.axes.len()]
            .iter()
            .map(|&u| self.levels - u.trailing_zeros().min(self.levels))
            .max()
            .unwrap_or(0)
    }

    /// The cells of the current partition (lower corner, size) of the points `known`: the
    /// base cells, each split where its midpoint (1D) or centre (2D) is known.
    fn leaves<T>(&self, known: &BTreeMap<Site, T>) -> Vec<(Site, u32)> {
        let s = self.scale();
        let n0 = self.axes[0].len() as u32;
        let mut out = Vec::new();
        let mut stack: Vec<(Site, u32)> = Vec::new();
        if self.axes.len() == 1 {
            stack.extend((0..n0.saturating_sub(1)).rev().map(|i| ([i * s, 0], s)));
        } else {
            let n1 = self.axes[1].len() as u32;
            for i in (0..n0.saturating_sub(1)).rev() {
                for j in (0..n1.saturating_sub(1)).rev() {
                    stack.push(([i * s, j * s], s));
                }
            }
        }
        while let Some((c, size)) = stack.pop() {
            let h = size / 2;
            let split = size >= 2 && known.contains_key(&self.centre(c, size));
            if !split {
                out.push((c, size));
            } else if self.axes.len() == 1 {
                stack.push(([c[0] + h, 0], h));
                stack.push((c, h));
            } else {
                for d in [[h, h], [0, h], [h, 0], [0, 0]] {
                    stack.push(([c[0] + d[0], c[1] + d[1]], h));
                }
            }
        }
        out
    }

    fn centre(&self, c: Site, size: u32) -> Site {
        let h = size / 2;
        if self.axes.len() == 1 {
            [c[0] + h, 0]
        } else {
            [c[0] + h, c[1] + h]
        }
    }

    fn corners(&self, c: Site, size: u32) -> Vec<Site> {
        if self.axes.len() == 1 {
            vec![c, [c[0] + size, 0]]
        } else {
            vec![
                c,
                [c[0] + size, c[1]],
                [c[0], c[1] + size],
                [c[0] + size, c[1] + size],
            ]
        }
    }

    /// The new points that splitting a cell needs: 1D its midpoint; 2D its four edge
    /// midpoints and its centre.
    fn midpoints(&self, c: Site, size: u32) -> Vec<Site> {
        let h = size / 2;
        if self.axes.len() == 1 {
            vec![[c[0] + h, 0]]
        } else {
            vec![
                [c[0] + h, c[1]],
                [c[0], c[1] + h],
                [c[0] + h, c[1] + h],
                [c[0] + size, c[1] + h],
                [c[0] + h, c[1] + size],
            ]
        }
    }
}

/// One slice's points: the refined axes' lattice sites with their classes (the other axes
/// of a sweep make one slice per combination, refined each on its own).
pub type Slice = BTreeMap<Site, Class>;

/// The next round's new points, `(slice, site)`, from the points done so far: at most
/// `room` points (a point runs once per seed: the caller divides the job budget left by the
/// seed count). Cells are taken largest first, then by slice and site, whole or not at all
/// (a 2D cell's five points together), until the next does not fit; the same input gives
/// the same points. Empty: the refinement is done (levels, budget, or no cell to split).
pub fn next_round(
    lattice: &Lattice,
    quantity: &Quantity,
    slices: &[Slice],
    room: usize,
) -> Vec<(usize, Site)> {
    let mut cells: Vec<(u32, usize, Site, Vec<Site>)> = Vec::new();
    for (k, known) in slices.iter().enumerate() {
        match quantity {
            Quantity::Minimum { .. } => {
                if let Some((c, size)) = minimum_interval(known) {
                    cells.push((size, k, c, vec![[c[0] + size / 2, 0]]));
                }
            }
            _ => {
                for (c, size) in lattice.leaves(known) {
                    if size < 2 {
                        continue;
                    }
                    let corners: Vec<&Class> = lattice
                        .corners(c, size)
                        .iter()
                        .filter_map(|s| known.get(s))
                        .collect();
                    let mixed = corners
                        .iter()
                        .any(|a| corners.iter().any(|b| differ(quantity, a, b)));
                    if mixed {
                        let new = lattice
                            .midpoints(c, size)
                            .into_iter()
                            .filter(|s| !known.contains_key(s))
                            .collect();
                        cells.push((size, k, c, new));
                    }
                }
            }
        }
    }
    cells.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut chosen: BTreeSet<(usize, Site)> = BTreeSet::new();
    for (_, k, _, new) in cells {
        let fresh: Vec<(usize, Site)> = new
            .into_iter()
            .map(|s| (k, s))
            .filter(|p| !chosen.contains(p))
            .collect();
        if chosen.len() + fresh.len() > room {
            break;
        }
        chosen.extend(fresh);
    }
    chosen.into_iter().collect()
}

/// The interval beside the lowest value (1D) to bisect next: the longer of the two beside
/// it (the left one on a tie), when it has a midpoint on the lattice; None when the lowest
/// point is at an end of the axis (no interior minimum) or the bracket is at the finest
/// spacing.
fn minimum_interval(known: &Slice) -> Option<(Site, u32)> {
    let points: Vec<(u32, f64)> = known
        .iter()
        .filter_map(|(s, c)| match c {
            Class::Value(v) => Some((s[0], *v)),
            _ => None,
        })
        .collect();
    let m = (0..points.len()).min_by(|&a, &b| points[a].1.total_cmp(&points[b].1))?;
    if m == 0 || m + 1 == points.len() {
        return None;
    }
    let (a, u, b) = (points[m - 1].0, points[m].0, points[m + 1].0);
    let (lo, len) = if u - a >= b - u {
        (a, u - a)
    } else {
        (u, b - u)
    };
    (len >= 2 && len.is_power_of_two()).then_some(([lo, 0], len))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(values: &[f64], levels: u32) -> Lattice {
        Lattice {
            axes: vec![values.to_vec()],
            levels,
        }
    }

    fn label(s: &str) -> Class {
        Class::Label(s.into())
    }

    /// The base grid's points with their classes from `truth`.
    fn base(lattice: &Lattice, truth: &dyn Fn(Site) -> Class) -> Slice {
        lattice
            .base_sites()
            .into_iter()
            .map(|s| (s, truth(s)))
            .collect()
    }

    /// Run rounds to the end with `truth` giving each site's class; the sites in order.
    fn refine_to_end(
        lattice: &Lattice,
        quantity: &Quantity,
        truth: &dyn Fn(Site) -> Class,
        mut room: usize,
    ) -> (Slice, usize) {
        let mut known = base(lattice, truth);
        let mut rounds = 0;
        loop {
            let new = next_round(lattice, quantity, std::slice::from_ref(&known), room);
            if new.is_empty() {
                return (known, rounds);
            }
            rounds += 1;
            room -= new.len();
            for (k, s) in new {
                assert_eq!(k, 0);
                assert!(known.insert(s, truth(s)).is_none(), "{s:?} computed twice");
            }
        }
    }

    /// Every cell of the final partition whose corners differ is of the finest size.
    fn assert_mixed_cells_are_finest(lat: &Lattice, all: &Slice) {
        for (c, size) in lat.leaves(all) {
            let cs = lat.corners(c, size);
            let mixed = cs.iter().any(|a| cs.iter().any(|b| all[a] != all[b]));
            assert!(!mixed || size == 1, "cell {c:?} of size {size} is mixed");
        }
    }

    #[test]
    fn one_dimension_bisects_the_interval_where_the_label_changes() {
        // base 0, 1, 2, 3 (lattice 0, 8, 16, 24 at 3 levels); plug below 1.3, slug above
        let lat = line(&[0.0, 1.0, 2.0, 3.0], 3);
        let truth = |s: Site| {
            if lat.value(0, s[0]) < 1.3 {
                label("plug")
            } else {
                label("slug")
            }
        };
        let (known, rounds) = refine_to_end(&lat, &Quantity::Label, &truth, 100);
        // one point per level, inside [1, 2]: 1.5, 1.25, 1.375
        let added: Vec<f64> = known
            .keys()
            .map(|s| lat.value(0, s[0]))
            .filter(|v| v.fract() != 0.0)
            .collect();
        assert_eq!(added, vec![1.25, 1.375, 1.5]);
        assert_eq!(rounds, 3);
        // the boundary's bracket is the finest spacing (1/8) and holds 1.3
        let levels: Vec<u32> = known.keys().map(|&s| lat.level(s)).collect();
        assert_eq!(levels, vec![0, 0, 2, 3, 1, 0, 0]);
    }

    #[test]
    fn uneven_base_values_interpolate() {
        let lat = line(&[0.6, 1.0, 3.0, 5.0], 2);
        assert_eq!(lat.value(0, 4), 1.0);
        assert_eq!(lat.value(0, 6), 2.0);
        assert_eq!(lat.value(0, 5), 1.5);
        assert_eq!(lat.value(0, 12), 5.0);
        assert_eq!(lat.level([6, 0]), 1);
        assert_eq!(lat.level([5, 0]), 2);
        // refined values are the decimals a researcher writes, not the interpolation's
        // rounding noise (1 + 3 (1.4 - 1) / 4 = 1.2999999999999998 in floating point)
        let lat = line(&[0.6, 1.0, 1.4, 1.8], 2);
        assert_eq!(lat.value(0, 7), 1.3);
        assert_eq!(lat.value(0, 3), 0.9);
        let lat = line(&[0.2, 0.6, 1.0], 5);
        assert_eq!(lat.value(0, 1), 0.2125);
        assert_eq!(lat.value(0, 63), 0.9875);
    }

    #[test]
    fn no_change_no_round() {
        let lat = line(&[0.0, 1.0, 2.0], 4);
        let (known, rounds) = refine_to_end(&lat, &Quantity::Label, &|_| label("plug"), 100);
        assert_eq!((known.len(), rounds), (3, 0));
    }

    #[test]
    fn other_is_its_own_class() {
        // failed | plug | plug | failed | failed: two boundaries (failed|plug, plug|failed),
        // none between the two failed points
        let lat = line(&[0.0, 1.0, 2.0, 3.0, 4.0], 1);
        let truth = |s: Site| match s[0] {
            0 | 1 => Class::Other,
            u if u <= 4 => label("plug"),
            u if u <= 5 => label("plug"),
            _ => Class::Other,
        };
        let (known, _) = refine_to_end(&lat, &Quantity::Label, &truth, 100);
        let added: Vec<u32> = known.keys().map(|s| s[0]).filter(|u| u % 2 == 1).collect();
        assert_eq!(added, vec![1, 5]);
        assert!(!differ(&Quantity::Label, &Class::Other, &Class::Other));
        assert!(differ(&Quantity::Label, &Class::Other, &label("plug")));
    }

    #[test]
    fn a_point_is_its_cells_label_when_two_thirds_of_its_seeds_are_steady() {
        assert_eq!(Class::of_cell(Some("plug"), 2, 2), label("plug"));
        assert_eq!(Class::of_cell(Some("mixed"), 3, 3), label("mixed"));
        // failed or not steady: one seed of three is tolerated, two are not
        assert_eq!(Class::of_cell(Some("plug"), 2, 3), label("plug"));
        assert_eq!(Class::of_cell(Some("plug"), 1, 3), Class::Other);
        assert_eq!(Class::of_cell(None, 0, 1), Class::Other);
        assert_eq!(Class::of_cell(Some("not-steady"), 1, 1), Class::Other);
        assert_eq!(Class::of_values(&[Some(1.0), Some(3.0)]), Class::Value(2.0));
        assert_eq!(Class::of_values(&[Some(1.0), None]), Class::Other);
        assert_eq!(Class::of_values(&[Some(f64::NAN)]), Class::Other);
    }

    #[test]
    fn a_relative_change_marks_a_boundary() {
        let q = Quantity::Change {
            column: "flow_rate".into(),
            relative: 0.1,
        };
        assert!(!differ(&q, &Class::Value(1.0), &Class::Value(1.09)));
        assert!(differ(&q, &Class::Value(1.0), &Class::Value(1.12)));
        // a steep step between 1 and 2 on a smooth background
        let lat = line(&[0.0, 1.0, 2.0, 3.0], 2);
        let truth = |s: Site| {
            let x = lat.value(0, s[0]);
            Class::Value(1.0 + 0.01 * x + if x > 1.6 { 1.0 } else { 0.0 })
        };
        let (known, _) = refine_to_end(&lat, &q, &truth, 100);
        let added: Vec<f64> = known
            .keys()
            .map(|s| lat.value(0, s[0]))
            .filter(|v| v.fract() != 0.0)
            .collect();
        assert_eq!(added, vec![1.5, 1.75]);
    }

    #[test]
    fn two_dimensions_bisect_edges_and_cells() {
        // a 3 x 3 base grid on [0, 2]^2, 2 levels; the boundary x + y = 1.9 (a diagonal)
        let lat = Lattice {
            axes: vec![vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 2.0]],
            levels: 2,
        };
        let truth = |s: Site| {
            if lat.value(0, s[0]) + lat.value(1, s[1]) < 1.9 {
                label("a")
            } else {
                label("b")
            }
        };
        let known = base(&lat, &truth);
        let first = next_round(&lat, &Quantity::Label, std::slice::from_ref(&known), 100);
        // round 1: the three cells with both labels among their corners ((0,0), (0,1),
        // (1,0); the cell (1,1) has b at every corner) get edge midpoints and centres, the
        // two shared edges' midpoints once: 3 centres + 12 - 2 edge midpoints
        assert_eq!(first.len(), 13);
        assert!(first.contains(&(0, [2, 2])) && first.contains(&(0, [2, 6])));
        assert!(!first.contains(&(0, [6, 6])), "the all-b cell is not split");
        let (all, rounds) = refine_to_end(&lat, &Quantity::Label, &truth, 1000);
        assert_eq!(rounds, 2);
        // every finest cell that the boundary crosses exists: its corners are known
        assert_mixed_cells_are_finest(&lat, &all);
        // fewer points than the full 9 x 9 lattice of the same resolution
        assert!(all.len() < 81, "{} points", all.len());
    }

    #[test]
    fn a_curved_2d_boundary_costs_under_a_fifth_of_the_regular_grid() {
        // 5 x 5 base values on [0, 1]^2, 4 levels: the finest spacing 1/64, a regular grid of
        // 65 x 65 = 4225 points; the boundary a quarter circle of radius 0.6
        let lat = Lattice {
            axes: vec![vec![0.0, 0.25, 0.5, 0.75, 1.0]; 2],
            levels: 4,
        };
        let truth = |s: Site| {
            let (x, y) = (lat.value(0, s[0]), lat.value(1, s[1]));
            if x * x + y * y < 0.36 {
                label("plug")
            } else {
                label("slug")
            }
        };
        let (all, rounds) = refine_to_end(&lat, &Quantity::Label, &truth, 10_000);
        assert_eq!(rounds, 4);
        // to the finest spacing wherever the circle crosses a cell's corners
        assert_mixed_cells_are_finest(&lat, &all);
        assert!(all.len() * 5 <= 65 * 65, "{} points of 4225", all.len());
    }

    #[test]
    fn ten_thousand_points_of_bookkeeping() {
        // a round over 100 slices of 100 points each (10 000 jobs) with a boundary in every
        // slice but the first: one midpoint per such slice
        let lat = line(&(0..100).map(f64::from).collect::<Vec<_>>(), 8);
        let slices: Vec<Slice> = (0..100)
            .map(|k| {
                lat.base_sites()
                    .into_iter()
                    .map(|s| (s, label(if s[0] / 256 < k { "a" } else { "b" })))
                    .collect()
            })
            .collect();
        let new = next_round(&lat, &Quantity::Label, &slices, usize::MAX);
        assert_eq!(new.len(), 99, "slice 0 is all b");
    }

    #[test]
    fn the_budget_stops_a_round_at_a_whole_cell() {
        let lat = line(&[0.0, 1.0, 2.0, 3.0], 4);
        let truth = |s: Site| {
            let x = lat.value(0, s[0]);
            if x < 0.3 || (1.3..2.7).contains(&x) {
                label("a")
            } else {
                label("b")
            }
        };
        let known = base(&lat, &truth);
        // three mixed intervals; room for two points: the first two in site order
        let new = next_round(&lat, &Quantity::Label, std::slice::from_ref(&known), 2);
        assert_eq!(new, vec![(0, [8, 0]), (0, [24, 0])]);
        // the whole refinement never exceeds its room
        let (all, _) = refine_to_end(&lat, &Quantity::Label, &truth, 5);
        assert!(all.len() <= 4 + 5, "{}", all.len());
        assert_eq!(all.len(), 9);
        // a 2D cell's five points go together or not at all
        let sq = Lattice {
            axes: vec![vec![0.0, 1.0], vec![0.0, 1.0]],
            levels: 2,
        };
        let mut k: Slice = sq
            .base_sites()
            .into_iter()
            .map(|s| (s, label("a")))
            .collect();
        k.insert([4, 4], label("b"));
        assert!(next_round(&sq, &Quantity::Label, std::slice::from_ref(&k), 4).is_empty());
        assert_eq!(
            next_round(&sq, &Quantity::Label, std::slice::from_ref(&k), 5).len(),
            5
        );
    }

    #[test]
    fn slices_refine_on_their_own() {
        let lat = line(&[0.0, 1.0], 1);
        let a: Slice = [([0, 0], label("x")), ([2, 0], label("y"))].into();
        let b: Slice = [([0, 0], label("x")), ([2, 0], label("x"))].into();
        assert_eq!(
            next_round(&lat, &Quantity::Label, &[b, a], 10),
            vec![(1, [1, 0])]
        );
    }

    #[test]
    fn the_minimum_is_bracketed_ever_closer() {
        // (x - 1.3)^2 on base 0, 1, 2, 3 with 6 levels: the bracket ends at 2/64
        let lat = line(&[0.0, 1.0, 2.0, 3.0], 6);
        let q = Quantity::Minimum {
            column: "flow_rate".into(),
        };
        let truth = |s: Site| Class::Value((lat.value(0, s[0]) - 1.3).powi(2));
        let (known, rounds) = refine_to_end(&lat, &q, &truth, 100);
        let best = known
            .iter()
            .min_by(|a, b| match (a.1, b.1) {
                (Class::Value(x), Class::Value(y)) => x.total_cmp(y),
                _ => unreachable!(),
            })
            .map(|(s, _)| lat.value(0, s[0]))
            .unwrap();
        assert!((best - 1.3).abs() <= 1.0 / 64.0, "best {best}");
        // each round halves the longer side of the bracket: 10 rounds here
        assert!(rounds <= 2 * 6, "{rounds} rounds");
        // a minimum at the end of the axis is no interior minimum: no round
        let edge = |s: Site| Class::Value(lat.value(0, s[0]));
        assert_eq!(refine_to_end(&lat, &q, &edge, 100).1, 0);
    }
}
