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

use super::cycle::SampledCycle;
use super::error::WearError;
use super::transfer::{eigenbasis, Linearisation, PoleExpansion, PoleTerm};
use super::Complex64;
use crate::classify::budget::Meter;
use crate::model::TreadOde;
use nalgebra::{Matrix3, RowVector3, Vector3};

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
    /// The cycle's mean friction power P̄ \[W\].
    pub mean_power_w: f64,
    /// The amplitude of the power's harmonic at the cycle's own frequency over P̄, |P₁|/P̄: what a
    /// cycle locked to an order prints onto it every revolution.
    pub power_harmonic_rel: f64,
    /// Its angular frequency ω_γ = 2π/T \[rad/s\].
    pub omega_rad_s: f64,
}

/// The cycle's samples with their linearisations and inverse fundamental matrices.
struct Linearised<'a> {
    cycle: &'a SampledCycle,
    lins: Vec<Linearisation>,
    phis_inv: Vec<Matrix3<f64>>,
    mean_power_w: f64,
}

type Mode = (Vector3<Complex64>, RowVector3<Complex64>);

fn cplx(x: f64) -> Complex64 {
    Complex64::new(x, 0.0)
}

impl Linearised<'_> {
    /// q_j·b and c·p_j/P̄ at every sample for the mode (r_j, l_j) of exponent μ.
    fn mode_series(&self, (rj, lj): &Mode, mu: Complex64) -> (Vec<Complex64>, Vec<Complex64>) {
        let cycle = self.cycle;
        let mut beta = Vec::with_capacity(cycle.samples.len());
        let mut gamma = Vec::with_capacity(cycle.samples.len());
        for ((s, lin), pinv) in cycle.samples.iter().zip(&self.lins).zip(&self.phis_inv) {
            let e = (-mu * s.t_s).exp();
            let p = s.phi.map(cplx) * rj * e;
            let q = lj * pinv.map(cplx) / e;
            beta.push((q * lin.b.map(cplx))[0]);
            gamma.push((lin.c.map(cplx) * p)[0] / self.mean_power_w);
        }
        (beta, gamma)
    }

    /// ⟨c Φ r l Φ⁻¹ b⟩/P̄ for a mode too fast to resolve (equal times: no exponential).
    fn quasi_static(&self, (rj, lj): &Mode) -> Complex64 {
        let cycle = self.cycle;
        cycle
            .samples
            .iter()
            .zip(&self.lins)
            .zip(&self.phis_inv)
            .map(|((s, lin), pinv)| {
                let p = s.phi.map(cplx) * rj;
                let q = lj * pinv.map(cplx);
                (lin.c.map(cplx) * p)[0] * (q * lin.b.map(cplx))[0]
            })
            .sum::<Complex64>()
            / (cycle.samples.len() as f64 * self.mean_power_w)
    }

    /// |P₁|/P̄, the power's harmonic at the cycle's frequency.
    fn power_harmonic_rel(&self) -> f64 {
        let cycle = self.cycle;
        let first: Complex64 = cycle
            .samples
            .iter()
            .zip(&self.lins)
            .map(|(s, l)| {
                Complex64::from_polar(l.power_w, -std::f64::consts::TAU * s.t_s / cycle.period_s)
            })
            .sum::<Complex64>()
            / cycle.samples.len() as f64;
        2.0 * first.norm() / self.mean_power_w
    }
}

impl CycleResponse {
    /// The response of `cycle` (of `ode`), from its samples (one linearisation per sample,
    /// charged to `meter` as one RHS evaluation each).
    pub fn of(ode: &TreadOde, cycle: &SampledCycle, meter: &Meter) -> Result<Self, WearError> {
        let n = cycle.samples.len();
        meter.charge(n);
        let lins: Vec<Linearisation> = cycle
            .samples
            .iter()
            .map(|s| Linearisation::at(ode, &s.x))
            .collect();
        let phis_inv = cycle
            .samples
            .iter()
            .map(|s| s.phi.try_inverse().ok_or(WearError::NoFloquetBasis))
            .collect::<Result<_, _>>()?;
        let mean_power_w = lins.iter().map(|l| l.power_w).sum::<f64>() / n as f64;
        let direct = cplx(lins.iter().map(|l| l.d).sum::<f64>() / n as f64 / mean_power_w);
        let data = Linearised {
            cycle,
            lins,
            phis_inv,
            mean_power_w,
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
        let mut phase_coupling_s = 0.0;
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
                phase_coupling_s = (a * bh[Twiddles::index(-1, n)]).norm();
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
        Ok(CycleResponse {
            transfer,
            phase_coupling_s,
            mean_power_w,
            power_harmonic_rel: data.power_harmonic_rel(),
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

    fn dft(&self, x: &[Complex64]) -> Vec<Complex64> {
        let n = x.len();
        (0..n)
            .map(|k| {
                x.iter()
                    .enumerate()
                    .map(|(m, v)| v * self.0[(k * m) % n])
                    .sum::<Complex64>()
                    / n as f64
            })
            .collect()
    }
}
