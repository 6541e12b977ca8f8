//! MODEL.md#step-11-wear-zone: where on the contact patch the friction power is deposited, and
//! the patch filters that follow from it. A patch-fixed coordinate x runs from the trailing edge
//! x = −a/2 to the leading edge x = +a/2; the tread element at tyre angle θ passes position x at
//! Ωt = θ − x/r_B (it enters at the leading edge and leaves at the trailing edge).
//!
//! A kernel K(x) (∫K dx = 1) turns a profile harmonic r(θ) = Re\[R e^{inθ}\] into the time signal
//! ∫K(x) r(Ωt + x/r_B) dx = Re\[H(n) R e^{inΩt}\], with the transfer H(n) = ∫K(x) e^{inx/r_B} dx;
//! laying a power harmonic Re\[P e^{inΩt}\] back onto the tyre through the same kernel gives
//! Re\[conj(H(n)) P e^{inθ}\]. A round trip profile → friction → wear therefore carries |H(n)|²,
//! whatever the zone's position on the patch.

use crate::numeric::Complex64;

named_enum! {
    /// Where the friction power wears the tread (the `wear_zone` setting; MODEL.md#step-11-wear-zone).
    /// A loud choice: it decides whether orders near 19 can grow at all.
    pub enum WearZone: "wear zone" {
        /// The rear sliding zone of the brush model (step 4): uniform over
        /// l_w = max(q, q_min)·a at the trailing edge. The shipped default.
        Trailing,
        /// The whole patch, weighted by the parabolic pressure 1 − (2x/a)² (Eq. 3, n = 2), as
        /// the paper's Eq. 17 lets the sliding zone cover the patch.
        WholePatch,
        /// The whole patch, uniform.
        WholePatchUniform,
    }
}

impl WearZone {
    /// Every zone, in the order of the declaration.
    pub const ALL: [WearZone; 3] = [
        WearZone::Trailing,
        WearZone::WholePatch,
        WearZone::WholePatchUniform,
    ];
    /// The zone every command uses unless told otherwise.
    pub const DEFAULT: WearZone = WearZone::Trailing;

    /// What the zone is, in a sentence (for `polywear params`).
    pub fn description(self) -> &'static str {
        match self {
            WearZone::Trailing => "uniform over the rear sliding zone, max(q, 0.05) of the patch",
            WearZone::WholePatch => "the whole patch, weighted by the parabolic pressure",
            WearZone::WholePatchUniform => "the whole patch, uniform",
        }
    }
}

/// The smallest sliding share the `trailing` zone is given, q_min: the brush model's rear
/// sliding zone shrinks to nothing at small toe-in, but the tread still slides somewhere, and a
/// zone of zero length would put all the wear on a line (judgement; 7.8 mm at the default patch).
pub(crate) const MIN_SLIDING_SHARE: f64 = 0.05;

/// The wear zone on one contact patch: its kernel, length and position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZoneGeometry {
    /// Which zone.
    pub zone: WearZone,
    /// Contact length a \[m\].
    pub patch_length_m: f64,
    /// Length of the zone \[m\].
    pub length_m: f64,
    /// Patch coordinate of the zone's centre \[m\] (+ towards the leading edge).
    pub centre_m: f64,
}

impl ZoneGeometry {
    /// The zone on a patch of length `patch_length_m` whose rear `sliding_share` slides (step 4).
    pub fn new(zone: WearZone, patch_length_m: f64, sliding_share: f64) -> Self {
        let a = patch_length_m;
        let (length_m, centre_m) = match zone {
            WearZone::Trailing => {
                let l = sliding_share.clamp(MIN_SLIDING_SHARE, 1.0) * a;
                (l, -0.5 * a + 0.5 * l)
            }
            WearZone::WholePatch | WearZone::WholePatchUniform => (a, 0.0),
        };
        ZoneGeometry {
            zone,
            patch_length_m: a,
            length_m,
            centre_m,
        }
    }

    /// The kernel K_w(x) \[1/m\] at patch coordinate `x_m` (0 outside the zone; ∫K_w dx = 1).
    pub fn weight_per_m(&self, x_m: f64) -> f64 {
        let s = 2.0 * (x_m - self.centre_m) / self.length_m;
        if s.abs() > 1.0 {
            return 0.0;
        }
        match self.zone {
            WearZone::Trailing | WearZone::WholePatchUniform => 1.0 / self.length_m,
            WearZone::WholePatch => 1.5 / self.length_m * (1.0 - s * s),
        }
    }

    /// The zone's filter about its own centre, real: sin u/u (uniform) or 3(sin u − u cos u)/u³
    /// (parabolic), u = n·l/(2 r_B). |H_w(n)| is its modulus.
    pub fn gain(&self, order: f64, r_b: f64) -> f64 {
        let u = order * self.length_m / (2.0 * r_b);
        match self.zone {
            WearZone::Trailing | WearZone::WholePatchUniform => sinc(u),
            WearZone::WholePatch => parabolic_gain(u),
        }
    }

    /// The transfer H_w(n) = ∫K_w(x) e^{inx/r_B} dx: the gain times the phase of the zone's
    /// position on the patch.
    pub fn transfer(&self, order: f64, r_b: f64) -> Complex64 {
        Complex64::from_polar(1.0, order * self.centre_m / r_b) * self.gain(order, r_b)
    }

    /// [`ZoneGeometry::gain`] at the consecutive orders `first`, `first` + 1, …: the sine and
    /// cosine of u_n = n·l/(2 r_B) by rotation from one order to the next (a complex
    /// multiplication instead of two trigonometric functions per order; the rounding grows by
    /// about an ulp per order).
    pub fn gains(&self, first: u32, r_b: f64) -> impl Iterator<Item = f64> + '_ {
        let step = self.length_m / (2.0 * r_b);
        let turn = Complex64::from_polar(1.0, step);
        let mut harmonic = Complex64::from_polar(1.0, first as f64 * step);
        (first..).map(move |n| {
            let u = n as f64 * step;
            let (sin, cos) = (harmonic.im, harmonic.re);
            harmonic *= turn;
            match self.zone {
                WearZone::Trailing | WearZone::WholePatchUniform => sinc_of(u, sin),
                WearZone::WholePatch => parabolic_gain_of(u, sin, cos),
            }
        })
    }

    /// [`ZoneGeometry::transfer`] at the consecutive orders `first`, `first` + 1, …, by
    /// rotation as [`ZoneGeometry::gains`].
    pub fn transfers(&self, first: u32, r_b: f64) -> impl Iterator<Item = Complex64> + '_ {
        let turn = Complex64::from_polar(1.0, self.centre_m / r_b);
        let mut phase = Complex64::from_polar(1.0, first as f64 * self.centre_m / r_b);
        self.gains(first, r_b).map(move |gain| {
            let h = phase * gain;
            phase *= turn;
            h
        })
    }

    /// ∫_{−∞}^{x} K_w dx, from 0 behind the zone to 1 ahead of it.
    pub fn cumulative(&self, x_m: f64) -> f64 {
        let s = (2.0 * (x_m - self.centre_m) / self.length_m).clamp(-1.0, 1.0);
        match self.zone {
            WearZone::Trailing | WearZone::WholePatchUniform => 0.5 * (1.0 + s),
            WearZone::WholePatch => 0.5 + 0.75 * (s - s * s * s / 3.0),
        }
    }

    /// The kernel's exact weight on each of `cells` equal cells of tyre angle when the element
    /// at the patch centre is at angle `centre_angle_rad` (element θ sits at x = r_B (θ − that
    /// angle)): (cell index, ∫ over the cell of K_w dx), the weights summing to 1. The same
    /// weights sample a profile under the zone ([`ZoneGeometry::average_on_cells`]) and lay
    /// wear onto it ([`super::law::deposit_revolution`]), so a round trip on cells is the
    /// adjoint pair of the transfers.
    pub fn cell_weights(
        &self,
        centre_angle_rad: f64,
        r_b: f64,
        cells: usize,
    ) -> impl Iterator<Item = (usize, f64)> + '_ {
        let d_theta = std::f64::consts::TAU / cells as f64;
        let lo = centre_angle_rad + (self.centre_m - 0.5 * self.length_m) / r_b;
        let hi = centre_angle_rad + (self.centre_m + 0.5 * self.length_m) / r_b;
        let (first, last) = ((lo / d_theta).floor() as i64, (hi / d_theta).floor() as i64);
        (first..=last).map(move |k| {
            let x0 = r_b * (k as f64 * d_theta - centre_angle_rad);
            let x1 = r_b * ((k + 1) as f64 * d_theta - centre_angle_rad);
            let w = self.cumulative(x1) - self.cumulative(x0);
            (k.rem_euclid(cells as i64) as usize, w)
        })
    }

    /// ∫K_w(x) r(θ_c + x/r_B) dx for a profile `radius_m` held constant on equal cells of tyre
    /// angle, θ_c = `centre_angle_rad` the angle of the element at the patch centre.
    pub fn average_on_cells(&self, radius_m: &[f64], centre_angle_rad: f64, r_b: f64) -> f64 {
        self.cell_weights(centre_angle_rad, r_b, radius_m.len())
            .map(|(i, w)| w * radius_m[i])
            .sum()
    }
}

/// H_p(n): the transfer of the parabolic pressure over the whole patch (centred, so real), the
/// kernel through which the belt envelopes the profile for the load feedback
/// (MODEL.md#step-12-feedback).
pub fn pressure_transfer(order: f64, patch_length_m: f64, r_b: f64) -> f64 {
    parabolic_gain(order * patch_length_m / (2.0 * r_b))
}

/// sin u / u, 1 at u = 0 (the series below 1e-4, where the quotient loses digits).
pub fn sinc(u: f64) -> f64 {
    sinc_of(u, u.sin())
}

/// [`sinc`] with sin u given.
fn sinc_of(u: f64, sin: f64) -> f64 {
    if u.abs() < 1e-4 {
        1.0 - u * u / 6.0
    } else {
        sin / u
    }
}

/// 3(sin u − u cos u)/u³, 1 at u = 0: the transfer of the parabolic kernel. Below u = 0.05 the
/// difference cancels to a few digits, so the series 1 − u²/10 + u⁴/280 − u⁶/15120 is used.
pub fn parabolic_gain(u: f64) -> f64 {
    let (sin, cos) = u.sin_cos();
    parabolic_gain_of(u, sin, cos)
}

/// [`parabolic_gain`] with sin u and cos u given.
fn parabolic_gain_of(u: f64, sin: f64, cos: f64) -> f64 {
    if u.abs() < 0.05 {
        let u2 = u * u;
        1.0 - u2 / 10.0 + u2 * u2 / 280.0 - u2 * u2 * u2 / 15120.0
    } else {
        3.0 * (sin - u * cos) / (u * u * u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transfers by rotation are the transfer at each order, within 1e-13, for every zone
    /// and over the orders the answer over the tread's life takes.
    #[test]
    fn transfers_by_rotation_are_the_transfer() {
        for zone in [
            WearZone::Trailing,
            WearZone::WholePatch,
            WearZone::WholePatchUniform,
        ] {
            let g = ZoneGeometry::new(zone, 0.15, 0.3);
            for (n, h) in (3..60).zip(g.transfers(3, 0.3)) {
                let want = g.transfer(n as f64, 0.3);
                assert!((h - want).norm() < 1e-13, "{zone:?} {n}: {h} {want}");
            }
        }
    }

    /// The kernels integrate to 1 and their transfers are their Fourier integrals, checked by
    /// quadrature (position phase included), for every zone and orders 1..40.
    #[test]
    fn transfers_are_the_kernels_fourier_integrals() {
        let r_b = 0.317;
        for zone in WearZone::ALL {
            for q in [0.01, 0.033, 0.3] {
                let g = ZoneGeometry::new(zone, 0.1551, q);
                let n_q = 20_000;
                let (lo, hi) = (g.centre_m - 0.5 * g.length_m, g.centre_m + 0.5 * g.length_m);
                let h = (hi - lo) / n_q as f64;
                let mut total = 0.0;
                for order in [0.0, 1.0, 7.0, 19.0, 19.36, 40.0] {
                    let mut integral = Complex64::new(0.0, 0.0);
                    for k in 0..n_q {
                        let x = lo + (k as f64 + 0.5) * h;
                        let w = g.weight_per_m(x) * h;
                        integral += Complex64::from_polar(w, order * x / r_b);
                        if order == 0.0 {
                            total += w;
                        }
                    }
                    let t = g.transfer(order, r_b);
                    assert!(
                        (t - integral).norm() < 1e-6,
                        "{zone} q {q} n {order}: {t} vs {integral}"
                    );
                }
                assert!((total - 1.0).abs() < 1e-6, "{zone}: {total}");
            }
        }
    }

    /// The series and the closed forms agree where they hand over.
    #[test]
    fn series_continue_the_closed_forms() {
        for u in [0.049_999f64, 0.05, 0.050_001] {
            let closed = 3.0 * (u.sin() - u * u.cos()) / (u * u * u);
            assert!((parabolic_gain(u) - closed).abs() < 1e-11, "{u}");
        }
        assert!((sinc(1.0001e-4) - sinc(0.9999e-4)).abs() < 1e-12);
        assert_eq!(parabolic_gain(0.0), 1.0);
        assert_eq!(sinc(0.0), 1.0);
    }

    /// Sampling a harmonic on cells through the zone gives Re[H R e^{inθ_c}] (times the cells'
    /// own box filter, sinc(n Δθ/2)), to second order in the cell size n·Δθ.
    #[test]
    fn cell_average_of_a_harmonic_is_the_transfer() {
        let r_b = 0.317;
        for zone in WearZone::ALL {
            let g = ZoneGeometry::new(zone, 0.1551, 0.033);
            let cells = 4096;
            for order in [3usize, 19, 40] {
                let n = order as f64;
                let r = Complex64::new(1.3e-6, -0.4e-6);
                let d_theta = std::f64::consts::TAU / cells as f64;
                // Cell averages of Re[R e^{inθ}].
                let profile: Vec<f64> = (0..cells)
                    .map(|i| {
                        let a = i as f64 * d_theta;
                        (r * (Complex64::from_polar(1.0, n * (a + d_theta))
                            - Complex64::from_polar(1.0, n * a))
                            / Complex64::new(0.0, n * d_theta))
                        .re
                    })
                    .collect();
                for c in [0.0, 1.0, 6.2] {
                    let got = g.average_on_cells(&profile, c, r_b);
                    let want = (g.transfer(n, r_b) * r * Complex64::from_polar(1.0, n * c)).re;
                    let box_filter = sinc(n * d_theta / 2.0);
                    assert!(
                        (got - want * box_filter).abs() < 0.5 * (n * d_theta).powi(2) * r.norm(),
                        "{zone} n {order} at {c}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn trailing_zone_sits_at_the_trailing_edge() {
        let g = ZoneGeometry::new(WearZone::Trailing, 0.2, 0.01);
        assert!((g.length_m - 0.2 * MIN_SLIDING_SHARE).abs() < 1e-15);
        assert!((g.centre_m - (-0.1 + 0.005)).abs() < 1e-15);
        assert_eq!(g.weight_per_m(0.0), 0.0);
        assert!(g.weight_per_m(-0.099) > 0.0);
        let g = ZoneGeometry::new(WearZone::Trailing, 0.2, 0.3);
        assert!((g.length_m - 0.06).abs() < 1e-15);
    }
}
