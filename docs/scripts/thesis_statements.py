#!/usr/bin/env python3
"""The thesis' statements of chapters 3-4 (docs/statistics.md) checked against a gathered sweep.

    python3 docs/scripts/thesis_statements.py results/thesis-ch3
    python3 docs/scripts/thesis_statements.py results/thesis-ch4-dense --dense
    python3 docs/scripts/thesis_statements.py results/thesis-ch4-dense --grid
    python3 docs/scripts/thesis_statements.py results/thesis-ch4-dilute --dilute

Reads the sweep's Parquet tables with DuckDB (pip install duckdb) and prints, per statement,
what granflow measured and whether it agrees, as the Markdown rows of docs/statistics.md's
table. Only jobs whose statistics window is filled count; a sweep still running is read as far
as it got (the row says how many jobs). Errors are the tables' batch-means standard errors;
"agrees" asks for the sign or order the thesis states beyond 2 standard errors where the
tables carry an error, and says "within error" otherwise.
"""
import sys
from pathlib import Path

import duckdb


def table(results, name):
    path = Path(results) / f"{name}.parquet"
    if not path.exists():
        sys.exit(f"{path}: missing (run `granflow gather {results}` first)")
    return f"read_parquet('{path}')"


def chapter3(results):
    con = duckdb.connect()
    jobs, profiles, moments = (table(results, n) for n in ("jobs", "profiles", "vdf_moments"))
    done = f"(SELECT * FROM {jobs} WHERE statistics_snapshots > 0)"
    n_jobs = con.execute(f"SELECT count(*) FROM {done}").fetchone()[0]
    rows = []

    # 1. Kn > 0.1 everywhere: where it is not, and the centre's range (profiles' y is y / W)
    kn = con.execute(
        f"SELECT min(p.value), max(p.value) FROM {profiles} p JOIN {done} j USING (job_id) "
        "WHERE p.quantity = 'Kn'").fetchone()
    below = con.execute(
        f"SELECT j.roughness, j.restitution, min(p.value), list(DISTINCT round(p.coordinate, 2)) "
        f"FROM {profiles} p JOIN {done} j USING (job_id) WHERE p.quantity = 'Kn' AND p.value <= 0.1 "
        "GROUP BY 1, 2 ORDER BY 1, 2").fetchall()
    centre = con.execute(f"SELECT min(knudsen_centre), max(knudsen_centre) FROM {done}").fetchone()
    where = sorted({y for row in below for y in row[3]})
    detail = (f"Kn(y) = lambda(y) / W over the slabs of {n_jobs} jobs: {kn[0]:.3g} to {kn[1]:.3g}; "
              f"at the centre {centre[0]:.3g} to {centre[1]:.3g}")
    if below:
        cases = "; ".join(f"beta = {b:g}, e = {e:g}: {m:.3g}" for b, e, m, _ in below)
        detail += (f"; <= 0.1 in {len(below)} jobs, only at y / W = "
                   f"{', '.join(f'{y:g}' for y in where)} ({cases})")
    rows.append(("Kn > 0.1 everywhere in the ch. 3 cases", detail,
                 "yes" if kn[0] > 0.1 else "no, in the slabs named"))

    # 2. wall slip largest at beta = 0
    slip = con.execute(
        f"SELECT restitution, roughness, slip_velocity FROM {done} ORDER BY restitution, roughness"
    ).fetchall()
    by_e = {}
    for e, beta, u in slip:
        by_e.setdefault(e, {})[beta] = u
    complete = {e: d for e, d in by_e.items() if len(d) == 3 and 0.0 in d}
    wins = [e for e, d in complete.items() if d[0.0] == max(d.values())]
    detail = "; ".join(
        f"e = {e:g}: " + ", ".join(f"{d[b]:.3g}" for b in sorted(d)) for e, d in sorted(by_e.items()))
    verdict = ("not yet measured (no e with all three beta done)" if not complete else
               f"{'yes' if len(wins) == len(complete) else 'partly'}: largest at beta = 0 for "
               f"{len(wins)} of {len(complete)} e")
    rows.append(("wall slip largest at beta = 0 (ch. 3)",
                 f"slip_velocity (sqrt(g d)) at beta = -0.99, 0, 0.99: {detail}", verdict))

    # 3. Lambda > 1/3 for beta = -0.99, < 1/3 for beta = 0 and 0.99
    lam = con.execute(
        f"SELECT roughness, restitution, lambda_centre, lambda_centre_error, lambda_mean FROM {done} "
        "ORDER BY roughness, restitution").fetchall()
    ok, total, parts = 0, 0, []
    for beta in sorted({r[0] for r in lam}):
        sel = [r for r in lam if r[0] == beta]
        want_above = beta < -0.5
        good = sum(1 for r in sel if (r[2] - 1 / 3 > 2 * r[3]) if want_above) if want_above else \
            sum(1 for r in sel if (1 / 3 - r[2] > 2 * r[3]))
        ok += good
        total += len(sel)
        parts.append(f"beta = {beta:g}: Lambda centre " + ", ".join(
            f"{r[2]:.4f} +- {r[3]:.4f}" for r in sel) + " (e = " + ", ".join(f"{r[1]:g}" for r in sel) + ")")
    rows.append(("Lambda > 1/3 for beta = -0.99, < 1/3 for beta = 0 and 0.99 (ch. 3)",
                 "; ".join(parts),
                 f"{'yes' if ok == total else 'partly'}: {ok} of {total} jobs on the stated side of "
                 "1/3 by more than 2 standard errors (centre slab)"))

    # 4. streamwise VDF skewed to the negative side
    sk = con.execute(
        f"SELECT count(*) FILTER (WHERE m.skewness < -2 * m.skewness_error), "
        f"count(*) FILTER (WHERE m.skewness > 2 * m.skewness_error), count(*), "
        f"median(m.skewness) FROM {moments} m JOIN {done} j USING (job_id) "
        "WHERE m.moment_component = 'C_x'").fetchone()
    rows.append(("streamwise VDF skewed to the negative side",
                 f"skewness of C_x over {sk[2]} slabs x jobs: negative beyond 2 errors in {sk[0]}, "
                 f"positive in {sk[1]}; median {sk[3]:.3g}",
                 "yes" if sk[0] > sk[2] / 2 and sk[1] == 0 else ("mostly" if sk[0] > sk[1] else "no")))

    # 5. all six VDFs tend to Gaussian as e -> 1 at beta = 0.99
    g = con.execute(
        f"SELECT j.restitution, avg(abs(m.kurtosis - 3)), avg(abs(m.skewness)) FROM {moments} m "
        f"JOIN {done} j USING (job_id) WHERE j.roughness = 0.99 GROUP BY j.restitution "
        "ORDER BY j.restitution").fetchall()
    decreasing = all(a[1] >= b[1] for a, b in zip(g, g[1:]))
    if len(g) < 2:
        verdict = f"not yet measured ({len(g)} value of e done at beta = 0.99)"
    else:
        verdict = ("yes" if decreasing else "not monotonic") + f" ({len(g)} values of e)"
    rows.append(("all six VDFs tend to Gaussian as e -> 1 at beta = 0.99",
                 "mean over slabs and the six components of abs(kurtosis - 3) (abs(skewness)) by e: " +
                 (", ".join(f"{e:g}: {k:.3g} ({s:.3g})" for e, k, s in g) or "none yet"),
                 verdict))
    return rows


def chapter4_dense(results):
    con = duckdb.connect()
    jobs, g, c = (table(results, n) for n in ("jobs", "pair_correlation", "velocity_correlation"))
    done = f"(SELECT * FROM {jobs} WHERE statistics_snapshots > 0 AND restitution = 0.9 AND roughness = 0.9)"
    # local maxima of the all-slab g(r)
    peaks = con.execute(
        f"WITH s AS (SELECT job_id, r, g, lag(g) OVER w AS gl, lead(g) OVER w AS gr FROM {g} "
        f"WHERE g_bin IS NULL AND job_id IN (SELECT job_id FROM {done}) WINDOW w AS (PARTITION BY job_id ORDER BY r)) "
        "SELECT r, g FROM s WHERE g > gl AND g >= gr AND g > 1.02 ORDER BY r").fetchall()
    centre = con.execute(
        f"SELECT c_pair, avg(c) FROM {c} WHERE job_id IN (SELECT job_id FROM {done}) "
        f"AND c_bin = (SELECT max(c_bin) / 2 FROM {c}) AND c_r BETWEEN 1.0 AND 2.0 "
        "AND c_pair IN ('xx', 'yy', 'zz') GROUP BY c_pair ORDER BY c_pair").fetchall()
    # a number is a result only where the method was valid: steady, and the collapse guard
    # (the TC model) did not change the physics
    validity = con.execute(
        f"SELECT steady, collapse_guard_valid, momentum_balance, momentum_balance_error, "
        f"energy_balance, energy_balance_error, window_tc_elastic_fraction, "
        f"window_suppressed_dissipation FROM {done}").fetchall()
    measured = ("g(r) maxima at r/d = " + ", ".join(f"{r:.2f} ({v:.2f})" for r, v in peaks[:6]) +
                "; centre slab, 1 <= r/d <= 2: " + ", ".join(f"C_{p} = {v:.3g}" for p, v in centre))
    invalid = [v for v in validity if not (v[0] and v[1])]
    if not validity:
        verdict = "not run yet"
    elif invalid:
        st, guard, mb, mbe, eb, ebe, tc, sup = invalid[0]
        verdict = (f"not a result: the run is {'steady' if st else 'not steady'} (momentum balance "
                   f"{mb:.3f} +- {mbe:.3f}, energy balance {eb:.3f} +- {ebe:.3f}) and its collapse "
                   f"guard {'held' if guard else 'changed the physics'} ({100 * tc:.0f} % of the "
                   f"pair collisions made elastic, {100 * sup:.1f} % of the dissipation suppressed)")
    else:
        verdict = "see the numbers"
    return [("phi = 0.5: g(r) peaks near integer r/d, C_xx ~ 0 while C_yy, C_zz significant at the centre",
             measured, verdict)]


def chapter4_dilute(results):
    """The thesis' statements of ch. 4.1 (phi = 0.1; spec B3.7, B3.8) that the tables can check.
    Only jobs that are results (steady, collapse guard valid) count for the verdict; the
    others are shown, marked '(not a result)'."""
    con = duckdb.connect()
    jobs, profiles, moments = (table(results, n) for n in ("jobs", "profiles", "vdf_moments"))
    done = (f"(SELECT *, steady AND collapse_guard_valid AS valid FROM {jobs} "
            "WHERE statistics_snapshots > 0)")
    mark = lambda valid: "" if valid else " (not a result)"
    rows = []

    def verdict(good, counted, what):
        if counted == 0:
            return "not measured: no job of these is a result" if what else "not yet measured"
        return f"{'yes' if good == counted else 'partly' if good else 'no'}: {good} of {counted} {what}"

    # 1. beta = 0: a dense plug even when nearly elastic. The thesis shows it in the mean
    #    profile phi(y) (Fig. 4.3): a plug there is a dense centre, i.e. phi(y) largest within
    #    0.1 W of the centre and above the channel mean there (EDMD profiles carry no errors).
    #    granflow's label classifies the 2D structure, which may be modulated along the flow
    #    (s-wave, slug) while phi(y) still has its dense centre: both are shown.
    plug = con.execute(
        "SELECT j.restitution, j.label, j.valid, f.max / f.min, f.max, f.mean, f.centre, f.near "
        "FROM (SELECT job_id, max(value) AS max, min(value) AS min, avg(value) AS mean, "
        "arg_min(value, abs(coordinate - 0.5)) AS centre, "
        "max(value) FILTER (WHERE abs(coordinate - 0.5) < 0.1) AS near "
        f"FROM {profiles} WHERE quantity = 'phi' GROUP BY job_id) f "
        f"JOIN {done} j USING (job_id) WHERE j.roughness = 0 ORDER BY j.restitution").fetchall()
    # dense centre: the largest phi(y) lies within 0.1 W of the centre, and the centre slab is
    # above the channel mean
    dense = lambda r: r[7] == r[4] and r[6] > r[5]
    counted = [r for r in plug if r[2]]
    rows.append((
        "beta = 0: a dense plug forms even when nearly elastic (ch. 4.1)",
        "phi(y): centre / mean, max / min; 2D label, at e = " + ", ".join(
            f"{r[0]:g}: {r[6]:.3g} / {r[5]:.3g}, {r[3]:.3g}; {r[1]}{mark(r[2])}" for r in plug),
        verdict(sum(1 for r in counted if dense(r)), len(counted),
                "e with a dense centre in phi(y)" + (
                    f" (2D label a plug at {sum(1 for r in counted if 'plug' in r[1])})"
                    if counted else "") if plug else "")))

    # 2. beta = 0.99, e = 0.7: an S-shaped density wave. The thesis saw it in snapshots; the
    #    share of the steady window's snapshots whose structure holds an S-wave (alone or with
    #    a slug: `label_probabilities`) is the measure; the label needs a two-thirds majority
    #    of one structure and may be `mixed` between two S-wave structures.
    sw = con.execute(
        f"SELECT label, valid, label_probabilities FROM {done} "
        "WHERE roughness = 0.99 AND restitution = 0.7").fetchall()

    def s_wave_share(probabilities):
        share = 0.0
        for part in (probabilities or "").split(";"):
            name, _, p = part.strip().rpartition(" ")
            if "s-wave" in name:
                share += float(p)
        return share

    rows.append((
        "beta = 0.99, e = 0.7: an S-shaped density wave (ch. 4.1)",
        (f"S-wave in {s_wave_share(sw[0][2]):.0%} of the steady snapshots ({sw[0][2]}); "
         f"label {sw[0][0]}{mark(sw[0][1])}") if sw else "not run yet",
        verdict(sum(1 for _, v, p in sw if v and s_wave_share(p) >= 2 / 3), sum(1 for _, v, _ in sw if v),
                "runs with an S-wave in at least two thirds of the snapshots" if sw else "")))

    # 3. beta = -0.99: Kn has a minimum at the centreline at high dissipation, deeper as e falls
    kn = con.execute(
        f"SELECT j.restitution, j.knudsen_centre, (SELECT max(p.value) FROM {profiles} p "
        "WHERE p.job_id = j.job_id AND p.quantity = 'Kn'), valid "
        f"FROM {done} j WHERE roughness = -0.99 ORDER BY restitution").fetchall()
    counted = [(e, c / m) for e, c, m, v in kn if v and e < 0.95]
    deepening = all(a[1] <= b[1] for a, b in zip(counted, counted[1:]))
    rows.append((
        "beta = -0.99: Kn has a minimum at the centreline at high dissipation (e < 0.95), deeper as e falls (ch. 4.1)",
        "Kn at the centre / its largest value across the channel at e = " + ", ".join(
            f"{e:g}: {c:.3g} / {m:.3g}{mark(v)}" for e, c, m, v in kn),
        verdict(sum(1 for _, d in counted if d < 1.0), len(counted),
                "e < 0.95 with the centre below the largest value"
                + (", deepening with dissipation" if deepening and len(counted) > 1 else "")
                if kn else "")))

    # 4. beta = 0.99: the three Omega VDFs approach the Gaussian as e -> 1
    g = con.execute(
        f"SELECT j.restitution, avg(abs(m.kurtosis - 3)), avg(abs(m.skewness)), bool_and(j.valid) "
        f"FROM {moments} m JOIN {done} j USING (job_id) WHERE j.roughness = 0.99 "
        "AND m.moment_component LIKE 'Omega%' GROUP BY j.restitution ORDER BY j.restitution").fetchall()
    counted = [r for r in g if r[3]]
    decreasing = all(a[1] >= b[1] for a, b in zip(counted, counted[1:]))
    rows.append((
        "beta = 0.99: all three Omega VDFs approach the Gaussian as e -> 1 (ch. 4.1)",
        "mean over slabs and Omega_x, Omega_y, Omega_z of abs(kurtosis - 3) (abs(skewness)) by e: " +
        (", ".join(f"{e:g}: {k:.3g} ({s:.3g}){mark(v)}" for e, k, s, v in g) or "none yet"),
        ("not measured: fewer than two e are results" if len(counted) < 2 else
         ("yes" if decreasing else "not monotonic") + f" over the {len(counted)} e that are results")))
    return rows


def grid(results):
    """One row per done job of a sweep: is it a result (steady, collapse guard valid), and the
    statistics a reader looks at first (contact value, Lambda at the centre, the centre slab's
    kurtosis of the six components, mean over them), with the job's cost."""
    con = duckdb.connect()
    jobs, moments = (table(results, n) for n in ("jobs", "vdf_moments"))
    rows = con.execute(
        f"SELECT j.restitution, j.roughness, j.label, j.steady, j.momentum_balance, "
        f"j.momentum_balance_error, j.window_tc_elastic_fraction, j.collapse_guard_valid, "
        f"j.contact_value, j.lambda_centre, j.lambda_centre_error, "
        f"(SELECT avg(m.kurtosis) FROM {moments} m WHERE m.job_id = j.job_id "
        f" AND m.moment_bin = (SELECT max(moment_bin) / 2 FROM {moments})), "
        f"j.wall_seconds, j.pair_collisions "
        f"FROM {jobs} j WHERE j.statistics_snapshots > 0 ORDER BY j.restitution, j.roughness DESC"
    ).fetchall()
    print("| e | beta | label | momentum balance | TC-elastic collisions | result? | g(d+) "
          "| Lambda centre | centre kurtosis (mean of 6) | wall time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for e, b, label, steady, mb, mbe, tc, guard, g, lam, lame, kurt, wall, coll in rows:
        valid = "yes" if steady and guard else (
            "no: " + " and ".join(w for w, bad in (("not steady", not steady),
                                                   ("guard changed the physics", not guard)) if bad))
        print(f"| {e:g} | {b:g} | {label} | {mb:.3f} +- {mbe:.3f} | {100 * tc:.0f} % | {valid} "
              f"| {g:.3g} | {lam:.4f} +- {lame:.4f} | {kurt:.2f} | {wall / 60:.0f} min |")
    if rows:
        print(f"\n{len(rows)} jobs, {sum(r[-1] for r in rows):.3g} pair collisions, "
              f"{sum(r[-2] for r in rows) / 3600:.1f} core-hours of job wall time")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    if "--grid" in sys.argv:
        grid(sys.argv[1])
        return
    if "--dense" in sys.argv:
        rows = chapter4_dense(sys.argv[1])
    elif "--dilute" in sys.argv:
        rows = chapter4_dilute(sys.argv[1])
    else:
        rows = chapter3(sys.argv[1])
    for statement, measured, agrees in rows:
        print(f"| {statement} | {measured} | {agrees} |")


if __name__ == "__main__":
    main()
