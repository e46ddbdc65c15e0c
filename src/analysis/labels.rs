//! Labels with probabilities: every snapshot of a window is classified on its own (the same
//! noise-derived thresholds as always), and the window's label is decided from those
//! per-snapshot verdicts rather than from one average.
//!
//! Rule (docs/analysis.md, "Labels with probabilities"):
//! 1. a family is *present* when it is significant in more than half of the window's snapshots
//!    (its `presence` is that fraction; its strength is the window-averaged significance);
//! 2. the candidate label is the structure the present families name (the label table; humps
//!    and coherence of the S-wave from the window-averaged spectrum; the slug content, the
//!    along-flow modes that are not even harmonics of the snapshot's S-wave, present like a
//!    family), so a combined label such as s-wave+slug needs each of its parts in most
//!    snapshots;
//! 3. its probability is the fraction of snapshots whose own label it is; it is the window's
//!    label when that fraction is at least [`CLEAR_MAJORITY`] (the label holds at least twice
//!    as often as all others together). Otherwise the result says `mixed` and lists the
//!    leading labels with their fractions.

use super::classify::{Assessment, name_structure};

/// The fraction of a window's snapshots that a label must hold to be the window's label.
pub const CLEAR_MAJORITY: f64 = 2.0 / 3.0;

/// What the per-snapshot verdicts of a window say.
#[derive(Clone, Debug, PartialEq)]
pub struct LabelStatistics {
    /// (label, fraction of snapshots), most frequent first; labels carry their humps
    /// (`s-wave(2)`); ties in first-seen order
    pub probabilities: Vec<(String, f64)>,
    /// the window's label: the candidate when it holds a clear majority, else "mixed"
    pub label: String,
    /// humps of the window's label (0 when it has none)
    pub humps: u32,
    /// the fraction of snapshots carrying the candidate label
    pub probability: f64,
    /// the candidate label (what the present families name), also when mixed
    pub candidate: String,
    /// fraction of snapshots in which each family is significant (`FAMILY_NAMES` order)
    pub presence: [f64; 5],
}

/// A per-snapshot label with its humps, as the probabilities name it.
pub fn label_key(label: &str, humps: u32) -> String {
    if humps > 0 {
        format!("{label}({humps})")
    } else {
        label.to_string()
    }
}

/// The mark a label carries when the structure varies along z (the spanwise family stands
/// above noise): `s-wave(2) 3d`.
pub const THREE_D_MARK: &str = " 3d";

/// A label as shown to a reader: with its humps and, for a three-dimensional structure, the
/// [`THREE_D_MARK`] (`s-wave(2) 3d`, `slug`).
pub fn shown(label: &str, humps: u32, three_dimensional: bool) -> String {
    let key = label_key(label, humps);
    if three_dimensional {
        format!("{key}{THREE_D_MARK}")
    } else {
        key
    }
}

/// Decide a window's label from the assessments of its snapshots and of its average.
pub fn statistics(snapshots: &[Assessment], average: &Assessment) -> LabelStatistics {
    let m = snapshots.len();
    let mut presence = [0.0; 5];
    let mut slug_presence = 0.0;
    let mut counts: Vec<(String, usize)> = Vec::new();
    for a in snapshots {
        for (f, p) in presence.iter_mut().enumerate() {
            if a.significance[f] > 1.0 {
                *p += 1.0 / m as f64;
            }
        }
        if a.slug > 1.0 {
            slug_presence += 1.0 / m as f64;
        }
        let key = label_key(a.label, a.humps);
        match counts.iter_mut().find(|(k, _)| *k == key) {
            Some(c) => c.1 += 1,
            None => counts.push((key, 1)),
        }
    }
    // stable sort: equal counts keep first-seen order
    counts.sort_by_key(|c| std::cmp::Reverse(c.1));
    let probabilities: Vec<(String, f64)> = counts
        .into_iter()
        .map(|(k, c)| (k, c as f64 / m.max(1) as f64))
        .collect();
    let mut present = presence.map(|p| p > 0.5);
    present[1] = slug_presence > 0.5;
    let (candidate, humps) = name_structure(present, average.coherence, average.antisymmetric_kx);
    // the probability of a label counts its snapshots whatever their hump numbers
    let probability =
        snapshots.iter().filter(|a| a.label == candidate).count() as f64 / m.max(1) as f64;
    let label = if m > 0 && probability >= CLEAR_MAJORITY {
        candidate.to_string()
    } else {
        "mixed".to_string()
    };
    LabelStatistics {
        probabilities,
        humps: if label == "mixed" { 0 } else { humps },
        label,
        probability,
        candidate: candidate.to_string(),
        presence,
    }
}

/// The probabilities as text: "slug 0.82; s-wave+slug(1) 0.18".
pub fn probabilities_text(probabilities: &[(String, f64)]) -> String {
    probabilities
        .iter()
        .map(|(k, p)| format!("{k} {p:.2}"))
        .collect::<Vec<_>>()
        .join("; ")
}
