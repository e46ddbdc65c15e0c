//! Figures a reader can trust: decimal points with ink at 96 dpi, `--dpi`
//! for every command that draws figures, log-axis ticks at 1, 2, 5 x 10^k written as decimals
//! and never overlapping, per-job figures headed by their job's parameters, a mark on every
//! cell or point that pools jobs whose labels differ, and a lattice-gas space-time picture of
//! a wave run sampled at every record over several wave periods.

use crate::common::{BIN, granflow_ok, scratch};
use base64::Engine as _;
use granflow::analysis::lattice::{self, LatticeSettings};
use granflow::engine::ParamValue;
use granflow::engine::lga::{LgaEngine, LgaParams};
use granflow::figure::text::width;
use granflow::figure::ticks::{self, Axis};
use granflow::figure::{Scale, Sizing};
use granflow::job_figures;
use granflow::sweep::curves::{CurvePlot, Point, Series};
use granflow::sweep::phase::{
    Cell, CellJob, DISAGREE, DISAGREE_LEGEND, Frame, PhaseDiagram, fmt_value,
};
use granflow::sweep::{load_sweep, store};
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// A tiny lattice-gas sweep: four jobs of a few thousand steps (well under a second).
const SWEEP: &str = r#"(
    name: "figs",
    engine: "lga",
    fixed: (length: 40, width: 3, gravity_probability: 0.5, bounce_back: 0.5),
    axes: (density: [1.0, 1.2], dissipation: [0.1, 0.5]),
    run: (steps: 4000, snapshot_interval: 10, checkpoint_every: 100),
)"#;

/// Run the tiny sweep into `dir`; (sweep file, results directory of the sweep).
fn run_sweep(dir: &Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let file = dir.join("figs.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let results = dir.join("results");
    granflow_ok(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
    ]);
    (file, results.join("figs"))
}

/// Width and height of a PNG from its header.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

/// The texts of an SVG with their x and y attributes.
fn svg_texts(svg: &str) -> Vec<(f64, f64, String)> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let head = &t[..t.find('>')?];
            let attr = |name: &str| -> Option<f64> {
                let at = head.find(&format!(" {name}=\""))? + name.len() + 3;
                head[at..].split('"').next()?.parse().ok()
            };
            let body = &t[t.find('>')? + 1..t.find("</text>")?];
            Some((
                attr("x")?,
                attr("y")?,
                body.trim().replace("&amp;", "&").replace("&lt;", "<"),
            ))
        })
        .collect()
}

/// The runs of columns with ink (a pixel darker than 200 of 255) of an RGB picture `w` wide:
/// (first column, last column, darkest value, lowest row with ink).
fn ink_runs(rgb: &[u8], w: usize) -> Vec<(usize, usize, u8, usize)> {
    let h = rgb.len() / (3 * w);
    let at = |x: usize, y: usize| {
        let i = 3 * (y * w + x);
        rgb[i].min(rgb[i + 1]).min(rgb[i + 2])
    };
    let mut runs: Vec<(usize, usize, u8, usize)> = Vec::new();
    let mut open = false;
    for x in 0..w {
        let inked: Vec<usize> = (0..h).filter(|&y| at(x, y) < 200).collect();
        if inked.is_empty() {
            open = false;
            continue;
        }
        let dark = (0..h).map(|y| at(x, y)).min().unwrap();
        let low = *inked.last().unwrap();
        match runs.last_mut() {
            Some(r) if open => {
                r.1 = x;
                r.2 = r.2.min(dark);
                r.3 = r.3.max(low);
            }
            _ => runs.push((x, x, dark, low)),
        }
        open = true;
    }
    runs
}

/// "0.25" in the figure font at every label size the figures use, at 96 dpi: after the "0"
/// comes a narrow run of ink of its own, at least half black, on the digits' baseline: the
/// full stop. With the monospaced face and plotters' own glyph placement the figures used
/// before, the stop was a pale smudge glued to the "0" and up to a pixel high, a wide gap
/// after it: "0.25" read "0 25".
#[test]
fn decimal_points_have_ink_at_96_dpi() {
    for size in [11.0, 12.0, 13.0, 14.0] {
        let (w, h) = (80u32, 30u32);
        let rgb = granflow::figure::render_rgb((w, h), Scale::CSS, |root, s| {
            root.fill(&WHITE)?;
            root.draw(&Text::new("0.25", (6, 6), s.font(size)))
        })
        .unwrap();
        let runs = ink_runs(&rgb, w as usize);
        assert!(runs.len() >= 3, "at {size} px: {runs:?}");
        let (zero, stop) = (runs[0], runs[1]);
        assert!(zero.1 - zero.0 >= 3, "at {size} px the 0 is {zero:?}");
        assert!(
            stop.1 - stop.0 <= 2,
            "at {size} px no narrow run of ink after the 0 (a stop of its own): {runs:?}"
        );
        assert!(
            stop.2 <= 127,
            "at {size} px the decimal point's darkest pixel is {} (255 white): no ink",
            stop.2
        );
        assert!(
            stop.3.abs_diff(zero.3) <= 1,
            "at {size} px the stop's lowest ink is on row {}, the 0's on row {}",
            stop.3,
            zero.3
        );
    }
}

/// Every command that draws figures takes `--dpi`: at 192 its PNGs have twice the pixels of
/// those at 96 each way (the same CSS size), and the report shows them at their CSS size.
#[test]
fn dpi_192_doubles_the_pixels_of_every_figure_command() {
    let dir = scratch("figures-dpi");
    let (_, tables) = run_sweep(&dir);
    let t = tables.to_str().unwrap();
    let sized = |cmd: &[&str], dpi: &str, file: &str| -> (u32, u32) {
        let mut args = cmd.to_vec();
        args.extend(["--dpi", dpi]);
        granflow_ok(&args);
        png_size(&std::fs::read(tables.join(file)).unwrap())
    };
    let commands: [(&[&str], &str); 2] = [
        (&["phase-diagram", t], "phase-density-dissipation.png"),
        (
            &[
                "plot",
                t,
                "--x",
                "density",
                "--y",
                "mean_velocity",
                "--by",
                "dissipation",
            ],
            "plot-mean_velocity-density-by-dissipation.png",
        ),
    ];
    for (cmd, file) in commands {
        let (w, h) = sized(cmd, "96", file);
        assert_eq!(sized(cmd, "192", file), (2 * w, 2 * h), "{cmd:?}");
        // a size asked for is the CSS size
        let mut args = cmd.to_vec();
        args.extend(["--width", "640", "--height", "400", "--dpi", "192"]);
        granflow_ok(&args);
        let png = std::fs::read(tables.join(file)).unwrap();
        assert_eq!(png_size(&png), (1280, 800), "{cmd:?}");
        let svg = std::fs::read_to_string(tables.join(file).with_extension("svg")).unwrap();
        assert!(
            svg.contains("width=\"640\"") && svg.contains("height=\"400\""),
            "{cmd:?}"
        );
    }
    // the report: every inline picture doubles, shown at the same CSS size
    let pictures = |dpi: &str| -> Vec<((u32, u32), (u32, u32))> {
        granflow_ok(&["report", t, "--dpi", dpi]);
        let html = std::fs::read_to_string(tables.join("report.html")).unwrap();
        html.split("<img ")
            .skip(1)
            .map(|tag| {
                let tag = &tag[..tag.find('>').unwrap()];
                let attr = |name: &str| -> String {
                    let at = tag.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
                    tag[at..].split('"').next().unwrap().to_string()
                };
                let data = attr("src");
                let png = base64::engine::general_purpose::STANDARD
                    .decode(data.trim_start_matches("data:image/png;base64,"))
                    .unwrap();
                let css = (
                    attr("width").parse().unwrap(),
                    attr("height").parse().unwrap(),
                );
                (png_size(&png), css)
            })
            .collect()
    };
    let at96 = pictures("96");
    let at192 = pictures("192");
    assert!(
        at96.len() >= 5,
        "the diagram and a figure per job: {at96:?}"
    );
    assert_eq!(at96.len(), at192.len());
    for ((px96, css96), (px192, css192)) in at96.iter().zip(&at192) {
        assert_eq!(px96, css96, "at 96 dpi a pixel is a CSS pixel");
        assert_eq!(css96, css192, "the page shows the same size");
        assert_eq!(*px192, (2 * px96.0, 2 * px96.1));
    }
    // out-of-range values are refused by every command, naming the option
    for cmd in [
        vec!["phase-diagram", t],
        vec!["plot", t, "--x", "density", "--y", "alpha"],
    ]
    .into_iter()
    .chain([vec!["report", t]])
    {
        for bad in [["--dpi", "1000"], ["--width", "10"], ["--height", "90000"]] {
            let mut args = cmd.clone();
            args.extend(bad);
            let out = Command::new(BIN).args(&args).output().unwrap();
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(
                err.contains(bad[0]) && err.contains("allowed"),
                "{args:?}: {err}"
            );
        }
    }
}

/// A curve plot over x = 0.1 .. 10 on a log axis.
fn decade_plot(log_y: bool) -> CurvePlot {
    let points = [0.1, 0.3, 1.0, 3.0, 10.0]
        .iter()
        .map(|&x: &f64| Point {
            x,
            y: 2.0 + x.ln(),
            error: f64::NAN,
            jobs: 1,
            valid: true,
            labels: vec![("steady".into(), 1)],
        })
        .collect();
    CurvePlot {
        x: "knudsen_number".into(),
        y: "flow_rate".into(),
        by: None,
        x_label: "Kn (knudsen_number)".into(),
        y_label: "flow_rate [u_c W]".into(),
        by_symbol: None,
        log_x: true,
        log_y,
        series: vec![Series {
            name: "flow_rate".into(),
            points,
        }],
        not_done: 0,
    }
}

/// The tick labels along the x axis of a plot's SVG: the numeric texts on the lowest row of
/// numbers, left to right.
fn x_tick_labels(svg: &str) -> Vec<(f64, String)> {
    let numeric: Vec<(f64, f64, String)> = svg_texts(svg)
        .into_iter()
        .filter(|(_, _, t)| t.parse::<f64>().is_ok())
        .collect();
    let row = numeric
        .iter()
        .map(|t| t.1)
        .fold(f64::NEG_INFINITY, f64::max);
    let mut ticks: Vec<(f64, String)> = numeric
        .into_iter()
        .filter(|t| (t.1 - row).abs() < 0.5)
        .map(|(x, _, t)| (x, t))
        .collect();
    ticks.sort_by(|a, b| a.0.total_cmp(&b.0));
    ticks
}

/// A log axis from 0.1 to 10 is ticked at exactly 0.1, 0.2, 0.5, 1, 2, 5, 10 (no
/// `0.30000000000000004`, no round-off) when there is room, in the plot as drawn; on a
/// narrow plot it keeps fewer ticks, and their labels never overlap.
#[test]
fn log_ticks_of_a_decade_axis_are_the_expected_labels() {
    let expected = ["0.1", "0.2", "0.5", "1", "2", "5", "10"];
    let ticks_of = |length: f64| -> Vec<String> {
        ticks::log_ticks(0.1, 10.0, length, 13.0, Axis::Horizontal)
            .into_iter()
            .map(ticks::label)
            .collect()
    };
    assert_eq!(ticks_of(700.0), expected);
    // in the plot as drawn (its x range padded by 5 % each way in log x)
    for log_y in [false, true] {
        let svg = decade_plot(log_y).svg(&Sizing::default()).unwrap();
        let labels: Vec<String> = x_tick_labels(&svg).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, expected, "log_y {log_y}");
    }
    // narrow: fewer ticks, apart
    let narrow = Sizing {
        width: Some(300),
        ..Sizing::default()
    };
    let svg = decade_plot(true).svg(&narrow).unwrap();
    let drawn = x_tick_labels(&svg);
    assert!(
        drawn.len() >= 2 && drawn.len() < expected.len(),
        "{drawn:?}"
    );
    for pair in drawn.windows(2) {
        // labels are centred on their ticks (plotters writes the centre as x)
        let half = |t: &str| 0.5 * width(t, 13.0);
        assert!(
            pair[1].0 - half(&pair[1].1) > pair[0].0 + half(&pair[0].1),
            "overlap: {pair:?}"
        );
    }
}

/// The per-job figures of a job are headed by its engine, seed, id and every parameter by
/// symbol with its value, those at their defaults on a line that says so (swept ones never),
/// in the files a job writes.
#[test]
fn per_job_figures_are_headed_by_the_parameters() {
    let dir = scratch("figures-heading");
    let (file, tables) = run_sweep(&dir);
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&dir.join("results"));
    assert_eq!(dirs.tables, tables);
    for job in &sweep.plan {
        let job_dir = dirs.job_dir(&job.id);
        let result = store::read_result(&job_dir).unwrap();
        let records = store::records_so_far(&job_dir).unwrap();
        let figures = job_figures::figures(&job.heading(), &result.analysis, &records);
        assert!(!figures.is_empty());
        // the figure file of the job is the figure drawn with this heading
        assert_eq!(
            std::fs::read(
                job_dir
                    .join("figures")
                    .join(format!("{}.png", figures[0].name))
            )
            .unwrap(),
            figures[0].png(&Sizing::default()).unwrap()
        );
        let svg = figures[0].svg(&Sizing::default()).unwrap();
        let width = figures[0].size(&Sizing::default()).0;
        let lines: Vec<String> = svg_texts(&svg)
            .into_iter()
            .filter(|t| t.1 < f64::from(figures[0].heading.height(width)))
            .map(|t| t.2)
            .collect();
        let heading = lines.join(" ");
        let value = |name: &str| fmt_value(&job.params.values[name]);
        for needle in [
            "lga".to_string(),
            format!("seed {}", job.params.seed),
            job.id.0.clone(),
            format!("L = {}", value("length")),
            format!("W = {}", value("width")),
            format!("rho = {}", value("density")),
            format!("p = {}", value("dissipation")),
            format!("g = {}", value("gravity_probability")),
            format!("b = {}", value("bounce_back")),
        ] {
            assert!(heading.contains(&needle), "no `{needle}` in `{heading}`");
        }
        // b = 0.5 and g = 0.5 are given at their defaults: on the defaults' line
        let defaults = lines
            .iter()
            .position(|l| l.starts_with("at their defaults:"))
            .unwrap_or_else(|| panic!("no line of defaults: {lines:?}"));
        let rest = lines[defaults..].join(" ");
        assert!(
            rest.contains("g = 0.5") && rest.contains("b = 0.5"),
            "{lines:?}"
        );
        assert!(!rest.contains("L = "), "{lines:?}");
        // rho and p are swept ([1.0, 1.2], [0.1, 0.5]): chosen, never "at their
        // defaults" (1 and 0.5 are their defaults)
        assert!(
            !rest.contains("rho = ") && !rest.contains("p = "),
            "{lines:?}"
        );
    }
}

fn cell_job(label: &str, weight: f64) -> CellJob {
    CellJob {
        label: label.into(),
        humps: 0,
        probabilities: vec![(label.into(), 1.0)],
        weight,
        steady: true,
        guard_valid: true,
        three_dimensional: false,
    }
}

/// A cell that pools a plug (e = 0.7) and a homogeneous job (e = 0.9) shows "plug 0.69" as
/// before, now marked, with a legend line in the picture and the text table; a cell whose
/// jobs agree is not marked. The curve plot marks a point averaging different labels.
#[test]
fn a_pooled_cell_with_two_labels_is_marked() {
    let mut cells = BTreeMap::new();
    cells.insert(
        (0, 0),
        Cell {
            jobs: vec![cell_job("plug", 69.0), cell_job("homogeneous", 31.0)],
            not_done: 0,
        },
    );
    cells.insert(
        (1, 0),
        Cell {
            jobs: vec![cell_job("plug", 50.0), cell_job("plug", 50.0)],
            not_done: 0,
        },
    );
    let diagram = PhaseDiagram {
        x: "length_over_width".into(),
        y: None,
        xs: vec![ParamValue::Number(1.0), ParamValue::Number(2.0)],
        ys: vec![ParamValue::Number(0.0)],
        cells,
        x_label: "L/W (length_over_width)".into(),
        y_label: None,
        refined: false,
        frame: Frame::default(),
    };
    let table = diagram.table();
    assert!(table.contains(&format!("plug[0.69]{DISAGREE}")), "{table}");
    assert!(table.contains("plug[1.00]") && !table.contains(&format!("plug[1.00]{DISAGREE}")));
    let legend = table
        .lines()
        .find(|l| l.trim_start().starts_with("length_over_width = 1:"))
        .unwrap_or_else(|| panic!("no legend line for the pooled cell: {table}"));
    assert!(
        legend.contains("plug (1 job)") && legend.contains("homogeneous (1 job)"),
        "{table}"
    );
    assert!(!table.contains("length_over_width = 2:"), "{table}");
    let dir = scratch("figures-pooled");
    let svg_path = dir.join("phase.svg");
    diagram.write_svg(&svg_path).unwrap();
    let texts = svg_texts(&std::fs::read_to_string(&svg_path).unwrap());
    let marks = texts.iter().filter(|t| t.2 == DISAGREE).count();
    assert_eq!(marks, 2, "one marked cell and the legend's mark: {texts:?}");
    assert!(texts.iter().any(|t| t.2 == DISAGREE_LEGEND), "{texts:?}");
    // the mark sits by the pooled cell (x = 1), left of the agreeing one (x = 2)
    let by_cell = texts.iter().find(|t| t.2 == DISAGREE).unwrap();
    let probability = texts.iter().find(|t| t.2 == "0.69").unwrap();
    assert!(
        (by_cell.0 - probability.0).abs() < 40.0,
        "{by_cell:?} {probability:?}"
    );

    // the curve plot: a point averaging two labels is marked, the others not
    let mut plot = decade_plot(false);
    plot.series[0].points[2].labels = vec![("plug".into(), 1), ("homogeneous".into(), 1)];
    plot.series[0].points[2].jobs = 2;
    let table = plot.table();
    assert_eq!(
        table.matches(DISAGREE).count(),
        2,
        "the point and the note: {table}"
    );
    let texts = svg_texts(&plot.svg(&Sizing::default()).unwrap());
    assert_eq!(
        texts.iter().filter(|t| t.2 == DISAGREE).count(),
        2,
        "{texts:?}"
    );
    assert!(
        texts
            .iter()
            .any(|t| t.2 == granflow::sweep::curves::POINT_DISAGREE_LEGEND)
    );
}

/// A lattice-gas run with density waves (L = 220, W = 11, rho = 1.2, p = g = b = 0.5, 655 360
/// steps, a record every 10; about 3 s): its space-time table holds every record of a window at
/// the end of the run, contiguous at the record interval and at least `spacetime_periods` of
/// the peak's periods long, and the picture says which steps it shows.
#[test]
fn lattice_spacetime_rows_of_a_wave_run_are_contiguous() {
    let settings = LatticeSettings::default();
    let mut engine = LgaEngine::new(LgaParams {
        length: 220,
        width: 11,
        density: 1.2,
        dissipation: 0.5,
        gravity: 0.5,
        bounce_back: 0.5,
        seed: 1,
    })
    .unwrap();
    let every = 10;
    let mut records = Vec::new();
    while engine.step() < 655_360 {
        engine.advance_to(engine.step() + every);
        records.push(lattice::record(&engine, &settings));
    }
    let a = lattice::analyse(&records, &settings);
    assert_eq!(a.summary.label, "density waves", "{}", a.summary.note);
    let mut steps: Vec<u64> = a.spacetime.iter().map(|c| c.step).collect();
    steps.dedup();
    assert!(
        steps.windows(2).all(|p| p[1] - p[0] == every),
        "not contiguous at the record interval: {:?}",
        &steps[..steps.len().min(5)]
    );
    assert_eq!(*steps.last().unwrap(), records.last().unwrap().step);
    let span = (steps.last().unwrap() - steps[0]) as f64;
    let period = a.summary.peak_period;
    assert!(
        span + every as f64 >= settings.spacetime_periods * period,
        "{span} steps for periods of {period}"
    );
    assert!(steps.len() <= settings.spacetime_rows);
    // every bin at every row
    assert_eq!(a.spacetime.len(), steps.len() * records[0].bins.len());
    // the picture states its span
    let text = lattice::spacetime_span(&a);
    assert!(
        text.contains(&format!("steps {} .. {}", steps[0], steps.last().unwrap()))
            && text.contains("a record every 10 steps")
            && text.contains("periods of the"),
        "{text}"
    );
    let path = std::env::temp_dir().join("granflow-figures-wave-spacetime.png");
    lattice::plot_spacetime(&a, &path).unwrap();
    println!("{}: {text}", path.display());
}
