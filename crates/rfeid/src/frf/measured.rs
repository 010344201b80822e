//! The FRF the data show: the H1 estimator `H1 = S_yu / S_uu` from a
//! measured force u and a response y, with the coherence
//! `γ² = |S_yu|² / (S_uu S_yy)`, by Welch's method (segments of a power of
//! two, Hann windows, half overlap, each segment's mean removed).
//!
//! H1 is unbiased by noise on y; noise on u biases it low. Its random error
//! (Bendat & Piersol, *Random Data*, eq. 9.90): the normalised standard
//! deviation of |H1| is `ε = √(1 − γ²) / (|γ| √(2 n))`, n the number of
//! independent averages (the segments, discounted for the overlap's
//! correlation: 1 + 2ρ² with ρ = 1/6 for Hann windows at half overlap).
use super::response::C64;
use super::FrfError;
use rustfft::FftPlanner;

/// A measured FRF on Welch's frequency grid.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredFrf {
    /// Frequencies, Hz: df, 2 df, …, fs/2 (no 0).
    pub frequencies: Vec<f64>,
    /// H1 per frequency (response per unit input).
    pub h1: Vec<C64>,
    /// Ordinary coherence γ² per frequency, in [0, 1].
    pub coherence: Vec<f64>,
    /// The normalised random error ε of |H1| per frequency (the standard
    /// deviation of |H1| over |H1|; also that of the phase in radians).
    pub random_error: Vec<f64>,
    /// Segments averaged.
    pub segments: usize,
}

/// H1 and the coherence of the response `y` to the input `u`, both sampled
/// at `fs` Hz, with segments of `segment` samples (a power of two, at most
/// the record).
pub fn h1(u: &[f64], y: &[f64], fs: f64, segment: usize) -> Result<MeasuredFrf, FrfError> {
    let m = segment;
    if !m.is_power_of_two() || m < 8 || m > u.len() || u.len() != y.len() {
        return Err(FrfError::Segment {
            segment: m,
            samples: u.len().min(y.len()),
        });
    }
    let fft = FftPlanner::<f64>::new().plan_fft_forward(m);
    let window: Vec<f64> = (0..m)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / m as f64).cos())
        .collect();
    let bins = m / 2;
    let (mut suu, mut syy) = (vec![0.0; bins], vec![0.0; bins]);
    let mut syu = vec![C64::new(0.0, 0.0); bins];
    let (mut a, mut b) = (vec![C64::default(); m], vec![C64::default(); m]);
    let mut segments = 0usize;
    let mut start = 0;
    while start + m <= u.len() {
        windowed(&u[start..start + m], &window, &mut a);
        windowed(&y[start..start + m], &window, &mut b);
        fft.process(&mut a);
        fft.process(&mut b);
        for k in 0..bins {
            let (uk, yk) = (a[k + 1], b[k + 1]);
            suu[k] += uk.norm_sqr();
            syy[k] += yk.norm_sqr();
            syu[k] += yk * uk.conj();
        }
        segments += 1;
        start += m / 2;
    }
    let rho = 1.0 / 6.0;
    let averages = segments as f64 / (1.0 + 2.0 * rho * rho * (1.0 - 1.0 / segments as f64));
    let mut out = MeasuredFrf {
        frequencies: (1..=bins).map(|k| k as f64 * fs / m as f64).collect(),
        h1: Vec::with_capacity(bins),
        coherence: Vec::with_capacity(bins),
        random_error: Vec::with_capacity(bins),
        segments,
    };
    for k in 0..bins {
        let h = if suu[k] > 0.0 {
            syu[k] / suu[k]
        } else {
            C64::new(f64::NAN, f64::NAN)
        };
        let g2 = match suu[k] * syy[k] {
            d if d > 0.0 => (syu[k].norm_sqr() / d).min(1.0),
            _ => 0.0,
        };
        out.h1.push(h);
        out.coherence.push(g2);
        out.random_error
            .push(((1.0 - g2) / (2.0 * averages * g2)).sqrt());
    }
    Ok(out)
}

/// The segment `x` less its mean, times the window, into `out`.
fn windowed(x: &[f64], window: &[f64], out: &mut [C64]) {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    for ((o, v), w) in out.iter_mut().zip(x).zip(window) {
        *o = C64::new((v - mean) * w, 0.0);
    }
}

/// The default segment: the largest power of two that gives at least 16
/// averages at half overlap (`2N/m − 1 ≥ 16`), and at least 8 samples.
pub fn default_segment(samples: usize) -> usize {
    let target = ((samples as f64 / 8.5) as usize).max(8);
    1usize << (usize::BITS - 1 - target.leading_zeros())
}
