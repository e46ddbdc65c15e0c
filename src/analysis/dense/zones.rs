//! The zones of a dense channel flow (Debnath, Rao & Kumaran 2022, §3.2, dem.md A2.1), from
//! the wall to the centre of the folded profiles: the wall layer (the paper's ~2 d_p), the
//! loose shearing zone (phi < phi_ad = 0.587), the dense shearing zone
//! (phi_ad <= phi < 0.63) and the plug (phi >= 0.63 and du_y/dx zero within its error).
//!
//! Rules (the paper judged the boundaries by eye):
//! - the dense zone starts where phi last rises through phi_ad on the way to the centre:
//!   the outermost point beyond which every folded bin has phi >= phi_ad, interpolated
//!   linearly between bin centres; at the wall when every bin has, NaN when the centre has
//!   not;
//! - the plug starts at the wall-side edge of the outermost bin from which every folded bin
//!   to the centre has phi >= 0.63 and |du_y/dx| <= 2 standard errors (zero within its
//!   error); NaN when there is no plug;
//! - the loose zone lies between the wall layer and the dense zone; it is empty when the
//!   dense zone starts inside the wall layer (as at phi-bar = 0.62 in the paper).

use serde::{Deserialize, Serialize};

/// phi_ad, the dense/loose boundary (the paper's 0.587, after Chialvo et al. 2012)
pub const PHI_AD: f64 = 0.587;
/// phi of the plug (the paper's 0.63)
pub const PHI_PLUG: f64 = 0.63;
/// the wall layer's thickness, d_p (the paper: "about two particle diameters")
pub const WALL_LAYER: f64 = 2.0;
/// |du_y/dx| within this many standard errors of zero counts as zero
pub const ZERO_SHEAR_ERRORS: f64 = 2.0;

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
    /// the folded bins of the dense zone: from this one to the centre (None: no dense zone)
    pub dense_from: Option<usize>,
    /// the folded bins of the plug: from this one to the centre (None: no plug)
    pub plug_from: Option<usize>,
}

/// The zones of folded profiles: bin centres and wall-side edges (distance from the wall),
/// phi, du_y/dx with its standard error, from the wall bin to the centre; W.
pub fn zones(
    centres: &[f64],
    edges: &[f64],
    phi: &[f64],
    shear: &[f64],
    shear_error: &[f64],
    width: f64,
) -> Zones {
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
    let plug =
        inner_run(&|k| phi[k] >= PHI_PLUG && shear[k].abs() <= ZERO_SHEAR_ERRORS * shear_error[k]);
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
        dense_from: dense,
        plug_from: plug,
    }
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
        let error = [0.01, 0.01, 0.01, 0.001, 0.001];
        let z = zones(&CENTRES, &EDGES, &phi, &shear, &error, 10.0);
        // phi crosses 0.587 between 2 (0.57) and 3 (0.60): at 2 + 17/30
        assert!(
            (z.dense_start - (2.0 + 0.017 / 0.03)).abs() < 1e-12,
            "{z:?}"
        );
        assert_eq!(z.plug_start, 3.5);
        assert_eq!(z.plug_width, 3.0);
        assert_eq!((z.dense_from, z.plug_from), (Some(2), Some(3)));
        assert!((z.loose_width - (z.dense_start - 2.0)).abs() < 1e-12);
    }

    #[test]
    fn a_sheared_dense_centre_is_no_plug_and_a_dense_wall_has_no_loose_zone() {
        let phi = [0.60, 0.62, 0.632, 0.635, 0.636];
        // the centre shears beyond its error
        let shear = [0.5, 0.2, 0.1, 0.05, 0.03];
        let error = [0.01; 5];
        let z = zones(&CENTRES, &EDGES, &phi, &shear, &error, 10.0);
        assert_eq!(z.dense_start, 0.0);
        assert_eq!(z.loose_width, 0.0);
        assert!(z.plug_start.is_nan() && z.plug_width == 0.0, "{z:?}");
        assert_eq!((z.dense_from, z.plug_from), (Some(0), None));
        // a loose centre: no dense zone
        let z = zones(&CENTRES, &EDGES, &[0.5; 5], &shear, &error, 10.0);
        assert!(z.dense_start.is_nan());
        assert_eq!(z.dense_from, None);
        assert_eq!(z.loose_width, 3.0);
    }
}
