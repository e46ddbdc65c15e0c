//! The HTML of a sweep's report: one self-contained page (figures inlined as base64 PNG, the
//! style and a small table-sorting script inline; no network resources at all), so that it can
//! be opened from disk, mailed or archived as one file.

use super::{DiagramView, JobView};
use crate::engine::EngineDef;
use crate::sweep::phase::{fmt_value, point_text, swept_in};
use crate::sweep::store::{self, JobState};
use crate::sweep::{PlannedJob, Sweep, SweepDirs};
use base64::Engine as _;
use std::fmt::Write as _;
use std::path::Path;

/// Escape text for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// The `src`, `width` and `height` of an image: its PNG inline and its size in CSS pixels.
fn picture_attrs(p: &super::Picture) -> String {
    format!(
        "src=\"{}\" width=\"{}\" height=\"{}\"",
        png_url(&p.png),
        p.css.0,
        p.css.1
    )
}

/// A PNG as a `data:` URL.
fn png_url(png: &[u8]) -> String {
    format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    )
}

/// A summary value as table text and its sort key (numbers sort as numbers).
fn value_cell(v: Option<&serde_json::Value>) -> (String, String) {
    match v {
        Some(serde_json::Value::Number(n)) => {
            let x = n.as_f64().unwrap_or(f64::NAN);
            (number(x), format!("{x}"))
        }
        Some(serde_json::Value::Bool(b)) => (if *b { "yes" } else { "no" }.into(), String::new()),
        Some(serde_json::Value::String(s)) => (s.clone(), String::new()),
        _ => (String::new(), String::new()),
    }
}

/// A number for reading: 4 significant digits, integers as integers.
fn number(x: f64) -> String {
    if !x.is_finite() {
        String::new()
    } else if x == x.round() && x.abs() < 1e9 {
        format!("{x}")
    } else if x.abs() >= 1e-3 && x.abs() < 1e5 {
        let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    } else {
        format!("{x:.3e}")
    }
}

const STYLE: &str = "
body { font-family: sans-serif; margin: 1.5em; color: #222; max-width: 1400px; }
h1 { margin-bottom: 0.2em; }
.meta { color: #555; margin-top: 0; }
table { border-collapse: collapse; margin: 0.5em 0; }
th, td { border: 1px solid #ccc; padding: 2px 6px; text-align: left; font-size: 0.9em; }
td.n { text-align: right; font-variant-numeric: tabular-nums; }
table.sortable th { cursor: pointer; background: #f0f0f0; user-select: none; }
table.sortable th[aria-sort=ascending]::after { content: ' \\25B2'; }
table.sortable th[aria-sort=descending]::after { content: ' \\25BC'; }
.state-done { color: #1a7f37; } .state-failed, .state-damaged { color: #c62828; }
.state-running, .state-partial { color: #b26a00; }
section.job { border-top: 2px solid #ddd; margin-top: 2em; }
figure { margin: 1em 0; } figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { color: #444; font-size: 0.9em; max-width: 70em; }
.note { background: #fff8e1; padding: 4px 8px; }
pre { background: #f7f7f7; padding: 6px; overflow-x: auto; }
";

/// Sorts a table by the clicked column (numbers by value, text alphabetically; again: the
/// other way round).
const SORT_SCRIPT: &str = "
(function () {
  function key(row, col) {
    var cell = row.cells[col];
    var v = cell.getAttribute('data-sort');
    return v === null ? cell.textContent.trim() : v;
  }
  var tables = document.querySelectorAll('table.sortable');
  Array.prototype.forEach.call(tables, function (table) {
    var heads = table.tHead.rows[0].cells;
    Array.prototype.forEach.call(heads, function (th, col) {
      th.addEventListener('click', function () {
        var ascending = th.getAttribute('aria-sort') !== 'ascending';
        Array.prototype.forEach.call(heads, function (h) { h.removeAttribute('aria-sort'); });
        th.setAttribute('aria-sort', ascending ? 'ascending' : 'descending');
        var body = table.tBodies[0];
        var rows = Array.prototype.slice.call(body.rows);
        rows.sort(function (a, b) {
          var x = key(a, col), y = key(b, col);
          var nx = parseFloat(x), ny = parseFloat(y);
          var c;
          if (x === '' || y === '') { c = (x === '') - (y === ''); return c; }
          if (!isNaN(nx) && !isNaN(ny)) { c = nx - ny; } else { c = x.localeCompare(y); }
          return ascending ? c : -c;
        });
        rows.forEach(function (r) { body.appendChild(r); });
      });
    });
  });
})();
";

/// The whole page.
pub fn page(
    sweep: &Sweep,
    dirs: &SweepDirs,
    diagram: Option<&DiagramView>,
    views: &[JobView],
    comparisons: &[super::Comparison],
) -> String {
    let engine = sweep.engine();
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <title>granflow report: {}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n",
        escape(&sweep.name)
    );
    let _ = write!(
        h,
        "<h1>{} <small>({})</small></h1>\n<p class=\"meta\">",
        escape(&sweep.name),
        escape(engine.name)
    );
    if let Some(d) = &sweep.spec.description {
        let _ = write!(h, "{}<br>", escape(d));
    }
    let count = |name: &str| {
        views
            .iter()
            .filter(|v| v.gathered.state.name() == name)
            .count()
    };
    let counts: Vec<String> = ["done", "running", "partial", "pending", "failed", "damaged"]
        .iter()
        .map(|n| (n, count(n)))
        .filter(|(_, c)| *c > 0)
        .map(|(n, c)| format!("{c} {n}"))
        .collect();
    let _ = writeln!(
        h,
        "{} jobs: {}. Results in <code>{}</code>. Written {} by granflow {} ({}); \
         run <code>granflow report {}</code> again to bring it up to date. \
         The page needs no network: every figure is inside this file.</p>",
        views.len(),
        counts.join(", "),
        escape(&dirs.tables.display().to_string()),
        escape(&crate::provenance::now()),
        escape(crate::provenance::VERSION),
        escape(crate::provenance::COMMIT),
        escape(&dirs.tables.display().to_string()),
    );
    // the refinement's rounds: the points each level added
    if let Some(r) = &sweep.spec.refine {
        let mut per_level: std::collections::BTreeMap<u32, usize> = Default::default();
        for v in views {
            *per_level.entry(v.gathered.job.level).or_default() += 1;
        }
        let levels: Vec<String> = per_level
            .iter()
            .map(|(l, n)| match l {
                0 => format!("{n} jobs of the base plan"),
                l => format!("{n} at level {l}"),
            })
            .collect();
        let _ = writeln!(
            h,
            "<p id=\"refinement\">Refined along {} ({} levels, budget {} jobs): {} \
             (<code>refinement_level</code> in jobs.parquet; the diagram draws each point in \
             its share and the estimated boundaries with +- half the last interval).</p>",
            escape(&r.axes.join(" x ")),
            r.levels,
            r.budget,
            levels.join(", ")
        );
    }
    // the phase diagram
    h.push_str("<section id=\"diagram\">\n<h2>Phase diagram</h2>\n");
    match diagram {
        Some(d) => {
            let _ = write!(
                h,
                "<img id=\"phase-diagram\" alt=\"phase diagram over {}{}\" {}>\n\
                 <details><summary>as a table</summary><pre>{}</pre></details>\n",
                escape(&d.x),
                d.y.as_ref()
                    .map(|y| format!(" and {}", escape(y)))
                    .unwrap_or_default(),
                picture_attrs(&d.picture),
                escape(&d.table)
            );
        }
        None => h.push_str("<p>Nothing is swept: no diagram.</p>\n"),
    }
    h.push_str("</section>\n");
    if !comparisons.is_empty() {
        h.push_str(
            "<section id=\"statistics\">\n<h2>Statistics across the sweep</h2>\n<p>The \
             thesis' chapter 3 and 4 measures of every job (columns of <code>jobs.parquet</code>; \
             definitions in docs/statistics.md).</p>\n",
        );
        for c in comparisons {
            let _ = writeln!(
                h,
                "<figure id=\"statistics-{}\"><img alt=\"{}\" src=\"{}\"><figcaption>{}</figcaption></figure>",
                escape(&c.name),
                escape(&c.name),
                png_url(&c.png),
                escape(&c.caption)
            );
        }
        h.push_str("</section>\n");
    }
    jobs_table(&mut h, sweep, views);
    for v in views {
        job_section(&mut h, sweep, dirs, v);
    }
    let _ = write!(h, "<script>{SORT_SCRIPT}</script>\n</body>\n</html>\n");
    h
}

fn jobs_table(h: &mut String, sweep: &Sweep, views: &[JobView]) {
    let engine = sweep.engine();
    let swept = swept_in(sweep);
    let seeds = sweep.spec.seeds.len() > 1;
    let keys = crate::registry::analysis_of(engine).key_columns();
    h.push_str(
        "<section id=\"jobs\">\n<h2>Jobs</h2>\n<p>Click a column heading to sort by it. \
         Values of running and partial jobs are from their records so far (in italics).</p>\n\
         <table id=\"job-table\" class=\"sortable\">\n<thead><tr><th>#</th><th>id</th>",
    );
    for name in &swept {
        let symbol = engine.param(name).map_or(*name, |d| d.symbol);
        let _ = write!(h, "<th title=\"{}\">{}</th>", escape(name), escape(symbol));
    }
    if seeds {
        h.push_str("<th>seed</th>");
    }
    h.push_str("<th>state</th><th>progress</th><th>label</th>");
    for (column, heading) in keys {
        // the unit under the heading, as results/README.md documents the column
        let unit = crate::sweep::tables::column_docs::unit_for("jobs", engine.name, column)
            .map_or(String::new(), |u| {
                format!("<br><small>{}</small>", escape(&u))
            });
        let _ = write!(
            h,
            "<th title=\"{}\">{}{unit}</th>",
            escape(column),
            escape(heading)
        );
    }
    h.push_str("<th>wall s</th></tr></thead>\n<tbody>\n");
    for v in views {
        let job = v.gathered.job;
        let state = v.gathered.state.name();
        let _ = write!(
            h,
            "<tr><td class=\"n\">{}</td><td><a href=\"#job-{}\"><code>{}</code></a></td>",
            job.index, job.id.0, job.id.0
        );
        for name in &swept {
            let value = job.params.values.get(*name);
            let text = value.map(fmt_value).unwrap_or_default();
            let sort = value
                .and_then(|v| v.as_f64())
                .map_or(String::new(), |x| format!("{x}"));
            let _ = write!(
                h,
                "<td class=\"n\" data-sort=\"{}\">{}</td>",
                escape(&if sort.is_empty() { text.clone() } else { sort }),
                escape(&text)
            );
        }
        if seeds {
            let _ = write!(h, "<td class=\"n\">{}</td>", job.params.seed);
        }
        let target = job.params.run.length();
        let fraction = v.progress.map(|p| p / target);
        let _ = write!(
            h,
            "<td class=\"state-{state}\">{state}</td><td class=\"n\" data-sort=\"{}\">{}</td>",
            fraction.map_or(String::new(), |f| format!("{f}")),
            fraction.map_or(String::new(), |f| format!("{:.0} %", 100.0 * f))
        );
        let summary = v.analysis.as_ref().map(|a| a.summary()).unwrap_or_default();
        let label = v.label();
        let (open, close) = if v.provisional() {
            ("<i>", "</i>")
        } else {
            ("", "")
        };
        let _ = write!(h, "<td>{open}{}{close}</td>", escape(&label));
        for (column, _) in keys {
            let (text, sort) = value_cell(summary.get(*column));
            let _ = write!(
                h,
                "<td class=\"n\" data-sort=\"{}\">{open}{}{close}</td>",
                escape(&sort),
                escape(&text)
            );
        }
        let wall = v.gathered.result.as_ref().map(|r| r.wall_seconds);
        let _ = writeln!(
            h,
            "<td class=\"n\" data-sort=\"{}\">{}</td></tr>",
            wall.map_or(String::new(), |w| format!("{w}")),
            wall.map_or(String::new(), |w| format!("{w:.1}"))
        );
    }
    h.push_str("</tbody>\n</table>\n</section>\n");
}

/// Analysis settings as a reader writes them in a sweep file: `grid = [12, 12, 12],
/// profile_bins = 25`, unset ones "automatic" (None without settings).
fn settings_text(settings: &serde_json::Value) -> Option<String> {
    let plain = |v: &serde_json::Value| match v {
        serde_json::Value::String(s) => s.clone(),
        // a setting left to the analysis (e.g. the grid, from the box)
        serde_json::Value::Null => "automatic".to_string(),
        other => other.to_string(),
    };
    match settings {
        serde_json::Value::Null => None,
        serde_json::Value::Object(m) if m.is_empty() => None,
        serde_json::Value::Object(m) => Some(
            m.iter()
                .map(|(k, v)| format!("{k} = {}", plain(v)))
                .collect::<Vec<_>>()
                .join(", "),
        ),
        other => Some(plain(other)),
    }
}

/// A two-column table of (name, value) rows.
fn pairs_table(h: &mut String, rows: &[(String, String)]) {
    h.push_str("<table>\n");
    for (k, v) in rows {
        let _ = writeln!(h, "<tr><th>{}</th><td>{}</td></tr>", escape(k), escape(v));
    }
    h.push_str("</table>\n");
}

fn job_section(h: &mut String, sweep: &Sweep, dirs: &SweepDirs, v: &JobView) {
    let dir = dirs.job_dir(&v.gathered.job.id);
    job_heading(h, sweep, &dir, v);
    parameters(h, sweep.engine(), v.gathered.job);
    provenance(h, &dir, v);
    analysis_numbers(h, v);
    job_figures(h, v);
    structure_evolution(h, v);
    h.push_str("</section>\n");
}

/// The job's heading, where it is and how far, and what went wrong.
fn job_heading(h: &mut String, sweep: &Sweep, dir: &Path, v: &JobView) {
    let engine = sweep.engine();
    let job = v.gathered.job;
    let run = &job.params.run;
    let state = &v.gathered.state;
    let point = point_text(engine, &job.params, &swept_in(sweep));
    let label = v.label();
    let _ = write!(
        h,
        "<section class=\"job\" id=\"job-{}\">\n<h2>[{}] {} <span class=\"state-{}\">{}</span> {}</h2>\n",
        job.id.0,
        job.index,
        escape(&point),
        state.name(),
        state.name(),
        escape(&label)
    );
    let progress = v.progress.map_or("-".to_string(), |p| {
        format!(
            "{} / {} {}",
            number(p),
            number(run.length()),
            run.clock().key()
        )
    });
    let _ = writeln!(
        h,
        "<p>Job <code>{}</code> in <code>{}</code>: {progress}, {} snapshot records{}.</p>",
        job.id.0,
        escape(&dir.display().to_string()),
        v.records,
        if v.provisional() {
            "; the analysis below is of the records so far, not a result"
        } else {
            ""
        }
    );
    match state {
        JobState::Failed(e) => {
            let _ = writeln!(h, "<p class=\"note\">Failed:</p><pre>{}</pre>", escape(e));
        }
        JobState::Damaged { reason, .. } => {
            let _ = writeln!(
                h,
                "<p class=\"note\">Damaged (set aside and recomputed by <code>run --retry-failed</code>):</p><pre>{}</pre>",
                escape(reason)
            );
        }
        _ => {}
    }
    for p in &v.problems {
        let _ = writeln!(h, "<p class=\"note\">{}</p>", escape(p));
    }
}

/// The job's parameters, seed, run and analysis settings.
fn parameters(h: &mut String, engine: &EngineDef, job: &PlannedJob) {
    let run = &job.params.run;
    h.push_str("<h3>Parameters</h3>\n");
    let mut rows: Vec<(String, String)> = engine
        .params
        .iter()
        .filter_map(|d| {
            let value = job.params.values.get(d.name)?;
            let unit = match d.unit {
                "1" | "-" | "" => String::new(),
                u => format!(" {u}"),
            };
            Some((
                format!("{} ({})", d.symbol, d.name),
                format!("{}{unit}", fmt_value(value)),
            ))
        })
        .collect();
    rows.push(("seed".into(), job.params.seed.to_string()));
    rows.push((
        "run".into(),
        format!(
            "{} {}, a snapshot every {}{}",
            run.length(),
            run.clock().key(),
            run.snapshot_interval,
            run.until_steady.as_ref().map_or(String::new(), |u| format!(
                ", until steady over {}",
                u.window
            ))
        ),
    ));
    if let Some(settings) = settings_text(&job.params.analysis) {
        rows.push(("analysis settings".into(), settings));
    }
    pairs_table(h, &rows);
}

/// Which build ran the job, where, when and how fast; for a job without a result, when it
/// started and who runs it.
fn provenance(h: &mut String, dir: &Path, v: &JobView) {
    let job = v.gathered.job;
    let state = &v.gathered.state;
    h.push_str("<h3>Provenance</h3>\n");
    let mut rows: Vec<(String, String)> = Vec::new();
    if let Some(r) = &v.gathered.result {
        let p = &r.provenance;
        rows.extend([
            (
                "granflow".to_string(),
                format!("{} ({})", p.granflow, p.commit),
            ),
            (
                "versions".into(),
                format!(
                    "engine {} {}, analysis {}",
                    r.engine, p.engine_version, p.analysis_version
                ),
            ),
            ("host".into(), p.host.clone()),
            ("started".into(), p.started.clone()),
            ("finished".into(), p.finished.clone()),
            (
                "wall time".into(),
                format!(
                    "{:.1} s, {} events/s",
                    r.wall_seconds,
                    number(r.events_per_second)
                ),
            ),
        ]);
        let def = job.params.def();
        if let Some(o) = p.outdated(def.version, crate::registry::analysis_of(def).version()) {
            rows.push((
                "OUTDATED".into(),
                format!("{} (`granflow run --rerun-outdated`)", o.reason),
            ));
        }
        if !r.stop_reason.is_empty() {
            rows.push(("stopped".into(), r.stop_reason.clone()));
        }
    } else {
        rows.push((
            "started".into(),
            store::first_start(dir).unwrap_or_else(|| "not yet".into()),
        ));
        if let Some(holder) = matches!(state, JobState::Running)
            .then(|| store::holder(dir))
            .flatten()
        {
            rows.push(("running on".into(), holder));
        }
    }
    pairs_table(h, &rows);
}

/// The analysis' note and every number of its summary.
fn analysis_numbers(h: &mut String, v: &JobView) {
    if let Some(a) = &v.analysis {
        let summary = a.summary();
        let note = summary
            .get("note")
            .or_else(|| summary.get("steady_reason"))
            .and_then(|n| n.as_str())
            .unwrap_or("");
        if !note.is_empty() {
            let _ = writeln!(h, "<p class=\"note\">{}</p>", escape(note));
        }
        let rows: Vec<(String, String)> = summary
            .iter()
            .map(|(k, v)| (k.clone(), value_cell(Some(v)).0))
            .collect();
        h.push_str("<details><summary>every number of the analysis</summary>\n");
        pairs_table(h, &rows);
        h.push_str("</details>\n");
    }
}

/// The job's figures with their captions.
fn job_figures(h: &mut String, v: &JobView) {
    let job = v.gathered.job;
    if !v.figures.is_empty() {
        h.push_str("<h3>Figures</h3>\n");
        for (f, picture) in &v.figures {
            let _ = writeln!(
                h,
                "<figure id=\"job-{}-{}\"><img alt=\"{}\" {}><figcaption>{}</figcaption></figure>",
                job.id.0,
                f.name,
                escape(f.name),
                picture_attrs(picture),
                escape(&f.caption)
            );
        }
    }
}

/// The structure label's changes along the run (structure analysis).
fn structure_evolution(h: &mut String, v: &JobView) {
    if let Some(crate::analysis::Analysis::Structure(a)) = &v.analysis
        && !a.evolution.is_empty()
    {
        h.push_str(
            "<h3>Structure evolution</h3>\n<p>The label of the first snapshot and every change \
             that held for at least two snapshots.</p>\n<table><tr><th>collisions per particle</th><th>label</th></tr>\n",
        );
        for c in &a.evolution {
            let _ = writeln!(
                h,
                "<tr><td class=\"n\">{}</td><td>{}</td></tr>",
                number(c.collisions_per_particle),
                escape(&crate::analysis::labels::label_key(&c.label, c.humps))
            );
        }
        h.push_str("</table>\n");
    }
}
