"""A gathered statistics sweep as the statement readings see it: its jobs by (e, beta), and per
job its profiles, VDF moments, VDFs, Lambda(y), g(r), velocity correlations and P(l).

Reads the Parquet tables of docs/tables.md and results/README.md with DuckDB. Only jobs that
are results count: statistics taken (`statistics_snapshots > 0`), `steady` and
`collapse_guard_valid`; the others are kept, so a row can say which of its jobs are not
results. A table that is missing reads as empty (the rows that need it say "not measured").
"""
import re
from pathlib import Path

import duckdb

# the thesis' bins 1, 4, 13, 21 (of 25) are the tables' slabs 0, 3, 12, 20
WALL, SHEAR, CENTRE, SHEAR_UPPER = 0, 3, 12, 20


def bin_name(slab):
    """The thesis' name of a slab: bin = slab + 1."""
    return f"bin {slab + 1}"


class Job:
    """One job of the sweep: its `jobs.parquet` row (as attributes) and its tables' rows."""

    def __init__(self, sweep, row):
        self.sweep = sweep
        self.row = row
        self.e = row["restitution"]
        self.beta = row["roughness"]
        self.id = row["job_id"]
        self.result = bool(row.get("statistics_snapshots") or 0) and bool(row.get("steady")) \
            and bool(row.get("collapse_guard_valid"))

    def __getitem__(self, column):
        return self.row.get(column)

    def name(self):
        return f"e = {self.e:g}, beta = {self.beta:g}"

    def profile(self, quantity):
        """[(y / W, value)] across the channel, wall to wall."""
        return [(y, v) for _, y, v in self.sweep.rows("profiles", self.id, quantity)
                if v is not None]

    def moment(self, slab, component):
        """{skewness, skewness_error, kurtosis, kurtosis_error, sigma} of a slab, or None (also
        when a moment or its error is null: too few samples)."""
        m = self.sweep.index("vdf_moments", ("moment_bin", "moment_component")).get(
            (self.id, slab, component))
        keys = ("skewness", "skewness_error", "kurtosis", "kurtosis_error")
        return m if m is not None and all(m.get(k) is not None for k in keys) else None

    def moment_slabs(self):
        return sorted({k[1] for k in self.sweep.index(
            "vdf_moments", ("moment_bin", "moment_component")) if k[0] == self.id})

    def vdf(self, slab, component):
        """[(x, p, gaussian)] of one slab and component (P(0) = 1 scaling)."""
        return sorted((r["x"], r["p"], r["gaussian"]) for r in self.sweep.select(
            "vdf", self.id, vdf_bin=slab, component=component) if r["p"] is not None)

    def lambdas(self):
        """[(slab, Lambda, error)] across the channel."""
        return sorted((r["lambda_bin"], r["lambda"], r["lambda_error"])
                      for r in self.sweep.select("orientation", self.id)
                      if r["lambda"] is not None and r["lambda_error"] is not None)

    def last_slab(self):
        """The slab at the wall y = W (the last slab of the orientation table)."""
        return max((r["lambda_bin"] for r in self.sweep.select("orientation", self.id)), default=None)

    def pair_correlation(self, slab):
        """[(r, g, pairs)] of one slab (None: all slabs)."""
        return sorted((r["r"], r["g"], r["g_pairs"]) for r in self.sweep.select(
            "pair_correlation", self.id, g_bin=slab) if r["g"] is not None)

    def velocity_correlation(self, slab, pair):
        """[(r, C, pairs)] of one slab and component pair ('xx', 'yy', ...)."""
        return sorted((r["c_r"], r["c"], r["c_pairs"]) for r in self.sweep.select(
            "velocity_correlation", self.id, c_bin=slab, c_pair=pair) if r["c"] is not None)

    def free_paths(self):
        """[(l, P(l))] over all slabs."""
        return sorted((r["l"], r["p_l"]) for r in self.sweep.select(
            "free_paths", self.id, l_bin=None) if r["p_l"] is not None)


def cells_of(ron):
    """The `cells: (n_x, n_z)` of a sweep's RON text ((1, 1) when not given)."""
    found = re.search(r"cells\s*:\s*[\[(]\s*(\d+)\s*,\s*(\d+)", ron)
    return (int(found.group(1)), int(found.group(2))) if found else (1, 1)


class Sweep:
    """The tables of one results directory."""

    def __init__(self, results):
        self.results = Path(results)
        self.con = duckdb.connect()
        self._tables, self._index = {}, {}
        self.jobs = [Job(self, r) for r in self.table("jobs")
                     if r.get("restitution") is not None]
        self.cells = self._cells()
        self.without_results = False

    @classmethod
    def planned(cls, sweep_file):
        """A sweep without results, with the cells of its sweep file (the readings alone)."""
        sweep = cls(Path(sweep_file).parent / "no results")
        sweep.cells = cells_of(Path(sweep_file).read_text())
        sweep.without_results = True
        return sweep

    def table(self, name):
        """Every row of a table as dicts ([] when the file is missing)."""
        if name not in self._tables:
            path = self.results / f"{name}.parquet"
            if not path.exists():
                self._tables[name] = []
            else:
                cur = self.con.execute(f"SELECT * FROM read_parquet('{path}')")
                names = [d[0] for d in cur.description]
                self._tables[name] = [dict(zip(names, r)) for r in cur.fetchall()]
        return self._tables[name]

    def has(self, name):
        """Whether the table exists (a planned sweep has every table, empty)."""
        return self.without_results or bool(self.table(name))

    def select(self, name, job_id, **where):
        return [r for r in self.by_job(name).get(job_id, [])
                if all(r.get(k) == v for k, v in where.items())]

    def by_job(self, name):
        key = (name, "job")
        if key not in self._index:
            out = {}
            for r in self.table(name):
                out.setdefault(r["job_id"], []).append(r)
            self._index[key] = out
        return self._index[key]

    def index(self, name, keys):
        key = (name, keys)
        if key not in self._index:
            self._index[key] = {(r["job_id"],) + tuple(r[k] for k in keys): r
                                for r in self.table(name)}
        return self._index[key]

    def rows(self, name, job_id, quantity):
        """Profile rows (bin, coordinate, value) of one quantity, in bin order."""
        return sorted((r["bin"], r["coordinate"], r["value"])
                      for r in self.select(name, job_id, quantity=quantity))

    def job(self, e, beta):
        """The job at (e, beta), whether a result or not (None: not in the tables)."""
        for j in self.jobs:
            if abs(j.e - e) < 1e-9 and abs(j.beta - beta) < 1e-9:
                return j
        return None

    def restitutions(self, beta=None):
        return sorted({j.e for j in self.jobs if beta is None or abs(j.beta - beta) < 1e-9})

    def _cells(self):
        """The fluctuation cells per slab (n_x, n_z) of the sweep's `statistics` block, read
        from the resolved sweep in the jobs table's metadata ((1, 1) when not given)."""
        path = self.results / "jobs.parquet"
        if not path.exists():
            return (1, 1)
        meta = self.con.execute(
            f"SELECT decode(value) FROM parquet_kv_metadata('{path}') "
            "WHERE decode(key) = 'granflow.sweep_ron'").fetchone()
        return cells_of(meta[0] if meta else "")

    def fluctuations(self):
        """How the fluctuations C, Omega of the statistics are taken."""
        nx, nz = self.cells
        if (nx, nz) == (1, 1):
            return "fluctuations about the slab mean (bin-wise)"
        return f"cell-wise fluctuations ({nx} x {nz} cells per slab along x and z)"
