//! Amplitude spectrum of a uniformly sampled signal (the paper's Fig. 10), by a radix-2 FFT with a
//! Hann window. Small enough to write here rather than pull in an FFT crate: `rustfft` costs 9
//! crates and 4.4 CPU-s of release build to replace 30 lines run once per plotted wheel, where
//! drawing the figure takes far longer than the transform.

use std::f64::consts::PI;

/// In-place iterative radix-2 FFT on (re, im) pairs; `data.len()` must be a power of two.
fn fft(data: &mut [(f64, f64)]) {
    let n = data.len();
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            data.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -2.0 * PI / len as f64;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (s, c) = (ang * k as f64).sin_cos();
                let (ar, ai) = data[start + k];
                let (br, bi) = data[start + k + len / 2];
                let (tr, ti) = (br * c - bi * s, br * s + bi * c);
                data[start + k] = (ar + tr, ai + ti);
                data[start + k + len / 2] = (ar - tr, ai - ti);
            }
        }
        len <<= 1;
    }
}

/// One-sided amplitude spectrum of the last power-of-two samples of `signal` (mean removed,
/// Hann window, amplitude-corrected). Returns (frequency \[Hz\], amplitude) pairs.
pub(crate) fn amplitude_spectrum(signal: &[f64], sample_rate_hz: f64) -> Vec<(f64, f64)> {
    if signal.len() < 4 {
        return Vec::new();
    }
    let n = 1usize << (usize::BITS - 1 - signal.len().leading_zeros());
    let tail = &signal[signal.len() - n..];
    let mean = tail.iter().sum::<f64>() / n as f64;
    let mut data: Vec<(f64, f64)> = tail
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let w = 0.5 - 0.5 * (2.0 * PI * i as f64 / n as f64).cos();
            ((v - mean) * w, 0.0)
        })
        .collect();
    fft(&mut data);
    // Hann window coherent gain 0.5; one-sided spectrum doubles the amplitude.
    (0..n / 2)
        .map(|k| {
            let (re, im) = data[k];
            (
                k as f64 * sample_rate_hz / n as f64,
                4.0 * re.hypot(im) / n as f64,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_peak_at_its_frequency_with_its_amplitude() {
        let fs = 8192.0;
        let sig: Vec<f64> = (0..8192)
            .map(|i| 0.3 * (2.0 * PI * 256.0 * i as f64 / fs).sin() + 1.0)
            .collect();
        let spec = amplitude_spectrum(&sig, fs);
        let peak = spec
            .iter()
            .cloned()
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        assert_eq!(peak.0, 256.0);
        assert!((peak.1 - 0.3).abs() < 1e-3, "{peak:?}");
    }
}
