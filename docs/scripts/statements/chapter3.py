"""The thesis' statements of chapter 3 (phi = 0.01, sweeps/thesis-ch3.ron), one function each:
mean fields (3.1) and Kn, slip and wall values (3.1.1) here, the VDF shapes (3.2) in
`chapter3_vdf`, g(r) (3.3) and Lambda (3.4) in `chapter3_correlations`. Each takes a `Sweep`
and returns its `Row`; the tolerances are those of `readings`. `STATEMENTS` lists them all.
"""
import math

from .readings import (
    Row, centre_value, fmt, holds, line_fit_r2, mean, non_monotonic, pearson, sequence, trend,
    wall_value,
)
from .cases import (
    BETAS, PROFILES, WALLS, by_beta, centre_excess, column_trend, compare_betas, dense_centre,
    minima_at_centre, value_trend,
)
from .chapter3_vdf import (
    bins_alike_smooth, cx_asymmetric_rough_every_e, cx_negative_rough, cx_negative_smooth,
    cx_slight_perfect, cx_tail_negative_grows, cy_tails_grow_symmetric, deviation_largest_rough,
    four_symmetric_rough, four_symmetric_smooth, four_tails_rough, four_tails_smooth,
    four_towards_gaussian_rough, little_affected_smooth, omega_z_asymmetric_smooth,
    omega_z_deviates_most_rough, omega_z_shear_asymmetric_rough, omega_z_super_smooth,
    omega_z_tails_rough, omega_z_to_gaussian_smooth, six_to_gaussian_perfect,
)
from .chapter3_correlations import (
    g_bins_alike, g_gas_like, lambda_above_smooth, lambda_below_perfect, lambda_below_rough,
    lambda_lower_middle_smooth, lambda_mean_non_monotonic_smooth, lambda_monotonic_rough,
    lambda_nearer_perfect, lambda_towards_third_perfect, lambda_towards_third_smooth,
    lambda_wall_smaller_rough,
)


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


def phi_centre_peak(sweep):
    r = Row("3.1", "\"the volume fraction is higher at the center, specifically for e=0.8\" "
            "(beta = -0.99)", "phi(y) largest in the centre bins and the centre above the channel "
            "mean at e = 0.8", PROFILES)
    for j in r.results(sweep, beta=-0.99, e=0.8):
        phi = j.profile("phi")
        if not phi:
            continue
        r.show(f"centre {fmt(centre_value(phi))}, mean {fmt(mean(v for _, v in phi))}, largest "
               f"at y / W = {max(phi, key=lambda p: p[1])[0]:.2f}")
        r.check(dense_centre(phi), "e = 0.8")
    return r


def phi_shifts_to_centre(sweep):
    r = Row("3.1", "\"as the dissipation is increased we see that the particles shift towards the "
            "center\" (beta = -0.99)", "phi(centre) / mean phi rises at every step from e = 0.99 "
            "to 0.8", PROFILES)
    return value_trend(sweep, r, -0.99, centre_excess, True, "phi(centre) / mean:")


def velocity_difference(j):
    u = j.profile("u_x")
    return centre_value(u) - wall_value(u) if u else None


def ux_gradient_rises(sweep):
    r = Row("3.1", "\"as the dissipation is increased to e=0.8 the velocity gradient across the "
            "channel width increases\" (beta = -0.99)", "U_x(centre) - U_x(wall bins) rises at "
            "every step from e = 0.99 to 0.8", PROFILES)
    return value_trend(sweep, r, -0.99, velocity_difference, True, "U_x(centre) - U_x(wall):")


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
            r.check(holds(lambda a, b: a > b, centre_excess(j), centre_excess(s)),
                    "higher than beta = -0.99")
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
        if not lam:
            continue
        a = decay_length([(l, p) for l, p in pl if 2 * lam <= l <= 4 * lam])
        b = decay_length([(l, p) for l, p in pl if 4 * lam <= l <= 8 * lam])
        if a and b:
            r.show(f"{j.name()}: {fmt(a / lam)} and {fmt(b / lam)} lambda")
            r.check(abs(b / a - 1) <= 0.25, j.name())
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
        rest = [o[e]["slip_velocity"] for o in others
                if e in o and o[e]["slip_velocity"] is not None]
        if rest and hi[e]["slip_velocity"] is not None:
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
        values = [j["wall_temperature"] for j in r.results(sweep, beta=beta)
                  if j["wall_temperature"] is not None]
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
        jobs = [j for j in r.results(sweep, beta=beta)
                if j["wall_rotational_temperature"] is not None and j["slip_rotational"] is not None]
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
