"""The thesis' statements of its section 4.1.1 (phi = 0.1): the VDFs at bins 1, 4, 13 and
the conclusion's (ch. 6) sentence on them, one function each.
"""
from .readings import (
    KURT_TOL, LOW_TOL, NULL, Row, SIG, SKEW_TOL, fmt, low_velocity_deviation, mean, peaks,
    sequence, trend,
)
from .cases import (
    BETAS, DISSIPATIVE, SIX, THREE, by_beta, excess, gaussian, kurt, moment_cases,
    moments_averaging, negative_skew, skew, skewed, super_gaussian, symmetric, tails_deviate,
)
from .sweep import CENTRE, SHEAR, WALL, bin_name


VDF3 = "bins 1, 4, 13"

PLUG_E = ("in bin 13 at e = 0.7, 0.8, 0.9 (the same paragraph has C_x, C_y, C_z approach the "
          "Gaussian at bin 13 as e -> 1: e = 0.99 is read there)")


def deviates(m):
    return tails_deviate(m) or abs(m["skewness"]) > SKEW_TOL + SIG * m["skewness_error"]


def every_e(sweep, r, beta, slabs, components, test, show, es=None):
    for j in r.results(sweep, beta=beta, es=es):
        moment_cases(sweep, r, beta, j.e, slabs, components, test,
                     lambda m, e=j.e: f"e = {e:g} {show(m)}")
    return r


def cx_negative_wall_shear_smooth(sweep):
    r = Row("4.1.1", "\"there is asymmetric deviation from the Gaussian towards negative side near the "
            "wall (bin = 1) as well as in the shear region (bin = 4)\" (beta = -0.99, C_x)",
            f"skewness of C_x below 0 by more than {SIG:g} errors in bins 1 and 4, at every e",
            moments_averaging(sweep, "bins 1, 4"))
    return every_e(sweep, r, -0.99, (WALL, SHEAR), ("C_x",), negative_skew, skew)


def cx_deviates_plug_smooth(sweep):
    r = Row("4.1.1", "\"the particles deviate significantly in the plug region (bin = 13)\" "
            "(beta = -0.99, C_x)", f"abs(kurtosis - 3) above {KURT_TOL:g} or abs(skewness) above "
            f"{SKEW_TOL:g}, by more than {SIG:g} errors, " + PLUG_E,
            moments_averaging(sweep, "bin 13"))
    return every_e(sweep, r, -0.99, (CENTRE,), ("C_x",), deviates, lambda m: f"{skew(m)}, {kurt(m)}",
                   es=DISSIPATIVE)


def gaussian_off_centre_deviating_centre(sweep, r, components):
    for j in r.results(sweep, beta=-0.99):
        for c in components:
            near = [j.moment(s, c) for s in (WALL, SHEAR)]
            mid = j.moment(CENTRE, c)
            if all(near) and mid:
                r.show(f"e = {j.e:g} {c}: bins 1, 4 kurtosis {fmt(near[0]['kurtosis'])}, "
                       f"{fmt(near[1]['kurtosis'])}; bin 13 {kurt(mid)}, skewness {skew(mid)}")
                r.check(all(gaussian(m) for m in near), f"e = {j.e:g} {c} Gaussian at bins 1, 4")
                if j.e < 0.95:
                    r.check(symmetric(mid) and tails_deviate(mid), f"e = {j.e:g} {c} bin 13")
    return r


def cy_smooth(sweep):
    r = Row("4.1.1", "\"The VDF of spanwise translational velocity C_y ... is almost Gaussian near the "
            "wall and in shear region (with negligible asymmetry) but the middle region (bin = 13), "
            "though symmetric, has significant deviation from a Gaussian\" (beta = -0.99)",
            f"bins 1, 4: abs(kurtosis - 3) <= {KURT_TOL:g} and abs(skewness) <= {SKEW_TOL:g}; bin 13: "
            f"skewness within {NULL:g} errors of 0 and abs(kurtosis - 3) above {KURT_TOL:g} by "
            f"{SIG:g} errors; at every e", moments_averaging(sweep, VDF3))
    return gaussian_off_centre_deviating_centre(sweep, r, ("C_y",))


def cz_omega_y_smooth(sweep):
    r = Row("4.1.1", "\"Similar symmetric deviations are observed for C_z in Fig. 4.7(c) and Omega_y "
            "in Fig. 4.7(e)\" (beta = -0.99)", "as the row above, for C_z and Omega_y",
            moments_averaging(sweep, VDF3))
    return gaussian_off_centre_deviating_centre(sweep, r, ("C_z", "Omega_y"))


def vdf_averaging(sweep, bins):
    return f"the VDFs of {bins} (P(0) = 1); {sweep.fluctuations()}"


def omega_x_low_smooth(sweep):
    r = Row("4.1.1", "\"the probability distribution function of Omega_x shows considerable "
            "deviations from a Gaussian near the low velocity region\" (beta = -0.99)",
            f"max abs(P(x) - exp(-x^2/2)) over abs(x) <= 1 above {LOW_TOL:g} in bins 1, 4, 13, at "
            "every e", vdf_averaging(sweep, VDF3))
    for j in r.results(sweep, beta=-0.99):
        for s in THREE:
            d = low_velocity_deviation(j.vdf(s, "Omega_x"))
            if d is not None:
                r.show(f"e = {j.e:g} {bin_name(s)}: {fmt(d, 2)}")
                r.check(d > LOW_TOL, f"e = {j.e:g} {bin_name(s)}")
    return r


def omega_z_low_rises_smooth(sweep):
    r = Row("4.1.1", "\"The VDF for Omega_z shows interesting deviation ... especially near the low "
            "velocity region which increases with dissipation (e)\" (beta = -0.99)",
            "max abs(P(x) - exp(-x^2/2)) over abs(x) <= 1 of Omega_z rises at every step from "
            "e = 0.99 to 0.7, in bins 1, 4, 13", vdf_averaging(sweep, VDF3))
    for s in THREE:
        pts = [(j.e, low_velocity_deviation(j.vdf(s, "Omega_z")), None)
               for j in r.results(sweep, beta=-0.99) if j.vdf(s, "Omega_z")]
        r.show(f"{bin_name(s)}: " + sequence(pts, 2))
        r.check(trend(pts, True), bin_name(s))
    return r


def double_peak(vdf):
    """Two or more maxima of P(x) within abs(x) <= 2 rising 0.05 above the dip between them."""
    return len(peaks([(x, p) for x, p, _ in vdf if abs(x) <= 2.0 + 1e-9], 0.05)) >= 2


def omega_z_double_peak_smooth(sweep):
    r = Row("4.1.1", "\"The double-peak deviations near the low-velocity region in the shear region "
            "(bin = 4) are also observed\" (beta = -0.99, Omega_z)", "P(Omega_z) in bin 4 has two "
            "maxima within abs(x) <= 2, each 0.05 above the dip between them, at one e at least",
            vdf_averaging(sweep, "bin 4"))
    found = [j.e for j in r.results(sweep, beta=-0.99) if double_peak(j.vdf(SHEAR, "Omega_z"))]
    done = [j for j in r.results(sweep, beta=-0.99) if j.vdf(SHEAR, "Omega_z")]
    r.show(f"double peak at e = {', '.join(f'{e:g}' for e in found) or 'none'} of "
           f"{len(done)} e")
    if done:
        r.check(bool(found), "any e")
    return r


def mean_excess3(j, components=SIX):
    values = [abs(j.moment(s, c)["kurtosis"] - 3) for s in THREE for c in components
              if j.moment(s, c)]
    return mean(values)


def deviations_grow(sweep, r, beta):
    pts = [(j.e, mean_excess3(j), None) for j in r.results(sweep, beta=beta) if mean_excess3(j)]
    r.show("mean abs(kurtosis - 3) " + sequence(pts, 2))
    r.check(trend(pts, True), by_beta(beta))
    return r


def deviations_grow_smooth(sweep):
    r = Row("4.1.1", "\"the deviations in all these cases are strongly affected by dissipation (e) "
            "and increase with increasing dissipation\" (beta = -0.99)", "the mean of abs(kurtosis "
            "- 3) over the six components and bins 1, 4, 13 rises at every step from e = 0.99 to 0.7",
            moments_averaging(sweep, VDF3 + " (mean)"))
    return deviations_grow(sweep, r, -0.99)


def to_gaussian_centre(sweep, r, beta, components):
    jobs = r.results(sweep, beta=beta)
    for c in components:
        pts = [(j.e,) + excess(j.moment(CENTRE, c)) for j in jobs if j.moment(CENTRE, c)]
        last = [j.moment(CENTRE, c) for j in jobs if abs(j.e - 0.99) < 1e-9 and j.moment(CENTRE, c)]
        r.show(f"{c}: abs(kurtosis - 3) " + sequence(pts, 2))
        r.check(trend(pts, True) and all(gaussian(m) for m in last) if last else None, c)
    return r


TO_GAUSSIAN = (f"per component in bin 13: abs(kurtosis - 3) falls from e = 0.7 to 0.99 (steps "
               f"against within {SIG:g} errors) and at e = 0.99 abs(kurtosis - 3) <= {KURT_TOL:g}, "
               f"abs(skewness) <= {SKEW_TOL:g}")


def c_to_gaussian_smooth(sweep):
    r = Row("4.1.1", "\"the VDFs of C_x, C_y and C_z at the channel centreline (bin = 13) approach a "
            "Gaussian distribution in the limit of elastic collisions\" (beta = -0.99)", TO_GAUSSIAN,
            moments_averaging(sweep, "bin 13"))
    return to_gaussian_centre(sweep, r, -0.99, ("C_x", "C_y", "C_z"))


def not_gaussian(j, s, c):
    m, vdf = j.moment(s, c), j.vdf(s, c)
    low = low_velocity_deviation(vdf) if vdf else None
    return m is not None and (deviates(m) or (low is not None and low > LOW_TOL))


NOT_GAUSSIAN = (f"abs(kurtosis - 3) above {KURT_TOL:g} or abs(skewness) above {SKEW_TOL:g} by "
                f"{SIG:g} errors, or a low-velocity deviation above {LOW_TOL:g}")


def omega_stay_smooth(sweep):
    r = Row("4.1.1", "\"In contrast, however, the VDFs of Omega_x, Omega_y and Omega_z deviate from a "
            "Gaussian even in the elastic limit\" (beta = -0.99, bin 13)", f"at e = 0.99 in bin 13: "
            f"{NOT_GAUSSIAN}, each component", moments_averaging(sweep, "bin 13") + "; its VDFs")
    for j in r.results(sweep, beta=-0.99, e=0.99):
        for c in ("Omega_x", "Omega_y", "Omega_z"):
            m = j.moment(CENTRE, c)
            if m:
                r.show(f"{c}: {kurt(m)}")
                r.check(not_gaussian(j, CENTRE, c), c)
    return r


def cx_asymmetric_rough(sweep):
    r = Row("4.1.1", "\"C_x which is asymmetric in the shear region (bin = 4) as well as in plug "
            "region (bin = 13) and near the wall (bin = 1)\" (beta = 0)", f"abs(skewness of C_x) "
            f"beyond {SIG:g} errors in bins 1, 4, 13, at every e", moments_averaging(sweep, VDF3))
    return every_e(sweep, r, 0.0, THREE, ("C_x",), skewed, skew)


def cy_cz_rough(sweep):
    r = Row("4.1.1", "\"The asymmetry is absent for C_y (except in bin = 4) but the deviation from a "
            "Gaussian is present in significant amount in the plug region ... Similar observations "
            "can be made for C_z\" (beta = 0)", f"C_y and C_z: skewness within {NULL:g} errors of 0 in "
            f"bins 1 and 13, beyond {SIG:g} errors in bin 4; abs(kurtosis - 3) above {KURT_TOL:g} by "
            f"{SIG:g} errors in bin 13; at every e", moments_averaging(sweep, VDF3))
    for j in r.results(sweep, beta=0.0):
        for c in ("C_y", "C_z"):
            ms = [j.moment(s, c) for s in THREE]
            if all(ms):
                r.show(f"e = {j.e:g} {c}: skewness " + ", ".join(skew(m) for m in ms) +
                       f"; bin 13 {kurt(ms[2])}")
                r.check(symmetric(ms[0]) and skewed(ms[1]) and symmetric(ms[2]),
                        f"e = {j.e:g} {c} asymmetry")
                r.check(tails_deviate(ms[2]), f"e = {j.e:g} {c} plug")
    return r


def wall_bin_rough(sweep):
    r = Row("4.1.1", "\"the VDFs for all velocities near the wall (bin = 1) is that though the VDF is "
            "symmetric and Gaussian near the tail region\" (beta = 0)", f"bin 1: abs(skewness) <= "
            f"{SKEW_TOL:g} and abs(kurtosis - 3) <= {KURT_TOL:g}, each component at every e",
            moments_averaging(sweep, "bin 1"))
    r.note = ("the same section has C_x asymmetric \"near the wall (bin = 1)\" and Omega_z "
              "asymmetric in bin 1: the thesis contradicts itself there")
    return every_e(sweep, r, 0.0, (WALL,), SIX, gaussian, lambda m: f"{skew(m)}, {kurt(m)}")


def wall_bin_low_rough(sweep):
    r = Row("4.1.1", "\"there is deviation in the low-velocity region which increases with decrease "
            "in elasticity\" (beta = 0, bin 1, all velocities)", "max abs(P(x) - exp(-x^2/2)) over "
            f"abs(x) <= 1 in bin 1 above {LOW_TOL:g} at e = 0.7 and rising at every step from e = 0.99 "
            "to 0.7, each component", vdf_averaging(sweep, "bin 1"))
    for c in SIX:
        pts = [(j.e, low_velocity_deviation(j.vdf(WALL, c)), None)
               for j in r.results(sweep, beta=0.0) if j.vdf(WALL, c)]
        if pts:
            r.show(f"{c}: " + sequence(pts, 2))
            r.check(trend(pts, True) and min(pts)[1] > LOW_TOL, c)
    return r


def omega_xy_symmetric_rough(sweep):
    r = Row("4.1.1", "\"The VDFs of Omega_x and Omega_y are symmetric in all bins\" (beta = 0)",
            f"their skewness within {NULL:g} errors of 0 in bins 1, 4, 13, at every e",
            moments_averaging(sweep, VDF3))
    return every_e(sweep, r, 0.0, THREE, ("Omega_x", "Omega_y"), symmetric, skew)


def omega_z_rough(sweep):
    r = Row("4.1.1", "\"The VDF of Omega_z is asymmetric in bin = 1 and bin = 4. Near the wall, the "
            "tail of P(Omega_z) follows a super-Gaussian whereas in the shear region there is "
            "interesting negative asymmetry. In the plug region, there is large deviation with "
            "highly stretched tails\" (beta = 0)", f"Omega_z: bin 1 skewness beyond {SIG:g} errors "
            f"and kurtosis above 3 by {SIG:g} errors; bin 4 skewness below 0 by {SIG:g} errors; bin "
            f"13 kurtosis above 3 + {KURT_TOL:g} by {SIG:g} errors; at every e",
            moments_averaging(sweep, VDF3))
    for j in r.results(sweep, beta=0.0):
        w, s, c = (j.moment(b, "Omega_z") for b in THREE)
        if w and s and c:
            r.show(f"e = {j.e:g}: bin 1 {skew(w)}, {kurt(w)}; bin 4 {skew(s)}; bin 13 {kurt(c)}")
            r.check(skewed(w) and super_gaussian(w), f"e = {j.e:g} bin 1")
            r.check(negative_skew(s), f"e = {j.e:g} bin 4")
            r.check(c["kurtosis"] - 3 > KURT_TOL + SIG * c["kurtosis_error"], f"e = {j.e:g} bin 13")
    return r


def deviations_grow_rough(sweep):
    r = Row("4.1.1", "\"increasing dissipation due to surface roughness with beta = 0 has resulted in "
            "increased deviations from the Gaussian distribution\" (beta = 0)", "the mean of "
            "abs(kurtosis - 3) over the six components and bins 1, 4, 13 rises at every step from "
            "e = 0.99 to 0.7", moments_averaging(sweep, VDF3 + " (mean)"))
    return deviations_grow(sweep, r, 0.0)


def c_like_smooth_perfect(sweep):
    r = Row("4.1.1", "\"The results for P(C_x), P(C_y) and P(C_z) are similar to those for smooth "
            "particles (beta = -0.99)\" (beta = 0.99)", f"per e, bin (1, 4, 13) and component: "
            f"kurtosis within {KURT_TOL:g} and skewness within {SKEW_TOL:g} of beta = -0.99's",
            moments_averaging(sweep, VDF3))
    rough = {j.e: j for j in r.results(sweep, beta=0.99)}
    smooth = {j.e: j for j in r.results(sweep, beta=-0.99)}
    for e in sorted(set(rough) & set(smooth), reverse=True):
        for s in THREE:
            for c in ("C_x", "C_y", "C_z"):
                a, b = rough[e].moment(s, c), smooth[e].moment(s, c)
                if a and b:
                    r.check(abs(a["kurtosis"] - b["kurtosis"]) <= KURT_TOL and
                            abs(a["skewness"] - b["skewness"]) <= SKEW_TOL,
                            f"e = {e:g} {bin_name(s)} {c}")
    r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} alike")
    return r


def omega_to_gaussian_perfect(sweep):
    r = Row("4.1.1", "\"the VDFs of Omega_x, Omega_y and Omega_z approach Gaussian distribution in the "
            "limit of elastic collisions\" (beta = 0.99; bin 13, as the contrasting beta = -0.99 "
            "sentence)", TO_GAUSSIAN, moments_averaging(sweep, "bin 13 (the old reading averaged "
                                                       "all slabs)"))
    return to_gaussian_centre(sweep, r, 0.99, ("Omega_x", "Omega_y", "Omega_z"))


def elastic_limit_conclusion(sweep):
    r = Row("6", "\"Even in the elastic limit (e -> 1), the VDFs of all velocity components deviate "
            "considerably from Gaussian\" (the moderately dense flow)", f"at e = 0.99 in bin 13: "
            f"{NOT_GAUSSIAN}, each of the six components at each beta",
            moments_averaging(sweep, "bin 13") + "; its VDFs")
    for beta in BETAS:
        for j in r.results(sweep, beta=beta, e=0.99):
            bad = [c for c in SIX if j.moment(CENTRE, c) and not_gaussian(j, CENTRE, c)]
            r.show(f"{by_beta(beta)}: deviating {', '.join(bad) or 'none'}")
            for c in SIX:
                if j.moment(CENTRE, c):
                    r.check(c in bad, f"{by_beta(beta)} {c}")
    r.note = ("the thesis contradicts itself: 4.1.1 has C_x, C_y, C_z at bin 13 (beta = -0.99) and "
              "the three Omega (beta = 0.99) approach the Gaussian as e -> 1; this row and those "
              "cannot all say yes")
    return r
