//! The extremes of a sampled periodic signal, refined between the samples: the amplitudes of a
//! limit cycle (MODEL.md#step-9-attractor) from the few long steps of a high-order integrator.

/// The largest of `sign`·`vals` over one period sampled at `times` (the first sample at 0, the
/// last at the period), refined by the vertex of the parabola through the largest sample and
/// its neighbours (across the period's ends for the first and last). A sampled peak lies
/// (δω)²/8 of the amplitude below the true one for samples δ apart; the vertex is off by a
/// term of order (δω)³ only, so amplitudes keep their accuracy with the few long steps of a
/// high-order integrator. Where the peak is a corner (the follower's friction switches at
/// w = 0, so v' jumps), a parabola overshoots: the vertex is kept only if the parabola also
/// predicts the next sample beyond it to within the correction it makes, otherwise the
/// sample stands (then off by less than that correction).
pub(super) fn refined_peak(times: &[f64], vals: &[f64], sign: f64) -> f64 {
    let n = vals.len();
    let (i, best) =
        vals.iter()
            .map(|v| sign * v)
            .enumerate()
            .fold(
                (0, f64::NEG_INFINITY),
                |a, (i, v)| if v > a.1 { (i, v) } else { a },
            );
    if n < 5 || !best.is_finite() {
        return best;
    }
    let period = times[n - 1];
    // Sample k steps away from i, the period wrapping around (the last sample is the first).
    let at = |k: isize| -> (f64, f64) {
        let j = i as isize + k;
        let m = (n - 1) as isize;
        if j < 0 {
            let j = (j + m) as usize;
            (times[j] - period, sign * vals[j])
        } else if j > m {
            let j = (j - m) as usize;
            (times[j] + period, sign * vals[j])
        } else {
            (times[j as usize], sign * vals[j as usize])
        }
    };
    let ((t_prev, f_prev), (t_next, f_next)) = (at(-1), at(1));
    let (d0, d2) = (t_prev - times[i], t_next - times[i]);
    let (s0, s2) = ((f_prev - best) / d0, (f_next - best) / d2);
    // f = best + b·τ + c·τ², τ = t − t_i.
    let c = (s2 - s0) / (d2 - d0);
    let b = s0 - c * d0;
    if c >= 0.0 {
        return best;
    }
    let tau = -b / (2.0 * c);
    if tau < d0 || tau > d2 {
        return best;
    }
    let correction = -b * b / (4.0 * c);
    let (t_out, f_out) = at(if tau > 0.0 { 2 } else { -2 });
    let tau_out = t_out - times[i];
    let predicted = best + b * tau_out + c * tau_out * tau_out;
    if (predicted - f_out).abs() > correction {
        return best;
    }
    best + correction
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The parabola's vertex recovers a sampled peak to far better than the samples do, also
    /// when the peak sits at the period's ends, and minima come out the same way.
    #[test]
    fn refined_peak_recovers_the_extremes_of_a_sampled_sine() {
        let period = 2.0;
        let omega = 2.0 * std::f64::consts::PI / period;
        for phase in [0.0, 0.37, 1.9, std::f64::consts::PI] {
            // 13 steps of uneven length, 8 samples each, as the orbit sampler takes them.
            let mut times = vec![0.0];
            let ends: Vec<f64> = (1..=13)
                .map(|k| period * (k as f64 + 0.3 * (k as f64).sin()) / 13.0)
                .map(|t: f64| t.min(period))
                .collect();
            let mut t0 = 0.0;
            for &t1 in &ends {
                for j in 1..=8 {
                    times.push(t0 + (t1 - t0) * j as f64 / 8.0);
                }
                t0 = t1;
            }
            *times.last_mut().unwrap() = period;
            let vals: Vec<f64> = times.iter().map(|t| (omega * t + phase).cos()).collect();
            let sampled = vals.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            let hi = refined_peak(&times, &vals, 1.0);
            let lo = -refined_peak(&times, &vals, -1.0);
            assert!((hi - 1.0).abs() < 1e-5, "phase {phase}: {hi}");
            assert!((lo + 1.0).abs() < 1e-5, "phase {phase}: {lo}");
            assert!(
                (hi - 1.0).abs() <= 1e-12 + 0.1 * (sampled - 1.0).abs(),
                "phase {phase}: {hi} against the sampled {sampled}"
            );
        }
    }
}
