//! `granflow report`: the HTML report of a sweep that is still running (three jobs done, one
//! held by a runner), checked as a file (self-contained, every job and figure in it, the figure
//! files of done jobs on disk) and in a real browser: headless Chromium (Debian's `chromium`,
//! installed by `.ci/run`) loads it without errors or network requests, the table sorts, and a
//! screenshot shows the phase diagram with the markers of its labels.

use crate::common::{BIN, granflow_ok, scratch};
use granflow::job_figures;
use granflow::sweep::execute::{self, JobEnd};
use granflow::sweep::phase::{PhaseDiagram, marker_colour};
use granflow::sweep::{load_sweep, store, tables};
use std::path::{Path, PathBuf};
use std::process::Command;

const CHROMIUM: &str = "/usr/bin/chromium";

const SWEEP: &str = r#"(
    name: "tiny",
    engine: "edmd",
    fixed: (width_over_diameter: 6.0, height_over_diameter: 6.0, volume_fraction: 0.15),
    axes: (length_over_width: [1.0, 2.0], restitution: [0.7, 0.9]),
    run: (collisions_per_particle: 1500.0, snapshot_interval: 100.0, checkpoint_every: 1),
    analysis: (profile_bins: 12),
)"#;

/// Chromium without anything that reaches out (no sync, updates, background networking, QUIC)
/// and with a profile of its own.
fn chromium(profile: &Path) -> Command {
    assert!(
        Path::new(CHROMIUM).exists(),
        "{CHROMIUM} is missing: the report test needs Debian's chromium \
         (apt-get install chromium; .ci/run installs it)"
    );
    let mut c = Command::new(CHROMIUM);
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        "--force-device-scale-factor=1",
        "--window-size=1400,1000",
        "--virtual-time-budget=3000",
        "--enable-logging=stderr",
        "--v=0",
    ])
    .arg(format!("--user-data-dir={}", profile.display()));
    c
}

/// Records errors (uncaught exceptions, failed loads, console.error) before any other script
/// of the page runs.
const HOOK: &str = "<script>window.__errors = [];
window.addEventListener('error', function (e) {
  window.__errors.push(String(e.message || (e.target && (e.target.src || e.target.tagName))));
}, true);
var __consoleError = console.error;
console.error = function () {
  window.__errors.push(Array.prototype.join.call(arguments, ' '));
  __consoleError.apply(console, arguments);
};</script>";

/// After load: the errors, whether every image decoded, any resource fetched other than the
/// page itself, the job table's first column after sorting it up and down, and where the
/// diagram is; written into the page as JSON.
const CHECK: &str = "<script>window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var table = document.getElementById('job-table');
  var head = table.tHead.rows[0].cells[0];
  function firstColumn() {
    return Array.prototype.map.call(table.tBodies[0].rows, function (r) {
      return parseInt(r.cells[0].textContent, 10);
    });
  }
  head.click();
  var up = firstColumn();
  head.click();
  var down = firstColumn();
  var d = document.getElementById('phase-diagram');
  var r = d.getBoundingClientRect();
  var out = {
    errors: window.__errors,
    images: images.length,
    broken: images.filter(function (i) { return !(i.complete && i.naturalWidth > 0); }).length,
    fetched: performance.getEntriesByType('resource').map(function (e) { return e.name; })
      .filter(function (n) { return n.indexOf('data:') !== 0; }),
    up: up,
    down: down,
    diagram: [r.left, r.top, r.width, r.height, d.naturalWidth, d.naturalHeight]
  };
  var pre = document.createElement('pre');
  pre.id = 'report-check';
  pre.textContent = JSON.stringify(out);
  document.body.appendChild(pre);
});</script>";

/// Decode a PNG into (width, height, RGB bytes).
fn decode_png(path: &Path) -> (usize, usize, Vec<u8>) {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let mut reader = png::Decoder::new(file).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let channels = info.color_type.samples();
    let (w, h) = (info.width as usize, info.height as usize);
    let mut rgb = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        let row = &buf[y * info.line_size..];
        for x in 0..w {
            rgb.extend_from_slice(&row[x * channels..x * channels + 3]);
        }
    }
    (w, h, rgb)
}

#[test]
fn report_of_a_running_sweep_loads_in_a_browser_and_shows_the_diagram() {
    let dir = scratch("report");
    let file = dir.join("tiny.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let results = dir.join("results");
    granflow_ok(&[
        "run",
        file.to_str().unwrap(),
        "--results",
        results.to_str().unwrap(),
        "--job-range",
        "0:3",
    ]);

    // the fourth job runs: claimed (as a live runner holds it) and stopped after 5 snapshots
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&results);
    let running = &sweep.plan[3];
    let running_dir = dirs.job_dir(&running.id);
    store::init_job_dir(&running_dir, running).unwrap();
    let claim = store::try_claim(&running_dir, false).unwrap().unwrap();
    match execute::run_job(
        running,
        &claim,
        Some(execute::StopAfter::Snapshot(5)),
        &mut |_| {},
    )
    .unwrap()
    {
        JobEnd::Stopped => {}
        other => panic!("the job ended early: {other:?}"),
    }

    let stdout = granflow_ok(&["report", dirs.tables.to_str().unwrap()]);
    let report: PathBuf = dirs.tables.join("report.html");
    assert!(
        stdout.contains(&format!("report: {}", report.display())),
        "{stdout}"
    );
    let html = std::fs::read_to_string(&report).unwrap();

    // self-contained: every image inline, no external script, style sheet or link
    assert!(html.starts_with("<!DOCTYPE html>"));
    for (i, _) in html.match_indices("src=\"") {
        assert!(
            html[i + 5..].starts_with("data:image/png;base64,"),
            "an image that is not inline: {}",
            &html[i..(i + 60).min(html.len())]
        );
    }
    for forbidden in [
        "<link",
        "@import",
        "url(",
        "href=\"http",
        "src=\"http",
        "<iframe",
    ] {
        assert!(!html.contains(forbidden), "the report holds {forbidden}");
    }
    // the diagram, the table, and every job with its state and figures
    assert!(html.contains("<img id=\"phase-diagram\""));
    assert!(html.contains("<table id=\"job-table\" class=\"sortable\">"));
    let figures = ["energy", "profiles", "spectra", "density", "labels"];
    for (k, job) in sweep.plan.iter().enumerate() {
        let section = format!("<section class=\"job\" id=\"job-{}\">", job.id.0);
        assert!(html.contains(&section), "job {k} has no section");
        let state = if k < 3 { "done" } else { "running" };
        assert!(
            html.contains(&format!(
                "<tr><td class=\"n\">{k}</td><td><a href=\"#job-{}\"><code>{}</code></a></td>",
                job.id.0, job.id.0
            )),
            "job {k} has no row"
        );
        let row_start = html.find(&format!("#job-{}\"", job.id.0)).unwrap();
        let row = &html[row_start..row_start + html[row_start..].find("</tr>").unwrap()];
        assert!(
            row.contains(&format!("<td class=\"state-{state}\">{state}</td>")),
            "job {k}: {row}"
        );
        for f in figures {
            assert!(
                html.contains(&format!("<figure id=\"job-{}-{f}\">", job.id.0)),
                "job {k} lacks its {f} figure"
            );
            // done jobs have their figure files; a running job's directory is left alone
            let on_disk = dirs
                .job_dir(&job.id)
                .join("figures")
                .join(format!("{f}.png"));
            assert_eq!(on_disk.exists(), k < 3, "job {k}: {}", on_disk.display());
            if k < 3 {
                let svg = on_disk.with_extension("svg");
                assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
            }
        }
    }
    assert!(html.contains("the analysis below is of the records so far, not a result"));
    // The table's headings carry their units; the analysis settings read as a sweep
    // file writes them, not as escaped JSON
    for heading in [
        "u_slip<br><small>sqrt(g d)</small>",
        "E_tr/N<br><small>m g d</small>",
        "window from<br><small>collisions per particle</small>",
    ] {
        assert!(html.contains(heading), "no heading {heading}");
    }
    let settings = html
        .split("analysis settings</th><td>")
        .nth(1)
        .and_then(|rest| rest.split("</td>").next())
        .expect("analysis settings");
    assert!(settings.contains("profile_bins = 12"), "{settings}");
    assert!(!settings.contains("null"), "{settings}");
    assert!(
        !html.contains("&quot;profile_bins"),
        "analysis settings as JSON"
    );
    // the files are exactly what the job module draws from the stored result and records
    let done_dir = dirs.job_dir(&sweep.plan[0].id);
    let result = store::read_result(&done_dir).unwrap();
    let records = store::records_so_far(&done_dir).unwrap();
    let drawn = job_figures::figures(&sweep.plan[0].heading(), &result.analysis, &records);
    assert_eq!(
        drawn.iter().map(|f| f.name).collect::<Vec<_>>(),
        figures.to_vec()
    );
    assert_eq!(
        std::fs::read(done_dir.join("figures/energy.png")).unwrap(),
        drawn[0].png(&granflow::figure::Sizing::default()).unwrap()
    );

    // the markers the diagram must show: the labels of its cells
    let labels = cell_labels(&sweep, &dirs);
    assert_eq!(labels.len(), 3, "three cells with done jobs: {labels:?}");
    drop(claim);

    // in the browser, with hooks that record errors and a check run after load
    let probe = dir.join("probe.html");
    let hooked = html
        .replacen("<head>", &format!("<head>\n{HOOK}"), 1)
        .replacen("</body>", &format!("{CHECK}\n</body>"), 1);
    std::fs::write(&probe, hooked).unwrap();
    let out = chromium(&dir.join("profile-dom"))
        .arg("--dump-dom")
        .arg(format!("file://{}", probe.display()))
        .output()
        .unwrap();
    let dom = String::from_utf8_lossy(&out.stdout);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "chromium failed: {log}");
    assert!(!log.contains("Uncaught"), "errors in the console: {log}");
    let start = dom
        .find("<pre id=\"report-check\">")
        .unwrap_or_else(|| panic!("the check did not run; console: {log}"))
        + "<pre id=\"report-check\">".len();
    let end = start + dom[start..].find("</pre>").unwrap();
    let json = dom[start..end]
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    let check: serde_json::Value = serde_json::from_str(&json).unwrap();
    eprintln!("browser check: {check}");
    assert_eq!(check["errors"], serde_json::json!([]), "errors: {check}");
    assert_eq!(check["broken"], 0, "images that did not decode: {check}");
    // diagram + 5 figures of each of 4 jobs
    assert_eq!(check["images"], 1 + 5 * 4);
    assert_eq!(check["fetched"], serde_json::json!([]), "network: {check}");
    assert_eq!(check["up"], serde_json::json!([0, 1, 2, 3]));
    assert_eq!(check["down"], serde_json::json!([3, 2, 1, 0]));
    let rect: Vec<f64> = check["diagram"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    // drawn at its own size, inside the first screen
    assert_eq!(
        (rect[2], rect[3]),
        (rect[4], rect[5]),
        "the diagram is scaled"
    );
    assert!(
        rect[1] + rect[3] <= 1000.0,
        "the diagram is below the first screen"
    );

    // the screenshot of the report itself shows the diagram: its frame and every marker
    let shot = dir.join("shot.png");
    let out = chromium(&dir.join("profile-shot"))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(format!("file://{}", report.display()))
        .output()
        .unwrap();
    assert!(
        out.status.success() && shot.exists(),
        "no screenshot: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (w, h, rgb) = decode_png(&shot);
    assert_eq!((w, h), (1400, 1000));
    // pixels of one colour where the page put the diagram
    let count = |colour: (u8, u8, u8)| {
        let (x0, y0) = (rect[0] as usize, rect[1] as usize);
        let (x1, y1) = (
            (x0 + rect[2] as usize).min(w),
            (y0 + rect[3] as usize).min(h),
        );
        (y0..y1)
            .flat_map(|y| (x0..x1).map(move |x| 3 * (y * w + x)))
            .filter(|&i| (rgb[i], rgb[i + 1], rgb[i + 2]) == colour)
            .count()
    };
    assert!(count((0, 0, 0)) > 400, "no frame where the diagram is");
    for label in &labels {
        let c = marker_colour(label);
        let n = count((c.0, c.1, c.2));
        assert!(
            n >= 20,
            "the {label} marker is not in the screenshot ({n} pixels)"
        );
    }
    let _ = std::fs::remove_dir_all(dir.join("profile-dom"));
    let _ = std::fs::remove_dir_all(dir.join("profile-shot"));
}

/// PNG width and height from its header.
/// The labels of the cells of the sweep's L/W x e diagram that hold a done job.
fn cell_labels(sweep: &granflow::sweep::Sweep, dirs: &granflow::sweep::SweepDirs) -> Vec<String> {
    let gathered = tables::collect(sweep, dirs);
    let diagram = PhaseDiagram::build(
        sweep.engine(),
        &gathered,
        "length_over_width",
        Some("restitution"),
    )
    .unwrap();
    diagram
        .cells
        .values()
        .filter_map(|c| c.verdict().map(|v| v.label))
        .collect()
}

fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn phase_diagram_has_symbols_a_title_a_full_legend_and_a_size() {
    let dir = scratch("report-phase");
    let file = dir.join("tiny.ron");
    std::fs::write(&file, SWEEP).unwrap();
    let results = dir.join("results");
    let granflow = |args: &[&str]| Command::new(BIN).args(args).output().unwrap();
    let (f, r) = (file.to_str().unwrap(), results.to_str().unwrap());
    granflow_ok(&["run", f, "--results", r, "--job-range", "0:3"]);
    let tables = results.join("tiny");
    let t = tables.to_str().unwrap();
    let text = granflow_ok(&[
        "phase-diagram",
        t,
        "--width",
        "900",
        "--height",
        "520",
        "--dpi",
        "192",
    ]);
    // the printed table stays as it was: rows e, columns L/W
    assert!(
        text.lines()
            .any(|l| l.starts_with("restitution \\ length_over_width")),
        "{text}"
    );
    let png = tables.join("phase-length_over_width-restitution.png");
    let svg = tables.join("phase-length_over_width-restitution.svg");
    // 192 dpi: twice the CSS size each way; the SVG keeps the CSS size
    assert_eq!(png_size(&png), (1800, 1040));
    let svg = std::fs::read_to_string(&svg).unwrap();
    assert!(svg.contains("width=\"900\"") && svg.contains("height=\"520\""));
    // the texts of the picture
    let texts: Vec<String> = svg
        .split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = &t[t.find('>')? + 1..t.find("</text>")?];
            Some(body.trim().replace("&amp;", "&"))
        })
        .collect();
    let has = |needle: &str| texts.iter().any(|t| t.contains(needle));
    for expected in [
        "L/W (length_over_width)",
        "e (restitution)",
        "tiny (edmd): 4 jobs, 1500 collisions per particle per job",
        "fixed: W/d = 6, H/d = 6, phi = 0.15",
        "share of snapshots with the label",
        "no job done yet",
    ] {
        assert!(has(expected), "the diagram lacks `{expected}`: {texts:?}");
    }
    // every label in a cell has its legend entry
    let sweep = load_sweep(&file, &[]).unwrap();
    let dirs = sweep.results_dir(&results);
    for label in cell_labels(&sweep, &dirs) {
        assert!(texts.contains(&label), "no legend for {label}: {texts:?}");
    }
    // bad sizes and an axis the sweep does not vary are refused (exit code 2)
    for bad in [
        vec!["--dpi", "1000"],
        vec!["--width", "10"],
        vec!["--height", "90000"],
        vec!["--x", "volume_fraction"],
        vec!["--x", "length_over_width", "--y", "roughness"],
    ] {
        let mut args = vec!["phase-diagram", t];
        args.extend(&bad);
        let out = granflow(&args);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains(bad[0]) || err.contains(bad[bad.len() - 1]),
            "{bad:?}: {err}"
        );
    }
}
