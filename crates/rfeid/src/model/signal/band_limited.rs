//! The band-limited interpolant of a table's samples (SPEC §1, `table`
//! signals with `interpolation = "band-limited"`): the value between samples
//! of a signal that holds no content at or above half the sample rate, as a
//! force measured behind an anti-alias filter does.
//!
//! For N samples `x_n` at `t_n = t_0 + nΔ`, with DFT `X_k = Σ_n x_n
//! e^{−2πikn/N}`, the interpolant is the trigonometric polynomial
//!
//! ```text
//! x(t) = (1/N) Σ_{|k| < N/2} X_k e^{2πiks/N} + [N even] (1/N) X_{N/2} cos(πs),
//! s = (t − t_0)/Δ,
//! ```
//!
//! the periodic sinc interpolation of the record: it passes through every
//! sample, and it is exact when the record is one or more whole periods of a
//! band-limited signal (the Nyquist bin is split evenly between ±N/2, so a
//! real record gives a real interpolant).
//!
//! Evaluating the sum at each instant would cost O(N). Instead the record is
//! upsampled once, at load time, by [`UPSAMPLING`] = 4 through the FFT (a
//! sub-sample delay `e^{2πikδ/N}` of the spectrum per fine phase δ = r/4,
//! one inverse FFT of size N each), and the fine grid is interpolated by a
//! centred [`ORDER`] = 16-point Lagrange polynomial: O(1) and no allocation
//! per evaluation, at every Runge–Kutta stage.
//!
//! # Accuracy
//!
//! The Lagrange step is the only approximation beyond rounding. For a
//! sinusoid of frequency f (a fraction f/fs of the sample rate) its largest
//! error, relative to the sinusoid's amplitude, is 2.6e-14 at f/fs = 0.2,
//! 1.6e-11 at 0.3, 1.4e-9 at 0.4 and 4.5e-8 at the Nyquist frequency 0.5.
//! The unit tests measure a multisine with content up to 0.3 fs.
//!
//! # Caveat
//!
//! The interpolant treats the record as periodic. A record that is not a
//! whole number of periods (a sweep from rest, a transient) is interpolated
//! as if its end joined its start: where they do not join smoothly, the
//! interpolant rings near both ends (a Gibbs error that decays as the
//! inverse of the distance from the end, in samples). At the samples
//! themselves it stays exact.
//!
//! # Memory
//!
//! The fine grid holds [`UPSAMPLING`] values per sample: 32 bytes per sample,
//! 32 MB for 10⁶ samples (besides the table's own times and values, 16 MB).
//! Building it takes one forward and two inverse FFTs of size N (any N:
//! mixed radix, or Bluestein's algorithm for large prime factors), and for
//! the while two complex buffers of N (32 bytes per sample), the FFT's
//! plan and its scratch. With a smooth N (10⁶ = 2⁶ · 5⁶) those are small:
//! `rfeid check` of a one-body model with a 10⁶-sample table peaks 72 bytes
//! per sample above linear interpolation (116 MB against 44 MB). With a
//! large prime factor (10⁶ + 1 = 101 · 9901) the FFT takes Bluestein's
//! algorithm, whose plan and scratch hold buffers of the next power of two
//! above 2N: 190 bytes per sample above linear (234 MB; it was 328 MB with
//! a second plan for the inverse transforms). Measured with
//! `/usr/bin/time -f %M`.
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;
use std::f64::consts::PI;

/// Fine grid points per sample interval (SPEC §1; see the module docs for
/// the error this gives).
pub const UPSAMPLING: usize = 4;

/// Points of the Lagrange polynomial on the fine grid: the interval
/// `[i, i + 1]` is interpolated from fine points `i − 7 … i + 8`.
pub const ORDER: usize = 16;

/// Fine points kept beyond each end of the record (its periodic extension),
/// so that a stencil never leaves the grid.
const HALO: usize = ORDER / 2;

/// `1 / Π_{k ≠ j} (j − k)` over the stencil's offsets `k = −7 … 8`: the
/// Lagrange weights' denominators, j = −7 … 8 at indices 0 … 15.
const INVERSE_DENOMINATORS: [f64; ORDER] = inverse_denominators();

const fn inverse_denominators() -> [f64; ORDER] {
    let mut out = [0.0; ORDER];
    let mut j = 0;
    while j < ORDER {
        let mut d = 1.0;
        let mut k = 0;
        while k < ORDER {
            if k != j {
                d *= j as f64 - k as f64;
            }
            k += 1;
        }
        out[j] = 1.0 / d;
        j += 1;
    }
    out
}

/// Why samples cannot be interpolated as a band-limited signal.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BandLimitedError {
    /// Fewer than two samples: no sample interval.
    #[error("band-limited interpolation needs at least 2 samples (found {found})")]
    TooFewSamples {
        /// Number of samples.
        found: usize,
    },
    /// The first and last instants do not increase.
    #[error("the samples span no time (t = {first} … {last} s)")]
    NoSpan {
        /// First instant, s.
        first: f64,
        /// Last instant, s.
        last: f64,
    },
    /// A sample off the even grid from the first instant to the last.
    #[error(
        "band-limited interpolation needs evenly spaced samples: sample {index} is at \
         t = {time} s, but even spacing from t = {first} s to t = {last} s puts it at \
         t = {expected} s (to within {tolerance:.3e} s); use interpolation = \"linear\" \
         for unevenly spaced samples"
    )]
    Uneven {
        /// 0-based sample index.
        index: usize,
        /// Its instant, s.
        time: f64,
        /// Where even spacing puts it, s.
        expected: f64,
        /// First instant, s.
        first: f64,
        /// Last instant, s.
        last: f64,
        /// The tolerance at this sample, s.
        tolerance: f64,
    },
}

/// The periodic band-limited interpolant of evenly spaced samples, on a
/// fine grid (module docs; SPEC §1).
#[derive(Clone, PartialEq)]
pub struct BandLimited {
    /// Instant of the first sample t_0, s.
    start: f64,
    /// Sample interval Δ, s.
    step: f64,
    /// Fine points per second, `UPSAMPLING / Δ`.
    fine_rate: f64,
    /// The last sample's fine index, `UPSAMPLING (N − 1)`, as a float.
    fine_end: f64,
    /// `x(t_0 + mΔ/UPSAMPLING)` at index `m + HALO`, for `m = −HALO …
    /// UPSAMPLING·N + HALO − 1` (periodically extended).
    grid: Vec<f64>,
}

impl std::fmt::Debug for BandLimited {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BandLimited")
            .field("start", &self.start)
            .field("step", &self.step)
            .field("samples", &self.samples())
            .finish_non_exhaustive()
    }
}

impl BandLimited {
    /// The interpolant of `values` at the instants `times`, which must be
    /// evenly spaced: each instant within `10⁻³ Δ + 2⁻²⁴ (|t_k| + |t_0| +
    /// |t_{N−1}|)` of `t_0 + kΔ`, with `Δ = (t_{N−1} − t_0)/(N − 1)`. That is
    /// the tolerance of measured records' time stamps
    /// ([`GRID_TOLERANCE`](crate::measurement::GRID_TOLERANCE)) plus the
    /// float32 rounding of the stamp and of the two ends that set Δ, so
    /// float32 time columns pass. The samples are then taken at exactly
    /// `t_0 + kΔ`.
    ///
    /// # Panics
    /// If `times` and `values` differ in length (a programmer error).
    pub fn new(times: &[f64], values: &[f64]) -> Result<Self, BandLimitedError> {
        assert_eq!(times.len(), values.len(), "one value per instant");
        let n = times.len();
        if n < 2 {
            return Err(BandLimitedError::TooFewSamples { found: n });
        }
        let (first, last) = (times[0], times[n - 1]);
        let step = (last - first) / (n - 1) as f64;
        if !(step > 0.0 && step.is_finite() && first.is_finite()) {
            return Err(BandLimitedError::NoSpan { first, last });
        }
        check_even(times, step)?;
        Ok(BandLimited {
            start: first,
            step,
            fine_rate: UPSAMPLING as f64 / step,
            fine_end: (UPSAMPLING * (n - 1)) as f64,
            grid: fine_grid(values),
        })
    }

    /// Number of samples N.
    fn samples(&self) -> usize {
        (self.grid.len() - 2 * HALO) / UPSAMPLING
    }

    /// The interpolant at t, clamped to the record's span `[t_0, t_{N−1}]`:
    /// the sample itself at a sample instant, the periodic band-limited
    /// interpolant between them (module docs). O(1), no allocation.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        let (window, x) = self.window(t);
        if x == 0.0 {
            return window[HALO - 1];
        }
        lagrange(window, x)
    }

    /// The fine points around t, clamped to the record's span, and t's
    /// place among them, x ∈ [0, 1): fine points i − 7 … i + 8 (grid
    /// indices i + 1 … i + 16) for the fine instant u = i + x.
    #[inline]
    fn window(&self, t: f64) -> (&[f64; ORDER], f64) {
        let u = ((t - self.start) * self.fine_rate).clamp(0.0, self.fine_end);
        // u ≥ 0, so truncation is the floor.
        let i = u as usize;
        let window = self.grid[i + 1..i + 1 + ORDER]
            .try_into()
            .expect("the halo keeps the stencil on the grid");
        (window, u - i as f64)
    }
}

impl BandLimited {
    /// The interpolant's time derivative at t: the derivative of the same
    /// Lagrange polynomial ([`BandLimited::at`]), t clamped to the record
    /// as there.
    pub fn rate(&self, t: f64) -> f64 {
        let (window, x) = self.window(t);
        self.fine_rate * lagrange_slope(window, x)
    }
}

/// The x-derivative of [`lagrange`]'s polynomial: `Σ_j y_j c_j Σ_{m≠j}
/// Π_{k≠j,m} (x − k)`, by the product rule (O(ORDER²); a cold path, the
/// excitation's rate at a located switch).
fn lagrange_slope(y: &[f64; ORDER], x: f64) -> f64 {
    let offset = (HALO - 1) as f64;
    let d: [f64; ORDER] = std::array::from_fn(|j| x + offset - j as f64);
    let mut sum = 0.0;
    for j in 0..ORDER {
        let mut slope = 0.0;
        for m in (0..ORDER).filter(|&m| m != j) {
            let product: f64 = (0..ORDER)
                .filter(|&k| k != j && k != m)
                .map(|k| d[k])
                .product();
            slope += product;
        }
        sum += y[j] * INVERSE_DENOMINATORS[j] * slope;
    }
    sum
}

/// Each instant within the grid tolerance of `t_0 + kΔ`.
fn check_even(times: &[f64], step: f64) -> Result<(), BandLimitedError> {
    let (first, last) = (times[0], times[times.len() - 1]);
    for (k, &time) in times.iter().enumerate() {
        let expected = first + k as f64 * step;
        let tolerance = crate::measurement::GRID_TOLERANCE * step
            + (time.abs() + first.abs() + last.abs()) / 16_777_216.0;
        // Written so that a NaN instant fails.
        if !((time - expected).abs() <= tolerance) {
            return Err(BandLimitedError::Uneven {
                index: k,
                time,
                expected,
                first,
                last,
                tolerance,
            });
        }
    }
    Ok(())
}

/// The record upsampled by [`UPSAMPLING`] through the FFT, periodically
/// extended by [`HALO`] fine points at each end. Phase 0 is the samples
/// themselves, so the interpolant passes through them exactly.
///
/// One forward plan serves every transform (an inverse one is its
/// conjugate: `ifft(Y) = conj(fft(conj(Y))) / N`), with one scratch buffer,
/// and each inverse transform yields two fine phases at once (the real and
/// imaginary parts of `ifft(D_a X + i D_b X)`, both signals being real):
/// for a record length with a large prime factor (10⁶ + 1 = 101 · 9901),
/// where the FFT takes Bluestein's algorithm and its plan holds buffers of
/// twice the record's length, a second (inverse) plan cost a further
/// 80 bytes per sample.
fn fine_grid(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    let fft = FftPlanner::<f64>::new().plan_fft_forward(n);
    let mut scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
    let mut spectrum: Vec<Complex<f64>> = values.iter().map(|&v| Complex::new(v, 0.0)).collect();
    fft.process_with_scratch(&mut spectrum, &mut scratch);
    let fine_len = UPSAMPLING * n;
    // Fine point m at grid[m + HALO].
    let mut grid = vec![0.0; fine_len + 2 * HALO];
    for (m, &v) in values.iter().enumerate() {
        grid[HALO + UPSAMPLING * m] = v;
    }
    let phases: Vec<usize> = (1..UPSAMPLING).collect();
    let mut work = vec![Complex::new(0.0, 0.0); n];
    for pair in phases.chunks(2) {
        let delta = |r: usize| r as f64 / UPSAMPLING as f64;
        for (k, (w, &x)) in work.iter_mut().zip(&spectrum).enumerate() {
            let mut factor = delay_factor(k, n, delta(pair[0]));
            if let Some(&b) = pair.get(1) {
                factor += Complex::<f64>::i() * delay_factor(k, n, delta(b));
            }
            // Conjugated, so that the forward transform inverts it.
            *w = (x * factor).conj();
        }
        fft.process_with_scratch(&mut work, &mut scratch);
        for (m, y) in work.iter().enumerate() {
            // ifft·N = conj(y): phase a is y.re, phase b is −y.im.
            grid[HALO + UPSAMPLING * m + pair[0]] = y.re / n as f64;
            if let Some(&b) = pair.get(1) {
                grid[HALO + UPSAMPLING * m + b] = -y.im / n as f64;
            }
        }
    }
    // The periodic extension (fine_len ≥ 8 = HALO, as n ≥ 2).
    for h in 0..HALO {
        grid[h] = grid[fine_len + h];
        grid[fine_len + HALO + h] = grid[HALO + h];
    }
    grid
}

/// The factor `e^{2πi k δ / N}` of bin k (k taken in `(−N/2, N/2)`) that
/// advances the interpolant by δ samples. For even N the Nyquist bin, split
/// evenly between ±N/2, takes `cos(πδ)`, so a real record stays real.
fn delay_factor(k: usize, n: usize, delta: f64) -> Complex<f64> {
    if 2 * k == n {
        return Complex::new((PI * delta).cos(), 0.0);
    }
    // The signed frequency index.
    let signed = if 2 * k < n {
        k as f64
    } else {
        k as f64 - n as f64
    };
    let (sin, cos) = (2.0 * PI * signed * delta / n as f64).sin_cos();
    Complex::new(cos, sin)
}

/// The Lagrange polynomial through `(j, y[j + 7])`, j = −7 … 8, at x in
/// (0, 1): `Σ_j y_j c_j Π_{k≠j} (x − k)`, the products from prefix and
/// suffix products (O(ORDER), no division).
#[inline]
fn lagrange(y: &[f64; ORDER], x: f64) -> f64 {
    let offset = (HALO - 1) as f64;
    let mut d = [0.0; ORDER];
    for (j, dj) in d.iter_mut().enumerate() {
        *dj = x + offset - j as f64;
    }
    // prefix[j] = Π_{k<j} d_k.
    let mut prefix = [1.0; ORDER];
    for j in 1..ORDER {
        prefix[j] = prefix[j - 1] * d[j - 1];
    }
    let mut suffix = 1.0;
    let mut sum = 0.0;
    for j in (0..ORDER).rev() {
        sum += y[j] * INVERSE_DENOMINATORS[j] * prefix[j] * suffix;
        suffix *= d[j];
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The benchmark's rate (Bouc–Wen, 750 Hz).
    const RATE: f64 = 750.0;

    /// A multisine of `count` seeded components on whole-period bins of an
    /// n-sample record at [`RATE`], the highest at bin `top` (always
    /// included): `(frequency, amplitude, phase)` each.
    fn multisine(n: usize, top: usize, count: usize, seed: u64) -> Vec<(f64, f64, f64)> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        (0..count)
            .map(|c| {
                let bin = if c == 0 {
                    top
                } else {
                    rng.random_range(1..top)
                };
                let amplitude = rng.random_range(0.5..1.5);
                let phase = rng.random_range(0.0..2.0 * PI);
                (bin as f64 * RATE / n as f64, amplitude, phase)
            })
            .collect()
    }

    /// The closed form Σ a sin(2πft + φ).
    fn exact(tones: &[(f64, f64, f64)], t: f64) -> f64 {
        tones
            .iter()
            .map(|&(f, a, phase)| a * (2.0 * PI * f * t + phase).sin())
            .sum()
    }

    /// The record's instants and samples.
    fn record(tones: &[(f64, f64, f64)], n: usize) -> (Vec<f64>, Vec<f64>) {
        let times: Vec<f64> = (0..n).map(|k| k as f64 / RATE).collect();
        let values = times.iter().map(|&t| exact(tones, t)).collect();
        (times, values)
    }

    /// Largest error of the band-limited and of the linear interpolant at
    /// seeded off-grid instants (and near both ends, where the stencil
    /// wraps), relative to the record's peak.
    fn errors(n: usize, top: usize) -> (f64, f64) {
        let tones = multisine(n, top, 60, n as u64);
        let (times, values) = record(&tones, n);
        let peak = values.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let bl = BandLimited::new(&times, &values).unwrap();
        let last = times[n - 1];
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let ends = (1..200).flat_map(|i| [i as f64 * 1.37e-5, last - i as f64 * 1.37e-5]);
        let probes: Vec<f64> = (0..20_000)
            .map(|_| rng.random_range(0.0..last))
            .chain(ends)
            .collect();
        let worst = |f: &dyn Fn(f64) -> f64| {
            probes
                .iter()
                .map(|&t| (f(t) - exact(&tones, t)).abs())
                .fold(0.0, f64::max)
                / peak
        };
        (
            worst(&|t| bl.at(t)),
            worst(&|t| super::super::interpolate(&times, &values, t, None)),
        )
    }

    #[test]
    fn band_limited_reproduces_a_multisine_up_to_0_3_fs() {
        // 3000 samples (2³·3·5³: not a power of two), content up to 225 Hz
        // = 0.3·750 Hz; and an odd record, 2999 samples, up to 224.9 Hz.
        for (n, top) in [(3000, 900), (2999, 899)] {
            let (band, linear) = errors(n, top);
            println!(
                "N = {n}, up to {:.1} Hz: band-limited {band:.2e}, linear {linear:.2e} \
                 (× {:.1e})",
                top as f64 * RATE / n as f64,
                linear / band
            );
            assert!(band <= 1e-9, "N = {n}: {band:e}");
            assert!(linear >= 1e6 * band, "N = {n}: {linear:e} vs {band:e}");
        }
    }

    /// Every fine phase of the grid (two from each inverse transform, the
    /// inverse taken by the forward plan) is the DFT interpolant summed
    /// directly, for even, odd and prime N.
    #[test]
    fn the_fine_grid_is_the_dft_interpolant_at_every_phase() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for n in [8, 9, 13, 64] {
            let values: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
            let grid = fine_grid(&values);
            let direct = |s: f64| {
                let mut sum = 0.0;
                for k in 0..n {
                    let x: Complex<f64> = values
                        .iter()
                        .enumerate()
                        .map(|(m, &v)| {
                            v * Complex::from_polar(1.0, -2.0 * PI * (k * m) as f64 / n as f64)
                        })
                        .sum();
                    sum += (x * delay_factor(k, n, s)).re;
                }
                sum / n as f64
            };
            for m in 0..n {
                for r in 0..UPSAMPLING {
                    let s = m as f64 + r as f64 / UPSAMPLING as f64;
                    let got = grid[HALO + UPSAMPLING * m + r];
                    assert!(
                        (got - direct(s)).abs() < 1e-12,
                        "N = {n}, s = {s}: {got} vs {}",
                        direct(s)
                    );
                }
            }
        }
    }

    #[test]
    fn band_limited_splits_the_nyquist_bin() {
        // cos(π fs t) is (−1)ᵏ at the samples; the interpolant is the
        // cosine itself, within the Lagrange error at fs/2 (4.5e-8).
        let n = 64;
        let tones = [(RATE / 2.0, 1.0, PI / 2.0), (RATE * 5.0 / 64.0, 0.5, 0.3)];
        let (times, values) = record(&tones, n);
        let bl = BandLimited::new(&times, &values).unwrap();
        let worst = (0..1000)
            .map(|i| times[n - 1] * (i as f64 + 0.5) / 1000.0)
            .map(|t| (bl.at(t) - exact(&tones, t)).abs())
            .fold(0.0, f64::max);
        assert!(worst <= 1e-7, "{worst:e}");
    }

    #[test]
    fn band_limited_passes_through_the_samples_and_clamps_to_the_span() {
        let tones = multisine(1000, 300, 10, 3);
        let (times, values) = record(&tones, 1000);
        let bl = BandLimited::new(&times, &values).unwrap();
        assert_eq!(bl.at(0.0), values[0]);
        // Within the rounding of t (the fine index of t is good to 4e-13).
        for (t, v) in times.iter().zip(&values) {
            assert!((bl.at(*t) - v).abs() <= 1e-10, "t = {t}");
        }
        assert_eq!(bl.at(-1.0), values[0]);
        assert!((bl.at(10.0) - values[999]).abs() <= 1e-12);
    }

    #[test]
    fn band_limited_refuses_unevenly_spaced_samples() {
        let n = 40_960;
        let even: Vec<f64> = (0..n).map(|k| k as f64 / RATE).collect();
        let values = vec![1.0; n];
        // Float32 stamps, as acquisition systems write them, pass.
        let float32: Vec<f64> = even.iter().map(|&t| f64::from(t as f32)).collect();
        assert!(BandLimited::new(&float32, &values).is_ok());
        let mut uneven = even.clone();
        uneven[17] += 0.01 / RATE;
        let err = BandLimited::new(&uneven, &values).unwrap_err();
        assert!(
            matches!(err, BandLimitedError::Uneven { index: 17, .. }),
            "{err:?}"
        );
        assert!(err.to_string().contains("evenly spaced"), "{err}");
        let short = BandLimited::new(&[0.0], &[1.0]).unwrap_err();
        assert_eq!(short, BandLimitedError::TooFewSamples { found: 1 });
        let flat = BandLimited::new(&[1.0, 1.0], &[1.0, 2.0]).unwrap_err();
        assert!(matches!(flat, BandLimitedError::NoSpan { .. }));
    }
}
