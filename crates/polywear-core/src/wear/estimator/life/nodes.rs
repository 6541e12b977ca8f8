//! The nodes of the tread's mean transfer Ḡ(x) over the orders a worn tread sweeps
//! (MODEL.md#the-estimator-over-the-treads-life): Ḡ at adaptive nodes, with the moments of its
//! linear pieces against the worn depth's slope, and far poles as one Chebyshev fit.

use super::*;

/// A smooth complex function of x on \[lo, hi\] from its values at the [`CHEBYSHEV_POINTS`]
/// Chebyshev points: Σ_j c_j T_j(t), t = (x − mid)/half.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Chebyshev {
    pub(super) mid: f64,
    pub(super) per_half: f64,
    pub(super) coefficients: [Complex64; CHEBYSHEV_POINTS],
}

impl Chebyshev {
    pub(super) fn fit(lo: f64, hi: f64, f: impl Fn(f64) -> Complex64) -> Self {
        const N: usize = CHEBYSHEV_POINTS;
        let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        // t_k = cos((k + ½)π/N), by rotation from t_0.
        let step = std::f64::consts::PI / N as f64;
        let (sin_step, cos_step) = step.sin_cos();
        let (mut s, mut c) = (0.5 * step).sin_cos();
        let mut coefficients = [Complex64::new(0.0, 0.0); N];
        for _ in 0..N {
            let t = c;
            let value = f(mid + half * t);
            // T_j(t) by its recurrence.
            let (mut before, mut now) = (1.0, t);
            coefficients[0] += value;
            for coefficient in coefficients.iter_mut().skip(1) {
                *coefficient += value * now;
                (before, now) = (now, 2.0 * t * now - before);
            }
            (s, c) = (s * cos_step + c * sin_step, c * cos_step - s * sin_step);
        }
        coefficients[0] /= N as f64;
        for coefficient in coefficients.iter_mut().skip(1) {
            *coefficient *= 2.0 / N as f64;
        }
        Chebyshev {
            mid,
            per_half: 1.0 / half,
            coefficients,
        }
    }

    /// The fit at `x` (Clenshaw's recurrence).
    pub(super) fn at(&self, x: f64) -> Complex64 {
        let t = (x - self.mid) * self.per_half;
        let zero = Complex64::new(0.0, 0.0);
        let (mut b1, mut b2) = (zero, zero);
        for &c in self.coefficients[1..].iter().rev() {
            (b1, b2) = (c + b1 * (2.0 * t) - b2, b1);
        }
        self.coefficients[0] + b1 * t - b2
    }

    /// |c_{N−2}| + |c_{N−1}|: about how far the fit is from the function.
    pub(super) fn tail(&self) -> f64 {
        self.coefficients[CHEBYSHEV_POINTS - 2..]
            .iter()
            .map(|c| c.norm())
            .sum()
    }
}

/// How the nodes of Ḡ(x) are laid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Nodes {
    /// A quarter of the spread's width in orders (within [`FINE_STEP_ORDERS`],
    /// [`MAX_NEAR_STEP_ORDERS`]) near the transfer's resonances, coarser away from them.
    Adaptive,
    /// [`FINE_STEP_ORDERS`] everywhere (what the adaptive nodes are tested against).
    #[cfg_attr(not(test), allow(dead_code))]
    UniformFine,
}

/// Ḡ(x), the tread's transfer averaged over the speed spread at order x, at nodes in x: a
/// function of x alone, so every order of a wheel reads the same nodes as ν drifts past it. With
/// it, its moments M_m(x) = ∫ x′^m Ḡ(x′) dx′ from the first node (m < [`WORN_DEGREE`]), Ḡ
/// linear between the nodes: an order's ∫Ḡ ds is a combination of them
/// ([`TreadDrift::slope_coefficients`]).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct TransferNodes {
    pub(super) x: Vec<f64>,
    pub(super) g: Vec<Complex64>,
    pub(super) moments: Vec<Moments>,
}

/// M_0 … M_{K−1} at one x.
pub(super) type Moments = [Complex64; WORN_DEGREE];

/// ∫_a^b x^m Ḡ(x) dx for m < [`WORN_DEGREE`], Ḡ linear from `ga` at a to `gb` at b: in
/// t = x − a, x^m = Σ C(m, i) a^{m−i} t^i, and ∫₀^h t^i (g_a (h − t) + g_b t)/h dt =
/// h^{i+1} (g_a/((i + 1)(i + 2)) + g_b/(i + 2)): no cancellation for a > 0.
pub(super) fn segment_moments(a: f64, b: f64, ga: Complex64, gb: Complex64) -> Moments {
    const _: () = assert!(
        WORN_DEGREE == 5,
        "segment_moments is written out for five moments"
    );
    let h = b - a;
    let (h2, a2) = (h * h, a * a);
    let (h3, a3) = (h2 * h, a2 * a);
    let (h4, a4) = (h3 * h, a3 * a);
    let l0 = (ga * 0.5 + gb * 0.5) * h;
    let l1 = (ga / 6.0 + gb / 3.0) * h2;
    let l2 = (ga / 12.0 + gb / 4.0) * h3;
    let l3 = (ga / 20.0 + gb / 5.0) * h4;
    let l4 = (ga / 30.0 + gb / 6.0) * (h4 * h);
    [
        l0,
        l0 * a + l1,
        l0 * a2 + l1 * (2.0 * a) + l2,
        l0 * a3 + l1 * (3.0 * a2) + l2 * (3.0 * a) + l3,
        l0 * a4 + l1 * (4.0 * a3) + l2 * (6.0 * a2) + l3 * (4.0 * a) + l4,
    ]
}

impl TransferNodes {
    /// Nodes from `lo` to `hi` (both included) laid as `nodes` asks, for a spread of
    /// `spread_mps` \[m/s\].
    pub(super) fn new(g: &WheelGrowth, lo: f64, hi: f64, spread_mps: f64, nodes: Nodes) -> Self {
        let transfer = &g.response.transfer;
        // Where each pole resonates, in orders: ω = x V / r_B at the pole's frequency; those
        // further than MAX_FAR_STEP_ORDERS/FAR_STEP_SHARE from the nodes cannot narrow them.
        let reach = MAX_FAR_STEP_ORDERS / FAR_STEP_SHARE;
        let mut resonances: Vec<f64> = g
            .resonance_orders()
            .filter(|&r| r > lo - reach && r < hi + reach)
            .collect();
        resonances.sort_by(f64::total_cmp);
        resonances.dedup();
        let quarter_width_per_order = 0.25 * spread_mps / g.speed_mps;
        let spacing = |x: f64| match nodes {
            Nodes::UniformFine => FINE_STEP_ORDERS,
            Nodes::Adaptive => {
                // A quarter of the spread's width in orders at x near a resonance.
                let near =
                    (quarter_width_per_order * x).clamp(FINE_STEP_ORDERS, MAX_NEAR_STEP_ORDERS);
                let distance = resonances
                    .iter()
                    .map(|r| (x - r).abs())
                    .fold(f64::INFINITY, f64::min);
                (FAR_STEP_SHARE * distance).clamp(near, MAX_FAR_STEP_ORDERS)
            }
        };
        let mut x = Vec::with_capacity(128);
        x.push(lo);
        while let Some(&last) = x.last() {
            if last >= hi {
                break;
            }
            x.push((last + spacing(last)).min(hi));
        }
        let (r_b, speed_mps) = (g.r_b, g.speed_mps);
        // The poles that resonate among (or near) the nodes are summed at every node; the rest
        // are smooth there and read from a Chebyshev fit, unless its tail says it is not within
        // [`CHEBYSHEV_TOLERANCE`] of the transfer.
        let margin = FAR_POLE_MARGIN * (hi - lo);
        let (near, far) = transfer.split_at_orders(lo - margin, hi + margin, r_b, speed_mps);
        let speeds = NormalSpeeds::new(speed_mps, spread_mps);
        let mean = |t: &PoleExpansion, x: f64| t.mean_over_speeds(x, r_b, &speeds);
        let fit = (far.terms.len() >= CHEBYSHEV_FAR_POLES && hi > lo)
            .then(|| Chebyshev::fit(lo, hi, |x| mean(&far, x)));
        let mut g: Vec<Complex64> = match &fit {
            Some(fit) => x.iter().map(|&x| mean(&near, x) + fit.at(x)).collect(),
            None => x.iter().map(|&x| mean(transfer, x)).collect(),
        };
        if let Some(fit) = &fit {
            let largest_sqr = g.iter().map(|g| g.norm_sqr()).fold(0.0, f64::max);
            let tail = fit.tail();
            let within = tail * tail <= CHEBYSHEV_TOLERANCE * CHEBYSHEV_TOLERANCE * largest_sqr;
            // A NaN tail is not within either.
            if !within {
                g = x.iter().map(|&x| mean(transfer, x)).collect();
            }
        }
        let mut moments = Vec::with_capacity(x.len());
        moments.push([Complex64::new(0.0, 0.0); WORN_DEGREE]);
        for k in 1..x.len() {
            let seg = segment_moments(x[k - 1], x[k], g[k - 1], g[k]);
            let last = moments[k - 1];
            moments.push(std::array::from_fn(|m| last[m] + seg[m]));
        }
        TransferNodes { x, g, moments }
    }

    /// The segment holding `x`: the index of its upper node (1 …, held at the ends).
    pub(super) fn segment(&self, x: f64) -> usize {
        self.x
            .partition_point(|&n| n <= x)
            .clamp(1, self.x.len() - 1)
    }

    /// [`TransferNodes::point`] for `x` at or below the `x` of the previous call, whose segment
    /// `hint` holds (start it at `x.len()`): the segment is found walking down from it, so a
    /// falling sequence of points costs no search.
    pub(super) fn point_below(&self, x: f64, hint: &mut usize) -> (Complex64, Moments) {
        let mut k = (*hint).clamp(1, self.x.len() - 1);
        while k > 1 && self.x[k - 1] > x {
            k -= 1;
        }
        *hint = k;
        self.point_in(x, k)
    }

    /// Ḡ at `x`, linear between the nodes (held past the ends), and the moments there (inside
    /// the nodes' span: the last node's below it and the rest of its segment).
    pub(super) fn point(&self, x: f64) -> (Complex64, Moments) {
        self.point_in(x, self.segment(x))
    }

    /// [`TransferNodes::point`] in the segment `k` (whose upper node is k).
    pub(super) fn point_in(&self, x: f64, k: usize) -> (Complex64, Moments) {
        let (a, b) = (self.x[k - 1], self.x[k]);
        let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
        let g = self.g[k - 1] * (1.0 - t) + self.g[k] * t;
        let seg = segment_moments(a, x.max(a), self.g[k - 1], g);
        let base = self.moments[k - 1];
        (g, std::array::from_fn(|m| base[m] + seg[m]))
    }
}
