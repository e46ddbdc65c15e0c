"""The thesis' statements of chapter 3 (phi = 0.01, sweeps/thesis-ch3.ron), one function each:
mean fields (3.1), Kn, slip and wall values (3.1.1), VDF shapes (3.2), g(r) (3.3) and Lambda
(3.4). Each takes a `Sweep` and returns its `Row`; the tolerances are those of `readings`."""
import math

from .readings import (KURT_TOL, NULL, SIG, SKEW_TOL, Row, centre_value, fmt, line_fit_r2,
                       low_velocity_deviation, maximum_at_centre, mean, merged, minimum_at_centre,
                       non_monotonic, pearson, pm, sequence, trend, wall_value)
from .sweep import CENTRE, SHEAR, SHEAR_UPPER, WALL, bin_name

BETAS = (-0.99, 0.0, 0.99)
THREE = (WALL, SHEAR, CENTRE)
PROFILES = "profiles: 25 bins over the window (T, theta about cell means of the structure grid)"
WALLS = "wall bins 1 and 25 of the profiles, odd quantities sign-folded (docs/statistics.md)"
OMEGAS = ("Omega_x", "Omega_y", "Omega_z")
SIX = ("C_x", "C_y", "C_z") + OMEGAS


def moments_averaging(sweep, bins):
    return f"VDF moments in {bins}; {sweep.fluctuations()}"


def by_beta(beta):
    return f"beta = {beta:g}"


# ---- 3.1 mean fields ---------------------------------------------------------------------

def no_structure(sweep):
    r = Row("3.1", "\"no dissipation-induced density inhomogeneity in the system even at e = 0.8\" "
            "(beta = -0.99); \"no dissipation-induced structure formation\" (beta = 0); \"no "
            "dissipation-induced inhomogeneity in the system across any plane\" (beta = 0.99)",
            "the job's structure label at e = 0.8 is homogeneous or plug (no structure along the "
            "flow or spanwise: the thesis calls the centre-peaked phi(y) of e = 0.8 \"no visible "
            "clustering\")", "2D label over the steady window")
    for beta in BETAS:
        for j in r.results(sweep, beta=beta, e=0.8):
            label = j["shown_label"] or j["label"]
            r.show(f"{by_beta(beta)}: {label}")
            r.check(label in ("homogeneous", "plug"), by_beta(beta))
    return r


def phi_uniform_elastic(sweep):
    r = Row("3.1", "\"When the dissipation is very less, e=0.99, the density profile is nearly "
            "uniform across the width of the channel\" (beta = -0.99)",
            "phi(y) in bins 2-24 within 10 % of their mean at e = 0.99 (bins 1 and 25 left out: a "
            "centre cannot come closer than d/2 to a wall, so a quarter of their volume is empty "
            "at any density)", PROFILES)
    for j in r.results(sweep, beta=-0.99, e=0.99):
        inner = [v for _, v in j.profile("phi")[1:-1]]
        if inner:
            spread = max(abs(v / mean(inner) - 1) for v in inner)
            r.show(f"largest deviation from the mean {100 * spread:.1f} %")
            r.check(spread <= 0.1, "e = 0.99")
    return r


def dense_centre(profile):
    return maximum_at_centre(profile) and centre_value(profile) > mean(v for _, v in profile)


def phi_centre_peak(sweep):
    r = Row("3.1", "\"the volume fraction is higher at the center, specifically for e=0.8\" "
            "(beta = -0.99)", "phi(y) largest in the centre bins and the centre above the channel "
            "mean at e = 0.8", PROFILES)
    for j in r.results(sweep, beta=-0.99, e=0.8):
        phi = j.profile("phi")
        r.show(f"centre {fmt(centre_value(phi))}, mean {fmt(mean(v for _, v in phi))}, largest "
               f"at y / W = {max(phi, key=lambda p: p[1])[0]:.2f}")
        r.check(dense_centre(phi), "e = 0.8")
    return r


def centre_excess(j):
    phi = j.profile("phi")
    return centre_value(phi) / mean(v for _, v in phi) if phi else None


def phi_shifts_to_centre(sweep):
    r = Row("3.1", "\"as the dissipation is increased we see that the particles shift towards the "
            "center\" (beta = -0.99)", "phi(centre) / mean phi rises at every step from e = 0.99 "
            "to 0.8", PROFILES)
    pts = [(j.e, centre_excess(j), None) for j in r.results(sweep, beta=-0.99)]
    r.show("phi(centre) / mean: " + sequence(pts))
    r.check(trend(pts, True), "beta = -0.99")
    return r


def velocity_difference(j):
    u = j.profile("u_x")
    return centre_value(u) - wall_value(u) if u else None


def ux_gradient_rises(sweep):
    r = Row("3.1", "\"as the dissipation is increased to e=0.8 the velocity gradient across the "
            "channel width increases\" (beta = -0.99)", "U_x(centre) - U_x(wall bins) rises at "
            "every step from e = 0.99 to 0.8", PROFILES)
    pts = [(j.e, velocity_difference(j), None) for j in r.results(sweep, beta=-0.99)]
    r.show("U_x(centre) - U_x(wall): " + sequence(pts))
    r.check(trend(pts, True), "beta = -0.99")
    return r


def omega_signs(sweep):
    r = Row("3.1", "\"The rotational velocity (omega_z) is positive in the upper half of the channel "
            "and negative in the lower half\" (beta = -0.99)", "omega_z < 0 in every bin below "
            "the centreline and > 0 in every bin above it, at every e", PROFILES)
    for j in r.results(sweep, beta=-0.99):
        w = j.profile("omega_z")
        wrong = [y for y, v in w if (y < 0.5 and v >= 0) or (y > 0.5 and v <= 0)]
        r.show(f"e = {j.e:g}: {len(wrong)} bins of the wrong sign")
        r.check(not wrong, f"e = {j.e:g}")
    return r


def omega_linear(sweep):
    r = Row("3.1", "omega_z \"has an almost linear profile in the elastic limit e=0.99\" "
            "(beta = -0.99)", "R^2 of the least-squares line through omega_z(y) >= 0.95 at e = 0.99",
            PROFILES)
    for j in r.results(sweep, beta=-0.99, e=0.99):
        r2 = line_fit_r2(j.profile("omega_z"))
        r.show(f"R^2 = {r2:.3f}")
        r.check(r2 >= 0.95, "e = 0.99")
    return r


def theta_opposite(sweep):
    r = Row("3.1", "\"The variation of the rotational granular temperature (theta) ... is found to "
            "be opposite to that of translational granular temperature\" (beta = -0.99)",
            "the correlation of theta(y) and T(y) across the 25 bins is negative, at every e",
            PROFILES)
    for j in r.results(sweep, beta=-0.99):
        c = pearson([v for _, v in j.profile("T")], [v for _, v in j.profile("theta")])
        r.show(f"e = {j.e:g}: {c:.2f}")
        r.check(c < 0, f"e = {j.e:g}")
    return r


def minima_at_centre(sweep, r, beta, quantities):
    for j in r.results(sweep, beta=beta):
        for q in quantities:
            p = j.profile(q)
            low = min(p, key=lambda t: t[1]) if p else (None, None)
            r.show(f"e = {j.e:g}: {q} lowest at y / W = {fmt(low[0], 2)}")
            r.check(minimum_at_centre(p), f"e = {j.e:g} {q}")
    return r


def t_minimum_smooth(sweep):
    r = Row("3.1", "\"In a region of increased density ... the granular temperature decreases, see "
            "Fig. 3.3(d)\" (beta = -0.99)", "T(y) lowest in the centre bins, at every e", PROFILES)
    return minima_at_centre(sweep, r, -0.99, ("T",))


def phi_rough_elastic(sweep):
    r = Row("3.1", "\"the volume fraction is much higher in the center region even for nearly "
            "elastic particles\" (beta = 0)", "at e = 0.99: phi(y) largest in the centre bins, and "
            "phi(centre) / mean above that of beta = -0.99 at e = 0.99", PROFILES)
    rough, smooth = r.results(sweep, beta=0.0, e=0.99), r.results(sweep, beta=-0.99, e=0.99)
    for j in rough:
        r.show(f"phi(centre) / mean {fmt(centre_excess(j))}" + "".join(
            f" (beta = -0.99: {fmt(centre_excess(s))})" for s in smooth))
        r.check(dense_centre(j.profile("phi")), "centre peak")
        for s in smooth:
            r.check(centre_excess(j) > centre_excess(s), "higher than beta = -0.99")
    return r


def compare_betas(sweep, r, value, beta, other, above=True):
    """Per e: value(job at `beta`) above (or below) value(job at `other`)."""
    one = {j.e: j for j in r.results(sweep, beta=beta)}
    two = {j.e: j for j in r.results(sweep, beta=other)}
    for e in sorted(set(one) & set(two), reverse=True):
        a, b = value(one[e]), value(two[e])
        r.show(f"e = {e:g}: {fmt(a)} against {fmt(b)}")
        r.check(a > b if above else a < b, f"e = {e:g}")
    return r


def ux_gradient_rough(sweep):
    r = Row("3.1", "\"This further results in higher velocity gradients for U_x\" (beta = 0, "
            "against beta = -0.99)", "U_x(centre) - U_x(wall bins) at beta = 0 above that at "
            "beta = -0.99, at every e", PROFILES)
    return compare_betas(sweep, r, velocity_difference, 0.0, -0.99)


def temperatures_low_rough(sweep):
    r = Row("3.1", "\"consequently lower granular temperatures in the center\" (beta = 0)",
            "T(y) and theta(y) lowest in the centre bins, at every e", PROFILES)
    return minima_at_centre(sweep, r, 0.0, ("T", "theta"))


def omega_wall_gradient_rough(sweep):
    r = Row("3.1", "\"the rotational velocity gradients are much higher near the wall in comparison "
            "to that for smooth particles\" (beta = 0)", "abs(wall gradient of omega_z) at beta = 0 "
            "above that at beta = -0.99, at every e", WALLS)
    return compare_betas(sweep, r, lambda j: abs(j["wall_gradient_omega_z"]), 0.0, -0.99)


def omega_smaller_rough(sweep):
    r = Row("3.1", "\"the rotational velocities are less in magnitude, Fig. 3.7(c), in comparison "
            "to beta=-0.99\" (beta = 0.99)", "max abs(omega_z(y)) at beta = 0.99 below that at "
            "beta = -0.99, at every e", PROFILES)
    value = lambda j: max(abs(v) for _, v in j.profile("omega_z"))
    return compare_betas(sweep, r, value, 0.99, -0.99, above=False)


def temperatures_low_perfect(sweep):
    r = Row("3.1", "\"We have translational as well as rotational temperature minima at the center "
            "of the channel\" (beta = 0.99)", "T(y) and theta(y) lowest in the centre bins, at "
            "every e", PROFILES)
    return minima_at_centre(sweep, r, 0.99, ("T", "theta"))


# ---- 3.1.1 Kn, slip and walls --------------------------------------------------------------

def kn_rises(sweep):
    r = Row("3.1.1", "\"Fig. 3.8 shows that Kn increases with dissipation, as e decreases from "
            "0.99 to 0.8\"", "Kn(y) rises at every step from e = 0.99 to 0.8 in every bin, for "
            "each beta", "Kn(y) = lambda(y) / W per bin (free paths by their midpoint)")
    for beta in BETAS:
        jobs = r.results(sweep, beta=beta)
        if len(jobs) < 2:
            continue
        profiles = [dict(j.profile("Kn")) for j in jobs]
        ys = sorted(set.intersection(*(set(p) for p in profiles)))
        good = sum(1 for y in ys if trend([(j.e, p[y], None) for j, p in zip(jobs, profiles)], True))
        r.show(f"{by_beta(beta)}: {good} of {len(ys)} bins; centre " +
               sequence([(j.e, j["knudsen_centre"], None) for j in jobs]))
        if ys:
            r.check(good == len(ys), by_beta(beta))
    return r


def kn_above(sweep):
    r = Row("3.2", "\"the Knudsen number for all cases is larger than 0.1 (Kn > 0.1)\"",
            "Kn(y) > 0.1 in every bin of every job", "Kn(y) per bin")
    for j in r.results(sweep):
        kn = j.profile("Kn")
        if kn:
            low = min(kn, key=lambda p: p[1])
            r.check(low[1] > 0.1, f"{j.name()} ({fmt(low[1])} at y / W = {low[0]:.2f})")
    r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} jobs above 0.1 everywhere; lowest "
           + ", ".join(label for ok, label in r.cases if not ok))
    return r


def decay_length(points):
    """The decay length of ln P(l) by least squares over [(l, P)] (None: too few points)."""
    pts = [(l, p) for l, p in points if p > 0]
    if len(pts) < 3:
        return None
    xs, ys = [l for l, _ in pts], [math.log(p) for _, p in pts]
    mx, my = mean(xs), mean(ys)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    return -1 / slope if slope < 0 else float("inf")


def free_path_tails(sweep):
    r = Row("3.1.1", "\"For all cases, the tails of P(l) appear to follow an exponential as in a "
            "molecular gas\"", "ln P(l) straight in the tail: its decay length fitted over "
            "2-4 lambda and over 4-8 lambda agree within 25 %, in every job",
            "P(l) of all slabs (free_paths.parquet), lambda the job's mean free path")
    if not r.needs(sweep, "free_paths"):
        return r
    for j in r.results(sweep):
        lam, pl = j["mean_free_path"], j.free_paths()
        a = decay_length([(l, p) for l, p in pl if 2 * lam <= l <= 4 * lam])
        b = decay_length([(l, p) for l, p in pl if 4 * lam <= l <= 8 * lam])
        if a and b:
            r.show(f"{j.name()}: {fmt(a / lam)} and {fmt(b / lam)} lambda")
            r.check(abs(b / a - 1) <= 0.25, j.name())
    return r


def column_trend(sweep, r, column, betas, rises, magnitude=False):
    for beta in betas:
        pts = [(j.e, abs(j[column]) if magnitude else j[column], None)
               for j in r.results(sweep, beta=beta) if j[column] is not None]
        r.show(f"{by_beta(beta)}: {sequence(pts)}")
        r.check(trend(pts, rises), by_beta(beta))
    return r


def slip_rises(sweep):
    r = Row("3.1.1", "\"The slip for translational ... velocities increases with increasing "
            "dissipation\"", "slip_velocity rises at every step from e = 0.99 to 0.8, each beta",
            WALLS)
    return column_trend(sweep, r, "slip_velocity", BETAS, True)


def rotational_slip_rises(sweep):
    r = Row("3.1.1", "\"The slip for ... rotational velocities increases with increasing "
            "dissipation\"", "slip_rotational rises at every step from e = 0.99 to 0.8, each beta",
            WALLS)
    return column_trend(sweep, r, "slip_rotational", BETAS, True)


def slip_smooth_above_perfect(sweep):
    r = Row("3.1.1", "\"The slip is larger for the smooth limit beta=-0.99 than the spin reversal "
            "case beta=0.99\"", "slip_velocity at beta = -0.99 above that at beta = 0.99, at every e",
            WALLS)
    return compare_betas(sweep, r, lambda j: j["slip_velocity"], -0.99, 0.99)


def slip_largest_rough(sweep):
    r = Row("3.1.1", "\"but the slip is largest for beta=0\"", "slip_velocity at beta = 0 above "
            "those at beta = -0.99 and 0.99, at every e", WALLS)
    hi = {j.e: j for j in r.results(sweep, beta=0.0)}
    others = [{j.e: j for j in r.results(sweep, beta=b)} for b in (-0.99, 0.99)]
    for e in sorted(hi, reverse=True):
        rest = [o[e]["slip_velocity"] for o in others if e in o]
        if rest:
            r.show(f"e = {e:g}: {fmt(hi[e]['slip_velocity'])} against " +
                   ", ".join(fmt(v) for v in rest))
            r.check(hi[e]["slip_velocity"] > max(rest), f"e = {e:g}")
    return r


def wall_temperature_falls(sweep):
    r = Row("3.1.1", "\"The translational granular temperature near the wall (T_w) decreases with "
            "increasing dissipation\" (\"However, for ... beta=0, there is negligible effect\")",
            "wall_temperature falls at every step from e = 0.99 to 0.8, at beta = -0.99 and 0.99",
            WALLS)
    return column_trend(sweep, r, "wall_temperature", (-0.99, 0.99), False)


def relative_range(values):
    return (max(values) - min(values)) / mean(values) if values else None


def wall_temperature_flat_rough(sweep):
    r = Row("3.1.1", "\"for the case of rough particles, beta=0, there is negligible effect of e on "
            "T_w\"", "at beta = 0, (max - min) / mean of wall_temperature over e <= 10 % and below "
            "that of beta = -0.99 and of 0.99", WALLS)
    spread = {}
    for beta in BETAS:
        values = [j["wall_temperature"] for j in r.results(sweep, beta=beta)]
        if len(values) >= 2:
            spread[beta] = relative_range(values)
            r.show(f"{by_beta(beta)}: {100 * spread[beta]:.1f} %")
    if 0.0 in spread:
        r.check(spread[0.0] <= 0.1, "within 10 %")
        for beta in (-0.99, 0.99):
            if beta in spread:
                r.check(spread[0.0] < spread[beta], f"below {by_beta(beta)}")
    return r


def temperature_jump(sweep):
    r = Row("3.1.1", "beta = 0 \"has smaller temperature jumps\" (the jump T_w - T_s)",
            "T_w - T_s at beta = 0 below that at the other beta", WALLS)
    r.missing = ("not measured: needs the wall temperature T_s, which a fixed wall with e_w = "
                 "beta_w = 1 does not have (T_w and theta_w are tabulated)")
    return r


def theta_wall_like_slip(sweep):
    r = Row("3.1.1", "\"The rotational temperature near the wall (theta_w) also has a similar "
            "dependence on e like the rotational velocity\"", "theta_w and slip_rotational change "
            "with e the same way: their correlation over e is positive, each beta", WALLS)
    for beta in BETAS:
        jobs = r.results(sweep, beta=beta)
        if len(jobs) >= 3:
            c = pearson([j["wall_rotational_temperature"] for j in jobs],
                        [j["slip_rotational"] for j in jobs])
            r.show(f"{by_beta(beta)}: {c:.2f}")
            r.check(c > 0, by_beta(beta))
    return r


def theta_wall_rises_rough(sweep):
    r = Row("3.1.1", "\"for rough particles, there is an increase in theta_w with increasing "
            "dissipation\"", "wall_rotational_temperature rises at every step from e = 0.99 to "
            "0.8 at beta = 0 (\"rough\" is beta = 0 in the thesis' naming)", WALLS)
    return column_trend(sweep, r, "wall_rotational_temperature", (0.0,), True)


def velocity_gradient_rises(sweep):
    r = Row("3.1.1", "\"translational velocity gradient near the walls whose magnitude increases "
            "with dissipation (e) for all beta\"", "abs(wall_gradient_u_x) rises at every step "
            "from e = 0.99 to 0.8, each beta", WALLS)
    return column_trend(sweep, r, "wall_gradient_u_x", BETAS, True, magnitude=True)


def rotational_gradient_rises(sweep):
    r = Row("3.1.1", "\"the rotational velocity gradient also increases with dissipation\"",
            "abs(wall_gradient_omega_z) rises at every step from e = 0.99 to 0.8, each beta", WALLS)
    return column_trend(sweep, r, "wall_gradient_omega_z", BETAS, True, magnitude=True)


def gradient_statement(sweep, r, column):
    for beta in (0.0, 0.99):
        pts = [(j.e, j[column], None) for j in r.results(sweep, beta=beta)]
        r.show(f"{by_beta(beta)}: {sequence(pts)}")
        r.check(trend(pts, False), by_beta(beta))
    pts = [(j.e, j[column], None) for j in r.results(sweep, beta=-0.99)]
    r.show(f"beta = -0.99: {sequence(pts)}")
    r.check(non_monotonic(pts), "beta = -0.99 non-monotonic")
    return r


def temperature_gradient(sweep):
    r = Row("3.1.1", "\"The gradient in translational temperature near wall decreases with "
            "increasing dissipation for both beta = 0 and beta = 0.99, however, for beta = -0.99, "
            "it behaves non-monotonically with e\"", "wall_gradient_temperature (dT/dy' into the "
            "channel, signed) falls at every step from e = 0.99 to 0.8 at beta = 0 and 0.99; at "
            "beta = -0.99 it changes direction", WALLS)
    return gradient_statement(sweep, r, "wall_gradient_temperature")


def rotational_temperature_gradient(sweep):
    r = Row("3.1.1", "\"A similar variation is observed for the gradient of rotational "
            "temperature\"", "wall_gradient_rotational_temperature as the row above",
            WALLS)
    return gradient_statement(sweep, r, "wall_gradient_rotational_temperature")


# ---- 3.2 VDFs -----------------------------------------------------------------------------

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


FOUR = ("C_y", "C_z", "Omega_x", "Omega_y")


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


def super_gaussian(m):
    return m["kurtosis"] - 3 > SIG * m["kurtosis_error"]


def sub_gaussian(m):
    return 3 - m["kurtosis"] > SIG * m["kurtosis_error"]


def omega_z_super_smooth(sweep):
    r = Row("3.2", "\"the tails of P(Omega_z) are super-Gaussian for beta = -0.99 in all bins "
            "(Fig. 3.12(f))\" (e = 0.8)", f"kurtosis of Omega_z above 3 by more than {SIG:g} "
            "errors in every bin", moments_averaging(sweep, "every bin"))
    for j in r.results(sweep, beta=-0.99, e=0.8):
        for s in j.moment_slabs():
            m = j.moment(s, "Omega_z")
            r.check(super_gaussian(m), f"{bin_name(s)} ({kurt(m)})")
        r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} bins")
    return r


def centre_points(sweep, r, beta, component, value):
    return [(j.e,) + value(j.moment(CENTRE, component)) for j in r.results(sweep, beta=beta)
            if j.moment(CENTRE, component)]


def cx_tail_negative_grows(sweep):
    r = Row("3.2", "\"as the dissipation is increased, the P(C_x) distribution tail deviates away "
            "from the Gaussian towards negative side\" (beta = -0.99, bin 13, Fig. 3.13)",
            "skewness of C_x in bin 13 falls at every step from e = 0.99 to 0.8 (steps against "
            f"within {SIG:g} errors)", moments_averaging(sweep, "bin 13"))
    pts = centre_points(sweep, r, -0.99, "C_x", lambda m: (m["skewness"], m["skewness_error"]))
    r.show("skewness " + sequence(pts, 2))
    r.check(trend(pts, False), "bin 13")
    return r


def excess(m):
    return abs(m["kurtosis"] - 3), m["kurtosis_error"]


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
    for j in r.results(sweep, beta=0.0, e=0.8):
        for s in j.moment_slabs():
            m = j.moment(s, "C_x")
            r.check(negative_skew(m), f"{bin_name(s)} ({skew(m)})")
        r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} bins")
    return r


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
        rest = [mean_excess(o[e]) for o in others if e in o]
        if rest:
            r.show(f"e = {e:g}: {fmt(mean_excess(rough[e]), 2)} against " +
                   ", ".join(fmt(v, 2) for v in rest))
            r.check(mean_excess(rough[e]) > max(rest), f"e = {e:g}")
    return r


# ---- 3.3 g(r) -----------------------------------------------------------------------------

G_TOL = 0.1


def g_deviation(curve):
    """max abs(g - 1) over 0.5 d bins from contact, and the counting error there."""
    m = merged(curve, 0.5, 1.0, 1e9)
    if not m:
        return None
    r, g, rel = max(m, key=lambda t: abs(t[1] - 1))
    return abs(g - 1), g * rel, r


G_AVERAGING = "g(r) of bins 1, 4, 13 (test particle in the bin), merged into 0.5 d shells"


def g_gas_like(sweep):
    r = Row("3.3", "\"there is negligible density correlation for any value of e, i.e., it behaves "
            "like a gas\"; \"no significant density correlation in any bin\"; \"without any density "
            "correlation irrespective of the value of particle roughness and dissipation level\"",
            f"abs(g(r) - 1) <= {G_TOL:g} in every 0.5 d shell from contact to r_max, bins 1, 4, 13, "
            "every job (a gas-like g = 1, against the liquid peaks g ~ 2-20 of ch. 4)", G_AVERAGING)
    if not r.needs(sweep, "pair_correlation"):
        return r
    worst = []
    for j in r.results(sweep):
        devs = [g_deviation(j.pair_correlation(s)) for s in THREE]
        devs = [d for d in devs if d]
        if devs:
            d = max(devs)
            worst.append((d, j))
            r.check(d[0] <= G_TOL, f"{j.name()} ({fmt(d[0], 2)} at r = {d[2]:.2f})")
    if worst:
        (d, err, rr), j = max(worst, key=lambda t: t[0][0])
        r.show(f"largest abs(g - 1) {fmt(d, 2)} +- {fmt(err, 1)} at r/d = {rr:.2f} ({j.name()})")
    return r


def g_bins_alike(sweep):
    r = Row("3.3", "\"there is no significant difference in g(r) for different bins\" (e = 0.8, "
            "Figs. 3.18(a)-3.20(a))", f"abs(g_bin(r) - g_13(r)) <= {G_TOL:g} in every 0.5 d shell "
            "for bins 1 and 4, each beta at e = 0.8", G_AVERAGING)
    if not r.needs(sweep, "pair_correlation"):
        return r
    for beta in BETAS:
        for j in r.results(sweep, beta=beta, e=0.8):
            ref = {round(x, 6): g for x, g, _ in merged(j.pair_correlation(CENTRE), 0.5, 1.0, 1e9)}
            diffs = [abs(g - ref[round(x, 6)]) for s in (WALL, SHEAR)
                     for x, g, _ in merged(j.pair_correlation(s), 0.5, 1.0, 1e9) if round(x, 6) in ref]
            if diffs:
                r.show(f"{by_beta(beta)}: largest difference {fmt(max(diffs), 2)}")
                r.check(max(diffs) <= G_TOL, by_beta(beta))
    return r


# ---- 3.4 Lambda ---------------------------------------------------------------------------

LAMBDA_AVERAGING = "Lambda(y) per bin, pooled over the window"


def lambda_side(sweep, r, beta, above):
    for j in r.results(sweep, beta=beta):
        lam = j.lambdas()
        if not lam:
            continue
        right = sum(1 for _, v, err in lam if (v - 1 / 3 if above else 1 / 3 - v) > SIG * err)
        wrong = sum(1 for _, v, err in lam if (1 / 3 - v if above else v - 1 / 3) > SIG * err)
        r.show(f"e = {j.e:g}: {right} of {len(lam)} bins on the stated side, {wrong} on the other")
        r.check(right == len(lam), f"e = {j.e:g}")
    return r


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


def lambda_above_smooth(sweep):
    r = Row("3.4", "\"Lambda(y) > 1/3 for every value of e\" (beta = -0.99)", "Lambda above 1/3 "
            f"by more than {SIG:g} errors in every bin (the whole profile; the old reading used the "
            "centre bin), at every e", LAMBDA_AVERAGING)
    return lambda_side(sweep, r, -0.99, True)


def lambda_towards_third_smooth(sweep):
    r = Row("3.4", "\"With increase of e, Lambda(y) shifts towards the molecular gas limit of 1/3\" "
            "(beta = -0.99)", "abs(mean of Lambda(y) - 1/3) falls at every step from e = 0.8 to "
            f"0.99 (steps against within {SIG:g} errors)", LAMBDA_AVERAGING + ", mean over the bins")
    pts = distance_points(sweep, r, -0.99, profile_mean)
    r.show("abs(mean - 1/3) " + sequence(pts, 2))
    r.check(trend(pts, True), "beta = -0.99")
    return r


def lambda_mean_non_monotonic_smooth(sweep):
    r = Row("3.4", "\"The mean of Lambda(y) varies non-monotonically with dissipation but remains "
            "above 1/3 limit\" (beta = -0.99)", "the mean of Lambda(y) over the bins changes "
            f"direction with e (beyond {SIG:g} errors) and lies above 1/3 by more than {SIG:g} "
            "errors at every e", LAMBDA_AVERAGING + ", mean over the bins")
    pts = [(j.e,) + profile_mean(j) for j in r.results(sweep, beta=-0.99) if profile_mean(j)]
    r.show("mean " + sequence(pts, 4))
    r.check(non_monotonic(pts), "non-monotonic")
    if pts:
        r.check(all(v - 1 / 3 > SIG * err for _, v, err in pts), "above 1/3")
    r.note = ("the thesis' previous sentence has Lambda(y) shift towards 1/3 as e grows, i.e. "
              "monotonically; both cannot hold for the mean")
    return r


def lambda_walls_vs_centre(sweep, r, beta, centre_lower):
    for j in r.results(sweep, beta=beta):
        lam = j.lambdas()
        if len(lam) < 3:
            continue
        c = dict((s, (v, e)) for s, v, e in lam)
        (vc, ec) = c[CENTRE]
        walls = [c[lam[0][0]], c[lam[-1][0]]]
        for (vw, ew), side in zip(walls, ("bin 1", f"bin {lam[-1][0] + 1}")):
            diff = vw - vc if centre_lower else vc - vw
            r.check(diff > SIG * (ec ** 2 + ew ** 2) ** 0.5, f"e = {j.e:g} {side}")
        r.show(f"e = {j.e:g}: centre {pm(vc, ec, 4)}, walls {pm(walls[0][0], walls[0][1], 4)}, "
               f"{pm(walls[1][0], walls[1][1], 4)}")
    return r


def lambda_lower_middle_smooth(sweep):
    r = Row("3.4", "\"Lambda(y) is lower in the middle region of the domain as compared to wall "
            "regions\" (beta = -0.99)", f"Lambda in bin 13 below that in bin 1 and in bin 25 by more "
            f"than {SIG:g} errors, at every e", LAMBDA_AVERAGING)
    return lambda_walls_vs_centre(sweep, r, -0.99, True)


def lambda_below_rough(sweep):
    r = Row("3.4", "\"we see that Lambda < 1/3 for all values of e\" (beta = 0)", f"Lambda below "
            f"1/3 by more than {SIG:g} errors in every bin, at every e", LAMBDA_AVERAGING)
    return lambda_side(sweep, r, 0.0, False)


def lambda_wall_smaller_rough(sweep):
    r = Row("3.4", "\"The value of Lambda(y) near the wall is much smaller than that in the bulk\" "
            "(beta = 0)", f"Lambda in bins 1 and 25 below that in bin 13 by more than {SIG:g} errors, "
            "at every e", LAMBDA_AVERAGING)
    return lambda_walls_vs_centre(sweep, r, 0.0, False)


def lambda_monotonic_rough(sweep):
    r = Row("3.4", "\"both Lambda(0) and the mean of Lambda(y) approach 1/3 monotonically with "
            "decrease in inelasticity\" (beta = 0)", "abs(Lambda(bin 13) - 1/3) and abs(mean of "
            f"Lambda(y) - 1/3) fall at every step from e = 0.8 to 0.99 (steps against within {SIG:g} "
            "errors)", LAMBDA_AVERAGING + "; bin 13 and the mean over the bins")
    for name, value in (("Lambda(0)", lambda_centre), ("mean", profile_mean)):
        pts = distance_points(sweep, r, 0.0, value)
        r.show(f"abs({name} - 1/3) " + sequence(pts, 2))
        r.check(trend(pts, True), name)
    return r


def lambda_below_perfect(sweep):
    r = Row("3.4", "\"Lambda(y) for any value of e is less than 1/3\" (beta = 0.99)", f"Lambda below "
            f"1/3 by more than {SIG:g} errors in every bin, at every e", LAMBDA_AVERAGING)
    return lambda_side(sweep, r, 0.99, False)


def lambda_nearer_perfect(sweep):
    r = Row("3.4", "\"the profiles are nearer to 1/3\" (beta = 0.99 against beta = 0)",
            "the mean over the bins of abs(Lambda(y) - 1/3) at beta = 0.99 below that at beta = 0, at "
            "every e", LAMBDA_AVERAGING)
    distance = lambda j: mean(abs(v - 1 / 3) for _, v, _ in j.lambdas())
    return compare_betas(sweep, r, distance, 0.99, 0.0, above=False)


def lambda_towards_third_perfect(sweep):
    r = Row("3.4", "\"Increasing elasticity also pushes Lambda(y) towards 1/3. The variation in the "
            "inset also indicates the increase of orientational correlation in the system with "
            "increase of inelasticity\" (beta = 0.99)", "abs(Lambda(bin 13) - 1/3) and abs(mean of "
            f"Lambda(y) - 1/3) fall at every step from e = 0.8 to 0.99 (steps against within {SIG:g} "
            "errors)", LAMBDA_AVERAGING + "; bin 13 and the mean over the bins")
    for name, value in (("Lambda(0)", lambda_centre), ("mean", profile_mean)):
        pts = distance_points(sweep, r, 0.99, value)
        r.show(f"abs({name} - 1/3) " + sequence(pts, 2))
        r.check(trend(pts, True), name)
    return r


STATEMENTS = [
    no_structure, phi_uniform_elastic, phi_centre_peak, phi_shifts_to_centre, ux_gradient_rises,
    omega_signs, omega_linear, theta_opposite, t_minimum_smooth, phi_rough_elastic,
    ux_gradient_rough, temperatures_low_rough, omega_wall_gradient_rough, omega_smaller_rough,
    temperatures_low_perfect,
    kn_rises, kn_above, free_path_tails, slip_rises, rotational_slip_rises,
    slip_smooth_above_perfect, slip_largest_rough, wall_temperature_falls,
    wall_temperature_flat_rough, temperature_jump, theta_wall_like_slip, theta_wall_rises_rough,
    velocity_gradient_rises, rotational_gradient_rises, temperature_gradient,
    rotational_temperature_gradient,
    cx_negative_smooth, omega_z_asymmetric_smooth, four_symmetric_smooth, four_tails_smooth,
    bins_alike_smooth, omega_z_super_smooth, cx_tail_negative_grows, cy_tails_grow_symmetric,
    little_affected_smooth, omega_z_to_gaussian_smooth, cx_negative_rough, four_symmetric_rough,
    four_tails_rough, omega_z_shear_asymmetric_rough, omega_z_tails_rough,
    cx_asymmetric_rough_every_e, four_towards_gaussian_rough, omega_z_deviates_most_rough,
    cx_slight_perfect, six_to_gaussian_perfect, deviation_largest_rough,
    g_gas_like, g_bins_alike,
    lambda_above_smooth, lambda_towards_third_smooth, lambda_mean_non_monotonic_smooth,
    lambda_lower_middle_smooth, lambda_below_rough, lambda_wall_smaller_rough,
    lambda_monotonic_rough, lambda_below_perfect, lambda_nearer_perfect,
    lambda_towards_third_perfect,
]
