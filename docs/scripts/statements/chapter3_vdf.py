"""The thesis' statements of its section 3.2 (phi = 0.01): the VDFs' shapes at bins 1, 4,
13 (and 21), one function each, as read on the tables' moments and VDFs.
"""
from .readings import (
    KURT_TOL, NULL, Row, SIG, SKEW_TOL, fmt, holds, low_velocity_deviation, mean, sequence, trend,
)
from .cases import (
    FOUR, SIX, THREE, by_beta, centre_points, excess, gaussian, kurt, moment_cases,
    moments_averaging, negative_skew, skew, skewed, sub_gaussian, super_gaussian, symmetric,
    tails_deviate,
)
from .sweep import CENTRE, SHEAR, SHEAR_UPPER, WALL, bin_name


def cx_negative_smooth(sweep):
    r = Row("3.2", "\"P(C_x) is asymmetric ... It deviates from the Gaussian distribution towards "
            "negative side\" (beta = -0.99, e = 0.8, Fig. 3.12)", "skewness of C_x below 0 by more "
            f"than {SIG:g} errors in bins 1, 4 and 13", moments_averaging(sweep, "bins 1, 4, 13"))
    return moment_cases(sweep, r, -0.99, 0.8, THREE, ("C_x",), negative_skew, skew)


def omega_z_asymmetric_smooth(sweep):
    r = Row("3.2", "\"there is significant dissipation induced asymmetry in the P(Omega_z) "
            "distribution\" (beta = -0.99, e = 0.8)", f"skewness of Omega_z beyond {SIG:g} errors "
            "in bins 1, 4 and 13", moments_averaging(sweep, "bins 1, 4, 13"))
    r.note = ("Omega_z changes sign under the mirror y -> W - y, so in bin 13, on the mirror "
              "plane, a symmetric flow has no Omega_z skewness")
    return moment_cases(sweep, r, -0.99, 0.8, THREE, ("Omega_z",), skewed, skew)


def four_symmetric_smooth(sweep):
    r = Row("3.2", "\"P(C_y), P(C_z), P(Omega_x) and P(Omega_y) distributions are symmetric\" "
            "(beta = -0.99, e = 0.8)", f"their skewness within {NULL:g} errors of 0 in bins 1, 4, 13",
            moments_averaging(sweep, "bins 1, 4, 13"))
    return moment_cases(sweep, r, -0.99, 0.8, THREE, FOUR, symmetric, skew)


def four_tails_smooth(sweep):
    r = Row("3.2", "\"but there are noticeable deviations at tail region from the Gaussian\" "
            "(the same four, beta = -0.99, e = 0.8)", f"abs(kurtosis - 3) above {KURT_TOL:g} by "
            f"more than {SIG:g} errors in bins 1, 4, 13", moments_averaging(sweep, "bins 1, 4, 13"))
    return moment_cases(sweep, r, -0.99, 0.8, THREE, FOUR, tails_deviate, kurt)


def bins_alike_smooth(sweep):
    r = Row("3.2", "\"there is negligible difference in the local (binwise) distribution functions "
            "of different bins\" (beta = -0.99, e = 0.8)", f"per component, kurtosis in bins 1, 4, "
            f"13 within {KURT_TOL:g} of each other and skewness within {SKEW_TOL:g}",
            moments_averaging(sweep, "bins 1, 4, 13"))
    for j in r.results(sweep, beta=-0.99, e=0.8):
        for c in SIX:
            ms = [j.moment(s, c) for s in THREE]
            if all(ms):
                dk = max(m["kurtosis"] for m in ms) - min(m["kurtosis"] for m in ms)
                ds = max(m["skewness"] for m in ms) - min(m["skewness"] for m in ms)
                r.show(f"{c}: kurtosis range {fmt(dk, 2)}, skewness range {fmt(ds, 2)}")
                r.check(dk <= KURT_TOL and ds <= SKEW_TOL, c)
    return r


def every_bin(sweep, r, beta, e, component, test, show):
    """One case per bin of the job at (e, beta): test(moment of `component`)."""
    for j in r.results(sweep, beta=beta, e=e):
        for s in j.moment_slabs():
            m = j.moment(s, component)
            if m:
                r.check(test(m), f"{bin_name(s)} ({show(m)})")
        r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} bins")
    return r


def omega_z_super_smooth(sweep):
    r = Row("3.2", "\"the tails of P(Omega_z) are super-Gaussian for beta = -0.99 in all bins "
            "(Fig. 3.12(f))\" (e = 0.8)", f"kurtosis of Omega_z above 3 by more than {SIG:g} "
            "errors in every bin", moments_averaging(sweep, "every bin"))
    return every_bin(sweep, r, -0.99, 0.8, "Omega_z", super_gaussian, kurt)


def cx_tail_negative_grows(sweep):
    r = Row("3.2", "\"as the dissipation is increased, the P(C_x) distribution tail deviates away "
            "from the Gaussian towards negative side\" (beta = -0.99, bin 13, Fig. 3.13)",
            "skewness of C_x in bin 13 falls at every step from e = 0.99 to 0.8 (steps against "
            f"within {SIG:g} errors)", moments_averaging(sweep, "bin 13"))
    pts = centre_points(sweep, r, -0.99, "C_x", lambda m: (m["skewness"], m["skewness_error"]))
    r.show("skewness " + sequence(pts, 2))
    r.check(trend(pts, False), "bin 13")
    return r


def cy_tails_grow_symmetric(sweep):
    r = Row("3.2", "\"P(C_y) also exhibits deviations in the tail region with increase of "
            "dissipation but maintaining the symmetry\" (beta = -0.99, bin 13)",
            "abs(kurtosis - 3) of C_y in bin 13 rises from e = 0.99 to 0.8 (steps against within "
            f"{SIG:g} errors), its skewness within {NULL:g} errors of 0 at every e",
            moments_averaging(sweep, "bin 13"))
    pts = centre_points(sweep, r, -0.99, "C_y", excess)
    r.show("abs(kurtosis - 3) " + sequence(pts, 2))
    r.check(trend(pts, True), "tails grow")
    for j in r.results(sweep, beta=-0.99):
        m = j.moment(CENTRE, "C_y")
        if m:
            r.check(symmetric(m), f"symmetric at e = {j.e:g} ({skew(m)})")
    return r


def little_affected_smooth(sweep):
    r = Row("3.2", "\"However P(C_z), P(Omega_x) and P(Omega_y) has little effect of dissipation\" "
            "(beta = -0.99, bin 13)", f"kurtosis of each in bin 13 varies by at most {KURT_TOL:g} "
            "over e", moments_averaging(sweep, "bin 13"))
    for c in ("C_z", "Omega_x", "Omega_y"):
        pts = centre_points(sweep, r, -0.99, c, lambda m: (m["kurtosis"], m["kurtosis_error"]))
        if len(pts) >= 2:
            spread = max(p[1] for p in pts) - min(p[1] for p in pts)
            r.show(f"{c}: range {fmt(spread, 2)}")
            r.check(spread <= KURT_TOL, c)
    return r


def omega_z_to_gaussian_smooth(sweep):
    r = Row("3.2", "\"P(Omega_z) shows deviation from Gaussian in its tails as well as in the low "
            "velocity region and as e -> 1, P(Omega_z) approaches a Gaussian\" (beta = -0.99, "
            "bin 13)", "abs(kurtosis - 3) of Omega_z and its low-velocity deviation max abs(P - "
            "exp(-x^2/2)) over abs(x) <= 1 both fall at every step from e = 0.8 to 0.99 (kurtosis "
            f"steps against within {SIG:g} errors)",
            moments_averaging(sweep, "bin 13") + "; the VDF of bin 13")
    pts = centre_points(sweep, r, -0.99, "Omega_z", excess)
    r.show("abs(kurtosis - 3) " + sequence(pts, 2))
    r.check(trend(pts, True), "tails")
    low = [(j.e, low_velocity_deviation(j.vdf(CENTRE, "Omega_z")), None)
           for j in r.results(sweep, beta=-0.99) if j.vdf(CENTRE, "Omega_z")]
    r.show("low-velocity deviation " + sequence(low, 2))
    r.check(trend(low, True), "low velocities")
    return r


def cx_negative_rough(sweep):
    r = Row("3.2", "\"The P(C_x) distribution deviates considerably from Gaussian distribution "
            "towards negative side. This deviation is present in all bins\" (beta = 0, e = 0.8)",
            f"skewness of C_x below 0 by more than {SIG:g} errors in every bin",
            moments_averaging(sweep, "every bin"))
    return every_bin(sweep, r, 0.0, 0.8, "C_x", negative_skew, skew)


def four_symmetric_rough(sweep):
    r = Row("3.2", "\"The P(C_y), P(C_z), P(Omega_x) and P(Omega_y) distributions remain "
            "symmetric\" (beta = 0, e = 0.8)", f"their skewness within {NULL:g} errors of 0 in bins "
            "1, 4, 13", moments_averaging(sweep, "bins 1, 4, 13"))
    return moment_cases(sweep, r, 0.0, 0.8, THREE, FOUR, symmetric, skew)


def four_tails_rough(sweep):
    r = Row("3.2", "\"but there is larger deviation at the tail regions, in comparison to smooth "
            "surface condition\" (beta = 0 against beta = -0.99, e = 0.8)", "abs(kurtosis - 3) of "
            f"C_y, C_z, Omega_x, Omega_y at beta = 0 above that at beta = -0.99 by more than {SIG:g} "
            "errors, in bins 1, 4, 13", moments_averaging(sweep, "bins 1, 4, 13"))
    rough, smooth = r.results(sweep, beta=0.0, e=0.8), r.results(sweep, beta=-0.99, e=0.8)
    for a in rough:
        for b in smooth:
            for s in THREE:
                for c in FOUR:
                    ma, mb = a.moment(s, c), b.moment(s, c)
                    if ma and mb:
                        (xa, ea), (xb, eb) = excess(ma), excess(mb)
                        r.check(xa - xb > SIG * (ea ** 2 + eb ** 2) ** 0.5,
                                f"{bin_name(s)} {c} ({fmt(xa, 2)} against {fmt(xb, 2)})")
        r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} bin-components larger")
    return r


def low_velocity_asymmetry(vdf):
    """max over 0 < x <= 1 of abs(P(x) - P(-x)) of a VDF [(x, p, gaussian)]."""
    p = {round(x, 6): v for x, v, _ in vdf}
    diffs = [abs(v - p[round(-x, 6)]) for x, v, _ in vdf if 0 < x <= 1 + 1e-9 and round(-x, 6) in p]
    return max(diffs) if diffs else None


def omega_z_shear_asymmetric_rough(sweep):
    r = Row("3.2", "\"there is asymmetry in the low velocity region of P(Omega_z) for the bin-4 "
            "and bin-21 (in shear layer)\" (beta = 0, e = 0.8)", "max abs(P(x) - P(-x)) over "
            "0 < x <= 1 of Omega_z above 0.08 in bins 4 and 21",
            f"the VDFs of bins 4 and 21; {sweep.fluctuations()}")
    for j in r.results(sweep, beta=0.0, e=0.8):
        for s in (SHEAR, SHEAR_UPPER):
            a = low_velocity_asymmetry(j.vdf(s, "Omega_z"))
            if a is not None:
                r.show(f"{bin_name(s)}: {fmt(a, 2)}")
                r.check(a > 0.08, bin_name(s))
    return r


def omega_z_tails_rough(sweep):
    r = Row("3.2", "\"they [the tails of P(Omega_z)] are super-Gaussian in the bulk region and "
            "sub-Gaussian near the walls for beta = 0\" (e = 0.8)", f"kurtosis of Omega_z above 3 "
            f"by more than {SIG:g} errors in bin 13, below 3 by more than {SIG:g} errors in bins 1 "
            "and 25", moments_averaging(sweep, "bins 1, 13, 25"))
    for j in r.results(sweep, beta=0.0, e=0.8):
        last = max(j.moment_slabs(), default=24)
        for s, test in ((CENTRE, super_gaussian), (WALL, sub_gaussian), (last, sub_gaussian)):
            m = j.moment(s, "Omega_z")
            if m:
                r.show(f"{bin_name(s)}: {kurt(m)}")
                r.check(test(m), bin_name(s))
    return r


def cx_asymmetric_rough_every_e(sweep):
    r = Row("3.2", "\"P(C_x), remains asymmetric for all e\" (beta = 0, bin 13, Fig. 3.15)",
            f"skewness of C_x in bin 13 below 0 by more than {SIG:g} errors at every e",
            moments_averaging(sweep, "bin 13"))
    for j in r.results(sweep, beta=0.0):
        m = j.moment(CENTRE, "C_x")
        if m:
            r.show(f"e = {j.e:g}: {skew(m)}")
            r.check(negative_skew(m), f"e = {j.e:g}")
    return r


def four_towards_gaussian_rough(sweep):
    r = Row("3.2", "\"P(C_y), P(C_z), P(Omega_x) and P(Omega_y) distributions remain symmetric but "
            "tend towards Gaussian with increase in elasticity; however, there is still large "
            "deviation in the tail region\" (beta = 0, bin 13)", "per component in bin 13: skewness "
            f"within {NULL:g} errors of 0 at every e; abs(kurtosis - 3) falls from e = 0.8 to 0.99 "
            f"(steps against within {SIG:g} errors); at e = 0.99 still above {KURT_TOL:g} by "
            f"{SIG:g} errors", moments_averaging(sweep, "bin 13"))
    jobs = r.results(sweep, beta=0.0)
    for c in FOUR:
        pts = centre_points(sweep, r, 0.0, c, excess)
        r.show(f"{c}: abs(kurtosis - 3) " + sequence(pts, 2))
        sym = all(symmetric(j.moment(CENTRE, c)) for j in jobs if j.moment(CENTRE, c))
        last = [j.moment(CENTRE, c) for j in jobs if abs(j.e - 0.99) < 1e-9 and j.moment(CENTRE, c)]
        r.check(sym and trend(pts, True) and all(tails_deviate(m) for m in last) if last else None,
                c)
    return r


def omega_z_deviates_most_rough(sweep):
    r = Row("3.2", "\"P(Omega_z) shows much higher deviation from Gaussian\" (beta = 0, bin 13)",
            "abs(kurtosis - 3) of Omega_z in bin 13 above that of each of C_y, C_z, Omega_x, "
            "Omega_y, at every e", moments_averaging(sweep, "bin 13"))
    for j in r.results(sweep, beta=0.0):
        m = j.moment(CENTRE, "Omega_z")
        rest = [j.moment(CENTRE, c) for c in FOUR]
        if m and all(rest):
            top = max(excess(x)[0] for x in rest)
            r.show(f"e = {j.e:g}: {fmt(excess(m)[0], 2)} against at most {fmt(top, 2)}")
            r.check(excess(m)[0] > top, f"e = {j.e:g}")
    return r


def cx_slight_perfect(sweep):
    r = Row("3.2", "\"Compared to two previous cases (beta = -0.99 and beta = 0) ... the degree of "
            "asymmetry in P(C_x) is relatively small\" (beta = 0.99, e = 0.8)", "abs(skewness of "
            "C_x) at beta = 0.99 below those at beta = -0.99 and beta = 0, in bins 1, 4, 13",
            moments_averaging(sweep, "bins 1, 4, 13"))
    for j in r.results(sweep, beta=0.99, e=0.8):
        for other in (-0.99, 0.0):
            for o in r.results(sweep, beta=other, e=0.8):
                for s in THREE:
                    a, b = j.moment(s, "C_x"), o.moment(s, "C_x")
                    if a and b:
                        r.check(abs(a["skewness"]) < abs(b["skewness"]),
                                f"{bin_name(s)} against {by_beta(other)}")
        r.show(", ".join(f"{bin_name(s)}: {skew(j.moment(s, 'C_x'))}" for s in THREE
                         if j.moment(s, "C_x")))
    return r


def six_to_gaussian_perfect(sweep):
    r = Row("3.2", "\"It is observed that all distribution functions approach Gaussian in the "
            "elastic limit\" (beta = 0.99, bin 13, Fig. 3.17)", "per component in bin 13: "
            f"abs(kurtosis - 3) falls from e = 0.8 to 0.99 (steps against within {SIG:g} errors) and "
            f"at e = 0.99 abs(kurtosis - 3) <= {KURT_TOL:g}, abs(skewness) <= {SKEW_TOL:g}",
            moments_averaging(sweep, "bin 13 (the thesis' bin; the old reading averaged all slabs)"))
    jobs = r.results(sweep, beta=0.99)
    for c in SIX:
        pts = centre_points(sweep, r, 0.99, c, excess)
        last = [j.moment(CENTRE, c) for j in jobs if abs(j.e - 0.99) < 1e-9 and j.moment(CENTRE, c)]
        r.show(f"{c}: abs(kurtosis - 3) " + sequence(pts, 2))
        r.check(trend(pts, True) and all(gaussian(m) for m in last) if last else None, c)
    return r


def mean_excess(job, slabs=None):
    """Mean over slabs (all when None) and the six components of abs(kurtosis - 3)."""
    slabs = job.moment_slabs() if slabs is None else slabs
    values = [abs(job.moment(s, c)["kurtosis"] - 3) for s in slabs for c in SIX
              if job.moment(s, c)]
    return mean(values)


def deviation_largest_rough(sweep):
    r = Row("3.2 summary", "\"The deviation from Gaussian is pronounced at beta ~ 0 for any value "
            "of normal restitution coefficient (even for e=0.99). This deviation starts decreasing "
            "if we move towards beta = +-1\"", "mean of abs(kurtosis - 3) over every bin and the six "
            "components at beta = 0 above those at beta = -0.99 and 0.99, at every e",
            moments_averaging(sweep, "every bin (all-slab mean)"))
    rough = {j.e: j for j in r.results(sweep, beta=0.0)}
    others = [{j.e: j for j in r.results(sweep, beta=b)} for b in (-0.99, 0.99)]
    for e in sorted(rough, reverse=True):
        rest = [mean_excess(o[e]) for o in others if e in o and mean_excess(o[e]) is not None]
        if rest:
            r.show(f"e = {e:g}: {fmt(mean_excess(rough[e]), 2)} against " +
                   ", ".join(fmt(v, 2) for v in rest))
            r.check(holds(lambda a, b: a > b, mean_excess(rough[e]), max(rest)), f"e = {e:g}")
    return r
