"""The thesis' statements of its sections 4.1.2 (g(r) in bin 13), 4.1.3 (Lambda) and 4.1.4
(velocity correlations) at phi = 0.1, and the conclusion's (ch. 6) on Lambda.
"""
from .readings import NULL, Row, SIG, fmt, mean, merged, near_contact, peaks, pm, sequence, trend
from .cases import BETAS, THREE, by_beta, lambda_centre, profile_mean, symmetric
from .sweep import CENTRE, SHEAR, WALL, bin_name


G13 = "g(r) of bin 13 (test particle in the bin), merged into 0.1 d shells"


def g_peaks(j):
    m = merged(j.pair_correlation(CENTRE), 0.1, 0.9, 1e9)
    return peaks([(r, g) for r, g, _ in m], 0.05)


def peak_near(found, r0):
    return any(abs(r - r0) <= 0.25 for r, _ in found)


def g_peaks_rough(sweep):
    r = Row("4.1.2", "\"It has a liquid-like structure ... There are peaks at r/d=2 and 3 ... However, "
            "there are no peaks at higher r/d\" (beta = 0)", "maxima of g(r) in bin 13 (each 0.05 "
            "above the dips beside it) within 0.25 d of r = 2 d and of r = 3 d, and none beyond "
            "3.5 d, at every e", G13)
    if not r.needs(sweep, "pair_correlation"):
        return r
    for j in r.results(sweep, beta=0.0):
        found = g_peaks(j)
        r.show(f"e = {j.e:g}: maxima at r/d = " + (", ".join(f"{x:.2f} ({g:.2f})" for x, g in found)
                                                   or "none"))
        r.check(peak_near(found, 2) and peak_near(found, 3) and not any(x > 3.5 for x, _ in found),
                f"e = {j.e:g}")
    r.note = "the contact peak at r = d, which every dense hard-sphere g(r) has, is not named by the thesis"
    return r


def g_local_order_perfect_smooth(sweep):
    r = Row("4.1.2", "\"In either case, there is no long range order for e -> 1, but the local ordering "
            "appears (peak at r/d=2) with increasing dissipation\" (beta = 0.99 and -0.99)",
            "bin 13: no maximum beyond 3.5 d at e = 0.99 and none within 0.25 d of 2 d; a maximum "
            "within 0.25 d of 2 d at e = 0.7", G13)
    if not r.needs(sweep, "pair_correlation"):
        return r
    for beta in (0.99, -0.99):
        for j in r.results(sweep, beta=beta, es=(0.99, 0.7)):
            found = g_peaks(j)
            r.show(f"{by_beta(beta)}, e = {j.e:g}: maxima at r/d = " +
                   (", ".join(f"{x:.2f}" for x, _ in found) or "none"))
            if abs(j.e - 0.99) < 1e-9:
                r.check(not peak_near(found, 2) and not any(x > 3.5 for x, _ in found),
                        f"{by_beta(beta)} e = 0.99")
            else:
                r.check(peak_near(found, 2), f"{by_beta(beta)} e = 0.7")
    return r


LAMBDA = "Lambda(y) per bin, pooled over the window"


def lam(j, slab):
    return {s: (v, e) for s, v, e in j.lambdas()}.get(slab)


def distance(value):
    return abs(value[0] - 1 / 3), value[1]


def lambda_plug_smooth(sweep):
    r = Row("4.1.3", "\"there is strong correlation in the plug region which increases with "
            "dissipation\" (beta = -0.99)", "abs(Lambda(bin 13) - 1/3) rises at every step from "
            f"e = 0.99 to 0.7 (steps against within {SIG:g} errors) and exceeds {SIG:g} errors at e = 0.7",
            LAMBDA)
    pts = [(j.e,) + distance(lam(j, CENTRE)) for j in r.results(sweep, beta=-0.99) if lam(j, CENTRE)]
    r.show("abs(Lambda(bin 13) - 1/3) " + sequence(pts, 2))
    r.check(trend(pts, True), "rises")
    strong = [p for p in pts if abs(p[0] - 0.7) < 1e-9]
    if strong:
        r.check(strong[0][1] > SIG * strong[0][2], "strong at e = 0.7")
    return r


def lambda_gas_elastic_smooth(sweep):
    r = Row("4.1.3", "\"For e = 0.99 we see negligible correlation and the system behaves like a "
            "molecular gas (Lambda = 1/3)\" (beta = -0.99)", f"every bin within {NULL:g} errors of "
            "1/3 at e = 0.99", LAMBDA)
    for j in r.results(sweep, beta=-0.99, e=0.99):
        ls = j.lambdas()
        off = [s for s, v, e in ls if abs(v - 1 / 3) > NULL * e]
        r.show(f"{len(ls) - len(off)} of {len(ls)} bins within")
        if ls:
            r.check(not off, "e = 0.99")
    return r


def lambda_inset_smooth(sweep):
    r = Row("4.1.3", "\"The inset shows the variation of Lambda(0) and the mean of Lambda with "
            "dissipation which decreases with dissipation\" (beta = -0.99)", "Lambda(bin 13) and "
            f"the mean of Lambda(y) fall at every step from e = 0.99 to 0.7 (steps against within "
            f"{SIG:g} errors; the values, as the thesis does not say towards or away from 1/3)",
            LAMBDA + "; bin 13 and the mean over the bins")
    for name, value in (("Lambda(0)", lambda_centre), ("mean", profile_mean)):
        pts = [(j.e,) + value(j) for j in r.results(sweep, beta=-0.99) if value(j)]
        r.show(f"{name} " + sequence(pts, 4))
        r.check(trend(pts, False), name)
    return r


def lambda_plug_negligible_rough(sweep):
    r = Row("4.1.3", "\"there is negligible orientational correlation in the plug region ... On the "
            "other hand the particles near the wall and in the shear region are strongly correlated "
            "in direction\" (beta = 0)", f"Lambda(bin 13) within {NULL:g} errors of 1/3; Lambda in "
            f"bins 1 and 4 beyond {SIG:g} errors from 1/3; at every e", LAMBDA)
    for j in r.results(sweep, beta=0.0):
        c, w, s = lam(j, CENTRE), lam(j, WALL), lam(j, SHEAR)
        if c and w and s:
            r.show(f"e = {j.e:g}: bin 13 {pm(*c, 4)}, bin 1 {pm(*w, 4)}, bin 4 {pm(*s, 4)}")
            r.check(abs(c[0] - 1 / 3) <= NULL * c[1], f"e = {j.e:g} plug")
            r.check(all(abs(v - 1 / 3) > SIG * e for v, e in (w, s)), f"e = {j.e:g} wall, shear")
    return r


def lambda_perfect(sweep):
    r = Row("4.1.3", "\"Here also we see weak orientational correlation in the middle dense region "
            "(which increases with dissipation) but significant correlation in the shear region and "
            "near the wall\" (beta = 0.99)", "abs(Lambda - 1/3) in bin 13 below those in bins 1 and 4, "
            f"which exceed {SIG:g} errors, at every e; abs(Lambda(bin 13) - 1/3) rises from e = 0.99 to "
            f"0.7 (steps against within {SIG:g} errors)", LAMBDA)
    pts = []
    for j in r.results(sweep, beta=0.99):
        c, w, s = lam(j, CENTRE), lam(j, WALL), lam(j, SHEAR)
        if c and w and s:
            dc, dw, ds = (abs(v[0] - 1 / 3) for v in (c, w, s))
            r.show(f"e = {j.e:g}: abs(Lambda - 1/3) bin 13 {fmt(dc, 2)}, bin 1 {fmt(dw, 2)}, "
                   f"bin 4 {fmt(ds, 2)}")
            r.check(dc < dw and dc < ds and dw > SIG * w[1] and ds > SIG * s[1], f"e = {j.e:g}")
            pts.append((j.e, dc, c[1]))
    r.check(trend(pts, True), "bin 13 grows with dissipation")
    return r


def lambda_conclusion(sweep):
    r = Row("6", "\"there are strong directional correlations over the whole channel width which "
            "increases with increasing dissipation\" (the moderately dense flow)", "per beta: "
            f"at e = 0.7 every bin beyond {SIG:g} errors from 1/3, and the mean over the bins of "
            "abs(Lambda - 1/3) rises at every step from e = 0.99 to 0.7", LAMBDA)
    for beta in BETAS:
        pts = []
        for j in r.results(sweep, beta=beta):
            ls = j.lambdas()
            if ls:
                pts.append((j.e, mean(abs(v - 1 / 3) for _, v, _ in ls), None))
                if abs(j.e - 0.7) < 1e-9:
                    far = sum(1 for _, v, e in ls if abs(v - 1 / 3) > SIG * e)
                    r.show(f"{by_beta(beta)}, e = 0.7: {far} of {len(ls)} bins beyond")
                    r.check(far == len(ls), f"{by_beta(beta)} whole width")
        r.show(f"{by_beta(beta)}: mean abs(Lambda - 1/3) " + sequence(pts, 2))
        r.check(trend(pts, True), f"{by_beta(beta)} grows")
    r.note = "4.1.3 has negligible correlation in the plug at beta = 0, against \"the whole width\""
    return r


STRONG, ZERO = 0.1, 0.05

VCF = ("velocity correlations of a bin (test particle in it), pair-weighted mean over "
       "1 <= r/d <= 2 with a counting error")


def vcf(j, slab, pair):
    return near_contact(j.velocity_correlation(slab, pair))


def strong(v):
    return v is not None and v[0] >= STRONG and v[0] > SIG * v[1]


def vcf_smooth_e07(sweep):
    r = Row("4.1.4", "\"due to the presence of plug in the middle region (bin = 13), there is strong "
            "correlation; on the other hand ... near the wall and in shear region the correlations "
            "are nearly zero. Similar observation can be made for C_yy and C_zz\" (beta = -0.99, "
            f"e = 0.7)", f"C_xx, C_yy, C_zz: at least {STRONG:g} (and beyond {SIG:g} errors) in bin 13, "
            f"abs(C) <= {ZERO:g} in bins 1 and 4", VCF + f"; {sweep.fluctuations()}")
    if not r.needs(sweep, "velocity_correlation"):
        return r
    for j in r.results(sweep, beta=-0.99, e=0.7):
        for p in ("xx", "yy", "zz"):
            w, s, c = (vcf(j, b, p) for b in THREE)
            if c and w and s:
                r.show(f"C_{p}: bin 13 {pm(*c, 2)}, bin 1 {pm(*w, 2)}, bin 4 {pm(*s, 2)}")
                r.check(strong(c), f"C_{p} bin 13")
                r.check(abs(w[0]) <= ZERO and abs(s[0]) <= ZERO, f"C_{p} bins 1, 4")
    return r


def vcf_cross_smooth(sweep):
    r = Row("4.1.4", "\"The cross-velocity correlations (C_xy, C_xz and C_yz) show significant "
            "correlation, again, in the dense plug region (not shown)\" (beta = -0.99, e = 0.7)",
            f"abs(C) at least {ZERO:g} and beyond {SIG:g} errors in bin 13, each cross pair",
            VCF + f"; {sweep.fluctuations()}")
    if not r.needs(sweep, "velocity_correlation"):
        return r
    for j in r.results(sweep, beta=-0.99, e=0.7):
        for p in ("xy", "xz", "yz"):
            c = vcf(j, CENTRE, p)
            if c:
                r.show(f"C_{p}: {pm(*c, 2)}")
                r.check(abs(c[0]) >= ZERO and abs(c[0]) > SIG * c[1], f"C_{p}")
    r.note = ("C_xy and C_yz change sign under the mirror y -> W - y: a symmetric flow has none "
              "on its mirror plane, where bin 13 lies")
    return r


def vcf_perfect_e07(sweep):
    r = Row("4.1.4", "\"Here also, as expected, we see strong correlations along the channel "
            "centerline. However, the correlations are weak comparing to the smooth limit case\" "
            f"(beta = 0.99, e = 0.7)", f"C_xx, C_yy, C_zz in bin 13 at least {STRONG:g} (beyond {SIG:g} "
            "errors) and below beta = -0.99's", VCF)
    if not r.needs(sweep, "velocity_correlation"):
        return r
    for j in r.results(sweep, beta=0.99, e=0.7):
        for o in r.results(sweep, beta=-0.99, e=0.7):
            for p in ("xx", "yy", "zz"):
                a, b = vcf(j, CENTRE, p), vcf(o, CENTRE, p)
                if a and b:
                    r.show(f"C_{p}: {pm(*a, 2)} against {pm(*b, 2)}")
                    r.check(strong(a) and a[0] < b[0], f"C_{p}")
    return r


def vcf_grow_with_dissipation(sweep):
    r = Row("4.1.4", "\"the increase in inelasticity increases the correlation ... For all cases we "
            "see that the correlation is close to zero in the elastic limit\" (Fig. 4.14, bin 13); "
            "\"inelasticity enhances their magnitudes\"", f"per beta and C_xx, C_yy, C_zz in bin 13: "
            f"rises at every step from e = 0.99 to 0.7, and abs(C) <= {ZERO:g} at e = 0.99", VCF)
    if not r.needs(sweep, "velocity_correlation"):
        return r
    for beta in BETAS:
        jobs = r.results(sweep, beta=beta)
        for p in ("xx", "yy", "zz"):
            pts = [(j.e,) + vcf(j, CENTRE, p) for j in jobs if vcf(j, CENTRE, p)]
            if pts:
                r.show(f"{by_beta(beta)} C_{p}: " + sequence(pts, 2))
                last = [v for e, v, _ in pts if abs(e - 0.99) < 1e-9]
                r.check(trend(pts, True) and abs(last[0]) <= ZERO if last else None,
                        f"{by_beta(beta)} C_{p}")
    return r


def vcf_elastic_zero_smooth(sweep):
    r = Row("4.1.4", "\"Since for nearly elastic system (e = 0.99) the correlations are close to "
            "zero\" (beta = -0.99)", f"abs(C_xx), abs(C_yy), abs(C_zz) <= {ZERO:g} in bins 1, 4, 13 "
            "at e = 0.99", VCF)
    if not r.needs(sweep, "velocity_correlation"):
        return r
    for j in r.results(sweep, beta=-0.99, e=0.99):
        for s in THREE:
            for p in ("xx", "yy", "zz"):
                c = vcf(j, s, p)
                if c:
                    r.check(abs(c[0]) <= ZERO, f"{bin_name(s)} C_{p} ({fmt(c[0], 2)})")
        r.show(f"{sum(ok for ok, _ in r.cases)} of {len(r.cases)} within")
    return r


def vcf_streamwise_largest(sweep):
    r = Row("4.1.4", "\"For any value of particle roughness, the spatial velocity correlations are "
            "largest for the streamwise velocity\"", "C_xx in bin 13 above C_yy and C_zz, each beta "
            "and e", VCF)
    if not r.needs(sweep, "velocity_correlation"):
        return r
    for j in r.results(sweep):
        xx, yy, zz = (vcf(j, CENTRE, p) for p in ("xx", "yy", "zz"))
        if xx and yy and zz:
            r.show(f"{j.name()}: {fmt(xx[0], 2)}, {fmt(yy[0], 2)}, {fmt(zz[0], 2)}")
            r.check(xx[0] > yy[0] and xx[0] > zz[0], j.name())
    return r


def vcf_rough_largest(sweep):
    r = Row("4.1.4", "\"For a given dissipation (fixed e), the magnitude of C_xx is the largest for "
            "rough particles (beta = 0)\"", "abs(C_xx) in bin 13 at beta = 0 above those at "
            "beta = -0.99 and 0.99, at every e", VCF)
    if not r.needs(sweep, "velocity_correlation"):
        return r
    rough = {j.e: j for j in r.results(sweep, beta=0.0)}
    others = [{j.e: j for j in r.results(sweep, beta=b)} for b in (-0.99, 0.99)]
    for e in sorted(rough, reverse=True):
        a = vcf(rough[e], CENTRE, "xx")
        rest = [vcf(o[e], CENTRE, "xx") for o in others if e in o]
        rest = [v for v in rest if v]
        if a and rest:
            r.show(f"e = {e:g}: {fmt(abs(a[0]), 2)} against " + ", ".join(fmt(abs(v[0]), 2) for v in rest))
            r.check(abs(a[0]) > max(abs(v[0]) for v in rest), f"e = {e:g}")
    return r
