//! One table to one Parquet file: typed columns filled cell by cell (NaN and cells of another
//! type become null), their Arrow arrays and the file, written through polars' Arrow and
//! Parquet crates with zstd, the table's metadata (provenance) both as Parquet key-value
//! metadata and as the Arrow schema's metadata, and each field's `unit` and `description` as
//! field metadata.
//!
//! Not through polars' `DataFrame` writer: that one always writes strings as Arrow
//! `string_view`, which pyarrow < 15 cannot read, and lists of structs would need polars'
//! `dtype-struct` feature. The Arrow types here are the plain ones every reader knows:
//! `double`, `int64`, `bool`, `string` (UTF-8) and `list<struct<...>>`.

use crate::analysis::columns::{Cell, ColumnDef, ColumnKind};
use polars_arrow::array::{Array, BooleanArray, ListArray, PrimitiveArray, StructArray, Utf8Array};
use polars_arrow::bitmap::Bitmap;
use polars_arrow::datatypes::{ArrowDataType, ArrowSchema, Field};
use polars_arrow::offset::Offsets;
use polars_arrow::record_batch::RecordBatchT;
use polars_parquet::write::{
    CompressionOptions, FileWriter, KeyValue, RowGroupIterator, StatisticsOptions, Version,
    WriteOptions, get_dtype_encoding,
};
use std::path::Path;
use std::sync::Arc;

/// Rows per row group (polars' default).
const ROW_GROUP_ROWS: usize = 512 * 512;

/// A named, typed column being filled.
pub struct Column {
    name: String,
    kind: ColumnKind,
    values: Values,
}

impl Column {
    pub fn new(name: impl Into<String>, kind: ColumnKind) -> Self {
        Column {
            name: name.into(),
            kind,
            values: Values::new(kind),
        }
    }

    /// A column of `kind` with these cells.
    pub fn from_cells(
        name: impl Into<String>,
        kind: ColumnKind,
        cells: impl IntoIterator<Item = Cell>,
    ) -> Self {
        let mut column = Column::new(name, kind);
        for cell in cells {
            column.push(cell);
        }
        column
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    pub fn kind(&self) -> ColumnKind {
        self.kind
    }

    /// Append a cell (NaN, and a cell of another type, as null).
    pub fn push(&mut self, cell: Cell) {
        self.values.push(cell);
    }

    fn len(&self) -> usize {
        self.values.len()
    }
}

/// The cells of a column, by type.
enum Values {
    F64(Vec<Option<f64>>),
    I64(Vec<Option<i64>>),
    Bool(Vec<Option<bool>>),
    Str(Vec<Option<String>>),
    /// per row: the number of structs (None: null); the structs' fields as columns
    List {
        fields: &'static [ColumnDef],
        lengths: Vec<Option<usize>>,
        children: Vec<Values>,
    },
}

impl Values {
    fn new(kind: ColumnKind) -> Self {
        match kind {
            ColumnKind::F64 => Values::F64(Vec::new()),
            ColumnKind::I64 => Values::I64(Vec::new()),
            ColumnKind::Bool => Values::Bool(Vec::new()),
            ColumnKind::Str => Values::Str(Vec::new()),
            ColumnKind::List(fields) => Values::List {
                fields,
                lengths: Vec::new(),
                children: fields.iter().map(|f| Values::new(f.kind)).collect(),
            },
        }
    }

    fn len(&self) -> usize {
        match self {
            Values::F64(v) => v.len(),
            Values::I64(v) => v.len(),
            Values::Bool(v) => v.len(),
            Values::Str(v) => v.len(),
            Values::List { lengths, .. } => lengths.len(),
        }
    }

    fn push(&mut self, cell: Cell) {
        match (self, cell) {
            (Values::F64(v), Cell::F64(x)) => v.push((!x.is_nan()).then_some(x)),
            (Values::F64(v), Cell::I64(x)) => v.push(Some(x as f64)),
            (Values::I64(v), Cell::I64(x)) => v.push(Some(x)),
            (Values::Bool(v), Cell::Bool(x)) => v.push(Some(x)),
            (Values::Str(v), Cell::Str(x)) => v.push(Some(x)),
            (
                Values::List {
                    lengths, children, ..
                },
                Cell::List(structs),
            ) => {
                lengths.push(Some(structs.len()));
                for fields in structs {
                    let mut cells = fields.into_iter();
                    for child in children.iter_mut() {
                        child.push(cells.next().unwrap_or(Cell::Null));
                    }
                }
            }
            (values, cell) => {
                debug_assert!(cell == Cell::Null, "a {cell:?} in a column of another type");
                values.push_null();
            }
        }
    }

    fn push_null(&mut self) {
        match self {
            Values::F64(v) => v.push(None),
            Values::I64(v) => v.push(None),
            Values::Bool(v) => v.push(None),
            Values::Str(v) => v.push(None),
            Values::List { lengths, .. } => lengths.push(None),
        }
    }

    fn into_array(self) -> anyhow::Result<Box<dyn Array>> {
        Ok(match self {
            Values::F64(v) => v.into_iter().collect::<PrimitiveArray<f64>>().boxed(),
            Values::I64(v) => v.into_iter().collect::<PrimitiveArray<i64>>().boxed(),
            Values::Bool(v) => v.into_iter().collect::<BooleanArray>().boxed(),
            Values::Str(v) => v.into_iter().collect::<Utf8Array<i64>>().boxed(),
            Values::List {
                fields,
                lengths,
                children,
            } => {
                let structs = children.first().map_or(0, Values::len);
                let children = children
                    .into_iter()
                    .map(Values::into_array)
                    .collect::<anyhow::Result<Vec<_>>>()?;
                let structs =
                    StructArray::try_new(struct_type(fields), structs, children, None)?.boxed();
                let validity: Bitmap = lengths.iter().map(Option::is_some).collect();
                let offsets =
                    Offsets::<i32>::try_from_lengths(lengths.iter().map(|n| n.unwrap_or(0)))?;
                ListArray::<i32>::try_new(
                    arrow_type(ColumnKind::List(fields)),
                    offsets.into(),
                    structs,
                    Some(validity),
                )?
                .boxed()
            }
        })
    }
}

/// The Arrow type of a column kind (every column and field nullable).
fn arrow_type(kind: ColumnKind) -> ArrowDataType {
    match kind {
        ColumnKind::F64 => ArrowDataType::Float64,
        ColumnKind::I64 => ArrowDataType::Int64,
        ColumnKind::Bool => ArrowDataType::Boolean,
        ColumnKind::Str => ArrowDataType::LargeUtf8,
        ColumnKind::List(fields) => ArrowDataType::List(Box::new(Field::new(
            "item".into(),
            struct_type(fields),
            true,
        ))),
    }
}

fn struct_type(fields: &[ColumnDef]) -> ArrowDataType {
    ArrowDataType::Struct(
        fields
            .iter()
            .map(|f| Field::new(f.name.into(), arrow_type(f.kind), true))
            .collect(),
    )
}

/// The type readers are told (the Arrow schema in the file's metadata): `string` where the
/// arrays are `large_string`, which polars' writer needs (Parquet stores both alike). `string`
/// is what pyarrow and pandas make themselves, so their tables join ours without casts.
fn read_type(dtype: &ArrowDataType) -> ArrowDataType {
    let field = |f: &Field| Field::new(f.name.clone(), read_type(&f.dtype), f.is_nullable);
    match dtype {
        ArrowDataType::LargeUtf8 => ArrowDataType::Utf8,
        ArrowDataType::List(item) => ArrowDataType::List(Box::new(field(item))),
        ArrowDataType::Struct(fields) => ArrowDataType::Struct(fields.iter().map(field).collect()),
        other => other.clone(),
    }
}

/// A column's unit and description, for its field metadata.
pub struct FieldDoc {
    pub unit: String,
    pub description: String,
}

/// Write the columns (of equal length) as a Parquet file, zstd-compressed, with the Arrow
/// schema and `metadata` as its key-value metadata and each column's [`FieldDoc`] (from
/// `describe`, by column name) as its field metadata; synced to disk.
pub fn write(
    path: &Path,
    columns: Vec<Column>,
    metadata: &[(String, String)],
    describe: &dyn Fn(&str) -> Option<FieldDoc>,
) -> anyhow::Result<()> {
    let rows = columns.first().map_or(0, Column::len);
    anyhow::ensure!(
        columns.iter().all(|c| c.len() == rows),
        "{}: columns of unequal length",
        path.display()
    );
    let field_metadata = |name: &str| {
        describe(name).map(|doc| {
            [
                ("unit".into(), doc.unit.into()),
                ("description".into(), doc.description.into()),
            ]
            .into_iter()
            .collect::<polars_arrow::datatypes::Metadata>()
        })
    };
    let schema: ArrowSchema = columns
        .iter()
        .map(|c| {
            let field = Field::new(c.name.as_str().into(), arrow_type(c.kind), true);
            match field_metadata(&c.name) {
                Some(m) => field.with_metadata(m),
                None => field,
            }
        })
        .collect();
    anyhow::ensure!(
        schema.len() == columns.len(),
        "{}: two columns of one name",
        path.display()
    );
    let schema = Arc::new(schema);
    let arrays = columns
        .into_iter()
        .map(|c| c.values.into_array())
        .collect::<anyhow::Result<Vec<_>>>()?;
    let options = WriteOptions {
        statistics: StatisticsOptions::default(),
        version: Version::V1,
        compression: CompressionOptions::Zstd(None),
        data_page_size: None,
    };
    let encodings = schema
        .iter_values()
        .map(|f| get_dtype_encoding(&f.dtype))
        .collect();
    let batches = (0..rows).step_by(ROW_GROUP_ROWS).map(|start| {
        let n = ROW_GROUP_ROWS.min(rows - start);
        let slices = arrays.iter().map(|a| a.sliced(start, n)).collect();
        RecordBatchT::try_new(n, schema.clone(), slices)
    });
    let groups = RowGroupIterator::try_new(batches, &schema, options, encodings)?;
    // encoded in memory, then written: the file system's errors (a full disk) then reach the
    // caller as themselves, with the path, not as a Parquet encoder's "transport error"
    let mut bytes = Vec::new();
    let mut writer = FileWriter::try_new(&mut bytes, (*schema).clone(), options)?;
    for (start, group) in (0..rows).step_by(ROW_GROUP_ROWS).zip(groups) {
        writer.write(ROW_GROUP_ROWS.min(rows - start) as u64, group?)?;
    }
    let read_as: ArrowSchema = schema
        .iter_values()
        .map(|f| Field {
            metadata: f.metadata.clone(),
            ..Field::new(f.name.clone(), read_type(&f.dtype), true)
        })
        .collect();
    let mut key_values = vec![arrow_schema_key(&read_as, metadata)];
    key_values.extend(metadata.iter().map(|(key, value)| KeyValue {
        key: key.clone(),
        value: Some(value.clone()),
    }));
    writer.end(Some(key_values))?;
    drop(writer);
    let written = std::fs::File::create(path).and_then(|mut file| {
        std::io::Write::write_all(&mut file, &bytes)?;
        file.sync_all()
    });
    written.map_err(|e| crate::sweep::fs_error::PathError::new(path, e))?;
    Ok(())
}

/// The `ARROW:schema` key-value of a Parquet file: the Arrow schema (IPC, base64) that Arrow
/// readers take the file's schema from, with `metadata` as the schema's own metadata, where
/// `pyarrow.parquet.read_schema(p).metadata`, `read_table(p).schema.metadata` and polars'
/// readers find it (the Parquet key-value metadata alone is seen only by Parquet-level
/// readers). As polars-parquet's `schema_to_metadata_key`, which has no schema metadata.
fn arrow_schema_key(schema: &ArrowSchema, metadata: &[(String, String)]) -> KeyValue {
    use base64::Engine as _;
    use polars_arrow::io::ipc::write::{default_ipc_fields, schema_to_bytes};
    let custom: polars_arrow::datatypes::Metadata = metadata
        .iter()
        .map(|(k, v)| (k.as_str().into(), v.as_str().into()))
        .collect();
    let ipc = schema_to_bytes(
        schema,
        &default_ipc_fields(schema.iter_values()),
        Some(&custom),
    );
    // the legacy IPC framing Arrow readers expect: continuation marker, length, message
    let mut framed = Vec::with_capacity(ipc.len() + 8);
    framed.extend_from_slice(&[255u8, 255, 255, 255]);
    framed.extend_from_slice(&(ipc.len() as u32).to_le_bytes());
    framed.extend_from_slice(&ipc);
    KeyValue {
        key: "ARROW:schema".into(),
        value: Some(base64::engine::general_purpose::STANDARD.encode(&framed)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use polars::prelude::{ParquetReader, SerReader};

    const MODE: &[ColumnDef] = &[
        ColumnDef {
            name: "k",
            kind: ColumnKind::I64,
            doc: "",
        },
        ColumnDef {
            name: "p",
            kind: ColumnKind::F64,
            doc: "",
        },
    ];

    /// More rows than a row group holds, NaN, nulls and a list column: read back (by polars,
    /// without the list column, which it reads only with `dtype-struct`) as written.
    #[test]
    fn a_table_reads_back_as_written() {
        let dir = std::env::temp_dir().join(format!("granflow-parquet-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.parquet");
        let rows = ROW_GROUP_ROWS + 5;
        let value = |i: usize| match i % 3 {
            0 => Cell::F64(f64::NAN),
            1 => Cell::Null,
            _ => Cell::F64(i as f64),
        };
        let mut modes = Column::new("modes", ColumnKind::List(MODE));
        for i in 0..rows {
            modes.push(match i % 2 {
                0 => Cell::Null,
                _ => Cell::List(vec![vec![Cell::I64(-1), Cell::F64(f64::NAN)]; i % 4]),
            });
        }
        let columns = vec![
            Column::from_cells(
                "id",
                ColumnKind::Str,
                (0..rows).map(|i| i.to_string().into()),
            ),
            Column::from_cells(
                "n",
                ColumnKind::I64,
                (0..rows).map(|i| Cell::I64(i as i64 - 1)),
            ),
            Column::from_cells("x", ColumnKind::F64, (0..rows).map(value)),
            modes,
        ];
        let describe = |name: &str| {
            (name == "x").then(|| FieldDoc {
                unit: "sqrt(g d)".into(),
                description: "a speed".into(),
            })
        };
        write(&path, columns, &[("k".into(), "v".into())], &describe).unwrap();
        let read = ParquetReader::new(std::fs::File::open(&path).unwrap())
            .with_columns(Some(vec!["id".into(), "n".into(), "x".into()]))
            .finish()
            .unwrap();
        assert_eq!(read.height(), rows);
        let x = read.column("x").unwrap().f64().unwrap();
        // NaN and null are both null; the rest as written
        assert_eq!(x.null_count(), (0..rows).filter(|i| i % 3 != 2).count());
        assert_eq!(x.get(rows - 1), value(rows - 1).into_f64());
        let n = read.column("n").unwrap().i64().unwrap();
        assert_eq!(
            (n.get(0), n.get(rows - 1)),
            (Some(-1), Some(rows as i64 - 2))
        );
        assert_eq!(
            read.column("id").unwrap().str().unwrap().get(rows - 1),
            Some((rows - 1).to_string().as_str())
        );
        // the field metadata, as pyarrow reads it back from the Arrow schema
        let mut file = std::fs::File::open(&path).unwrap();
        let schema = ParquetReader::new(&mut file).schema().unwrap();
        let x = schema.get("x").unwrap();
        let md = x.metadata.as_ref().expect("field metadata of x");
        assert_eq!(md.get("unit").map(|v| v.as_str()), Some("sqrt(g d)"));
        assert_eq!(md.get("description").map(|v| v.as_str()), Some("a speed"));
        assert!(schema.get("n").unwrap().metadata.is_none());
        let _ = std::fs::remove_dir_all(&dir);
    }

    impl Cell {
        fn into_f64(self) -> Option<f64> {
            match self {
                Cell::F64(x) if !x.is_nan() => Some(x),
                _ => None,
            }
        }
    }
}
