//! The response of a limit cycle to a small forcing ε(t) = Re\[ε_n e^{iωt}\] fixed to the tyre
//! (MODEL.md#growth-of-a-vibrating-wheel): the periodic linearisation δẋ = A(t)δx + b(t)ε about
//! the cycle x_γ(t) of period T, δP = c(t)·δx + d(t)ε, and of δP/P̄ the part at ω itself, the
//! only part stationary on the tyre (the others drift at ω ± kω_γ).
//!
//! Floquet's theorem writes the fundamental matrix Φ(t) = Σ_j p_j(t) e^{μ_j t} l_j with
//! T-periodic p_j(t) = Φ(t) r_j e^{−μ_j t} and q_j(t) = e^{μ_j t} l_j Φ(t)⁻¹ (r_j, l_j the right
//! and left eigenvectors of the monodromy matrix, multipliers ρ_j = e^{μ_j T}). Each mode
//! responds to its share q_j b = Σ_k β̂_jk e^{ikω_γ t}, and reads out through c p_j/P̄ =
//! Σ_k γ̂_jk e^{ikω_γ t}, so the response at ω is a sum of poles (harmonic balance on the Floquet
//! system, exact for the sampled coefficients):
//!
//! ```text
//! G(iω) = ⟨d⟩/P̄ + Σ_j Σ_k γ̂_j,−k β̂_jk / (i(ω + kω_γ) − μ_j).
//! ```
//!
//! The phase mode (ρ = 1, p ∝ ẋ_γ) has μ = 0: its pole at ω = ω_γ is the cycle pulled towards
//! the order, the response growing like 1/δ towards lock. Its coupling also gives the lock-in
//! tongue (Adler): the cycle locks to order n when |δ_n| ≤ ν |ε_n| |ĝ₋₁|, ĝ₋₁ the harmonic
//! e^{−iω_γ t} of Z(t)·b(t) with Z the phase response normalised Z·ẋ_γ = 1.

use super::transfer::{eigenbasis, Linearisation, PoleExpansion, PoleTerm};
use crate::model::TreadOde;
use crate::numeric::Complex64;
use crate::wear::error::WearError;
use crate::wear::physics::cycle::SampledCycle;
use nalgebra::{RowVector3, Vector3};

/// A mode whose multiplier is below this decays within a small part of the period: its
/// periodic eigenfunction cannot be read off Φ (e^{−μt} would amplify Φ's integration error),
/// and it responds quasi-statically, −⟨c Φ r l Φ⁻¹ b⟩/(μ P̄).
const QUASI_STATIC_MULTIPLIER: f64 = 1e-8;

/// Terms whose residue is below this share of the largest are dropped: the harmonics of the
/// cycle's coefficients fall so fast that 25–27 of the 45 terms (16 samples) are below it, and
/// none of them is near a resonance, where the largest residues are, so what they would add to
/// G is below 1e-6 of it.
const NEGLIGIBLE_RESIDUE: f64 = 1e-6;

/// The cycle's response to ε at the frequencies fixed to the tyre.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleResponse {
    /// δP/P̄ per unit ε as poles in ω.
    pub transfer: PoleExpansion,
    /// |ĝ₋₁| \[s\]: the phase response's coupling to ε at the cycle's own frequency.
    pub phase_coupling_s: f64,
    /// ĝ₋₁ itself \[s\] (its phase relative to the amplitude mode's coupling gives the shear).
    pub phase_coupling: Complex64,
    /// The slowest-decaying mode beside the phase mode (the amplitude mode): its rate −μ \[1/s\]
    /// and Î₋₁, the harmonic e^{−iω_γ t} of q·b (its scale is the eigenvector's, arbitrary; its
    /// phase is not). None where no other mode has a real positive multiplier, or where it is
    /// taken quasi-statically (multiplier below 10⁻⁸: it relaxes within the period).
    pub amplitude_mode: Option<(f64, Complex64)>,
    /// The cycle's mean friction power P̄ \[W\].
    pub mean_power_w: f64,
    /// The amplitude of the power's harmonic at the cycle's own frequency over P̄, |P₁|/P̄: what a
    /// cycle locked to an order prints onto it every revolution.
    pub power_harmonic_rel: f64,
    /// That harmonic itself, 2P̂₁/P̄ with P̂₁ the harmonic e^{iω_γ t} of P(t), from the same time
    /// origin as ĝ₋₁ (its phase against ĝ₋₁'s places the locked print on the polygon).
    pub power_harmonic: Complex64,
    /// Its angular frequency ω_γ = 2π/T \[rad/s\].
    pub omega_rad_s: f64,
}

/// The cycle's samples with what every mode reads off them: c Φ(t)/P̄ and Φ(t)⁻¹ b, real, once
/// per sample (a mode's series are then two complex dot products per sample).
struct Linearised<'a> {
    cycle: &'a SampledCycle,
    lins: Vec<Linearisation>,
    /// c(t) Φ(t)/P̄ at each sample.
    c_phi: Vec<RowVector3<f64>>,
    /// Φ(t)⁻¹ b(t) at each sample.
    phi_inv_b: Vec<Vector3<f64>>,
}

type Mode = (Vector3<Complex64>, RowVector3<Complex64>);

fn cplx(x: f64) -> Complex64 {
    Complex64::new(x, 0.0)
}

/// a·r for a real row `a` and a complex column `r`.
fn real_dot(a: &RowVector3<f64>, r: &Vector3<Complex64>) -> Complex64 {
    r[0] * a[0] + r[1] * a[1] + r[2] * a[2]
}

/// l·u for a complex row `l` and a real column `u`.
fn dot_real(l: &RowVector3<Complex64>, u: &Vector3<f64>) -> Complex64 {
    l[0] * u[0] + l[1] * u[1] + l[2] * u[2]
}

impl Linearised<'_> {
    /// q_j·b and c·p_j/P̄ at every sample for the mode (r_j, l_j) of exponent μ: p_j = Φ r_j
    /// e^{−μt} and q_j = e^{μt} l_j Φ⁻¹.
    fn mode_series(&self, (rj, lj): &Mode, mu: Complex64) -> (Vec<Complex64>, Vec<Complex64>) {
        let cycle = self.cycle;
        let mut beta = Vec::with_capacity(cycle.samples.len());
        let mut gamma = Vec::with_capacity(cycle.samples.len());
        for ((s, c_phi), phi_inv_b) in cycle.samples.iter().zip(&self.c_phi).zip(&self.phi_inv_b) {
            let e = (-mu * s.t_s).exp();
            beta.push(dot_real(lj, phi_inv_b) / e);
            gamma.push(real_dot(c_phi, rj) * e);
        }
        (beta, gamma)
    }

    /// ⟨c Φ r l Φ⁻¹ b⟩/P̄ for a mode too fast to resolve (equal times: no exponential).
    fn quasi_static(&self, (rj, lj): &Mode) -> Complex64 {
        self.c_phi
            .iter()
            .zip(&self.phi_inv_b)
            .map(|(c_phi, phi_inv_b)| real_dot(c_phi, rj) * dot_real(lj, phi_inv_b))
            .sum::<Complex64>()
            / self.cycle.samples.len() as f64
    }

    /// P̂₁, the power's harmonic e^{iω_γ t} \[W\].
    fn power_first_harmonic_w(&self) -> Complex64 {
        let cycle = self.cycle;
        cycle
            .samples
            .iter()
            .zip(&self.lins)
            .map(|(s, l)| {
                Complex64::from_polar(l.power_w, -std::f64::consts::TAU * s.t_s / cycle.period_s)
            })
            .sum::<Complex64>()
            / cycle.samples.len() as f64
    }
}

impl CycleResponse {
    /// The response of `cycle` (of `ode`), from its samples: one linearisation per sample, from
    /// the vector field and Jacobian the integration took there (no evaluation of its own).
    pub fn of(ode: &TreadOde, cycle: &SampledCycle) -> Result<Self, WearError> {
        let n = cycle.samples.len();
        let lins: Vec<Linearisation> = cycle
            .samples
            .iter()
            .map(|s| Linearisation::from_field(ode, &s.x, &s.field, s.jacobian))
            .collect();
        let mean_power_w = lins.iter().map(|l| l.power_w).sum::<f64>() / n as f64;
        let direct = cplx(lins.iter().map(|l| l.d).sum::<f64>() / n as f64 / mean_power_w);
        let phi_inv_b = cycle
            .samples
            .iter()
            .zip(&lins)
            .map(|(s, l)| {
                s.phi
                    .try_inverse()
                    .map(|inv| inv * l.b)
                    .ok_or(WearError::NoFloquetBasis)
            })
            .collect::<Result<_, _>>()?;
        let c_phi = cycle
            .samples
            .iter()
            .zip(&lins)
            .map(|(s, l)| l.c * s.phi / mean_power_w)
            .collect();
        let data = Linearised {
            cycle,
            lins,
            c_phi,
            phi_inv_b,
        };
        let omega = std::f64::consts::TAU / cycle.period_s;
        let ev = multipliers(&cycle.monodromy);
        let (r, l) = eigenbasis(&cycle.monodromy, &ev).ok_or(WearError::NoFloquetBasis)?;
        let phase_mode = (0..3)
            .min_by(|&a, &b| (ev[a] - 1.0).norm().total_cmp(&(ev[b] - 1.0).norm()))
            .unwrap_or(0);
        let mut transfer = PoleExpansion {
            direct,
            terms: Vec::with_capacity(3 * n),
        };
        let twiddle = Twiddles::new(n);
        let mut phase_coupling = cplx(0.0);
        let amplitude = (0..3)
            .filter(|&j| j != phase_mode && ev[j].im == 0.0 && ev[j].re > 0.0)
            .max_by(|&a, &b| ev[a].re.total_cmp(&ev[b].re));
        let mut amplitude_mode = None;
        for (j, rho) in ev.iter().enumerate() {
            let mode: Mode = (r.column(j).into_owned(), l.row(j).into_owned());
            let phase = j == phase_mode;
            let mu = if phase {
                cplx(0.0)
            } else {
                rho.ln() / cycle.period_s
            };
            if !phase && rho.norm() < QUASI_STATIC_MULTIPLIER {
                transfer.direct -= data.quasi_static(&mode) / mu;
                continue;
            }
            let (beta, gamma) = data.mode_series(&mode, mu);
            let (bh, gh) = (twiddle.dft(&beta), twiddle.dft(&gamma));
            if Some(j) == amplitude {
                amplitude_mode = Some((-mu.re, bh[Twiddles::index(-1, n)]));
            }
            let half = n as i64 / 2;
            for k in (1 - half)..half {
                transfer.terms.push(PoleTerm {
                    pole: mu - Complex64::new(0.0, k as f64 * omega),
                    residue: gh[Twiddles::index(-k, n)] * bh[Twiddles::index(k, n)],
                    phase,
                });
            }
            if phase {
                // p_phase(t) = a ẋ_γ(t), so Z = a q_phase: |ĝ₋₁| = |a β̂₋₁|.
                let f0 = ode.rhs(&cycle.samples[0].x).map(cplx);
                let f0 = Vector3::new(f0[0], f0[1], f0[2]);
                let a = (f0.transpose() * mode.0)[0] / f0.norm_squared();
                phase_coupling = a * bh[Twiddles::index(-1, n)];
            }
        }
        let largest = transfer
            .terms
            .iter()
            .map(|t| t.residue.norm())
            .fold(0.0, f64::max);
        transfer
            .terms
            .retain(|t| t.residue.norm() >= NEGLIGIBLE_RESIDUE * largest);
        let first = data.power_first_harmonic_w();
        Ok(CycleResponse {
            transfer,
            phase_coupling_s: phase_coupling.norm(),
            phase_coupling,
            amplitude_mode,
            mean_power_w,
            power_harmonic_rel: 2.0 * first.norm() / mean_power_w,
            power_harmonic: 2.0 * first / mean_power_w,
            omega_rad_s: omega,
        })
    }
}

/// The three Floquet multipliers (eigenvalues of the monodromy matrix).
fn multipliers(m: &nalgebra::Matrix3<f64>) -> [Complex64; 3] {
    match m.try_schur(f64::EPSILON, 10_000) {
        Some(s) => {
            let e = s.complex_eigenvalues();
            [e[0], e[1], e[2]]
        }
        None => [Complex64::new(f64::NAN, f64::NAN); 3],
    }
}

/// The discrete Fourier transform on n samples of one period: x̂_k = (1/n) Σ_m x_m e^{−2πikm/n}.
struct Twiddles(Vec<Complex64>);

impl Twiddles {
    fn new(n: usize) -> Self {
        Twiddles(
            (0..n)
                .map(|m| Complex64::from_polar(1.0, -std::f64::consts::TAU * m as f64 / n as f64))
                .collect(),
        )
    }

    /// Where harmonic k (negative ones wrap around) sits in [`Twiddles::dft`]'s output.
    fn index(k: i64, n: usize) -> usize {
        k.rem_euclid(n as i64) as usize
    }

    /// x̂_k for k = 0 … n − 1: by the radix-2 FFT when n is a power of two (the shipped 16
    /// samples: 32 butterflies instead of 256 products), else term by term.
    fn dft(&self, x: &[Complex64]) -> Vec<Complex64> {
        let n = x.len();
        if n >= 2 && n.is_power_of_two() && self.0.len() == n {
            return self.fft(x);
        }
        (0..n)
            .map(|k| {
                // The twiddle's index k·m mod n, advanced by k from sample to sample.
                let mut at = 0;
                x.iter()
                    .map(|v| {
                        let t = v * self.0[at];
                        at += k;
                        if at >= n {
                            at -= n;
                        }
                        t
                    })
                    .sum::<Complex64>()
                    / n as f64
            })
            .collect()
    }

    /// Iterative Cooley–Tukey on a power of two n ≥ 2 (decimation in time: the samples in
    /// bit-reversed order, then log₂ n stages of butterflies), scaled by 1/n.
    fn fft(&self, x: &[Complex64]) -> Vec<Complex64> {
        let n = x.len();
        let shift = usize::BITS - n.trailing_zeros();
        let mut a: Vec<Complex64> = (0..n).map(|i| x[i.reverse_bits() >> shift]).collect();
        let mut len = 2;
        while len <= n {
            let (half, stride) = (len / 2, n / len);
            for block in a.chunks_exact_mut(len) {
                let (lo, hi) = block.split_at_mut(half);
                for (k, (u, v)) in lo.iter_mut().zip(hi.iter_mut()).enumerate() {
                    let t = *v * self.0[k * stride];
                    (*u, *v) = (*u + t, *u - t);
                }
            }
            len *= 2;
        }
        let scale = 1.0 / n as f64;
        a.iter_mut().for_each(|v| *v *= scale);
        a
    }
}

#[cfg(test)]
mod dft_tests {
    use super::*;

    /// The FFT is the DFT term by term, within 10⁻¹⁵ of the largest sample, at the shipped 16
    /// samples and other powers of two; other lengths take the direct sum.
    #[test]
    fn the_fft_is_the_dft() {
        for n in [2, 4, 8, 16, 32, 12] {
            let x: Vec<Complex64> = (0..n)
                .map(|m| {
                    Complex64::new(
                        (0.7 * m as f64).sin() + 0.1 * m as f64,
                        (1.3 * m as f64).cos(),
                    )
                })
                .collect();
            let twiddle = Twiddles::new(n);
            let direct: Vec<Complex64> = (0..n)
                .map(|k| {
                    x.iter()
                        .enumerate()
                        .map(|(m, v)| v * twiddle.0[(k * m) % n])
                        .sum::<Complex64>()
                        / n as f64
                })
                .collect();
            let largest = x.iter().map(|v| v.norm()).fold(0.0, f64::max);
            for (k, (a, b)) in twiddle.dft(&x).iter().zip(&direct).enumerate() {
                assert!(
                    (a - b).norm() < 1e-15 * largest,
                    "n = {n}, k = {k}: {a} {b}"
                );
            }
        }
    }
}
