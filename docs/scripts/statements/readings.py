"""The tests the thesis' sentences are read as, and the row that reports one statement.

Tolerances (one set for every row; docs/statistics.md states them with the table):
- SIG: a stated sign, order or difference holds when it exceeds SIG = 2 standard errors where
  the tables carry errors (VDF moments, Lambda; g(r) and the velocity correlations get a
  counting error from their pair counts); a step of a trend against the stated direction is
  tolerated when it lies within SIG combined errors. Profiles and wall values carry no error:
  their order is read as it is.
- NULL: "symmetric", "negligible", "= 1/3" hold within NULL = 3 standard errors (a row tests
  up to ~40 such numbers: at 3 errors a true null fails one of them with ~10 % chance, at 2
  errors with ~85 %).
- Gaussian shape: "Gaussian (tails)" is abs(kurtosis - 3) <= KURT_TOL = 0.3 and abs(skewness)
  <= SKEW_TOL = 0.1 (an excess kurtosis of 0.3 changes P(x) by 4 % at abs(x) <= 1 and by a
  third at abs(x) = 3 in the Gram-Charlier expansion: not visible on the thesis' log-scale
  plots spanning decades); "deviates" is beyond the tolerance by SIG errors. The low-velocity
  region (abs(x) <= 1) is read off the VDF itself: max abs(P(x) - exp(-x^2/2)) above LOW_TOL
  = 0.08 is a deviation (an elastic gas stays within it: the equilibrium oracle of
  tests/analysis/statistics.rs measures 0.036 against this same 0.08).
- Centre: "at the centre(line)" is the three middle bins of 25 (abs(y / W - 1/2) <= 0.06, 6 d
  of the 50 d channel); the wall bins are bins 1 and 25.
"""

SIG = 2.0
NULL = 3.0
KURT_TOL = 0.3
SKEW_TOL = 0.1
LOW_TOL = 0.08
CENTRE_HALF_WIDTH = 0.06


def fmt(v, digits=3):
    if v is None:
        return "-"
    return f"{v:.{digits}g}"


def pm(v, err, digits=3):
    return fmt(v, digits) if err is None else f"{fmt(v, digits)} +- {fmt(err, 2)}"


def known(points):
    """The (e, value, error) points whose value the tables hold (null: too few samples)."""
    return [p for p in points if p[1] is not None]


def safe(fn, *args):
    """fn(*args), or None where the tables lack a value it needs (a null, an empty bin)."""
    try:
        return fn(*args)
    except (TypeError, ValueError, ZeroDivisionError, KeyError, IndexError):
        return None


def holds(test, *values):
    """test(*values), or None (the case cannot be read) when a value is missing."""
    return None if any(v is None for v in values) else test(*values)


def sequence(points, digits=3):
    """'e = 0.99: v, 0.95: v' over (e, value, error) points, most elastic first."""
    pts = sorted(known(points), key=lambda p: -p[0])
    return "e = " + ", ".join(f"{e:g}: {pm(v, err, digits)}" for e, v, err in pts)


def _against(a, b, err_a, err_b, rising):
    """Whether the step a -> b goes against the stated direction beyond SIG errors."""
    step = b - a if rising else a - b
    if err_a is None or err_b is None:
        return step <= 0
    return step < -SIG * (err_a ** 2 + err_b ** 2) ** 0.5


def trend(points, rises_as_e_falls):
    """A quantity rises (or falls) with dissipation, i.e. as e decreases: every step from
    one e to the next lower one goes the stated way (or against it within SIG errors where
    errors exist), and the whole change does, beyond SIG errors. points: [(e, v, err)];
    points without a value are left out."""
    pts = sorted(known(points), key=lambda p: -p[0])
    if len(pts) < 2:
        return None
    for (_, a, ea), (_, b, eb) in zip(pts, pts[1:]):
        if _against(a, b, ea, eb, rises_as_e_falls):
            return False
    (_, a, ea), (_, b, eb) = pts[0], pts[-1]
    whole = b - a if rises_as_e_falls else a - b
    if ea is None or eb is None:
        return whole > 0
    return whole > SIG * (ea ** 2 + eb ** 2) ** 0.5


def non_monotonic(points):
    """The sequence over e changes direction: one step up and one step down, each beyond SIG
    combined errors where errors exist (a flat sequence is not non-monotonic)."""
    pts = sorted(known(points), key=lambda p: -p[0])
    if len(pts) < 3:
        return None
    up = down = False
    for (_, a, ea), (_, b, eb) in zip(pts, pts[1:]):
        tol = 0.0 if ea is None or eb is None else SIG * (ea ** 2 + eb ** 2) ** 0.5
        up, down = up or b - a > tol, down or a - b > tol
    return up and down


def centre_bins(profile):
    return [(y, v) for y, v in profile if abs(y - 0.5) <= CENTRE_HALF_WIDTH + 1e-9]


def centre_value(profile):
    """The value in the bin holding the centreline (the mean of the two middle ones)."""
    best = min(abs(y - 0.5) for y, _ in profile)
    vals = [v for y, v in profile if abs(abs(y - 0.5) - best) < 1e-9]
    return sum(vals) / len(vals)


def minimum_at_centre(profile):
    """The smallest value of the profile lies in the centre bins."""
    if not profile:
        return None
    low = min(v for _, v in profile)
    return any(v == low for _, v in centre_bins(profile))


def maximum_at_centre(profile):
    if not profile:
        return None
    high = max(v for _, v in profile)
    return any(v == high for _, v in centre_bins(profile))


def mean(values):
    values = list(values)
    return sum(values) / len(values) if values else None


def pearson(a, b):
    ma, mb = mean(a), mean(b)
    sab = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    saa = sum((x - ma) ** 2 for x in a)
    sbb = sum((y - mb) ** 2 for y in b)
    return sab / (saa * sbb) ** 0.5 if saa > 0 and sbb > 0 else 0.0


def line_fit_r2(profile):
    """R^2 of the least-squares straight line through a profile."""
    ys, vs = [y for y, _ in profile], [v for _, v in profile]
    r = pearson(ys, vs)
    return r * r


def parabola_residual(profile):
    """rms residual of the least-squares even parabola a + b (y - 1/2)^2 over the profile,
    relative to the profile's largest value."""
    xs = [(y - 0.5) ** 2 for y, _ in profile]
    vs = [v for _, v in profile]
    mx, mv = mean(xs), mean(vs)
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (v - mv) for x, v in zip(xs, vs)) / sxx if sxx > 0 else 0.0
    a = mv - b * mx
    rms = mean((v - a - b * x) ** 2 for x, v in zip(xs, vs)) ** 0.5
    return rms / max(abs(v) for v in vs)


def wall_value(profile):
    """The mean of the two wall bins (an even quantity)."""
    return 0.5 * (profile[0][1] + profile[-1][1])


def low_velocity_deviation(vdf):
    """max abs(P(x) - exp(-x^2/2)) over abs(x) <= 1 of a VDF [(x, p, gaussian)]."""
    inner = [abs(p - g) for x, p, g in vdf if abs(x) <= 1.0 + 1e-9]
    return max(inner) if inner else None


def peaks(values, prominence):
    """Local maxima of a sampled curve [(x, v)] (3-point smoothed) that rise above the
    lowest point on each side (up to the next higher maximum or the end) by `prominence`."""
    v = [p[1] for p in values]
    s = [mean(v[max(0, i - 1):i + 2]) for i in range(len(v))]
    out = []
    for i in range(1, len(s) - 1):
        if s[i] > s[i - 1] and s[i] >= s[i + 1]:
            left = min(s[:i]) if i else s[i]
            right = min(s[i + 1:]) if i + 1 < len(s) else s[i]
            if s[i] - left > prominence and s[i] - right > prominence:
                out.append((values[i][0], s[i]))
    return out


def merged(curve, width, lo, hi):
    """A counted curve [(r, value, pairs)] merged into bins of `width` over [lo, hi]: the
    pair-weighted value, and its counting error sqrt(2 / pairs) times the value scale (pairs
    are counted from both ends)."""
    out = {}
    for r, v, n in curve:
        if lo <= r < hi and n:
            k = int((r - lo) / width)
            acc = out.setdefault(k, [0.0, 0])
            acc[0] += v * n
            acc[1] += n
    return [(lo + (k + 0.5) * width, s / n, (2.0 / n) ** 0.5) for k, (s, n) in sorted(out.items())]


def near_contact(curve):
    """The pair-weighted mean of a velocity correlation over 1 <= r/d <= 2 and its counting
    error (the product of two independent unit-variance fluctuations has variance 1; each
    pair is counted from both ends), or None."""
    m = merged(curve, 1.0, 1.0, 2.0 + 1e-9)
    return (m[0][1], m[0][2]) if m else None


class Row:
    """One statement: the thesis' words and section, the literal reading, the averaging,
    and what the tables give; `check` adds one case (one e, one beta, one bin ...), the
    verdict counts them."""

    def __init__(self, section, words, reading, averaging):
        self.section, self.words, self.reading, self.averaging = section, words, reading, averaging
        self.measured, self.cases, self.not_results, self.missing = [], [], [], None
        self.note = None

    def results(self, sweep, beta=None, e=None, es=None):
        """The jobs that are results at a beta (every e, or one e, or the e in es), most
        elastic first; jobs that exist but are not results are named in the row."""
        out = []
        for j in sorted(sweep.jobs, key=lambda j: -j.e):
            if beta is not None and abs(j.beta - beta) > 1e-9:
                continue
            if e is not None and abs(j.e - e) > 1e-9:
                continue
            if es is not None and not any(abs(j.e - x) < 1e-9 for x in es):
                continue
            if j.result:
                out.append(j)
            elif j.name() not in self.not_results:
                self.not_results.append(j.name())
        return out

    def show(self, text):
        self.measured.append(text)

    def check(self, ok, label):
        """One case of the statement; ok None means the case could not be read."""
        if ok is not None:
            self.cases.append((bool(ok), label))

    def needs(self, sweep, *tables):
        """Marks the row not measured when a table it reads is missing."""
        gone = [t for t in tables if not sweep.has(t)]
        if gone:
            self.missing = f"not measured: needs {', '.join(t + '.parquet' for t in gone)}"
        return not gone

    def verdict(self):
        if self.missing:
            return self.missing
        if not self.cases:
            return "not measured: no job of these is a result" if self.not_results else \
                "not measured: no job of these in the tables"
        good = [label for ok, label in self.cases if ok]
        bad = [label for ok, label in self.cases if not ok]
        word = "yes" if not bad else "no" if not good else "partly"
        text = f"{word}: {len(good)} of {len(self.cases)}"
        if bad and good:
            text += f" (not: {'; '.join(bad)})"
        return text

    def word(self):
        """yes, partly, no or not measured."""
        v = self.verdict()
        return "not measured" if v.startswith("not measured") else v.split(":")[0]

    def cells(self):
        measured = "; ".join(self.measured) or "-"
        if self.not_results:
            measured += f" (not results, left out: {', '.join(self.not_results)})"
        if self.note:
            measured += f". Note: {self.note}"
        return (self.section, self.words, self.reading, self.averaging, measured, self.verdict())


def summary(rows):
    """'R rows: Y yes, P partly, N no, M not measured'."""
    words = [r.word() for r in rows]
    return (f"{len(rows)} rows: {words.count('yes')} yes, {words.count('partly')} partly, "
            f"{words.count('no')} no, {words.count('not measured')} not measured")
