//! 2D power spectra of plane fields (thesis 5.1): X = FFT2(f) over the N1 x N2 grid,
//! P = 2 X conj(X) / (N1 N2)^2, folded onto non-negative wave numbers.
//!
//! With this normalisation the sum of P over all (unfolded) modes k != 0 is
//! 2 <(f - <f>)^2> (Parseval), which is how the family powers are computed in real space.

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

/// Unfolded power P(k1, k2) = 2 |X|^2 / (n1 n2)^2 of a real field `f` laid out as
/// f[i n2 + j] (i along the first axis); output in the same layout, k in 0..n.
pub fn power_2d(f: &[f64], n1: usize, n2: usize) -> Vec<f64> {
    assert_eq!(f.len(), n1 * n2, "field size does not match the grid");
    let mut planner = FftPlanner::<f64>::new();
    let mut data: Vec<Complex<f64>> = f.iter().map(|&v| Complex::new(v, 0.0)).collect();
    // along the second axis: contiguous rows of length n2
    planner.plan_fft_forward(n2).process(&mut data);
    // along the first axis: transpose, transform rows of length n1, transpose back
    let mut t = vec![Complex::new(0.0, 0.0); n1 * n2];
    for i in 0..n1 {
        for j in 0..n2 {
            t[j * n1 + i] = data[i * n2 + j];
        }
    }
    planner.plan_fft_forward(n1).process(&mut t);
    let norm = 2.0 / ((n1 * n2) as f64).powi(2);
    let mut p = vec![0.0; n1 * n2];
    for i in 0..n1 {
        for j in 0..n2 {
            p[i * n2 + j] = norm * t[j * n1 + i].norm_sqr();
        }
    }
    p
}

/// |signed wave number| of FFT index `k` on an axis of `n` points: k for k <= n/2, else n - k.
pub fn folded_wavenumber(k: usize, n: usize) -> usize {
    if k <= n / 2 { k } else { n - k }
}

/// How many unfolded wave numbers fold onto |k| = `k` on an axis of `n` points (1 for k = 0
/// and for the Nyquist k = n/2 of even n, else 2).
pub fn multiplicity(k: usize, n: usize) -> usize {
    if k == 0 || 2 * k == n { 1 } else { 2 }
}

/// Fold an unfolded spectrum onto non-negative wave numbers: output (n1/2 + 1) x (n2/2 + 1),
/// index k1 (n2/2 + 1) + k2, each entry the sum over (+-k1, +-k2).
pub fn fold(p: &[f64], n1: usize, n2: usize) -> Vec<f64> {
    let (m1, m2) = (n1 / 2 + 1, n2 / 2 + 1);
    let mut out = vec![0.0; m1 * m2];
    for i in 0..n1 {
        for j in 0..n2 {
            out[folded_wavenumber(i, n1) * m2 + folded_wavenumber(j, n2)] += p[i * n2 + j];
        }
    }
    out
}

/// Shape (n1/2 + 1, n2/2 + 1) of a folded spectrum.
pub fn folded_shape(n1: usize, n2: usize) -> (usize, usize) {
    (n1 / 2 + 1, n2 / 2 + 1)
}
