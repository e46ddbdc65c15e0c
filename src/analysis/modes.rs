//! The strongest modes a structure summary lists: the dominant xy modes of the window-averaged
//! spectrum and each family's peak against its threshold. Records (list-of-struct columns of
//! `jobs.parquet`, fields declared here), their one-line text (`sim --analyse`), and the text
//! that results written before these were records hold in their place (read back into
//! records, at the precision that text printed).

use super::columns::{ColumnDef, ColumnKind};
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::marker::PhantomData;

/// One of the strongest modes of the folded xy spectrum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DominantMode {
    /// always "xy" (the plane of the spectrum; joins `spectra.parquet` on plane, k1, k2)
    pub plane: String,
    /// k_x, k_y
    pub k1: u32,
    pub k2: u32,
    /// window-averaged power
    pub power: f64,
    /// power / its shot-noise power (1 for a random arrangement)
    pub ratio: f64,
}

/// A family's strongest folded mode against the peak-test threshold.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FamilyPeak {
    /// transverse, along-flow, antisymmetric, symmetric-rest or spanwise
    pub family: String,
    /// xy, xy-antisymmetric, xy-symmetric (the reflection parts of the xy field), xz or yz
    pub plane: String,
    pub k1: u32,
    pub k2: u32,
    /// power / its shot-noise power
    pub ratio: f64,
    /// the peak-test threshold of that mode
    pub threshold: f64,
}

/// The struct fields of `dominant_modes` in `jobs.parquet`.
pub const DOMINANT_MODE_FIELDS: &[ColumnDef] = &[
    field("plane", ColumnKind::Str, "xy"),
    field("k1", ColumnKind::I64, "k_x"),
    field("k2", ColumnKind::I64, "k_y"),
    field("power", ColumnKind::F64, "window-averaged power"),
    field("ratio", ColumnKind::F64, "power / shot-noise power"),
];

/// The struct fields of `family_peaks` in `jobs.parquet`.
pub const FAMILY_PEAK_FIELDS: &[ColumnDef] = &[
    field("family", ColumnKind::Str, "the family"),
    field(
        "plane",
        ColumnKind::Str,
        "the plane or reflection part of the mode",
    ),
    field(
        "k1",
        ColumnKind::I64,
        "wave number along the plane's first axis",
    ),
    field(
        "k2",
        ColumnKind::I64,
        "wave number along the plane's second axis",
    ),
    field("ratio", ColumnKind::F64, "power / shot-noise power"),
    field("threshold", ColumnKind::F64, "the peak-test threshold"),
];

const fn field(name: &'static str, kind: ColumnKind, doc: &'static str) -> ColumnDef {
    ColumnDef { name, kind, doc }
}

/// The list columns of the structure summary, by name, with their struct fields.
pub fn list_column(name: &str) -> Option<&'static [ColumnDef]> {
    match name {
        "dominant_modes" => Some(DOMINANT_MODE_FIELDS),
        "family_peaks" => Some(FAMILY_PEAK_FIELDS),
        _ => None,
    }
}

impl fmt::Display for DominantMode {
    /// `(k_x,k_y) P [P/noise x]`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "({},{}) {:.3e} [{:.1}x]",
            self.k1, self.k2, self.power, self.ratio
        )
    }
}

impl fmt::Display for FamilyPeak {
    /// `family plane(k1,k2) ratio/threshold`
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} {}({},{}) {:.1}/{:.1}",
            self.family, self.plane, self.k1, self.k2, self.ratio, self.threshold
        )
    }
}

/// Records joined by "; " (the one-line form of a list).
pub fn joined<T: fmt::Display>(items: &[T]) -> String {
    items
        .iter()
        .map(T::to_string)
        .collect::<Vec<_>>()
        .join("; ")
}

/// A record that older results wrote as text, in the format [`fmt::Display`] gives it.
pub(super) trait Legacy: Sized {
    const WHAT: &'static str;
    fn parse(text: &str) -> Option<Self>;
}

/// `(k1,k2)` -> (k1, k2)
fn wave_numbers(text: &str) -> Option<(u32, u32)> {
    let (k1, k2) = text.strip_prefix('(')?.strip_suffix(')')?.split_once(',')?;
    Some((k1.parse().ok()?, k2.parse().ok()?))
}

impl Legacy for DominantMode {
    const WHAT: &'static str = "dominant mode \"(k1,k2) power [ratio x]\"";

    fn parse(text: &str) -> Option<Self> {
        let (modes, rest) = text.split_once(' ')?;
        let (power, ratio) = rest.split_once(' ')?;
        let (k1, k2) = wave_numbers(modes)?;
        let ratio = ratio.strip_prefix('[')?.strip_suffix("x]")?;
        Some(DominantMode {
            plane: "xy".into(),
            k1,
            k2,
            power: power.parse().ok()?,
            ratio: ratio.parse().ok()?,
        })
    }
}

impl Legacy for FamilyPeak {
    const WHAT: &'static str = "family peak \"family plane(k1,k2) ratio/threshold\"";

    fn parse(text: &str) -> Option<Self> {
        let (family, rest) = text.split_once(' ')?;
        let (mode, numbers) = rest.split_once(' ')?;
        let open = mode.find('(')?;
        let (k1, k2) = wave_numbers(&mode[open..])?;
        let (ratio, threshold) = numbers.split_once('/')?;
        Some(FamilyPeak {
            family: family.into(),
            plane: mode[..open].into(),
            k1,
            k2,
            ratio: ratio.parse().ok()?,
            threshold: threshold.parse().ok()?,
        })
    }
}

/// Read a list of records, or the "; "-joined text older results hold in its place.
pub(super) fn list_or_legacy_text<'de, D, T>(deserializer: D) -> Result<Vec<T>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de> + Legacy,
{
    struct ListOrText<T>(PhantomData<T>);

    impl<'de, T: Deserialize<'de> + Legacy> Visitor<'de> for ListOrText<T> {
        type Value = Vec<T>;

        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            write!(f, "a list of records or the text of a {}", T::WHAT)
        }

        fn visit_str<E: de::Error>(self, text: &str) -> Result<Vec<T>, E> {
            text.split("; ")
                .filter(|part| !part.is_empty())
                .map(|part| {
                    T::parse(part).ok_or_else(|| {
                        E::custom(format!("`{part}` is not a {} of older results", T::WHAT))
                    })
                })
                .collect()
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
            let mut out = Vec::new();
            while let Some(item) = seq.next_element()? {
                out.push(item);
            }
            Ok(out)
        }
    }

    deserializer.deserialize_any(ListOrText(PhantomData))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Deserialize)]
    struct Holder {
        #[serde(deserialize_with = "list_or_legacy_text")]
        modes: Vec<DominantMode>,
        #[serde(deserialize_with = "list_or_legacy_text")]
        peaks: Vec<FamilyPeak>,
    }

    #[test]
    fn legacy_text_reads_as_records_and_prints_back_the_same() {
        // as a result of commit 7062f8f holds them
        let modes = "(1,1) 7.060e-3 [0.8x]; (2,1) 5.513e-3 [1.3x]; (0,1) 1.864e-3 [0.4x]";
        let peaks = "transverse xy(0,2) 0.7/27.7; antisymmetric xy-antisymmetric(1,1) 1.1/16.5; spanwise xz(2,1) 2.4/17.4";
        let h: Holder =
            ron::from_str(&format!("(modes: \"{modes}\", peaks: \"{peaks}\")")).unwrap();
        assert_eq!(h.modes.len(), 3);
        assert_eq!((h.modes[1].k1, h.modes[1].k2), (2, 1));
        assert_eq!(h.modes[1].power, 5.513e-3);
        assert_eq!(h.modes[1].ratio, 1.3);
        assert_eq!(h.peaks[1].plane, "xy-antisymmetric");
        assert_eq!((h.peaks[2].k1, h.peaks[2].k2), (2, 1));
        assert_eq!(h.peaks[2].threshold, 17.4);
        assert_eq!(joined(&h.modes), modes);
        assert_eq!(joined(&h.peaks), peaks);
        // lists read as lists; empty text is no record; text of another shape is an error
        let h: Holder = ron::from_str(
            "(modes: [(plane: \"xy\", k1: 3, k2: 1, power: 0.5, ratio: 2.0)], peaks: \"\")",
        )
        .unwrap();
        assert_eq!(h.modes[0].k1, 3);
        assert!(h.peaks.is_empty());
        let bad = ron::from_str::<Holder>("(modes: \"(1,1) 7.0e-3\", peaks: \"\")");
        assert!(
            bad.as_ref()
                .is_err_and(|e| e.to_string().contains("(1,1) 7.0e-3")),
            "{:?}",
            bad.err()
        );
    }
}
