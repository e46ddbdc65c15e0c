//! Table schemas as analyses declare them: named, typed, documented columns and the cells of a
//! row. `sweep::tables` writes them to Parquet; the schema is fixed by the declaration, never by
//! which jobs happen to be done.

/// The type of a column. Integers are signed 64-bit (whatever the Rust field: counts, indices
/// and wave numbers subtract and multiply without surprises in every reader); floats are f64
/// with NaN written as null; text is UTF-8.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ColumnKind {
    F64,
    I64,
    Bool,
    Str,
    /// a list of structs with these fields (each of a scalar kind)
    List(&'static [ColumnDef]),
}

impl ColumnKind {
    /// The type as `results/README.md` writes it: `f64`, `i64`, `bool`, `str`, or
    /// `list<struct<name: type, ...>>`.
    pub fn doc_name(self) -> String {
        match self {
            ColumnKind::F64 => "f64".into(),
            ColumnKind::I64 => "i64".into(),
            ColumnKind::Bool => "bool".into(),
            ColumnKind::Str => "str".into(),
            ColumnKind::List(fields) => format!(
                "list<struct<{}>>",
                fields
                    .iter()
                    .map(|f| format!("{}: {}", f.name, f.kind.doc_name()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }
}

/// One column of a table (or one field of a list column's structs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnDef {
    pub name: &'static str,
    pub kind: ColumnKind,
    pub doc: &'static str,
}

/// A table an analysis writes one block of rows into per job (after a `job_id` column).
#[derive(Clone, Copy, Debug)]
pub struct TableDef {
    /// file stem: `<name>.parquet`
    pub name: &'static str,
    pub columns: &'static [ColumnDef],
    /// units of columns, written into the Parquet field metadata as `unit` (column name,
    /// unit; columns not listed carry no field metadata)
    pub units: &'static [(&'static str, &'static str)],
}

/// One value of a row.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    F64(f64),
    I64(i64),
    Bool(bool),
    Str(String),
    /// the structs of a list column, each as its fields' cells in declared order
    List(Vec<Vec<Cell>>),
    Null,
}

impl From<f64> for Cell {
    fn from(v: f64) -> Self {
        Cell::F64(v)
    }
}

impl From<i64> for Cell {
    fn from(v: i64) -> Self {
        Cell::I64(v)
    }
}

impl From<u32> for Cell {
    fn from(v: u32) -> Self {
        Cell::I64(i64::from(v))
    }
}

impl From<u64> for Cell {
    /// Null above `i64::MAX` (no count gets there).
    fn from(v: u64) -> Self {
        i64::try_from(v).map_or(Cell::Null, Cell::I64)
    }
}

impl From<usize> for Cell {
    fn from(v: usize) -> Self {
        i64::try_from(v).map_or(Cell::Null, Cell::I64)
    }
}

impl From<bool> for Cell {
    fn from(v: bool) -> Self {
        Cell::Bool(v)
    }
}

impl From<&str> for Cell {
    fn from(v: &str) -> Self {
        Cell::Str(v.to_string())
    }
}

impl From<String> for Cell {
    fn from(v: String) -> Self {
        Cell::Str(v)
    }
}

impl<T: Into<Cell>> From<Option<T>> for Cell {
    fn from(v: Option<T>) -> Self {
        v.map_or(Cell::Null, Into::into)
    }
}
