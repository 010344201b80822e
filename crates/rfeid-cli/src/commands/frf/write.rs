//! What `rfeid frf` writes and prints: the CSV (one row per pair, curve and
//! frequency), the JSON, the peaks table and the measured data's line.
use crate::format::{sig, table};
use rfeid::frf::study::{MeasuredCurves, PairCurves};
use rfeid::frf::FrfStudy;
use std::fmt::Write;

/// The CSV header.
const HEADER: &str = "excitation,output,curve,frequency_hz,magnitude,phase_deg,real,imag,\
magnitude_lo95,magnitude_hi95,phase_lo95_deg,phase_hi95_deg,coherence,random_error";

/// The study as CSV: the model's rows (with the band where there is one),
/// then each measured curve's; an absent value is an empty cell.
pub fn csv(s: &FrfStudy) -> String {
    let mut out = format!("{HEADER}\n");
    let num = |v: Option<f64>| {
        v.filter(|x| x.is_finite())
            .map_or(String::new(), |x| format!("{x:e}"))
    };
    for p in &s.pairs {
        let names = format!("{},{}", quote(&p.excitation), quote(&p.output));
        for (k, f) in s.frequencies_hz.iter().enumerate() {
            let b = p.band.as_ref();
            let _ = writeln!(
                out,
                "{names},model,{},{},{},{},{},{},{},{},{},,",
                num(Some(*f)),
                num(Some(p.magnitude[k])),
                num(Some(p.phase_deg[k])),
                num(Some(p.real[k])),
                num(Some(p.imag[k])),
                num(b.map(|b| b.magnitude_lo[k])),
                num(b.map(|b| b.magnitude_hi[k])),
                num(b.map(|b| b.phase_lo_deg[k])),
                num(b.map(|b| b.phase_hi_deg[k])),
            );
        }
        for m in &p.measured {
            let curve = quote(&format!("H1 {}", m.label));
            for (k, f) in m.frequencies_hz.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "{names},{curve},{},{},{},{},{},,,,,{},{}",
                    num(Some(*f)),
                    num(Some(m.magnitude[k])),
                    num(Some(m.phase_deg[k])),
                    num(Some(m.real[k])),
                    num(Some(m.imag[k])),
                    num(Some(m.coherence[k])),
                    num(Some(m.random_error[k])),
                );
            }
        }
    }
    out
}

/// A CSV field, quoted if it needs to be.
fn quote(s: &str) -> String {
    match s.contains([',', '"', '\n']) {
        true => format!("\"{}\"", s.replace('"', "\"\"")),
        false => s.to_owned(),
    }
}

/// The study as JSON, with why there is no band if there is none.
pub fn json(s: &FrfStudy, band_error: Option<&str>) -> String {
    let mut v = serde_json::to_value(s).unwrap_or_default();
    if let (Some(why), Some(map)) = (band_error, v.as_object_mut()) {
        map.insert("band_error".into(), why.into());
    }
    let mut text = serde_json::to_string_pretty(&v).unwrap_or_default();
    text.push('\n');
    text
}

/// The pair's resonance peaks (local maxima of |H|, the five largest by
/// frequency), each with its band in per cent.
pub fn peaks_table(s: &FrfStudy, p: &PairCurves) -> String {
    let m = &p.magnitude;
    let mut peaks: Vec<usize> = (1..m.len().saturating_sub(1))
        .filter(|&k| m[k] > m[k - 1] && m[k] >= m[k + 1])
        .collect();
    peaks.sort_by(|a, b| m[*b].total_cmp(&m[*a]));
    peaks.truncate(5);
    peaks.sort_unstable();
    let rows: Vec<Vec<String>> = peaks
        .iter()
        .map(|&k| {
            let band = p.band.as_ref().map_or("-".into(), |b| {
                format!(
                    "{} … +{} %",
                    sig(100.0 * (b.magnitude_lo[k] / m[k] - 1.0), 2),
                    sig(100.0 * (b.magnitude_hi[k] / m[k] - 1.0), 2)
                )
            });
            vec![
                sig(s.frequencies_hz[k], 5),
                sig(m[k], 4),
                sig(p.phase_deg[k], 4),
                band,
            ]
        })
        .collect();
    if rows.is_empty() {
        return "  no resonance peak in the band\n".into();
    }
    table(&["peak Hz", "|H|", "phase °", "95 % band of |H|"], &rows)
}

/// One measured curve in words: its averaging and where it is coherent.
pub fn measured_line(m: &MeasuredCurves) -> String {
    let coherent = m.coherence.iter().filter(|g| **g > 0.9).count();
    format!(
        "H1 {}: {} segments of {} samples ({} Hz resolution); coherence above 0.9 at {} of {} frequencies",
        m.label,
        m.segments,
        m.segment,
        sig(m.resolution_hz, 3),
        coherent,
        m.coherence.len()
    )
}
