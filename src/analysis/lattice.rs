//! Density-wave analysis of the lattice gas, after Peng & Herrmann (1994): particle counts in
//! bins along the pipe over time (the space-time picture of their Fig. 1), the power spectrum
//! of the count in one fixed bin (their Fig. 2: segment averaging with a Parzen window, the
//! 1/f^alpha fit after removing the sharp peak, the peak's frequency and the wave velocity it
//! implies), and a noise-referenced label "density waves" / "no waves".
//!
//! **Records.** One [`LatticeRecord`] per snapshot: the step, the particles in each bin of
//! `bin_length` rows (all W sites of a row), the total momentum, L and W. The snapshots must
//! be equally spaced in steps (the seed: every 10 steps).
//!
//! **Spectrum** ([`power_spectrum`]). The series x_n of the count in bin `region_bin`, its
//! mean (over the whole series) subtracted, is cut into S = `segments` consecutive segments
//! of M = floor(n / S) samples; each is multiplied by the Parzen window of the seed's
//! reference (Numerical Recipes in C, 1st ed., 1988: w_j = 1 - |(j - M/2) / (M/2)|, the
//! triangular window that later editions call Bartlett's), Fourier transformed, and the
//! powers are averaged: P_k = c_k sum_segments |X_k|^2 / (S M sum_j w_j^2), k = 1..M/2,
//! c_k = 2 below the Nyquist frequency, so that sum_k P_k is the variance of the series.
//! **Frequency unit of the seed.** Its f = 1000 is a period T = 328 steps and its peak
//! f = 596 is T = 328000 / 596 = 550 steps; both fit f = 327680 / T exactly, i.e. f counts
//! cycles per 32768 samples of 10 steps. 256K samples in segments of 32768 are 8 segments:
//! the seed's "S = 4" is the argument k of Numerical Recipes' `spctrm`, which transforms 2k
//! segments (two per FFT). Hence the default `segments` = 8, and frequencies are reported in
//! the seed's unit f = 327680 nu (nu in cycles per step, [`SEED_FREQUENCY_UNIT`]).
//!
//! **Noise model.** Where the series is noise-like, each periodogram ordinate of a segment is
//! exponentially distributed about the local mean spectrum, so the ratio R_k = P_k / B_k of
//! the S-segment average to the mean level B_k is Gamma(S, 1/S) distributed (mean 1,
//! variance 1/S): P(R > r) = exp(-S r) sum_{m<S} (S r)^m / m!.
//!
//! **Fit and peak** ([`fit_spectrum`]). B_k is a power law A f^-alpha fitted by least squares
//! to (log f_k, log P_k) over the bins with `fit_min` <= f <= `fit_max` (seed: 40 .. 1000),
//! scaled from the mean of log P to the mean of P (the offset psi(S) - ln S of the log of a
//! Gamma(S, 1/S) variable). The peak is the bin of the fit band with the largest R_k; its
//! false-alarm probability is that of the largest of the n_band ratios of pure noise,
//! F = 1 - (1 - P(R > R_max))^n_band, and `peak_significance` = -log10 F. If F is below
//! `false_alarm`, the sharp peak is removed (the contiguous bins around it with R_k > 1,
//! at least the +-2 bins of the window's main lobe, and the same around each harmonic
//! n f_peak in the band whose own ratio is significant at `false_alarm` / (number of
//! harmonics tested)), and the power law is fitted again; two rounds. alpha_error is the
//! standard error of the fitted slope. The wave velocity is v = L / T_peak (sites per step).
//!
//! **Bin-density fluctuations.** For each record after the transient, the variance of the
//! counts of the full bins, against that of a random arrangement of the same N particles
//! on the 7 L W states (each bin then holds a hypergeometric count, variance
//! sigma^2 = N q (1 - q) (C - N) / (C - 1), q = c / C, c = 7 b W states per bin,
//! C = 7 L W): `bin_fluctuation_ratio` is the mean over records of
//! s^2 / sigma^2, s^2 = (nb - 1) / nb sum_full (n_i - mean)^2 / (n_full - 1), which is 1 on
//! average for the random arrangement. For one record of a random arrangement the ratio is
//! chi^2_nu / nu distributed (nu = n_full - 1); the threshold `fluctuation_threshold` is its
//! 1 - `false_alarm` quantile. Averaging over correlated records only narrows the
//! distribution, so the single-record threshold is conservative.
//!
//! **Label.** "density waves" when the spectrum has both a significant sharp peak (F <
//! `false_alarm`: a density wave travelling round the pipe) and a significantly red
//! background (alpha_z = alpha / (alpha_error c_w) above the upper `false_alarm` quantile of
//! the standard normal distribution, c_w = [`window_correlation_factor`]: density structures
//! that live much longer than one passage, the seed's 1/f^alpha), else "no waves". A flat
//! spectrum of independent fluctuations has alpha = 0 within its error. Neither test alone
//! tells the seed's regimes apart: at p = 0 the gas carries sound modes round the periodic
//! pipe (a significant peak, alpha <= 0) and at b = 0 the flow falls freely and carries its
//! frozen pattern (a huge peak, alpha < 0). The bin-density fluctuation ratio is reported but
//! is not part of the label: in this automaton the wave state is *more* ordered than a random
//! arrangement (about 0.07 x at the seed's Fig. 2 parameters: nearly every site carries one
//! particle falling along gravity), so a random arrangement is not a no-wave reference.
//! "not-enough-data" when the records cannot support the tests (fewer than 4 records after
//! the transient, irregular spacing, or segments too short to reach the fit band's lowest
//! frequency). The numbers behind the label are in the summary and its note.

use crate::engine::lga::LgaEngine;
use plotters::prelude::*;
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The seed's frequency unit: f = SEED_FREQUENCY_UNIT nu, nu in cycles per step (f = 1000 is
/// a period of 327.68 steps).
pub const SEED_FREQUENCY_UNIT: f64 = 327_680.0;

/// Analysis settings of a lattice-gas job (all have documented defaults).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LatticeSettings {
    /// rows of sites (along the pipe) per bin (seed: 10)
    pub bin_length: usize,
    /// the bin whose count the power spectrum is taken of
    pub region_bin: usize,
    /// number of spectrum segments S (seed: 256K samples in 8 segments of 32768, see the
    /// module docs)
    pub segments: usize,
    /// lower end of the fit (and peak-search) band, in the seed's frequency unit (seed: 40)
    pub fit_min: f64,
    /// upper end of the fit band, seed units (seed: 1000)
    pub fit_max: f64,
    /// false-alarm probability of both tests of the label
    pub false_alarm: f64,
    /// fraction of the records at the start left out of all statistics (the transient)
    pub transient_fraction: f64,
    /// most records (rows) of the space-time table
    pub spacetime_rows: usize,
    /// periods of the spectrum's peak the space-time table covers: a contiguous window of
    /// records at the end of the run (see [`spacetime`])
    pub spacetime_periods: f64,
}

impl Default for LatticeSettings {
    fn default() -> Self {
        LatticeSettings {
            bin_length: 10,
            region_bin: 0,
            segments: 8,
            fit_min: 40.0,
            fit_max: 1000.0,
            false_alarm: 0.01,
            transient_fraction: 0.1,
            spacetime_rows: 500,
            spacetime_periods: 4.0,
        }
    }
}

impl LatticeSettings {
    /// Check the settings; the message names the key, its value and what is allowed.
    pub fn validate(&self) -> Result<(), String> {
        if self.bin_length == 0 {
            return Err("bin_length = 0 is not allowed: at least 1 row per bin".into());
        }
        if self.segments == 0 {
            return Err("segments = 0 is not allowed: at least 1 spectrum segment".into());
        }
        if !(self.fit_min.is_finite() && self.fit_min > 0.0 && self.fit_max > self.fit_min) {
            return Err(format!(
                "fit_min = {}, fit_max = {} are not allowed: need 0 < fit_min < fit_max \
                 (seed frequency units)",
                self.fit_min, self.fit_max
            ));
        }
        if !(self.false_alarm > 0.0 && self.false_alarm < 1.0) {
            return Err(format!(
                "false_alarm = {} is out of range (0, 1): it is a probability",
                self.false_alarm
            ));
        }
        if !(0.0..1.0).contains(&self.transient_fraction) {
            return Err(format!(
                "transient_fraction = {} is out of range [0, 1)",
                self.transient_fraction
            ));
        }
        if self.spacetime_rows == 0 {
            return Err("spacetime_rows = 0 is not allowed: at least 1 row".into());
        }
        if !(self.spacetime_periods.is_finite() && self.spacetime_periods > 0.0) {
            return Err(format!(
                "spacetime_periods = {} is not allowed: a number of periods > 0",
                self.spacetime_periods
            ));
        }
        Ok(())
    }
}

/// One snapshot of a lattice-gas run: what the analysis needs, a few bytes per bin.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LatticeRecord {
    /// time step of the snapshot
    pub step: u64,
    /// particles per bin along the pipe (bin i: rows i b .. (i+1) b - 1; the last bin is
    /// shorter when b does not divide L)
    pub bins: Vec<u32>,
    /// total momentum (x along gravity in half lattice spacings, y in sqrt(3)/2)
    pub momentum: [i64; 2],
    /// L, sites along the pipe
    pub length: u32,
    /// W, sites across the pipe
    pub width: u32,
}

/// The record of a lattice snapshot at time step `step`: its row counts summed into bins of
/// `settings.bin_length` rows (the last bin shorter when that does not divide L).
pub fn record_of(
    step: u64,
    lattice: &crate::engine::Lattice,
    settings: &LatticeSettings,
) -> LatticeRecord {
    let b = settings.bin_length.max(1);
    LatticeRecord {
        step,
        bins: lattice
            .row_counts
            .chunks(b)
            .map(|c| c.iter().sum())
            .collect(),
        momentum: lattice.momentum,
        length: lattice.length as u32,
        width: lattice.width as u32,
    }
}

/// The record of the engine's current state.
pub fn record(engine: &LgaEngine, settings: &LatticeSettings) -> LatticeRecord {
    let p = engine.params();
    LatticeRecord {
        step: engine.step(),
        bins: engine.bin_counts(settings.bin_length.max(1)),
        momentum: engine.momentum(),
        length: p.length as u32,
        width: p.width as u32,
    }
}

/// One ordinate of the power spectrum.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrequencyPower {
    /// f in the seed's unit (327680 cycles per step)
    pub frequency: f64,
    /// period 1 / nu in steps
    pub period: f64,
    /// P_k (particles^2 per frequency bin; the sum over k is the variance of the count)
    pub power: f64,
    /// in the fit band and not removed as part of the sharp peak
    pub fitted: bool,
}

/// One cell of the space-time table.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpacetimeCell {
    pub step: u64,
    pub bin: u32,
    pub count: u32,
}

/// The numbers behind a job's label.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LatticeSummary {
    /// "density waves", "no waves" or "not-enough-data"
    pub label: String,
    /// alpha of the fitted 1/f^alpha (NaN without a spectrum)
    pub alpha: f64,
    /// standard error of alpha
    pub alpha_error: f64,
    /// frequency of the sharp peak (largest ratio to the fit), seed units
    pub peak_frequency: f64,
    /// its period in steps
    pub peak_period: f64,
    /// L / peak period, sites per step
    pub wave_velocity: f64,
    /// peak ratio R = P / B at the peak
    pub peak_ratio: f64,
    /// -log10 of the peak's false-alarm probability F (large: significant)
    pub peak_significance: f64,
    /// alpha over its standard error corrected for the window's correlation of neighbouring
    /// bins (the redness test: a flat spectrum gives a standard normal value)
    pub alpha_z: f64,
    /// the value of `alpha_z` that a flat spectrum exceeds with probability `false_alarm`
    pub alpha_z_threshold: f64,
    /// mean bin-count variance over that of a random arrangement (not part of the label)
    pub bin_fluctuation_ratio: f64,
    /// the ratio a random arrangement exceeds with probability `false_alarm`
    pub fluctuation_threshold: f64,
    /// mean particle velocity along gravity u = P_x / N (sites per step)
    pub mean_velocity: f64,
    /// samples and segments used for the spectrum
    pub samples: usize,
    pub segments: usize,
    /// steps between records
    pub sample_interval: u64,
    /// what decided the label, or why there is none
    pub note: String,
}

/// A job's lattice analysis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LatticeAnalysis {
    pub summary: LatticeSummary,
    /// P(f) for k = 1 .. M/2 (empty without a spectrum)
    pub spectrum: Vec<FrequencyPower>,
    /// counts of every bin at the records of a window at the end of the run ([`spacetime`])
    pub spacetime: Vec<SpacetimeCell>,
}

/// Segment-averaged power spectrum with the Parzen (triangular) window: (P_k for k = 1..M/2,
/// M). `x` must have its mean subtracted. Empty when M < 4.
pub fn power_spectrum(x: &[f64], segments: usize) -> (Vec<f64>, usize) {
    let s = segments.max(1);
    let m = x.len() / s;
    if m < 4 {
        return (Vec::new(), m);
    }
    let half = m as f64 / 2.0;
    let window: Vec<f64> = (0..m)
        .map(|j| 1.0 - ((j as f64 - half) / half).abs())
        .collect();
    let w2: f64 = window.iter().map(|w| w * w).sum();
    let fft = FftPlanner::<f64>::new().plan_fft_forward(m);
    let mut sum = vec![0.0; m / 2 + 1];
    let mut buf = vec![Complex::new(0.0, 0.0); m];
    for seg in x.chunks_exact(m).take(s) {
        for ((b, &v), &w) in buf.iter_mut().zip(seg).zip(&window) {
            *b = Complex::new(v * w, 0.0);
        }
        fft.process(&mut buf);
        for (k, acc) in sum.iter_mut().enumerate() {
            *acc += buf[k].norm_sqr();
        }
    }
    let p = (1..=m / 2)
        .map(|k| {
            let c = if 2 * k == m { 1.0 } else { 2.0 };
            c * sum[k] / (s as f64 * m as f64 * w2)
        })
        .collect();
    (p, m)
}

/// P(R > r) for R ~ Gamma(S, 1/S): the tail of an S-segment average of exponential ordinates.
pub fn gamma_tail(r: f64, segments: usize) -> f64 {
    if r <= 0.0 {
        return 1.0;
    }
    let sr = segments as f64 * r;
    let mut term = 1.0;
    let mut sum = 1.0;
    for m in 1..segments {
        term *= sr / m as f64;
        sum += term;
    }
    ((-sr).exp() * sum).min(1.0)
}

/// psi(S) - ln S: the mean of ln R for R ~ Gamma(S, 1/S) (digamma of an integer).
fn log_mean_offset(segments: usize) -> f64 {
    const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;
    let psi = -EULER_GAMMA + (1..segments).map(|k| 1.0 / k as f64).sum::<f64>();
    psi - (segments as f64).ln()
}

/// Regularised lower incomplete gamma P(a, x) (series below a + 1, continued fraction above;
/// Numerical Recipes' gammp).
fn gamma_p(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let gln = libm::lgamma(a);
    if x < a + 1.0 {
        let (mut ap, mut del) = (a, 1.0 / a);
        let mut sum = del;
        for _ in 0..10_000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        (sum.ln() - x + a * x.ln() - gln).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-15 {
                break;
            }
        }
        1.0 - (-x + a * x.ln() - gln).exp() * h
    }
}

/// The 1 - `tail` quantile of chi^2_nu / nu.
pub fn chi2_ratio_quantile(nu: usize, tail: f64) -> f64 {
    let a = nu as f64 / 2.0;
    let (mut lo, mut hi) = (0.0, 2.0 * nu as f64 + 100.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 1.0 - gamma_p(a, mid / 2.0) > tail {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) / nu as f64
}

/// The upper `tail` quantile of the standard normal distribution (via chi^2_1).
pub fn normal_quantile(tail: f64) -> f64 {
    chi2_ratio_quantile(1, 2.0 * tail).sqrt()
}

/// sqrt(1 + 2 sum_{lag >= 1} r_lag): how much the correlation of neighbouring periodogram
/// ordinates widens the standard error of a fit over many bins, for the Parzen window of M
/// points. r_lag = |sum_j w_j^2 e^{-2 pi i lag j / M}|^2 / (sum_j w_j^2)^2 is the correlation
/// of the ordinates k and k + lag of Gaussian white noise (Percival & Walden 1993, eq. 231);
/// the sum converges within a few lags.
pub fn window_correlation_factor(m: usize) -> f64 {
    if m < 4 {
        return 1.0;
    }
    let half = m as f64 / 2.0;
    let w2: Vec<f64> = (0..m)
        .map(|j| (1.0 - ((j as f64 - half) / half).abs()).powi(2))
        .collect();
    let norm: f64 = w2.iter().sum();
    let mut sum = 0.0;
    for lag in 1..=(m / 2).min(64) {
        let (mut re, mut im) = (0.0, 0.0);
        for (j, &w) in w2.iter().enumerate() {
            let a = -2.0 * std::f64::consts::PI * (lag * j) as f64 / m as f64;
            re += w * a.cos();
            im += w * a.sin();
        }
        sum += (re * re + im * im) / (norm * norm);
    }
    (1.0 + 2.0 * sum).sqrt()
}

/// Result of the power-law fit with the peak removed.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumFit {
    pub alpha: f64,
    /// standard error of the least-squares slope (as the seed quotes it)
    pub alpha_error: f64,
    /// index into the spectrum (k - 1) of the peak, if the band has bins
    pub peak: Option<usize>,
    pub peak_ratio: f64,
    /// false-alarm probability of the peak
    pub peak_false_alarm: f64,
    /// per spectrum bin: used in the final fit
    pub fitted: Vec<bool>,
}

/// Least-squares line through (x, y): (slope, its standard error, intercept).
fn line_fit(pts: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    let n = pts.len() as f64;
    if pts.len() < 3 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    let icpt = my - slope * mx;
    let rss: f64 = pts.iter().map(|p| (p.1 - icpt - slope * p.0).powi(2)).sum();
    Some((slope, (rss / (n - 2.0) / sxx).sqrt(), icpt))
}

/// Fit 1/f^alpha over the band and find and remove the sharp peak (see the module docs).
/// `freq` in seed units, `power` the spectrum, `segments` S.
pub fn fit_spectrum(
    freq: &[f64],
    power: &[f64],
    segments: usize,
    settings: &LatticeSettings,
) -> SpectrumFit {
    let band: Vec<usize> = (0..freq.len())
        .filter(|&i| freq[i] >= settings.fit_min && freq[i] <= settings.fit_max && power[i] > 0.0)
        .collect();
    let mut fitted = vec![false; freq.len()];
    for &i in &band {
        fitted[i] = true;
    }
    let mut out = SpectrumFit {
        alpha: f64::NAN,
        alpha_error: f64::NAN,
        peak: None,
        peak_ratio: f64::NAN,
        peak_false_alarm: 1.0,
        fitted: fitted.clone(),
    };
    let offset = log_mean_offset(segments);
    let fit = |use_: &[bool]| {
        let pts: Vec<(f64, f64)> = band
            .iter()
            .filter(|&&i| use_[i])
            .map(|&i| (freq[i].ln(), power[i].ln()))
            .collect();
        line_fit(&pts)
    };
    for _round in 0..2 {
        let Some((slope, err, icpt)) = fit(&fitted) else {
            return out;
        };
        out.alpha = -slope;
        out.alpha_error = err;
        // mean level B = exp(intercept + slope ln f - offset)
        let ratio = |i: usize| power[i] / (icpt + slope * freq[i].ln() - offset).exp();
        let Some(&peak) = band.iter().max_by(|&&a, &&b| ratio(a).total_cmp(&ratio(b))) else {
            return out;
        };
        let r = ratio(peak);
        let single = gamma_tail(r, segments);
        let fa = 1.0 - (1.0 - single).powf(band.len() as f64);
        // -expm1(n ln(1 - q)) is accurate for tiny q
        let fa = if single < 1e-12 {
            single * band.len() as f64
        } else {
            fa
        };
        out.peak = Some(peak);
        out.peak_ratio = r;
        out.peak_false_alarm = fa;
        fitted = band.iter().fold(vec![false; freq.len()], |mut f, &i| {
            f[i] = true;
            f
        });
        if fa >= settings.false_alarm {
            break;
        }
        // remove the peak and its significant harmonics, then fit again
        let remove = |fitted: &mut Vec<bool>, centre: usize| {
            let lo_keep = centre.saturating_sub(2);
            let hi_keep = (centre + 2).min(freq.len() - 1);
            for f in fitted.iter_mut().take(hi_keep + 1).skip(lo_keep) {
                *f = false;
            }
            let mut i = lo_keep;
            while i > 0 && ratio(i - 1) > 1.0 {
                i -= 1;
                fitted[i] = false;
            }
            let mut i = hi_keep;
            while i + 1 < freq.len() && ratio(i + 1) > 1.0 {
                i += 1;
                fitted[i] = false;
            }
        };
        remove(&mut fitted, peak);
        let f0 = freq[peak];
        let harmonics: Vec<usize> = (2..)
            .map(|n| n as f64 * f0)
            .take_while(|&f| f <= settings.fit_max)
            .filter_map(|f| {
                // the largest ratio within the main lobe around n f_peak
                let i = freq.iter().position(|&g| g >= f)?;
                (i.saturating_sub(2)..=(i + 2).min(freq.len() - 1))
                    .max_by(|&a, &b| ratio(a).total_cmp(&ratio(b)))
            })
            .collect();
        let per = settings.false_alarm / harmonics.len().max(1) as f64;
        for h in harmonics {
            if gamma_tail(ratio(h), segments) < per {
                remove(&mut fitted, h);
            }
        }
        out.fitted = fitted.clone();
    }
    if let Some((slope, err, _)) = fit(&out.fitted) {
        out.alpha = -slope;
        out.alpha_error = err;
    }
    out
}

fn not_enough(note: String, records: &[LatticeRecord]) -> LatticeAnalysis {
    LatticeAnalysis {
        summary: LatticeSummary {
            label: "not-enough-data".into(),
            alpha: f64::NAN,
            alpha_error: f64::NAN,
            peak_frequency: f64::NAN,
            peak_period: f64::NAN,
            wave_velocity: f64::NAN,
            peak_ratio: f64::NAN,
            peak_significance: f64::NAN,
            alpha_z: f64::NAN,
            alpha_z_threshold: f64::NAN,
            bin_fluctuation_ratio: f64::NAN,
            fluctuation_threshold: f64::NAN,
            mean_velocity: f64::NAN,
            samples: records.len(),
            segments: 0,
            sample_interval: 0,
            note,
        },
        spectrum: Vec::new(),
        spacetime: Vec::new(),
    }
}

/// Analyse the records of one job (never panics; see the module docs).
pub fn analyse(records: &[LatticeRecord], settings: &LatticeSettings) -> LatticeAnalysis {
    if let Err(e) = settings.validate() {
        return not_enough(format!("invalid settings: {e}"), records);
    }
    let skip = (records.len() as f64 * settings.transient_fraction).floor() as usize;
    let used = &records[skip.min(records.len())..];
    if used.len() < 4 {
        return not_enough(
            format!(
                "{} records after the transient, at least 4 needed",
                used.len()
            ),
            records,
        );
    }
    let first = &used[0];
    let (l, w, nb) = (
        first.length as usize,
        first.width as usize,
        first.bins.len(),
    );
    if l == 0
        || w == 0
        || nb == 0
        || used
            .iter()
            .any(|r| r.bins.len() != nb || r.length != first.length || r.width != first.width)
    {
        return not_enough("records of different or empty lattices".into(), records);
    }
    let mut out = not_enough(String::new(), records);
    // the space-time table once the spectrum's peak period is known (or not)
    let finish = |mut out: LatticeAnalysis| {
        out.spacetime = spacetime(records, settings, out.summary.peak_period);
        out
    };
    let s = &mut out.summary;

    bin_fluctuations(s, used, settings, (l, w, nb));

    // spectrum of the region bin
    let dt = used[1].step.saturating_sub(used[0].step);
    s.sample_interval = dt;
    if dt == 0
        || used
            .windows(2)
            .any(|p| p[1].step.saturating_sub(p[0].step) != dt)
    {
        s.note = "records are not equally spaced in steps: no spectrum".into();
        return finish(out);
    }
    if settings.region_bin >= nb {
        s.note = format!(
            "region_bin {} is beyond the {nb} bins: no spectrum",
            settings.region_bin
        );
        return finish(out);
    }
    let x: Vec<f64> = used
        .iter()
        .map(|r| f64::from(r.bins[settings.region_bin]))
        .collect();
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let x: Vec<f64> = x.iter().map(|v| v - mean).collect();
    let (power, m) = power_spectrum(&x, settings.segments);
    s.samples = m * settings.segments;
    s.segments = settings.segments;
    let to_seed = |k: usize| SEED_FREQUENCY_UNIT * k as f64 / (m as f64 * dt as f64);
    if power.is_empty() || to_seed(1) > settings.fit_min {
        s.note = format!(
            "segments of {m} samples x {dt} steps do not reach f = {} (seed units): \
             at least {} samples per segment needed",
            settings.fit_min,
            (SEED_FREQUENCY_UNIT / (settings.fit_min * dt as f64)).ceil()
        );
        return finish(out);
    }
    let freq: Vec<f64> = (1..=power.len()).map(to_seed).collect();
    let fit = fit_spectrum(&freq, &power, settings.segments, settings);
    s.alpha = fit.alpha;
    s.alpha_error = fit.alpha_error;
    if let Some(i) = fit.peak {
        s.peak_frequency = freq[i];
        s.peak_period = SEED_FREQUENCY_UNIT / freq[i];
        s.wave_velocity = l as f64 / s.peak_period;
        s.peak_ratio = fit.peak_ratio;
        s.peak_significance = -fit.peak_false_alarm.max(1e-300).log10();
    }
    out.spectrum = freq
        .iter()
        .zip(&power)
        .zip(&fit.fitted)
        .map(|((&f, &p), &used)| FrequencyPower {
            frequency: f,
            period: SEED_FREQUENCY_UNIT / f,
            power: p,
            fitted: used,
        })
        .collect();
    let s = &mut out.summary;
    s.alpha_z = fit.alpha / (fit.alpha_error * window_correlation_factor(m));
    s.alpha_z_threshold = normal_quantile(settings.false_alarm);
    let red = s.alpha_z > s.alpha_z_threshold;
    let peak = fit.peak_false_alarm < settings.false_alarm;
    s.label = if red && peak {
        "density waves"
    } else {
        "no waves"
    }
    .into();
    s.note = format!(
        "peak at f = {:.1} (T = {:.0} steps, v = {:.3}): P/B = {:.2}, false alarm {:.2e} \
         ({} {}); alpha = {:.3} +- {:.3}, z = {:.2} ({} threshold {:.2})",
        s.peak_frequency,
        s.peak_period,
        s.wave_velocity,
        s.peak_ratio,
        fit.peak_false_alarm,
        if peak { "below" } else { "not below" },
        settings.false_alarm,
        s.alpha,
        s.alpha_error,
        s.alpha_z,
        if red { "above" } else { "not above" },
        s.alpha_z_threshold
    );
    finish(out)
}

/// The bin-density fluctuations against a random arrangement of the same particles (their
/// ratio and the chi^2 threshold) and the mean velocity, over the records `used`.
fn bin_fluctuations(
    s: &mut LatticeSummary,
    used: &[LatticeRecord],
    settings: &LatticeSettings,
    (l, w, nb): (usize, usize, usize),
) {
    let b = settings.bin_length;
    let full = if l % b == 0 { nb } else { nb - 1 };
    let cap = (7 * l * w) as f64;
    let c = (7 * b * w) as f64;
    let mut ratios = Vec::new();
    let mut velocity = 0.0;
    for r in used {
        let n: f64 = r.bins.iter().map(|&v| f64::from(v)).sum();
        if n > 0.0 {
            velocity += r.momentum[0] as f64 / (2.0 * n);
        }
        let q = c / cap;
        let sigma2 = n * q * (1.0 - q) * (cap - n) / (cap - 1.0);
        if full >= 2 && sigma2 > 0.0 {
            let m = r.bins[..full].iter().map(|&v| f64::from(v)).sum::<f64>() / full as f64;
            let ss: f64 = r.bins[..full]
                .iter()
                .map(|&v| (f64::from(v) - m).powi(2))
                .sum();
            let s2 = ss / (full - 1) as f64 * (nb - 1).max(1) as f64 / nb as f64;
            ratios.push(s2 / sigma2);
        }
    }
    s.mean_velocity = velocity / used.len() as f64;
    if !ratios.is_empty() {
        s.bin_fluctuation_ratio = ratios.iter().sum::<f64>() / ratios.len() as f64;
        s.fluctuation_threshold = chi2_ratio_quantile(full - 1, settings.false_alarm);
    }
}

/// The space-time table: every bin at the records of a window at the end of the run. The
/// window is contiguous at the record interval and `spacetime_periods` periods of the
/// spectrum's peak long (`peak_period` in steps; at least 20 records), so that the waves the
/// label speaks of show as bands; a window of more than `spacetime_rows` records keeps every
/// n-th (the fewest n that fit). Without a peak period the window is the last
/// `spacetime_rows` records. (Before, the table spread `spacetime_rows` records over the whole
/// run: every ~5000 steps of a spectrum run, far apart for waves of ~550 steps.)
pub fn spacetime(
    records: &[LatticeRecord],
    settings: &LatticeSettings,
    peak_period: f64,
) -> Vec<SpacetimeCell> {
    if records.is_empty() {
        return Vec::new();
    }
    let rows = settings.spacetime_rows.max(1);
    let dt = match records {
        [.., a, b] => b.step.saturating_sub(a.step),
        _ => 0,
    };
    let wanted = if peak_period.is_finite() && peak_period > 0.0 && dt > 0 {
        ((settings.spacetime_periods * peak_period / dt as f64).ceil() as usize).max(20)
    } else {
        rows
    }
    .min(records.len());
    let stride = wanted.div_ceil(rows).max(1);
    let count = wanted.div_ceil(stride);
    let start = records.len() - 1 - (count - 1) * stride;
    records[start..]
        .iter()
        .step_by(stride)
        .flat_map(|r| {
            r.bins.iter().enumerate().map(move |(i, &c)| SpacetimeCell {
                step: r.step,
                bin: i as u32,
                count: c,
            })
        })
        .collect()
}

/// The steps of the space-time table's records, in order.
fn spacetime_steps(analysis: &LatticeAnalysis) -> Vec<u64> {
    let mut steps: Vec<u64> = analysis.spacetime.iter().map(|c| c.step).collect();
    steps.dedup();
    steps
}

/// What time the space-time picture shows, e.g. "steps 2617040 .. 2621430 (the run's last
/// 4390 steps), a record every 10 steps, 8.0 periods of the 550-step peak".
pub fn spacetime_span(analysis: &LatticeAnalysis) -> String {
    let steps = spacetime_steps(analysis);
    let (Some(&first), Some(&last)) = (steps.first(), steps.last()) else {
        return "no records".into();
    };
    let span = last - first;
    let every = match steps.as_slice() {
        [a, b, ..] => b - a,
        _ => 0,
    };
    let mut text = format!("steps {first} .. {last} (the run's last {span} steps)");
    if every > 0 {
        let record = analysis.summary.sample_interval;
        if record > 0 && every != record {
            text.push_str(&format!(
                ", every {} records ({every} steps)",
                every / record
            ));
        } else {
            text.push_str(&format!(", a record every {every} steps"));
        }
    }
    let period = analysis.summary.peak_period;
    if period.is_finite() && period > 0.0 {
        text.push_str(&format!(
            ", {:.1} periods of the {:.0}-step peak",
            span as f64 / period,
            period
        ));
    }
    text
}
/// Draw the space-time picture as a PNG in the style of the seed's Fig. 1 at its own size and
/// 96 dpi, without a job heading (see [`draw_spacetime`]; the per-job figure adds one).
pub fn plot_spacetime(analysis: &LatticeAnalysis, path: &Path) -> anyhow::Result<()> {
    crate::figure::save_png(
        path,
        spacetime_size(analysis),
        crate::figure::Scale::CSS,
        |root, s| draw_spacetime(analysis, root, s),
    )
}

/// Margins of the space-time picture around its cells (left, top, right, bottom), CSS pixels:
/// room for the bin labels and for three lines of text below.
const SPACETIME_MARGINS: [u32; 4] = [70, 16, 20, 78];

/// Columns (records) and rows (bins) of the space-time picture.
fn spacetime_cells(analysis: &LatticeAnalysis) -> (usize, usize) {
    let cols = spacetime_steps(analysis).len();
    let rows = analysis
        .spacetime
        .iter()
        .map(|c| c.bin as usize + 1)
        .max()
        .unwrap_or(0);
    (cols.max(1), rows.max(1))
}

/// The size of the space-time picture in CSS pixels: 1 to 8 pixels per cell, about 600 x 400
/// of cells, at least wide enough for its text.
pub fn spacetime_size(analysis: &LatticeAnalysis) -> (u32, u32) {
    let (cols, rows) = spacetime_cells(analysis);
    let px = (600 / cols).clamp(1, 8) as u32;
    let py = (400 / rows).clamp(1, 8) as u32;
    let [left, top, right, bottom] = SPACETIME_MARGINS;
    (
        (left + right + px * cols as u32).max(640),
        top + bottom + py * rows as u32,
    )
}

/// Draw the space-time picture in the style of the seed's Fig. 1: bins along the pipe from top
/// to bottom (gravity downwards), time from left to right, gray level linear in the bin count
/// n_i (white at the smallest count of the picture, black at the largest); below, the time
/// span it shows ([`spacetime_span`]). The cells fill the area inside the margins.
pub fn draw_spacetime<DB: DrawingBackend>(
    analysis: &LatticeAnalysis,
    root: &plotters::drawing::DrawingArea<DB, plotters::coord::Shift>,
    s: crate::figure::Scale,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let cells = &analysis.spacetime;
    let (cols, rows) = spacetime_cells(analysis);
    let (w, h) = root.dim_in_pixel();
    let (w, h) = (s.css(w), s.css(h));
    let [left, top, right, bottom] = SPACETIME_MARGINS.map(f64::from);
    let (plot_w, plot_h) = ((w - left - right).max(1.0), (h - top - bottom).max(1.0));
    let x = |col: usize| s.px(left + plot_w * col as f64 / cols as f64);
    let y = |bin: usize| s.px(top + plot_h * bin as f64 / rows as f64);
    let lo = cells.iter().map(|c| c.count).min().unwrap_or(0);
    let hi = cells.iter().map(|c| c.count).max().unwrap_or(1).max(lo + 1);
    root.fill(&WHITE)?;
    let mut col = 0usize;
    let mut last = None;
    for c in cells {
        if last != Some(c.step) {
            if last.is_some() {
                col += 1;
            }
            last = Some(c.step);
        }
        let g = 255 - (255.0 * f64::from(c.count - lo) / f64::from(hi - lo)).round() as u8;
        let bin = c.bin as usize;
        // at least one device pixel each way, so that no column or row is lost
        let (x0, y0) = (x(col), y(bin));
        let (x1, y1) = (x(col + 1).max(x0 + 1), y(bin + 1).max(y0 + 1));
        root.draw(&Rectangle::new(
            [(x0, y0), (x1, y1)],
            RGBColor(g, g, g).filled(),
        ))?;
    }
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = s.font(13.0);
    let right_aligned = TextStyle::from(font.clone()).pos(Pos::new(HPos::Right, VPos::Center));
    let edge = |bin: usize| s.px(top + plot_h * (bin as f64 + 0.5) / rows as f64);
    root.draw(&Text::new(
        "bin 0",
        (s.px(left - 6.0), edge(0)),
        right_aligned.clone(),
    ))?;
    if rows > 1 {
        root.draw(&Text::new(
            format!("bin {}", rows - 1),
            (s.px(left - 6.0), edge(rows - 1)),
            right_aligned,
        ))?;
    }
    let below = top + plot_h;
    let lines = [
        format!("time -> {}", spacetime_span(analysis)),
        format!(
            "{rows} bins of the pipe top to bottom (gravity down); gray: {lo} (white) .. {hi} \
             (black) particles per bin"
        ),
    ];
    let wrapped = lines
        .iter()
        .flat_map(|l| crate::figure::text::wrap(l, 13.0, w - left - 10.0));
    for (k, line) in wrapped.take(4).enumerate() {
        root.draw(&Text::new(
            line,
            (s.px(left), s.px(below + 6.0 + 17.0 * k as f64)),
            font.clone(),
        ))?;
    }
    Ok(())
}
