//! Power spectral densities of sampled signals (Welch's method), for showing
//! where in frequency a residual lies.
//!
//! The record is cut into segments of `segment` samples (a power of two)
//! overlapping by half, each Hann-windowed and transformed by a radix-2 FFT;
//! their periodograms are averaged. The density is one-sided, in the
//! signal's unit squared per Hz, scaled so that it integrates to the mean
//! square over 0 … fs/2.

/// A one-sided power spectral density on equally spaced frequencies.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// Frequencies, Hz: 0, df, …, fs/2.
    pub frequencies: Vec<f64>,
    /// Density at each frequency, unit²/Hz.
    pub density: Vec<f64>,
}

impl Spectrum {
    /// The frequency of the largest density, and the band around it where
    /// the density stays above a tenth of that; `None` for an empty
    /// spectrum.
    pub fn peak_band(&self) -> Option<(f64, f64, f64)> {
        let (k, &top) = self
            .density
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))?;
        let above = |i: &usize| self.density[*i] >= 0.1 * top;
        let lo = (0..=k).rev().take_while(above).last().unwrap_or(k);
        let hi = (k..self.density.len())
            .take_while(above)
            .last()
            .unwrap_or(k);
        Some((
            self.frequencies[k],
            self.frequencies[lo],
            self.frequencies[hi],
        ))
    }
}

/// Welch's estimate of the density of `x` sampled at `fs` Hz, with segments
/// of the largest power of two up to `segment` that the record holds (at
/// least 8 samples); `None` for a shorter record.
pub fn welch(x: &[f64], fs: f64, segment: usize) -> Option<Spectrum> {
    let mut m = segment.next_power_of_two();
    while m > x.len() {
        m /= 2;
    }
    if m < 8 {
        return None;
    }
    let window: Vec<f64> = (0..m)
        .map(|i| 0.5 - 0.5 * (std::f64::consts::TAU * i as f64 / m as f64).cos())
        .collect();
    let power: f64 = window.iter().map(|w| w * w).sum();
    let mut sum = vec![0.0; m / 2 + 1];
    let (mut re, mut im) = (vec![0.0; m], vec![0.0; m]);
    let mut segments = 0usize;
    let mut start = 0;
    while start + m <= x.len() {
        for i in 0..m {
            re[i] = x[start + i] * window[i];
            im[i] = 0.0;
        }
        fft(&mut re, &mut im);
        for (k, s) in sum.iter_mut().enumerate() {
            *s += re[k] * re[k] + im[k] * im[k];
        }
        segments += 1;
        start += m / 2;
    }
    let scale = 1.0 / (fs * power * segments as f64);
    let density = sum
        .iter()
        .enumerate()
        .map(|(k, s)| {
            // One-sided: every bin but DC and Nyquist holds both halves.
            let both = if k == 0 || k == m / 2 { 1.0 } else { 2.0 };
            both * s * scale
        })
        .collect();
    let frequencies = (0..=m / 2).map(|k| k as f64 * fs / m as f64).collect();
    Some(Spectrum {
        frequencies,
        density,
    })
}

/// In-place iterative radix-2 FFT (`re.len()` a power of two).
fn fft(re: &mut [f64], im: &mut [f64]) {
    let n = re.len();
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let angle = -std::f64::consts::TAU / len as f64;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (s, c) = (angle * k as f64).sin_cos();
                let (a, b) = (start + k, start + k + len / 2);
                let tr = re[b] * c - im[b] * s;
                let ti = re[b] * s + im[b] * c;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
            }
        }
        len <<= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fft_matches_the_direct_transform() {
        let n = 16;
        let x: Vec<f64> = (0..n).map(|i| ((i * 7 + 3) % 11) as f64 - 5.0).collect();
        let (mut re, mut im) = (x.clone(), vec![0.0; n]);
        fft(&mut re, &mut im);
        for k in 0..n {
            let (mut a, mut b) = (0.0, 0.0);
            for (i, v) in x.iter().enumerate() {
                let w = -std::f64::consts::TAU * (i * k) as f64 / n as f64;
                a += v * w.cos();
                b += v * w.sin();
            }
            assert!((re[k] - a).abs() < 1e-12 && (im[k] - b).abs() < 1e-12);
        }
    }

    #[test]
    fn a_sine_peaks_at_its_frequency_with_its_mean_square() {
        let fs = 1000.0;
        let x: Vec<f64> = (0..8192)
            .map(|k| 3.0 * (std::f64::consts::TAU * 125.0 * k as f64 / fs).sin())
            .collect();
        let s = welch(&x, fs, 256).unwrap();
        let (peak, lo, hi) = s.peak_band().unwrap();
        assert_eq!(peak, 125.0);
        assert!(lo >= 115.0 && hi <= 135.0, "{lo} {hi}");
        let df = s.frequencies[1];
        let total: f64 = s.density.iter().sum::<f64>() * df;
        // Mean square of the sine: 4.5.
        assert!((total - 4.5).abs() < 0.05, "{total}");
    }

    #[test]
    fn short_records_have_no_spectrum() {
        assert!(welch(&[1.0; 7], 10.0, 256).is_none());
        assert_eq!(welch(&[1.0; 9], 10.0, 256).unwrap().frequencies.len(), 5);
    }
}
