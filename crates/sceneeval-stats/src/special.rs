//! The two distribution functions the tests need: the standard normal's lower tail (for the
//! Wilcoxon test's approximation) and the binomial(n, 1/2) distribution function (for
//! McNemar's exact test).

/// `1 / sqrt(2)`.
const SQRT_HALF: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The standard normal distribution function `Φ(a)`, computed as Cephes' `ndtr` (which SciPy's
/// `special.ndtr` is): `0.5 + 0.5 erf(a / √2)` near 0 (`|a / √2| < 1/√2`), otherwise
/// `0.5 erfc(|a| / √2)` (and one minus that above 0), with musl's `erf` and `erfc` (through
/// `libm`, error below 1 ulp). The lower tail keeps its relative accuracy far out (no
/// cancellation: `Φ(-10) ≈ 7.6e-24` to about 1e-15 relative).
#[must_use]
pub fn normal_cdf(a: f64) -> f64 {
    let x = a * SQRT_HALF;
    let z = x.abs();
    if z < SQRT_HALF {
        0.5 + 0.5 * libm::erf(x)
    } else {
        let y = 0.5 * libm::erfc(z);
        if x > 0.0 { 1.0 - y } else { y }
    }
}

/// `P(X <= k)` for `X ~ Binomial(n, 1/2)` (1 for `k >= n`).
///
/// For `2k <= n`: the term `C(n, k) / 2^n`, built as a running product of the factors
/// `(n - k + j) / j` with its binary exponent kept apart (no overflow or underflow on the way),
/// times the sum of the ratios of the lower terms to it, summed from the largest down and
/// stopped once the rest is below 1e-17 of the sum. Relative error at most about `2k + 4` ulps
/// (the product's roundings), far less in practice since they do not all go the same way:
/// within 1e-14 of exact fractions on the Python tests' cases (`n` up to 7800); subnormal below
/// about 2e-308, 0 below 5e-324. For `2k > n` it is one minus the other
/// tail.
/// Time linear in `min(k, n - k)`.
#[must_use]
pub fn binomial_half_cdf(k: u64, n: u64) -> f64 {
    if k >= n {
        return 1.0;
    }
    if 2 * k > n {
        // P(X <= k) = 1 - P(X >= k + 1) = 1 - P(X <= n - k - 1) by symmetry.
        return 1.0 - binomial_half_cdf(n - k - 1, n);
    }
    const BIG: f64 = 1.0e150;
    // C(n, k) = prod_{j=1..k} (n - k + j) / j, as mantissa * 2^exponent.
    let mut mantissa = 1.0f64;
    let mut exponent: i64 = 0;
    for j in 1..=k {
        mantissa *= (n - k + j) as f64 / j as f64;
        if mantissa > BIG {
            let (m, e) = split(mantissa);
            mantissa = m;
            exponent += e;
        }
    }
    // sum_{i <= k} C(n, i) / C(n, k): ratios r_{i-1} = r_i * i / (n - i + 1), decreasing.
    let mut sum = 0.0f64;
    let mut ratio = 1.0f64;
    let mut i = k;
    loop {
        sum += ratio;
        if i == 0 || ratio * (i as f64) < sum * 1e-17 {
            break;
        }
        ratio *= i as f64 / (n - i + 1) as f64;
        i -= 1;
    }
    let (m, e) = split(mantissa * sum);
    scale(m, exponent + e - i64::try_from(n).unwrap_or(i64::MAX))
}

/// `x = m * 2^e` with `m` in [0.5, 1) (x finite and positive).
fn split(x: f64) -> (f64, i64) {
    let (m, e) = libm::frexp(x);
    (m, i64::from(e))
}

/// `m * 2^e`, exact unless the result is subnormal or underflows.
fn scale(m: f64, e: i64) -> f64 {
    let e = i32::try_from(e.clamp(i64::from(i32::MIN), i64::from(i32::MAX))).unwrap_or(i32::MIN);
    libm::scalbn(m, e)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_cdf_values() {
        assert_eq!(normal_cdf(0.0), 0.5);
        // Reference values (mpmath at 40 digits, rounded to f64).
        let cases = [
            (-1.96, 0.024_997_895_148_220_435),
            (-5.0, 2.866_515_718_791_939e-7),
            (-10.0, 7.619_853_024_160_525e-24),
            (1.0, 0.841_344_746_068_542_9),
            (-0.5, 0.308_537_538_725_986_9),
        ];
        for (a, expected) in cases {
            let got = normal_cdf(a);
            assert!(
                ((got - expected) / expected).abs() < 4e-15,
                "{a}: {got} vs {expected}"
            );
        }
        assert_eq!(normal_cdf(-40.0), 0.0);
        assert_eq!(normal_cdf(40.0), 1.0);
    }

    #[test]
    fn binomial_by_hand() {
        // n = 4: C = 1, 4, 6, 4, 1 over 16.
        assert_eq!(binomial_half_cdf(0, 4), 1.0 / 16.0);
        assert_eq!(binomial_half_cdf(1, 4), 5.0 / 16.0);
        assert_eq!(binomial_half_cdf(2, 4), 11.0 / 16.0);
        assert_eq!(binomial_half_cdf(3, 4), 15.0 / 16.0);
        assert_eq!(binomial_half_cdf(4, 4), 1.0);
        assert_eq!(binomial_half_cdf(0, 0), 1.0);
        // n = 10: 1 + 10 + 45 = 56 of 1024.
        assert_eq!(binomial_half_cdf(2, 10), 56.0 / 1024.0);
        // Exact sums for every k of n = 60 (integers below 2^60, so the reference is exact
        // up to one rounding).
        let n = 60u64;
        let mut c = vec![1u128; 1];
        for j in 1..=n {
            let next = c[(j - 1) as usize] * u128::from(n - j + 1) / u128::from(j);
            c.push(next);
        }
        let total = 2f64.powi(60);
        let mut cumulative = 0u128;
        for k in 0..=n {
            cumulative += c[k as usize];
            let expected = cumulative as f64 / total;
            let got = binomial_half_cdf(k, n);
            assert!(
                ((got - expected) / expected).abs() < 1e-14,
                "{k}: {got} vs {expected}"
            );
        }
    }

    #[test]
    fn binomial_far_tails() {
        // P(X = 0) = 2^-n, exact; 2^-1074 is the smallest subnormal, below it 0.
        assert_eq!(binomial_half_cdf(0, 1000), 2f64.powi(-1000));
        assert_eq!(binomial_half_cdf(0, 1074), f64::from_bits(1));
        assert_eq!(binomial_half_cdf(0, 1200), 0.0);
        // Symmetric around n/2 for odd n: P(X <= (n-1)/2) = 1/2 exactly in theory.
        let half = binomial_half_cdf(2500, 5001);
        assert!((half - 0.5).abs() < 1e-13, "{half}");
        // Large n, k near the middle: the product has overflowed its range many times.
        let p = binomial_half_cdf(4800, 10_000);
        // Normal approximation with continuity correction: z = (4800.5 - 5000) / 50 = -3.99.
        let approx = normal_cdf(-3.99);
        assert!((p / approx - 1.0).abs() < 0.02, "{p} vs {approx}");
    }
}
