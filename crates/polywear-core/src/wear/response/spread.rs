//! The speed spread (MODEL.md#the-speed-spread): the cruising speed V is normal around the
//! operating point's speed with standard deviation σ_V, and an order n, fixed to the tyre,
//! grows at the mean of its rate over that spread. The rates are sums of poles in the forcing
//! frequency ω_n = nV/r_B, each resonance a few hundredths of an order wide while the spread
//! spans an order or more, so a few quadrature nodes in V cannot resolve them; the Gaussian
//! mean of a pole is exact instead, E\[1/(V − z)\] = i√(π/2) w(ζ)/σ with ζ = (z − V̄)/(√2 σ) and
//! w the Faddeeva function, and its principal value −√2 D(ζ)/σ (D Dawson's integral) for a
//! pole on the real axis.

use crate::numeric::Complex64;

/// 1/√π.
const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// The Faddeeva function w(z) = e^{−z²} erfc(−iz). Inside |z| < 4 its Taylor series
/// Σ (iz)ⁿ/Γ(n/2 + 1) (the largest term there is below 1e7, so about 1e-9 of accuracy is
/// lost at worst); outside, Laplace's continued fraction (i/√π)/(z − ½/(z − 1/(z − 3/2/…)))
/// in the upper half-plane, and w(z) = 2e^{−z²} − w(−z) below it.
#[cfg(test)]
pub(crate) fn faddeeva(z: Complex64) -> Complex64 {
    if z.norm_sqr() < 16.0 {
        return faddeeva_series(z);
    }
    if z.im < 0.0 {
        return (-(z * z)).exp() * 2.0 - faddeeva(-z);
    }
    // Depth for about 1e-12 at |z| = 4 on the real axis, where the fraction converges slowest.
    let depth = if z.norm_sqr() > 100.0 { 16 } else { 60 };
    let mut tail = z;
    for k in (1..=depth).rev() {
        tail = z - Complex64::new(0.5 * k as f64, 0.0) / tail;
    }
    Complex64::new(0.0, FRAC_1_SQRT_PI) / tail
}

/// The Faddeeva function by Humlíček's four rational approximations (J. Quant. Spectrosc.
/// Radiat. Transfer 27, 437 (1982), "w4"), relative error below 1e-4 in the upper half-plane,
/// for a few dozen operations instead of [`faddeeva`]'s series or fraction: what the speed means
/// need (a spread mean good to 1e-4 is far inside the estimator's other approximations).
/// Im z ≥ 0.
pub(crate) fn faddeeva_fast(z: Complex64) -> Complex64 {
    let (x, y) = (z.re, z.im.max(0.0));
    let t = Complex64::new(y, -x);
    let s = x.abs() + y;
    let c = |v: f64| Complex64::new(v, 0.0);
    if s >= 15.0 {
        t * 0.564_189_6 / (t * t + 0.5)
    } else if s >= 5.5 {
        let u = t * t;
        t * (u * 0.564_189_6 + 1.410_474) / (u * (u + 3.0) + 0.75)
    } else if y >= 0.195 * x.abs() - 0.176 {
        (c(16.4955) + t * (c(20.20933) + t * (c(11.96482) + t * (c(3.778987) + t * 0.5642236))))
            / (c(16.4955)
                + t * (c(38.82363) + t * (c(39.27121) + t * (c(21.69274) + t * (t + 6.699398)))))
    } else {
        let u = t * t;
        let num = t
            * (c(36183.31)
                - u * (c(3321.9905)
                    - u * (c(1540.787)
                        - u * (c(219.0313)
                            - u * (c(35.76683) - u * (c(1.320522) - u * 0.56419))))));
        let den = c(32066.6)
            - u * (c(24322.84)
                - u * (c(9022.228)
                    - u * (c(2186.181)
                        - u * (c(364.2191) - u * (c(61.57037) - u * (c(1.841439) - u))))));
        u.exp() - num / den
    }
}

#[cfg(test)]
fn faddeeva_series(z: Complex64) -> Complex64 {
    let iz = Complex64::new(-z.im, z.re);
    let iz2 = iz * iz;
    // Even terms from 1, odd terms from iz/Γ(3/2); a_n = a_{n−2} (iz)² / (n/2).
    let mut even = Complex64::new(1.0, 0.0);
    let mut odd = iz * (2.0 * FRAC_1_SQRT_PI);
    let mut sum = even + odd;
    let mut n = 2.0;
    loop {
        even = even * iz2 / (0.5 * n);
        odd = odd * iz2 / (0.5 * (n + 1.0));
        sum += even + odd;
        if n > 4.0 && (even.norm() + odd.norm()) < 1e-17 * sum.norm().max(1e-300) {
            return sum;
        }
        n += 2.0;
        if n > 400.0 {
            return sum;
        }
    }
}

/// Dawson's integral D(x) = e^{−x²}∫₀ˣ e^{t²} dt = (√π/2) Im w(x).
#[cfg(test)]
pub(crate) fn dawson(x: f64) -> f64 {
    0.5 / FRAC_1_SQRT_PI * faddeeva(Complex64::new(x, 0.0)).im
}

/// Beyond |ζ| = this the pole is far from the spread, and the first six terms of the moments'
/// series give its mean to within 10⁻⁶ (the next term is 10395/(2|ζ|²)⁶ of it): closer than
/// [`faddeeva_fast`]'s 10⁻⁴, for a division instead of a rational approximation (most poles of a
/// vibrating wheel at most orders, and the resonance's flanks).
const FAR_POLE_ZETA: f64 = 5.0;

/// Beyond |ζ|² = this times [`FAR_POLE_ZETA`]² the series' first three terms suffice (the
/// fourth is 15/(2|ζ|²)³ of the sum: below 3·10⁻⁸ from |ζ| = 20) ...
const FAR_POLE_TERMS_3: f64 = 16.0;

/// ... and beyond this times it, the first four (the fifth is 105/(2|ζ|²)⁴: below 7·10⁻⁸ from
/// |ζ| = 10).
const FAR_POLE_TERMS_4: f64 = 4.0;

/// E\[1/(V − z)\] for V normal with mean `mean` and standard deviation `sd` (1/(mean − z) for
/// sd = 0). A pole on the real axis has no mean: its principal value is returned (0 at the
/// pole itself when sd = 0).
#[cfg(test)]
fn normal_mean_of_pole(z: Complex64, mean: f64, sd: f64) -> Complex64 {
    NormalSpeeds::new(mean, sd).mean_of_pole(z)
}

/// Speeds normal around `mean` with standard deviation `sd` \[m/s\], with what every pole's
/// mean over them shares (taken once for all the poles of a transfer, and all its nodes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NormalSpeeds {
    mean: f64,
    sd: f64,
    /// 1/(√2 σ).
    per_scale: f64,
    /// (FAR_POLE_ZETA √2 σ)².
    far_sqr: f64,
    /// √(π/2)/σ.
    k: f64,
}

impl NormalSpeeds {
    pub(crate) fn new(mean: f64, sd: f64) -> Self {
        let scale = std::f64::consts::SQRT_2 * sd;
        NormalSpeeds {
            mean,
            sd,
            per_scale: 1.0 / scale,
            far_sqr: (FAR_POLE_ZETA * scale) * (FAR_POLE_ZETA * scale),
            k: (std::f64::consts::PI / 2.0).sqrt() / sd,
        }
    }

    /// E\[1/(V − z)\]: [`normal_mean_of_pole`].
    pub(crate) fn mean_of_pole(&self, z: Complex64) -> Complex64 {
        let (mean, sd) = (self.mean, self.sd);
        if sd <= 0.0 {
            let d = Complex64::new(mean, 0.0) - z;
            return if d.norm_sqr() == 0.0 {
                Complex64::new(0.0, 0.0)
            } else {
                d.inv()
            };
        }
        let to_mean = Complex64::new(mean, 0.0) - z;
        let distance_sqr = to_mean.norm_sqr();
        if distance_sqr > self.far_sqr {
            // Far from the spread: the moments' series 1/(V̄−z) Σ (2k−1)!! (σ/(V̄−z))^{2k} (one
            // division), to the term before the first below 10⁻⁶ of the sum. In the upper
            // half-plane of ζ (where the poles are read) it has no exponentially small part to
            // leave out.
            let inv = to_mean.conj() * (1.0 / distance_sqr);
            let r = inv * inv * (sd * sd);
            let one = Complex64::new(1.0, 0.0);
            let sum = if distance_sqr > self.far_sqr * FAR_POLE_TERMS_3 {
                one + r * (one + r * 3.0)
            } else if distance_sqr > self.far_sqr * FAR_POLE_TERMS_4 {
                one + r * (one + r * (3.0 + r * 15.0))
            } else {
                let tail = r * (15.0 + r * (105.0 + r * 945.0));
                one + r * (one + r * (3.0 + tail))
            };
            return inv * sum;
        }
        let zeta = -to_mean * self.per_scale;
        let k = self.k;
        if z.im > 0.0 {
            Complex64::new(0.0, k) * faddeeva_fast(zeta)
        } else if z.im < 0.0 {
            (Complex64::new(0.0, k) * faddeeva_fast(zeta.conj())).conj()
        } else {
            // The principal value: −√2 D(ζ)/σ, D(x) = (√π/2) Im w(x).
            let dawson = 0.5 / FRAC_1_SQRT_PI * faddeeva_fast(Complex64::new(zeta.re, 0.0)).im;
            Complex64::new(-std::f64::consts::SQRT_2 * dawson / sd, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// w against its integral (i/π)∫e^{−t²}/(z − t) dt (fine trapezoid) in the upper half-plane,
    /// on both sides of |z| = 4, and against known values of Dawson's integral on the real axis.
    #[test]
    fn faddeeva_matches_its_integral() {
        let integral = |z: Complex64| {
            let h = 2e-4;
            let mut s = Complex64::new(0.0, 0.0);
            let mut t = -12.0f64;
            while t <= 12.0 {
                s += Complex64::new((-t * t).exp() * h, 0.0) / (z - t);
                t += h;
            }
            Complex64::new(0.0, 1.0 / std::f64::consts::PI) * s
        };
        for (re, im) in [
            (0.0, 0.5),
            (1.0, 1.0),
            (3.9, 0.3),
            (4.1, 0.3),
            (-5.0, 0.4),
            (2.0, 3.0),
            (8.0, 1.0),
            (-15.0, 0.5),
            (0.3, 6.0),
        ] {
            let z = Complex64::new(re, im);
            let (w, r) = (faddeeva(z), integral(z));
            assert!((w - r).norm() < 1e-8 * r.norm(), "{z}: {w} vs {r}");
        }
        // Dawson's integral: D(1), its maximum at 0.9241388730, D(5), D(−2.5) (SciPy's dawsn).
        assert!((dawson(1.0) - 0.538_079_506_912_768_4).abs() < 1e-9);
        assert!((dawson(0.924_138_873_004_591_8) - 0.541_044_224_635_181).abs() < 1e-9);
        assert!((dawson(5.0) - 0.102_134_074_424_276_9).abs() < 1e-9);
        assert!((dawson(-2.5) + 0.223_083_722_167_435_6).abs() < 1e-9);
        // Below the real axis through the reflection.
        let z = Complex64::new(1.0, -0.5);
        let want = (-(z * z)).exp() * 2.0 - faddeeva(-z);
        assert!((faddeeva(z) - want).norm() < 1e-12);
    }

    /// Humlíček's approximation against the series and fraction: 1e-4 relative over the upper
    /// half-plane (a grid of 0 ≤ Im z ≤ 20, |Re z| ≤ 30, the real axis included).
    #[test]
    fn fast_faddeeva_is_within_1e_4() {
        let mut worst: f64 = 0.0;
        for i in 0..=240 {
            for j in 0..=80 {
                let z = Complex64::new(-30.0 + 0.25 * i as f64, 0.25 * j as f64);
                let (a, b) = (faddeeva_fast(z), faddeeva(z));
                worst = worst.max((a - b).norm() / b.norm());
            }
        }
        assert!(worst < 1e-4, "{worst}");
    }

    /// The normal mean of a pole against a fine trapezoid over ±10 sd, in both half-planes;
    /// for a real pole, the principal value (the symmetric trapezoid straddling the pole).
    #[test]
    fn normal_mean_of_a_pole_is_the_quadrature() {
        let (mean, sd) = (27.8, 1.4);
        let quad = |z: Complex64| {
            let n = 400_000;
            let h = 20.0 * sd / n as f64;
            let mut s = Complex64::new(0.0, 0.0);
            for k in 0..n {
                let v = mean - 10.0 * sd + (k as f64 + 0.5) * h;
                let g = (-(v - mean).powi(2) / (2.0 * sd * sd)).exp()
                    / (sd * (std::f64::consts::TAU).sqrt());
                s += Complex64::new(g * h, 0.0) / (Complex64::new(v, 0.0) - z);
            }
            s
        };
        for z in [
            Complex64::new(27.0, 0.2),
            Complex64::new(29.5, -0.05),
            Complex64::new(40.0, 3.0),
            Complex64::new(46.0, -0.5),
            Complex64::new(10.0, 0.0),
            Complex64::new(27.8, 0.01),
        ] {
            let (got, want) = (normal_mean_of_pole(z, mean, sd), quad(z));
            assert!(
                (got - want).norm() < 1e-4 * want.norm(),
                "{z}: {got} vs {want}"
            );
        }
        // A real pole placed on a cell boundary of the trapezoid: its principal value.
        let h = 20.0 * sd / 400_000.0;
        let z = Complex64::new(mean - 10.0 * sd + 123_456.0 * h, 0.0);
        let (got, want) = (normal_mean_of_pole(z, mean, sd), quad(z));
        assert!(
            (got - want).norm() < 1e-4 * want.norm(),
            "{z}: {got} vs {want}"
        );
        // No spread: the pole itself.
        let z = Complex64::new(27.0, 0.2);
        assert_eq!(
            normal_mean_of_pole(z, mean, 0.0),
            (Complex64::new(mean, 0.0) - z).inv()
        );
    }
}
