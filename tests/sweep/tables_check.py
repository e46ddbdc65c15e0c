"""Reads the tables of one engine's sweep in three states (no job done, some, all) with pyarrow
and with DuckDB, and checks that they have the declared schema in every state: the same
columns and types, signed 64-bit integers, plain UTF-8 strings, lists of structs, no NaN,
`job_id` the one key shared by the tables, zstd. Run by tests/sweep/tables.rs:

    python3 tables_check.py '<json: engine, jobs, some_done, tables: [[name, [[column, type]]]],
                              states: {none|some|all: directory}>'
"""

import json
import sys

import duckdb
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

spec = json.loads(sys.argv[1])
engine, states = spec["engine"], spec["states"]
declared = dict(spec["tables"])  # in file order: jobs first


def doc_type(t):
    """A pyarrow type as results/README.md names it."""
    if pa.types.is_float64(t):
        return "f64"
    if pa.types.is_int64(t):
        return "i64"
    if pa.types.is_boolean(t):
        return "bool"
    if pa.types.is_string(t):  # plain string: neither large_string nor string_view
        return "str"
    if pa.types.is_list(t) and pa.types.is_struct(t.value_type):
        fields = ", ".join(f"{f.name}: {doc_type(f.type)}" for f in t.value_type)
        return f"list<struct<{fields}>>"
    return f"unexpected {t}"


def duckdb_type(doc):
    """The DuckDB type a column of a README type reads as."""
    scalar = {"f64": "DOUBLE", "i64": "BIGINT", "bool": "BOOLEAN", "str": "VARCHAR"}
    if doc in scalar:
        return scalar[doc]
    fields = doc[len("list<struct<") : -len(">>")].split(", ")
    inner = ", ".join(f"{n} {scalar[t]}" for n, t in (f.split(": ") for f in fields))
    return f"STRUCT({inner})[]"


def leaves(t, path=()):
    """(path, type) of every scalar inside a type."""
    if pa.types.is_list(t) or pa.types.is_large_list(t):
        yield from leaves(t.value_type, path)
    elif pa.types.is_struct(t):
        for f in t:
            yield from leaves(f.type, path + (f.name,))
    else:
        yield path, t


def float_arrays(table):
    """(name, array) of every float column and float field of a list-of-struct column."""
    for field in table.schema:
        column = table.column(field.name)
        if pa.types.is_floating(field.type):
            yield field.name, column
        elif pa.types.is_list(field.type):
            values = pc.list_flatten(column)
            for f in field.type.value_type:
                if pa.types.is_floating(f.type):
                    yield f"{field.name}.{f.name}", pc.struct_field(values, f.name)


con = duckdb.connect()
seen = {}  # table -> (pyarrow schema, duckdb description) of the first state
for state in ["none", "some", "all"]:
    d = states[state]
    ids_done = None
    for table, columns in declared.items():
        path = f"{d}/{table}.parquet"
        where = f"{engine} {table}.parquet ({state} done)"
        # pyarrow: the declared columns and types
        schema = pq.read_schema(path)
        got = [[f.name, doc_type(f.type)] for f in schema]
        assert got == columns, f"{where}: pyarrow reads\n{got}\ndeclared\n{columns}"
        for f in schema:
            for leaf, t in leaves(f.type):
                name = ".".join((f.name,) + leaf)
                assert not pa.types.is_unsigned_integer(t), f"{where}: {name} is {t}"
                assert "view" not in str(t), f"{where}: {name} is {t}"
        # every field carries its unit and meaning (results/README.md) as field metadata
        for f in schema:
            md = f.metadata or {}
            assert md.get(b"unit") and md.get(b"description"), f"{where}: {f.name} has no unit: {md}"
        for column, unit in spec.get("units", {}).get(table, {}).items():
            meta = schema.field(column).metadata or {}
            assert meta.get(b"unit", b"").decode() == unit, f"{where}: {column} unit {meta}"
        provenance = pq.ParquetFile(path).metadata.metadata
        assert provenance[b"granflow.engine"].decode() == engine, where
        # the same provenance in the Arrow schema, where readers of tables look
        for arrow_meta in [schema.metadata, pq.read_table(path).schema.metadata]:
            assert arrow_meta is not None, f"{where}: no Arrow schema metadata"
            for key in [b"granflow.engine", b"granflow.version", b"granflow.commit", b"granflow.sweep_ron"]:
                assert arrow_meta.get(key) == provenance[key], f"{where}: {key} in the Arrow schema"
        kv = dict(con.execute(
            f"SELECT decode(key), decode(value) FROM parquet_kv_metadata('{path}')"
        ).fetchall())
        assert kv["granflow.engine"] == engine, f"{where}: DuckDB reads {sorted(kv)}"
        # DuckDB: the types the declaration gives, and arithmetic on every integer
        described = con.execute(f"DESCRIBE SELECT * FROM read_parquet('{path}')").fetchall()
        duck = [[row[0], row[1].replace('"', "")] for row in described]
        assert duck == [[n, duckdb_type(t)] for n, t in columns], f"{where}: DuckDB reads {duck}"
        for name, t in columns:
            if t == "i64":
                a, b = con.execute(
                    f'SELECT min("{name}" - 1), min("{name}") - 1 FROM read_parquet(\'{path}\')'
                ).fetchone()
                assert a == b, f"{where}: {name} - 1: {a} != {b}"
            elif t.startswith("list<"):
                for field in [f.split(": ")[0] for f in t[12:-2].split(", ") if f.endswith("i64")]:
                    a, b = con.execute(
                        f'SELECT min(m.{field} - 1), min(m.{field}) - 1 FROM '
                        f'(SELECT unnest("{name}") AS m FROM read_parquet(\'{path}\'))'
                    ).fetchone()
                    assert a == b, f"{where}: {name}.{field} - 1: {a} != {b}"
        # the same schema in every state, for both readers
        if table in seen:
            first, first_duck = seen[table]
            assert schema.remove_metadata().equals(first), f"{where}: {schema} vs {first}"
            assert duck == first_duck, f"{where}: {duck} vs {first_duck}"
        else:
            seen[table] = (schema.remove_metadata(), duck)
        # the values: rows, nulls (never NaN), keys
        data = pq.read_table(path)
        rows = con.execute(f"SELECT count(*) FROM read_parquet('{path}')").fetchone()[0]
        assert rows == data.num_rows, f"{where}: DuckDB {rows} rows, pyarrow {data.num_rows}"
        for name, values in float_arrays(data):
            nan = pc.sum(pc.is_nan(values)).as_py() or 0
            assert nan == 0, f"{where}: {nan} NaN in {name} (null is meant)"
        assert data.column_names[0] == "job_id", f"{where}: {data.column_names[:3]}"
        metadata = pq.ParquetFile(path).metadata
        for g in range(metadata.num_row_groups):
            for c in range(metadata.num_columns):
                chunk = metadata.row_group(g).column(c)
                assert chunk.compression == "ZSTD", f"{where}: {chunk.path_in_schema} {chunk.compression}"
        if table == "jobs":
            assert data.num_rows == spec["jobs"], f"{where}: {data.num_rows} rows"
            states_of = data.column("state").to_pylist()
            ids_done = {i for i, s in zip(data.column("job_id").to_pylist(), states_of) if s == "done"}
            expect = {"none": 0, "some": spec["some_done"], "all": spec["jobs"]}[state]
            assert len(ids_done) == expect, f"{where}: states {states_of}"
            # the build that computed each done job, per row
            for n in ["granflow_version", "granflow_commit"]:
                known = data.num_rows - data.column(n).null_count
                assert known == expect, f"{where}: {n} known for {known} jobs"
            final = [n for n, _ in columns if n.startswith("final_")]
            assert final, f"{where}: no final clock"
            for n in final:
                known = data.num_rows - data.column(n).null_count
                assert known == expect, f"{where}: {n} known for {known} jobs"
        else:
            ids = set(data.column("job_id").to_pylist())
            assert ids <= ids_done, f"{where}: rows of jobs not done: {ids - ids_done}"
            if state == "all":
                assert ids == ids_done, f"{where}: no rows of {ids_done - ids}"
# one key: no column but job_id in two tables (joins do not clash)
names = {t: {n for n, _ in cols} for t, cols in declared.items()}
for a in names:
    for b in names:
        if a < b:
            shared = names[a] & names[b]
            assert shared == {"job_id"}, f"{engine}: {a} and {b} share {shared}"
# a join on the key works in DuckDB
d = states["all"]
for table in declared:
    if table != "jobs":
        joined = con.execute(
            f"SELECT count(*) FROM read_parquet('{d}/jobs.parquet') j "
            f"JOIN read_parquet('{d}/{table}.parquet') t USING (job_id)"
        ).fetchone()[0]
        rows = con.execute(f"SELECT count(*) FROM read_parquet('{d}/{table}.parquet')").fetchone()[0]
        assert joined == rows, f"{engine}: jobs JOIN {table}: {joined} of {rows} rows"
print(f"{engine}: {len(declared)} tables, same schema in 3 states (pyarrow {pa.__version__}, duckdb {duckdb.__version__})")
