//! The unit and meaning of every table column, read from `results/README.md` (compiled in), so
//! that the one document a reader sees is also what each Parquet field carries as its metadata
//! (`unit`, `description`). A test checks that the document covers every column of every table
//! of every engine with its type and a unit.
//!
//! The document's tables are rows `| names | type | unit | meaning |` (several names of one row
//! separated by ", ") under headings `## <table>.parquet ...` (or `### <table>.parquet ...`)
//! and, for engine-specific columns, `### <engine>` or a table heading that names engines in
//! parentheses.

use std::sync::OnceLock;

/// The document, as compiled into this build.
const DOCUMENT: &str = include_str!("../../../results/README.md");

/// One documented column.
#[derive(Clone, Debug, PartialEq)]
pub struct ColumnDoc {
    /// the table (`jobs`, `profiles`, ...)
    pub table: String,
    /// the engines the row is about (empty: every engine)
    pub engines: Vec<String>,
    pub name: String,
    /// the type as written (`f64`, `list<struct<...>>`)
    pub kind: String,
    pub unit: String,
    pub meaning: String,
}

/// Every documented column, in the document's order.
pub fn all() -> &'static [ColumnDoc] {
    static DOCS: OnceLock<Vec<ColumnDoc>> = OnceLock::new();
    DOCS.get_or_init(|| parse(DOCUMENT))
}

/// The unit and meaning of `column` of `table` for `engine`: a row of that table about that
/// engine, else one about every engine, else the column as documented for another table
/// (`job_id`).
pub fn lookup(table: &str, engine: &str, column: &str) -> Option<&'static ColumnDoc> {
    let docs = all();
    let named = |d: &&ColumnDoc| d.name == column;
    docs.iter()
        .filter(named)
        .find(|d| d.table == table && d.engines.iter().any(|e| e == engine))
        .or_else(|| {
            docs.iter()
                .filter(named)
                .find(|d| d.table == table && d.engines.is_empty())
        })
        .or_else(|| docs.iter().find(named))
}

/// The unit of `column` of `table` for `engine` as an axis label shows it: the engine's own
/// part of a unit documented per engine (`sqrt(g d) (edmd); u_c (dsmc)` gives `sqrt(g d)` for
/// edmd), none for pure numbers (`1`) and text (`-`).
pub fn unit_for(table: &str, engine: &str, column: &str) -> Option<String> {
    let unit = lookup(table, engine, column)?.unit.trim();
    let own = format!("({engine})");
    let unit = if unit.contains(';') {
        unit.split(';')
            .map(str::trim)
            .find(|part| part.ends_with(&own))?
    } else {
        unit
    };
    let unit = unit.trim_end_matches(&own).trim();
    match unit {
        "" | "1" | "-" => None,
        unit => Some(unit.to_string()),
    }
}

/// The documented columns of a markdown text (see the module doc).
pub fn parse(text: &str) -> Vec<ColumnDoc> {
    let mut out = Vec::new();
    let (mut table, mut engines) = (String::new(), Vec::<String>::new());
    for line in text.lines() {
        let heading = line
            .strip_prefix("## ")
            .or_else(|| line.strip_prefix("### ").filter(|h| h.contains(".parquet")));
        if let Some(heading) = heading {
            table = heading
                .split(".parquet")
                .next()
                .filter(|_| heading.contains(".parquet"))
                .unwrap_or("")
                .trim()
                .to_string();
            // engines in parentheses right after the table's name: `## profiles.parquet
            // (edmd, dsmc): ...` (not a parenthesis later in the heading: `g(r)`)
            engines = heading
                .split_once(".parquet")
                .and_then(|(_, rest)| rest.trim_start().strip_prefix('('))
                .and_then(|rest| rest.split_once(')'))
                .map(|(inside, _)| inside.split(',').map(|e| e.trim().to_string()).collect())
                .unwrap_or_default();
        } else if let Some(engine) = line.strip_prefix("### ") {
            engines = vec![engine.trim().to_string()];
        } else if line.starts_with("| ")
            && !line.starts_with("| column")
            && !line.starts_with("| ---")
            && !table.is_empty()
        {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let [_, names, kind, unit, meaning, ..] = cells.as_slice() else {
                continue;
            };
            for name in names.split(", ") {
                out.push(ColumnDoc {
                    table: table.clone(),
                    engines: engines.clone(),
                    name: name.trim_matches('`').to_string(),
                    kind: kind.to_string(),
                    unit: unit.to_string(),
                    meaning: meaning.to_string(),
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_take_their_table_and_engines_from_the_headings() {
        let text = "## jobs.parquet: one row per job\n| column | type | unit | meaning |\n| --- | --- | --- | --- |\n| job_id | str | - | the id |\n### lga\n| a, b | f64 | sites | two |\n## profiles.parquet (edmd, dsmc): x\n| value | f64 | 1 | v |\n## Statistics\n### g.parquet: g(r)\n| r | f64 | d | distance |\n";
        let docs = parse(text);
        assert_eq!(docs.len(), 5);
        assert_eq!((docs[4].table.as_str(), docs[4].unit.as_str()), ("g", "d"));
        assert!(docs[4].engines.is_empty());
        assert_eq!(docs[1].name, "a");
        assert_eq!(docs[2].name, "b");
        assert_eq!(docs[2].engines, ["lga"]);
        assert_eq!(docs[2].unit, "sites");
        assert_eq!(docs[3].table, "profiles");
        assert_eq!(docs[3].engines, ["edmd", "dsmc"]);
        assert!(docs[0].engines.is_empty());
    }

    #[test]
    fn the_compiled_document_is_parsed() {
        let id = lookup("spectra", "edmd", "job_id").expect("job_id documented");
        assert_eq!(id.kind, "str");
        let mean = lookup("jobs", "lga", "mean_velocity").unwrap();
        assert_eq!(mean.unit, "sites per step (lga)");
        let dsmc = lookup("jobs", "dsmc", "mean_velocity").unwrap();
        assert_eq!(dsmc.unit, "u_c");
    }

    #[test]
    fn axis_units_take_the_engines_own_part() {
        assert_eq!(
            unit_for("jobs", "edmd", "slip_velocity").as_deref(),
            Some("sqrt(g d)")
        );
        assert_eq!(
            unit_for("jobs", "dsmc", "slip_velocity").as_deref(),
            Some("u_c")
        );
        assert_eq!(
            unit_for("jobs", "lga", "mean_velocity").as_deref(),
            Some("sites per step")
        );
        assert_eq!(unit_for("jobs", "edmd", "restitution"), None);
        assert_eq!(unit_for("jobs", "edmd", "label"), None);
        assert_eq!(unit_for("jobs", "edmd", "no_such_column"), None);
    }
}
