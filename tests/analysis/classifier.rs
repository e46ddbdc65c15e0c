//! The classifier on synthetic density fields of known structure with the shot noise of the
//! thesis' W/d = 15, 30, 50 boxes (`synthetic.rs`): every structure gets its name (label,
//! humps and 3D flag) in every box and seed, and the confusion table of docs/analysis.md is
//! printed by `cargo test --release --test integration -- analysis::classifier::confusion
//! --nocapture`.

use super::synthetic::{Structure, SyntheticBox, tall_box, thesis_boxes, window};
use granflow::analysis::labels::label_key;
use granflow::analysis::{AnalysisSettings, analyse_job};

/// Snapshots per window (the milestone window's default).
const SNAPSHOTS: usize = 5;

/// Seeds per structure and box.
const SEEDS: u64 = 4;

/// The window label the analysis gives (with its humps) and its 3D flag.
fn classify(b: &SyntheticBox, s: Structure, seed: u64) -> (String, bool) {
    let a = analyse_job(&window(b, s, SNAPSHOTS, seed), &AnalysisSettings::default());
    (
        label_key(&a.summary.label, a.summary.humps),
        a.summary.three_dimensional,
    )
}

/// The boxes a structure is tried in: the thesis' L/W = 3 boxes, and the tall box of Fig. 5.20
/// for the 3D waves.
fn boxes_for(s: Structure) -> Vec<SyntheticBox> {
    let mut boxes = thesis_boxes();
    if matches!(s, Structure::SWave3d | Structure::Slug3d) {
        boxes.push(tall_box());
    }
    boxes
}

/// (true structure, label as shown with a ` 3d` mark, count) over boxes and seeds.
fn confusion() -> Vec<(String, Vec<(String, usize)>)> {
    Structure::all()
        .into_iter()
        .map(|s| {
            let mut counts: Vec<(String, usize)> = Vec::new();
            for (bi, b) in boxes_for(s).iter().enumerate() {
                for seed in 0..SEEDS {
                    let (label, three_d) = classify(b, s, 1000 * bi as u64 + seed);
                    let shown = if three_d {
                        format!("{label} 3d")
                    } else {
                        label
                    };
                    match counts.iter_mut().find(|c| c.0 == shown) {
                        Some(c) => c.1 += 1,
                        None => counts.push((shown, 1)),
                    }
                }
            }
            (s.name(), counts)
        })
        .collect()
}

#[test]
fn confusion_table_of_synthetic_structures() {
    let table = confusion();
    println!("| true structure | labels given (count over boxes x seeds) |");
    println!("|---|---|");
    for (name, counts) in &table {
        let cells: Vec<String> = counts.iter().map(|(l, c)| format!("{l} {c}")).collect();
        println!("| {name} | {} |", cells.join(", "));
    }
    let mut wrong = Vec::new();
    for (s, (name, counts)) in Structure::all().into_iter().zip(&table) {
        let (label, three_d) = s.expected();
        let want = if three_d {
            format!("{label} 3d")
        } else {
            label
        };
        for (shown, c) in counts {
            if *shown != want {
                wrong.push(format!("{name}: {c} x {shown} (want {want})"));
            }
        }
    }
    assert!(wrong.is_empty(), "misnamed:\n{}", wrong.join("\n"));
}

/// Where a label is shown, a structure that varies along z says so: the job's `shown_label`
/// (label with humps and ` 3d`), the milestone table's `structure` and `three_dimensional`,
/// and the phase diagram's cell text; a flat structure carries no mark.
#[test]
fn labels_show_the_3d_mark_where_they_are_shown() {
    use granflow::analysis::milestones::MilestonePlan;
    use granflow::engine::Clock;
    use granflow::sweep::phase::{Cell, CellJob};
    let b = tall_box();
    let settings = AnalysisSettings {
        milestones: Some(MilestonePlan {
            clock: Clock::CollisionsPerParticle,
            readings: vec![300.0],
            every: 0.0,
            window: 5,
        }),
        ..AnalysisSettings::default()
    };
    for (s, mark) in [
        (Structure::SWave3d, true),
        (Structure::SWave(2, true), false),
    ] {
        let a = analyse_job(&window(&b, s, SNAPSHOTS, 7), &settings);
        let (label, three_d) = s.expected();
        assert_eq!(a.summary.three_dimensional, three_d, "{}", s.name());
        let shown = if mark { format!("{label} 3d") } else { label };
        assert_eq!(a.summary.shown_label, shown, "{}", s.name());
        let m = &a.milestones[0];
        assert_eq!(
            (m.structure.as_str(), m.three_dimensional),
            (shown.as_str(), mark)
        );
        let cell = Cell {
            jobs: (0..3)
                .map(|_| CellJob {
                    label: a.summary.label.clone(),
                    humps: a.summary.humps,
                    probabilities: vec![(label_key(&a.summary.label, a.summary.humps), 1.0)],
                    weight: 5.0,
                    steady: true,
                    guard_valid: true,
                    three_dimensional: a.summary.three_dimensional,
                })
                .collect(),
            not_done: 0,
        };
        assert_eq!(cell.text().contains(" 3d"), mark, "{}", cell.text());
    }
}
