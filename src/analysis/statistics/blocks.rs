//! Standard errors by batch means: the window's samples are cut into B = min(10, n)
//! contiguous blocks, the estimator is applied to each block's samples, and the error of the
//! window's estimate is the standard deviation of the block values over sqrt(B). Contiguous
//! blocks of several snapshots are far less correlated than single snapshots, so this does
//! not trust snapshots to be independent.

/// Most blocks of a batch-means error.
pub const BLOCKS: usize = 10;

/// The batch-means standard error of `estimate` over `samples` (NaN with fewer than 2 blocks
/// or when a block's value is not finite).
pub fn batch_error<T>(samples: &[&T], estimate: impl Fn(&[&T]) -> f64) -> f64 {
    let n = samples.len();
    let blocks = BLOCKS.min(n);
    if blocks < 2 {
        return f64::NAN;
    }
    let values: Vec<f64> = (0..blocks)
        .map(|b| estimate(&samples[b * n / blocks..(b + 1) * n / blocks]))
        .collect();
    if values.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    let mean = values.iter().sum::<f64>() / blocks as f64;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (blocks - 1) as f64;
    (var / blocks as f64).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_of_a_mean_of_independent_values() {
        // blocks of equal sums: no spread, no error
        let xs: Vec<f64> = (0..20).map(|i| (i % 2) as f64).collect();
        let refs: Vec<&f64> = xs.iter().collect();
        let mean = |s: &[&f64]| s.iter().map(|x| **x).sum::<f64>() / s.len() as f64;
        assert_eq!(batch_error(&refs, mean), 0.0);
        assert!(batch_error(&refs[..1], mean).is_nan());
    }
}
