//! Table schemas as analyses declare them: named, typed, documented columns and the cells of a
//! row. `sweep::tables` writes them to Parquet; the schema is fixed by the declaration, never by
//! which jobs happen to be done.

/// The type of a column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnKind {
    F64,
    U32,
    U64,
    I64,
    Bool,
    Str,
}

/// One column of a table.
#[derive(Clone, Copy, Debug)]
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
}

/// One value of a row.
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    F64(f64),
    U32(u32),
    U64(u64),
    I64(i64),
    Bool(bool),
    Str(String),
    Null,
}

impl From<f64> for Cell {
    fn from(v: f64) -> Self {
        Cell::F64(v)
    }
}

impl From<u32> for Cell {
    fn from(v: u32) -> Self {
        Cell::U32(v)
    }
}

impl From<u64> for Cell {
    fn from(v: u64) -> Self {
        Cell::U64(v)
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
