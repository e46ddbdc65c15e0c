//! The zones of a dense channel flow (Debnath, Rao & Kumaran 2022, §3.2, dem.md A2.1), from
//! the wall to the centre of the folded profiles: the wall layer (the paper's ~2 d_p), the
//! loose shearing zone (phi < phi_ad = 0.587), the dense shearing zone
//! (phi_ad <= phi < 0.63) and the plug (phi ~ 0.63, constant, unsheared).
//!
//! Rules (the paper judged the boundaries by eye):
//! - the dense zone starts where phi last rises through phi_ad on the way to the centre:
//!   the outermost point beyond which every folded bin has phi >= phi_ad, interpolated
//!   linearly between bin centres; at the wall when every bin has, NaN when the centre has
//!   not;
//! - the plug starts at the paper's "change of slope in phi": the break of the least-squares
//!   fit of a ramp that rises into a constant, phi(x) = phi_p + s min(x - x_b, 0), to the
//!   folded bins outside the wall bin, x_b tried at every bin's wall-side edge. The bins from
//!   x_b to the centre are a plug when (i) their mean phi is 0.63 or above within two of its
//!   standard errors (the bins' spread over their number: a plug moves as one block, so the
//!   bin-to-bin phi of its frozen packing, +-0.02 in a 5 d_p span, never averages out),
//!   (ii) the ramp rises (s > 0), and (iii) they are unsheared: their mean |du_y/dx| (over
//!   their width) is at most 1 % of that of the shearing zones between the wall and x_b. The
//!   plateau has at least two folded bins (a plug of at least 3 d_p): one bin alone is always
//!   constant, and the central one always unsheared (its folded du_y/dx is 0). A per-bin
//!   test, phi >= 0.63 in every bin and du_y/dx within two standard errors of zero, finds no
//!   plug in such a block: its frozen phi dips below 0.63 in some bins, and its slow creep,
//!   0.1 % of the wall's shear rate, is many standard errors from zero in a long average.
//!   NaN when there is no plug;
//! - the loose zone lies between the wall layer and the dense zone; it is empty when the
//!   dense zone starts inside the wall layer (as at phi-bar = 0.62 in the paper).

use super::standard_error;
use serde::{Deserialize, Serialize};

/// phi_ad, the dense/loose boundary (the paper's 0.587, after Chialvo et al. 2012)
pub const PHI_AD: f64 = 0.587;
/// phi of the plug (the paper's 0.63)
pub const PHI_PLUG: f64 = 0.63;
/// the wall layer's thickness, d_p (the paper: "about two particle diameters")
pub const WALL_LAYER: f64 = 2.0;
/// the plug's mean phi may fall short of [`PHI_PLUG`] by this many of its standard errors
pub const PLUG_PHI_ERRORS: f64 = 2.0;
/// an unsheared plug: its mean |du_y/dx| over that of the shearing zones is at most this
pub const PLUG_SHEAR_FRACTION: f64 = 0.01;

/// Zone boundaries as distances from the wall (d_p).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Zones {
    /// where the dense shearing zone begins (NaN: phi stays below phi_ad)
    pub dense_start: f64,
    /// where the plug begins (NaN: no plug)
    pub plug_start: f64,
    /// width of the loose shearing zone (0 when the dense zone reaches into the wall layer)
    pub loose_width: f64,
    /// width of the plug, W - 2 plug_start (0 without a plug)
    pub plug_width: f64,
    /// mean phi of the plug's folded bins (NaN: no plug)
    pub plug_volume_fraction: f64,
    /// the folded bins of the dense zone: from this one to the centre (None: no dense zone)
    pub dense_from: Option<usize>,
    /// the folded bins of the plug: from this one to the centre (None: no plug)
    pub plug_from: Option<usize>,
}

/// The zones of folded profiles: bin centres and wall-side edges (distance from the wall),
/// phi and du_y/dx, from the wall bin to the centre (the last bin is the central one: it
/// straddles W/2 when the bins are odd in number, it ends there when they are even); W.
pub fn zones(centres: &[f64], edges: &[f64], phi: &[f64], shear: &[f64], width: f64) -> Zones {
    let n = phi.len();
    // the outermost bin from which all bins inward satisfy `ok`
    let inner_run = |ok: &dyn Fn(usize) -> bool| -> Option<usize> {
        let mut first = None;
        for k in (0..n).rev() {
            if ok(k) {
                first = Some(k);
            } else {
                break;
            }
        }
        first
    };
    let dense = inner_run(&|k| phi[k] >= PHI_AD);
    let dense_start = match dense {
        None => f64::NAN,
        Some(0) => 0.0,
        Some(k) => {
            // interpolate the crossing between centres k-1 (below) and k (at or above)
            let t = (PHI_AD - phi[k - 1]) / (phi[k] - phi[k - 1]);
            centres[k - 1] + t.clamp(0.0, 1.0) * (centres[k] - centres[k - 1])
        }
    };
    let plug = plug_bins(centres, edges, phi, shear, width);
    let plug_start = plug.map_or(f64::NAN, |k| edges[k]);
    let loose_width = if dense_start.is_nan() {
        (width / 2.0 - WALL_LAYER).max(0.0)
    } else {
        (dense_start - WALL_LAYER).max(0.0)
    };
    Zones {
        dense_start,
        plug_start,
        loose_width,
        plug_width: if plug_start.is_nan() {
            0.0
        } else {
            (width - 2.0 * plug_start).max(0.0)
        },
        plug_volume_fraction: plug.map_or(f64::NAN, |k| mean(&phi[k..])),
        dense_from: dense,
        plug_from: plug,
    }
}

/// The first folded bin of the plug (see the module's rules), None without one.
fn plug_bins(
    centres: &[f64],
    edges: &[f64],
    phi: &[f64],
    shear: &[f64],
    width: f64,
) -> Option<usize> {
    let n = phi.len();
    // the ramp needs a bin outside the wall bin, the plateau two bins
    if n < 4 {
        return None;
    }
    let (k, slope) = slope_break(centres, edges, phi)?;
    let plateau = &phi[k..];
    let (phi_p, error) = (mean(plateau), standard_error(plateau));
    // (a one-bin plateau has no error: NaN.max(0) is 0)
    let dense_enough = phi_p + PLUG_PHI_ERRORS * error.max(0.0) >= PHI_PLUG;
    // bin widths (the central bin counts half of its width when it straddles W/2)
    let bin_width = |b: usize| {
        let upper = if b + 1 < edges.len() {
            edges[b + 1]
        } else {
            width / 2.0
        };
        upper.min(width / 2.0) - edges[b]
    };
    // mean |du_y/dx| over a range of bins, weighted by their widths
    let mean_rate = |bins: std::ops::Range<usize>| -> f64 {
        let (mut sum, mut span) = (0.0, 0.0);
        for b in bins {
            sum += shear[b].abs() * bin_width(b);
            span += bin_width(b);
        }
        sum / span
    };
    let unsheared = mean_rate(k..n) <= PLUG_SHEAR_FRACTION * mean_rate(0..k);
    (dense_enough && slope > 0.0 && unsheared).then_some(k)
}

/// The break of the least-squares fit phi(x) = phi_p + s min(x - x_b, 0) over the folded bins
/// 1 .. n (the wall bin left out), x_b at the wall-side edge of bin k for k = 2 .. n - 2 (a
/// ramp of at least one bin, a plateau of at least two: one bin alone is always "constant",
/// and the central one is always unsheared, its folded du_y/dx being 0): the k with the
/// smallest sum of squares (the first of equal ones) and its slope s. None when no fit is
/// defined (fewer than four bins, or degenerate positions).
fn slope_break(centres: &[f64], edges: &[f64], phi: &[f64]) -> Option<(usize, f64)> {
    let n = phi.len();
    let mut best: Option<(f64, usize, f64)> = None;
    for k in 2..n - 1 {
        let xb = edges[k];
        // linear least squares in (phi_p, s) with the regressor u = min(x - x_b, 0)
        let (mut m, mut su, mut sy, mut suu, mut suy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for b in 1..n {
            let u = (centres[b] - xb).min(0.0);
            m += 1.0;
            su += u;
            sy += phi[b];
            suu += u * u;
            suy += u * phi[b];
        }
        let det = m * suu - su * su;
        // (NaN positions give a NaN determinant: no fit)
        if det.is_nan() || det <= 0.0 {
            continue;
        }
        let s = (m * suy - su * sy) / det;
        let p = (sy - s * su) / m;
        let sse: f64 = (1..n)
            .map(|b| {
                let r = phi[b] - (p + s * (centres[b] - xb).min(0.0));
                r * r
            })
            .sum();
        if best.is_none_or(|(e, _, _)| sse < e) {
            best = Some((sse, k, s));
        }
    }
    best.map(|(_, k, s)| (k, s))
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bins of a W = 10 channel folded: centres 0.75, 2, 3, 4, 5 (the centre bin).
    const CENTRES: [f64; 5] = [0.75, 2.0, 3.0, 4.0, 5.0];
    const EDGES: [f64; 5] = [0.0, 1.5, 2.5, 3.5, 4.5];

    #[test]
    fn a_known_profile_gives_its_zones() {
        let phi = [0.50, 0.57, 0.60, 0.632, 0.635];
        let shear = [0.5, 0.2, 0.05, 0.001, 0.0];
        let z = zones(&CENTRES, &EDGES, &phi, &shear, 10.0);
        // phi crosses 0.587 between 2 (0.57) and 3 (0.60): at 2 + 17/30
        assert!(
            (z.dense_start - (2.0 + 0.017 / 0.03)).abs() < 1e-12,
            "{z:?}"
        );
        // the ramp 0.57, 0.60 breaks into the plateau 0.632, 0.635 (which shears at 0.2 % of
        // the outer bins' mean rate) at the edge of bin 3
        assert_eq!(z.plug_start, 3.5);
        assert_eq!(z.plug_width, 3.0);
        assert!((z.plug_volume_fraction - 0.6335).abs() < 1e-12, "{z:?}");
        assert_eq!((z.dense_from, z.plug_from), (Some(2), Some(3)));
        assert!((z.loose_width - (z.dense_start - 2.0)).abs() < 1e-12);
    }

    #[test]
    fn a_sheared_dense_centre_is_no_plug_and_a_dense_wall_has_no_loose_zone() {
        let phi = [0.60, 0.62, 0.632, 0.635, 0.636];
        // the centre shears (at a fifth to a tenth of the outer bins' mean rate)
        let shear = [0.5, 0.2, 0.1, 0.05, 0.03];
        let z = zones(&CENTRES, &EDGES, &phi, &shear, 10.0);
        assert_eq!(z.dense_start, 0.0);
        assert_eq!(z.loose_width, 0.0);
        assert!(z.plug_start.is_nan() && z.plug_width == 0.0, "{z:?}");
        assert!(z.plug_volume_fraction.is_nan());
        assert_eq!((z.dense_from, z.plug_from), (Some(0), None));
        // a loose centre: no dense zone, no plug
        let z = zones(&CENTRES, &EDGES, &[0.5; 5], &shear, 10.0);
        assert!(z.dense_start.is_nan() && z.plug_start.is_nan());
        assert_eq!(z.dense_from, None);
        assert_eq!(z.loose_width, 3.0);
    }

    /// Folded bins of a W = 40 channel: the wall bin [0, 1.5], then unit bins, the central
    /// one [19.5, 20.5] counting half.
    fn wide() -> (Vec<f64>, Vec<f64>) {
        let edges: Vec<f64> = std::iter::once(0.0)
            .chain((0..19).map(|k| 1.5 + k as f64))
            .collect();
        let centres = (0..20)
            .map(|k| if k == 0 { 0.75 } else { edges[k] + 0.5 })
            .collect();
        (centres, edges)
    }

    /// A plug moving as one block keeps the bin-to-bin phi of its frozen packing (+-0.02
    /// about 0.633, some bins below 0.63) and creeps at 0.1 % of the wall's shear rate: the
    /// plug is found where the ramp of phi (0.01 per d_p, reaching 0.633 at x = 7.5) breaks
    /// into the plateau, as a per-bin rule would not; a plateau that stays below 0.63 is no
    /// plug, nor is a ramp without a plateau.
    #[test]
    fn a_frozen_plug_is_found_at_the_change_of_slope() {
        let (centres, edges) = wide();
        let ramp = [0.36, 0.578, 0.588, 0.598, 0.608, 0.618, 0.628];
        let frozen = [
            0.643, 0.623, 0.63, 0.652, 0.629, 0.643, 0.612, 0.634, 0.617, 0.645, 0.626, 0.618, 0.64,
        ];
        let phi: Vec<f64> = ramp.iter().chain(&frozen).copied().collect();
        let mut shear = vec![3.5, 2.1, 0.75, 0.37, 0.19, 0.09, 0.04];
        shear.extend((0..13).map(|k| if k % 2 == 0 { 0.003 } else { -0.002 }));
        shear[19] = 0.0;
        let z = zones(&centres, &edges, &phi, &shear, 40.0);
        assert!(frozen.iter().any(|&p| p < PHI_PLUG));
        assert_eq!(z.plug_from, Some(7), "{z:?}");
        assert_eq!((z.plug_start, z.plug_width), (7.5, 25.0));
        let plateau_mean = frozen.iter().sum::<f64>() / 13.0;
        assert!((z.plug_volume_fraction - plateau_mean).abs() < 1e-12);
        // the same shape 0.015 looser: the plateau is the dense zone's, not a plug
        let looser: Vec<f64> = phi.iter().map(|p| p - 0.015).collect();
        let z = zones(&centres, &edges, &looser, &shear, 40.0);
        assert_eq!(z.plug_from, None, "{z:?}");
        // phi rising to the centre without a plateau (and shearing there): no plug
        let rising: Vec<f64> = (0..20).map(|k| 0.55 + 0.0045 * k as f64).collect();
        let sheared: Vec<f64> = (0..20).map(|k| 3.0 * (1.0 - k as f64 / 19.0)).collect();
        let z = zones(&centres, &edges, &rising, &sheared, 40.0);
        assert_eq!(z.plug_from, None, "{z:?}");
    }
}
