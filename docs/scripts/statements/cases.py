"""Case builders the chapters' statements share: the beta values and bins, the averaging
texts, per-beta trends and comparisons, extrema of profiles, and the tests on one VDF
moment row (`Job.moment`) against the tolerances of `readings`.
"""
from .readings import (
    KURT_TOL, NULL, SIG, SKEW_TOL, centre_value, fmt, maximum_at_centre, mean, minimum_at_centre,
    pm, safe, sequence, trend,
)
from .sweep import CENTRE, SHEAR, WALL, bin_name


BETAS = (-0.99, 0.0, 0.99)
# the dissipative e of chapter 4.1 (its e = 0.99 is the elastic limit)
DISSIPATIVE = (0.7, 0.8, 0.9)

THREE = (WALL, SHEAR, CENTRE)

PROFILES = "profiles: 25 bins over the window (T, theta about cell means of the structure grid)"

WALLS = "wall bins 1 and 25 of the profiles, odd quantities sign-folded (docs/statistics.md)"

OMEGAS = ("Omega_x", "Omega_y", "Omega_z")

SIX = ("C_x", "C_y", "C_z") + OMEGAS


def moments_averaging(sweep, bins):
    return f"VDF moments in {bins}; {sweep.fluctuations()}"


def by_beta(beta):
    return f"beta = {beta:g}"


def dense_centre(profile):
    return maximum_at_centre(profile) and centre_value(profile) > mean(v for _, v in profile)


def centre_excess(j):
    phi = j.profile("phi")
    return centre_value(phi) / mean(v for _, v in phi) if phi else None


def minima_at_centre(sweep, r, beta, quantities):
    for j in r.results(sweep, beta=beta):
        for q in quantities:
            p = j.profile(q)
            low = min(p, key=lambda t: t[1]) if p else (None, None)
            r.show(f"e = {j.e:g}: {q} lowest at y / W = {fmt(low[0], 2)}")
            r.check(minimum_at_centre(p), f"e = {j.e:g} {q}")
    return r


def compare_betas(sweep, r, value, beta, other, above=True):
    """Per e: value(job at `beta`) above (or below) value(job at `other`)."""
    one = {j.e: j for j in r.results(sweep, beta=beta)}
    two = {j.e: j for j in r.results(sweep, beta=other)}
    for e in sorted(set(one) & set(two), reverse=True):
        a, b = safe(value, one[e]), safe(value, two[e])
        if a is None or b is None:
            continue
        r.show(f"e = {e:g}: {fmt(a)} against {fmt(b)}")
        r.check(a > b if above else a < b, f"e = {e:g}")
    return r


def value_trend(sweep, r, beta, value, rises, label):
    """A per-job value (value(job) -> number) rises (or falls) with dissipation at one beta."""
    pts = [(j.e, safe(value, j), None) for j in r.results(sweep, beta=beta)]
    r.show(f"{label} " + sequence(pts))
    r.check(trend(pts, rises), by_beta(beta))
    return r


def column_trend(sweep, r, column, betas, rises, magnitude=False):
    for beta in betas:
        pts = [(j.e, abs(j[column]) if magnitude else j[column], None)
               for j in r.results(sweep, beta=beta) if j[column] is not None]
        r.show(f"{by_beta(beta)}: {sequence(pts)}")
        r.check(trend(pts, rises), by_beta(beta))
    return r


def moment_cases(sweep, r, beta, e, slabs, components, test, show):
    """One case per (slab, component) of the job at (e, beta): test(moment) -> bool."""
    for j in r.results(sweep, beta=beta, e=e):
        for s in slabs:
            for c in components:
                m = j.moment(s, c)
                if m is not None:
                    r.show(f"{bin_name(s)} {c}: {show(m)}")
                    r.check(test(m), f"{bin_name(s)} {c}")
    return r


def skew(m):
    return pm(m["skewness"], m["skewness_error"], 2)


def kurt(m):
    return pm(m["kurtosis"], m["kurtosis_error"], 3)


def negative_skew(m):
    return m["skewness"] < -SIG * m["skewness_error"]


def skewed(m):
    return abs(m["skewness"]) > SIG * m["skewness_error"]


def symmetric(m):
    return abs(m["skewness"]) <= NULL * m["skewness_error"]


def tails_deviate(m):
    return abs(m["kurtosis"] - 3) > KURT_TOL + SIG * m["kurtosis_error"]


def gaussian(m):
    return abs(m["kurtosis"] - 3) <= KURT_TOL and abs(m["skewness"]) <= SKEW_TOL


def super_gaussian(m):
    return m["kurtosis"] - 3 > SIG * m["kurtosis_error"]


def sub_gaussian(m):
    return 3 - m["kurtosis"] > SIG * m["kurtosis_error"]


def centre_points(sweep, r, beta, component, value):
    return [(j.e,) + value(j.moment(CENTRE, component)) for j in r.results(sweep, beta=beta)
            if j.moment(CENTRE, component)]


def excess(m):
    return abs(m["kurtosis"] - 3), m["kurtosis_error"]


def profile_mean(job):
    """The mean of Lambda(y) over the bins and its error (independent bins)."""
    lam = job.lambdas()
    if not lam:
        return None
    return mean(v for _, v, _ in lam), sum(e * e for _, _, e in lam) ** 0.5 / len(lam)


def distance_points(sweep, r, beta, value):
    """(e, abs(value - 1/3), error) per job of a beta; value(job) -> (v, err) or None."""
    out = []
    for j in r.results(sweep, beta=beta):
        v = value(j)
        if v:
            out.append((j.e, abs(v[0] - 1 / 3), v[1]))
    return out


def lambda_centre(job):
    lam = {s: (v, e) for s, v, e in job.lambdas()}
    return lam.get(CENTRE)


FOUR = ("C_y", "C_z", "Omega_x", "Omega_y")
