//! Dormand–Prince 5(4) with Hairer's PI step-size control and dense output (Hairer, Nørsett,
//! Wanner, "Solving ODEs I", DOPRI5).

use super::driver::{drive, EmbeddedPair};
use super::types::{
    axpy, error_norm, Control, Dense, IntegrationError, Outcome, SolverOptions, Step,
};
use super::OdeSystem;

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Integrates `sys` from (t0, x0) to `t_end`, calling `on_step` after every accepted step.
pub fn integrate<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    t0: f64,
    x0: [f64; N],
    t_end: f64,
    opts: &SolverOptions<N>,
    on_step: impl FnMut(&Step<'_, N>) -> Control,
) -> Result<Outcome<N>, IntegrationError> {
    drive::<N, S, Dopri5<N>>(sys, t0, x0, t_end, opts, on_step)
}

/// DOPRI5's stages (k7 = f at the new state is the next step's k1) and Hairer's PI controller.
struct Dopri5<const N: usize> {
    k: [[f64; N]; 7],
    /// Dense output of the last accepted step (Hairer's CONTD5 coefficients).
    cont: [[f64; N]; 5],
    /// The previous accepted step's error norm, for the PI controller.
    facold: f64,
}

const SAFE: f64 = 0.9;
const BETA: f64 = 0.04;
const EXPO1: f64 = 0.2 - BETA * 0.75;

impl<const N: usize> EmbeddedPair<N> for Dopri5<N> {
    const ORDER: i32 = 5;

    #[inline(always)]
    fn start(f0: [f64; N]) -> Self {
        let mut k = [[0.0; N]; 7];
        k[0] = f0;
        Dopri5 {
            k,
            cont: [[0.0; N]; 5],
            facold: 1e-4,
        }
    }

    #[inline(always)]
    fn f0(&self) -> &[f64; N] {
        &self.k[0]
    }

    #[inline(always)]
    fn try_step<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        x: &[f64; N],
        h: f64,
        opts: &SolverOptions<N>,
    ) -> ([f64; N], f64, usize) {
        let k1 = self.k[0];
        let k2 = sys.rhs(&axpy(x, h, &[(A21, &k1)]));
        let k3 = sys.rhs(&axpy(x, h, &[(A31, &k1), (A32, &k2)]));
        let k4 = sys.rhs(&axpy(x, h, &[(A41, &k1), (A42, &k2), (A43, &k3)]));
        let k5 = sys.rhs(&axpy(
            x,
            h,
            &[(A51, &k1), (A52, &k2), (A53, &k3), (A54, &k4)],
        ));
        let k6 = sys.rhs(&axpy(
            x,
            h,
            &[(A61, &k1), (A62, &k2), (A63, &k3), (A64, &k4), (A65, &k5)],
        ));
        let x_new = axpy(
            x,
            h,
            &[(A71, &k1), (A73, &k3), (A74, &k4), (A75, &k5), (A76, &k6)],
        );
        let k7 = sys.rhs(&x_new);
        let err: [f64; N] = std::array::from_fn(|i| {
            h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i])
        });
        let err = error_norm(&err, x, &x_new, opts, S::ERROR_NORM_COMPONENTS);
        self.k = [k1, k2, k3, k4, k5, k6, k7];
        (x_new, err, 6)
    }

    #[inline(always)]
    fn accepted_factor(&mut self, err: f64) -> f64 {
        let fac = (err.powf(EXPO1) / self.facold.powf(BETA) / SAFE).clamp(0.2, 10.0);
        self.facold = err.max(1e-4);
        fac
    }

    #[inline(always)]
    fn rejected_factor(&self, err: f64) -> f64 {
        (err.powf(EXPO1) / SAFE).min(5.0)
    }

    #[inline(always)]
    fn finish_step<S: OdeSystem<N>>(
        &mut self,
        _sys: &S,
        x: &[f64; N],
        x_new: &[f64; N],
        h: f64,
    ) -> usize {
        let [k1, _, k3, k4, k5, k6, k7] = &self.k;
        for i in 0..N {
            let ydiff = x_new[i] - x[i];
            let bspl = h * k1[i] - ydiff;
            self.cont[0][i] = x[i];
            self.cont[1][i] = ydiff;
            self.cont[2][i] = bspl;
            self.cont[3][i] = ydiff - h * k7[i] - bspl;
            self.cont[4][i] =
                h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
        self.k[0] = self.k[6];
        0
    }

    #[inline(always)]
    fn dense(&self) -> Dense<'_, N> {
        Dense::Dopri5(&self.cont)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Oscillator;
    impl OdeSystem<2> for Oscillator {
        fn rhs(&self, x: &[f64; 2]) -> [f64; 2] {
            [x[1], -x[0]]
        }
    }

    fn opts(rtol: f64) -> SolverOptions<2> {
        SolverOptions {
            rtol,
            atol: [rtol; 2],
            h_max: 1.0,
            h0: None,
            max_steps: 1_000_000,
        }
    }

    #[test]
    fn harmonic_oscillator_is_accurate_and_converges_at_order_five() {
        let t_end = 20.0;
        let mut errs = vec![];
        for rtol in [1e-6, 1e-9, 1e-12] {
            let out = integrate(&Oscillator, 0.0, [1.0, 0.0], t_end, &opts(rtol), |_| {
                Control::Continue
            })
            .unwrap();
            let e = (out.x[0] - t_end.cos()).abs() + (out.x[1] + t_end.sin()).abs();
            assert_eq!(out.t, t_end);
            errs.push((e, out.accepted_steps));
        }
        assert!(errs[2].0 < 1e-9, "{errs:?}");
        assert!(errs[0].0 > errs[1].0 && errs[1].0 > errs[2].0, "{errs:?}");
        // Fifth order: 1000x tighter tolerance costs about 1000^(1/5) ≈ 4x the steps.
        let ratio = errs[2].1 as f64 / errs[1].1 as f64;
        assert!(ratio > 2.5 && ratio < 6.5, "{errs:?}");
    }

    #[test]
    fn dense_output_is_accurate_inside_steps() {
        let mut worst: f64 = 0.0;
        integrate(&Oscillator, 0.0, [1.0, 0.0], 10.0, &opts(1e-10), |s| {
            for j in 1..4 {
                let t = s.t0 + (s.t1 - s.t0) * j as f64 / 4.0;
                let x = s.interpolate(t);
                worst = worst.max((x[0] - t.cos()).abs());
            }
            Control::Continue
        })
        .unwrap();
        assert!(worst < 1e-8, "{worst}");
    }

    #[test]
    fn callback_can_stop_and_blowup_is_an_error() {
        let out = integrate(&Oscillator, 0.0, [1.0, 0.0], 10.0, &opts(1e-8), |s| {
            if s.t1 > 1.0 {
                Control::Stop
            } else {
                Control::Continue
            }
        })
        .unwrap();
        assert!(out.stopped && out.t > 1.0 && out.t < 10.0);

        struct Blowup;
        impl OdeSystem<1> for Blowup {
            fn rhs(&self, x: &[f64; 1]) -> [f64; 1] {
                [x[0] * x[0]]
            }
        }
        let o = SolverOptions {
            rtol: 1e-8,
            atol: [1e-8],
            h_max: 1.0,
            h0: None,
            max_steps: 100_000,
        };
        // x' = x² from 1 blows up at t = 1.
        let r = integrate(&Blowup, 0.0, [1.0], 2.0, &o, |_| Control::Continue);
        assert!(r.is_err(), "{r:?}");
    }
}
