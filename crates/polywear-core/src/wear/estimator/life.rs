//! The per-sample estimator over the tread's life (MODEL.md#the-estimator-over-the-treads-life).
//!
//! The new-tire estimator grows every order at the rate of the new tread for ever. The long-term
//! loop's tread wears: its height falls at the position's whole even wear, the block stiffens in
//! series with the carcass and loses mass (MODEL.md#the-ageing-tread), and the tread frequency
//! f rises by 40–60% before the tire is worn out. ν = f/f_rot sweeps past several orders, and each
//! grows only while ν is just above it. This reading follows that drift:
//!
//! ```text
//! ln D_n(s) = ln 2R⁰ + ∫₀^s β_n(x_n(s′)) ds′,      x_n(s) = n · f₀ / f(h₀ − ẇ s),
//! ```
//!
//! β_n(x) being the new tire's closed loop with the tread's transfer (and a vibrating wheel's
//! tongue) read at order x, the zone and the forcing at n: a tread whose stiffness and mass
//! scale its poles by f/f₀ answers at n·f_rot as the new one does at x·f_rot. The polygon is
//! visible where ln D_n first reaches ln d_visible, if that is before the tire is worn out.

use super::{
    band_share, per_spread, tread_life_km, Complex64, NarrowBand, WheelGrowth,
    NARROW_BAND_DEVIATIONS, NEGLIGIBLE_LOCKED_SHARE,
};
use crate::long_term::wheel_loop::FEEDBACK_ORDERS;
use crate::model::tire::worn_tread_block;
use crate::model::ContactPatch;
use crate::params::Params;
use crate::wear::physics::fitted::{FittedConstants, WearAnswer};
use crate::wear::physics::law::MM_PER_1000KM_PER_M_PER_M;
use crate::wear::response::spread::NormalSpeeds;
use crate::wear::response::transfer::PoleExpansion;

mod depth_lock;
mod profile;
mod saturated;
pub use depth_lock::DepthLock;
pub use profile::{
    answer_saturated_per_step, LifeProfile, PiecewiseRate, SaturatedSteps, SpeedTerm,
    LIFE_PROFILE_INTERVALS, SLIDING_MODULATION_MAX,
};
pub use saturated::SATURATED_SPEED_LEGS;

/// Points of the table of f₀/f over the usable depth the worn depth's polynomial is fitted
/// through (17 give it within 2.5·10⁻⁷ of the usable depth of the ageing law, as 33 do).
const DRIFT_POINTS: usize = 17;

/// Degree of the polynomial in f₀/f − 1 that gives the worn depth (its derivative weighs Ḡ in
/// the distance, so that every order's integral of Ḡ is read from a few moments of it shared by
/// all orders): within 2.5·10⁻⁷ of the usable depth of the ageing law at carcass shares of
/// 0–0.7 (tested).
const WORN_DEGREE: usize = 5;

/// The finest spacing of the nodes in x, in orders: where the spread is narrow the resonance
/// is a few hundredths of an order wide; and the uniform grid the adaptive one is tested
/// against.
const FINE_STEP_ORDERS: f64 = 0.02;

/// The coarsest spacing near a resonance, in orders (a quarter of the spread's width, up to
/// this): a polygon seen late in the tire's life crosses the visible depth slowly, so its
/// distance magnifies the integral's error. At 0.1 the highway followers' median distance of
/// the fit over the tread's life is within 0.5% of a uniform grid of 0.02 order (0.15: 0.9%;
/// 0.25: 2.7%, enough to move a grid point across the field's 25,000 km).
const MAX_NEAR_STEP_ORDERS: f64 = 0.1;

/// Away from the transfer's resonances the nodes are spaced by this share of the distance to
/// the nearest one (Ḡ bends on that scale there: linear interpolation is within about
/// share²/8 of it) ...
const FAR_STEP_SHARE: f64 = 0.1;

/// ... up to this many orders.
const MAX_FAR_STEP_ORDERS: f64 = 0.5;

/// The change of ln D below which the locked print of an order is left out over its whole
/// life (its largest share of the spread times its growth over the life bounds it).
const NEGLIGIBLE_LOCKED_LOG: f64 = 1e-4;

/// Poles resonating within this share of the nodes' span outside it are summed at every node;
/// the rest through [`Chebyshev`].
const FAR_POLE_MARGIN: f64 = 0.25;

/// The fewest far poles worth a Chebyshev fit: its sum at a node costs about what three poles'
/// series do (a stable wheel has two far poles, a vibrating one 15 or so).
const CHEBYSHEV_FAR_POLES: usize = 4;

/// Points of the Chebyshev fit of the far poles' sum: for a pole resonating a quarter of the
/// span beyond its end the coefficients fall as 2.6^{−j} (the Bernstein ellipse through it),
/// and that pole's share is at most a few % of Ḡ there; the fit's tail is checked
/// ([`CHEBYSHEV_TOLERANCE`]), and on the default study a vibrating wheel falls back to the sum
/// at every node about once in 500.
const CHEBYSHEV_POINTS: usize = 12;

/// The fit's last two coefficients, against the largest |Ḡ| at the nodes, above which the far
/// poles are summed at every node after all (far inside [`faddeeva_fast`]'s 10⁻⁴; against the
/// smallest |Ḡ| every wheel fell back, Ḡ passing near zero).
///
/// [`faddeeva_fast`]: crate::wear::response::spread
const CHEBYSHEV_TOLERANCE: f64 = 1e-7;

/// A smooth complex function of x on \[lo, hi\] from its values at the [`CHEBYSHEV_POINTS`]
/// Chebyshev points: Σ_j c_j T_j(t), t = (x − mid)/half.
#[derive(Debug, Clone, PartialEq)]
struct Chebyshev {
    mid: f64,
    per_half: f64,
    coefficients: [Complex64; CHEBYSHEV_POINTS],
}

impl Chebyshev {
    fn fit(lo: f64, hi: f64, f: impl Fn(f64) -> Complex64) -> Self {
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
    fn at(&self, x: f64) -> Complex64 {
        let t = (x - self.mid) * self.per_half;
        let zero = Complex64::new(0.0, 0.0);
        let (mut b1, mut b2) = (zero, zero);
        for &c in self.coefficients[1..].iter().rev() {
            (b1, b2) = (c + b1 * (2.0 * t) - b2, b1);
        }
        self.coefficients[0] + b1 * t - b2
    }

    /// |c_{N−2}| + |c_{N−1}|: about how far the fit is from the function.
    fn tail(&self) -> f64 {
        self.coefficients[CHEBYSHEV_POINTS - 2..]
            .iter()
            .map(|c| c.norm())
            .sum()
    }
}

/// How the nodes of Ḡ(x) are laid.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Nodes {
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
struct TransferNodes {
    x: Vec<f64>,
    g: Vec<Complex64>,
    moments: Vec<Moments>,
}

/// M_0 … M_{K−1} at one x.
type Moments = [Complex64; WORN_DEGREE];

/// ∫_a^b x^m Ḡ(x) dx for m < [`WORN_DEGREE`], Ḡ linear from `ga` at a to `gb` at b: in
/// t = x − a, x^m = Σ C(m, i) a^{m−i} t^i, and ∫₀^h t^i (g_a (h − t) + g_b t)/h dt =
/// h^{i+1} (g_a/((i + 1)(i + 2)) + g_b/(i + 2)): no cancellation for a > 0.
fn segment_moments(a: f64, b: f64, ga: Complex64, gb: Complex64) -> Moments {
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
    fn new(g: &WheelGrowth, lo: f64, hi: f64, spread_mps: f64, nodes: Nodes) -> Self {
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
    fn segment(&self, x: f64) -> usize {
        self.x
            .partition_point(|&n| n <= x)
            .clamp(1, self.x.len() - 1)
    }

    /// [`TransferNodes::point`] for `x` at or below the `x` of the previous call, whose segment
    /// `hint` holds (start it at `x.len()`): the segment is found walking down from it, so a
    /// falling sequence of points costs no search.
    fn point_below(&self, x: f64, hint: &mut usize) -> (Complex64, Moments) {
        let mut k = (*hint).clamp(1, self.x.len() - 1);
        while k > 1 && self.x[k - 1] > x {
            k -= 1;
        }
        *hint = k;
        self.point_in(x, k)
    }

    /// Ḡ at `x`, linear between the nodes (held past the ends), and the moments there (inside
    /// the nodes' span: the last node's below it and the rest of its segment).
    fn point(&self, x: f64) -> (Complex64, Moments) {
        self.point_in(x, self.segment(x))
    }

    /// [`TransferNodes::point`] in the segment `k` (whose upper node is k).
    fn point_in(&self, x: f64, k: usize) -> (Complex64, Moments) {
        let (a, b) = (self.x[k - 1], self.x[k]);
        let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
        let g = self.g[k - 1] * (1.0 - t) + self.g[k] * t;
        let seg = segment_moments(a, x.max(a), self.g[k - 1], g);
        let base = self.moments[k - 1];
        (g, std::array::from_fn(|m| base[m] + seg[m]))
    }
}

/// The orders ν passes over the tread's life, ⌊ν₀⌋ − 2 (at least 1) … ⌈ν₀ f_end/f₀⌉ + 2, for a
/// new tire's `nu_new` and f₀/f_end = `end_ratio`; the last no higher than the orders the
/// long-term loop resolves ([`FEEDBACK_ORDERS`]: its profile feeds back no higher order, the
/// zone filtering what lies beyond) or, where ν₀ itself lies beyond them, than ⌈ν₀⌉ + 2
/// (MODEL.md#the-estimator-over-the-treads-life). The ceiling bounds the walk's work whatever
/// the depths: a tread worn to nothing has f_end = ∞ (its mass ρabh is gone), and ν would
/// pass every order.
pub(in crate::wear::estimator) fn passed_orders(nu_new: f64, end_ratio: f64) -> (u32, u32) {
    let lo = (nu_new.floor() - 2.0).max(1.0);
    let ceiling = (FEEDBACK_ORDERS as f64).max(nu_new.ceil() + 2.0);
    let hi = ((nu_new / end_ratio).ceil() + 2.0).min(ceiling).max(lo);
    (lo as u32, hi as u32)
}

/// f₀/f(h₀ − w) over the worn depth w ∈ \[0, usable\]: the new tread's undamped frequency
/// √(K_s/m) over the worn one's (MODEL.md#the-ageing-tread; `worn_tread_block`).
#[derive(Debug, Clone, PartialEq)]
struct TreadDrift {
    usable_m: f64,
    ratio: Vec<f64>,
    /// The worn depth as a polynomial in r − 1, r = f₀/f: w(r) = Σ_k worn_poly\[k−1\] (r − 1)^k
    /// \[m\] (k = 1 … [`WORN_DEGREE`]; w(1) = 0), least squares through the table read
    /// backwards. Every node of every order reads it, and its derivative in x = n r weighs Ḡ
    /// in the distance.
    worn_poly: [f64; WORN_DEGREE],
}

impl TreadDrift {
    fn of(p: &Params, patch: &ContactPatch) -> Self {
        let usable_m = p.usable_wear_m().clamp(0.0, p.tread_height);
        let frequency = |h: f64| {
            let b = worn_tread_block(p, patch, h);
            (b.stiffness_n_per_m / b.mass_kg).sqrt()
        };
        let new = frequency(p.tread_height);
        let worn = |k: usize| usable_m * k as f64 / (DRIFT_POINTS - 1) as f64;
        let ratio = (0..DRIFT_POINTS)
            .map(|k| {
                if k == 0 {
                    1.0
                } else {
                    new / frequency(p.tread_height - worn(k))
                }
            })
            .collect::<Vec<f64>>();
        let span = 1.0 - ratio[DRIFT_POINTS - 1];
        let mut worn_poly = [0.0; WORN_DEGREE];
        if span > 0.0 && usable_m > 0.0 {
            // Least squares in v = (r − 1)/span ∈ [−1, 0] (normal equations: a 5×5 system
            // whose monomials on [−1, 0] are conditioned well enough), then unscaled.
            type Square = nalgebra::SMatrix<f64, WORN_DEGREE, WORN_DEGREE>;
            type Column = nalgebra::SVector<f64, WORN_DEGREE>;
            let (mut gram, mut rhs) = (Square::zeros(), Column::zeros());
            for (k, &r) in ratio.iter().enumerate() {
                let v = (r - 1.0) / span;
                let basis = Column::from_fn(|j, _| v.powi(j as i32 + 1));
                gram += basis * basis.transpose();
                rhs += basis * (worn(k) / usable_m);
            }
            if let Some(solution) = gram.cholesky().map(|c| c.solve(&rhs)) {
                let mut scale = usable_m;
                for (j, w) in worn_poly.iter_mut().enumerate() {
                    scale /= span;
                    *w = solution[j] * scale;
                }
            }
        }
        TreadDrift {
            usable_m,
            ratio,
            worn_poly,
        }
    }

    /// The worn depth at which f₀/f is `ratio` \[m\] (the ratio falls as the tread wears), from
    /// its polynomial; 0 above 1 and the usable depth below the end's.
    fn worn_at(&self, ratio: f64) -> f64 {
        if ratio >= 1.0 {
            return 0.0;
        }
        if ratio <= self.at_end() {
            return self.usable_m;
        }
        let v = ratio - 1.0;
        let inner = self.worn_poly.iter().rev().fold(0.0, |acc, &b| acc * v + b);
        (inner * v).clamp(0.0, self.usable_m)
    }

    /// e_m such that the worn depth's slope along order n's path is
    /// dw(x/n)/dx = Σ_m e_m x^m / n^{m+1} (m < [`WORN_DEGREE`]): w′(r) = Σ_k k b_k (r − 1)^{k−1}
    /// expanded in powers of r = x/n.
    fn slope_coefficients(&self) -> [f64; WORN_DEGREE] {
        let mut e = [0.0; WORN_DEGREE];
        for (k1, &b) in self.worn_poly.iter().enumerate() {
            // Term k = k1 + 1: k b_k (r − 1)^{k1} = k b_k Σ_m C(k1, m) r^m (−1)^{k1−m}.
            let mut binomial = 1.0;
            for (m, em) in e.iter_mut().enumerate().take(k1 + 1) {
                let sign = if (k1 - m) % 2 == 0 { 1.0 } else { -1.0 };
                *em += (k1 + 1) as f64 * b * binomial * sign;
                binomial = binomial * (k1 - m) as f64 / (m + 1) as f64;
            }
        }
        e
    }

    /// f₀/f at the worn depth `worn_m` \[m\]: [`TreadDrift::worn_at`] inverted by bisection
    /// (it falls with the ratio), so that a grid of depths and the integrals' weights read one
    /// polynomial; 1 at no wear and the end's ratio at the usable depth and beyond.
    fn ratio_at(&self, worn_m: f64) -> f64 {
        let end = self.at_end();
        if worn_m <= 0.0 || end >= 1.0 {
            return 1.0;
        }
        if worn_m >= self.usable_m {
            return end;
        }
        let (mut lo, mut hi) = (end, 1.0);
        // 52 halvings take the bracket below an ulp of 1.
        for _ in 0..52 {
            let mid = 0.5 * (lo + hi);
            if self.worn_at(mid) > worn_m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// f₀/f of the worn-out tire.
    fn at_end(&self) -> f64 {
        self.ratio[DRIFT_POINTS - 1]
    }
}

/// The previous node of an order's walk in [`WheelGrowth::life`]: its distance and ln D where
/// they were taken.
struct Prev {
    x: f64,
    /// Its index among the nodes (none: the start, whose ln D is 0, or the end).
    j: Option<usize>,
    s: Option<f64>,
    log: Option<f64>,
    /// β of the linear loop there, and the locked print's part.
    linear: f64,
    locked: f64,
    /// The locked print's part of ln D there.
    locked_log: f64,
}

/// What [`WheelGrowth::life_answer`] takes from the wheel alone, whatever the fitted constants.
struct LifeOrders {
    drift: TreadDrift,
    /// The worn depth's slope along an order's path ([`TreadDrift::slope_coefficients`]).
    slope: [f64; WORN_DEGREE],
    /// f₀/f of the worn-out tire.
    end: f64,
    /// The orders ν passes, ⌊ν₀⌋ − 2 … ⌈ν₀ f_end/f₀⌉ + 2.
    lo: u32,
    hi: u32,
    /// Each order's zone transfer, forcing, and tongue (centre and half-width at x = 1, m/s).
    fixed: Vec<(Complex64, Complex64, (f64, f64))>,
    /// The transfer's uniform means over the widest tongue, once an order asks.
    tongue_means: std::cell::OnceCell<crate::wear::response::transfer::TongueMeans>,
}

/// ... and what it takes from the speed spread: the nodes of Ḡ(x).
struct LifeNodes {
    spread_mps: f64,
    transfer: TransferNodes,
    /// 1/x at the nodes.
    per_x: Vec<f64>,
    /// The narrow tongue's share of the spread at each node, once an order needs it.
    tongue_nodes: std::cell::OnceCell<Vec<NarrowBand>>,
}

/// The wear answer over the tread's life, with how near the deepest order came.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LifeAnswer {
    /// The order that becomes visible first, or (none visible) the one that got deepest; its
    /// distance to a visible polygon (+inf: none before the tire is worn out); the tread's life.
    pub answer: WearAnswer,
    /// The deepest order's largest depth over the life, as a share of d_visible (1 where a
    /// polygon is visible).
    pub peak_share_of_visible: f64,
}

impl LifeAnswer {
    /// A wheel without figures (past its wall-clock limit).
    pub const UNKNOWN: LifeAnswer = LifeAnswer {
        answer: WearAnswer::UNKNOWN,
        peak_share_of_visible: f64::NAN,
    };

    /// Its figures' bits, to compare answers exactly (NaN, an order where every order
    /// levels, equal to itself).
    #[cfg(test)]
    pub(crate) fn bits(&self) -> [u64; 4] {
        [
            self.answer.polygon_order_wear.to_bits(),
            self.answer.distance_to_visible_km.to_bits(),
            self.answer.tread_life_km.to_bits(),
            self.peak_share_of_visible.to_bits(),
        ]
    }

    /// The answer of a walk over a wheel's orders: the first polygon `first` (distance \[km\],
    /// order) if any, else none and the order that got deepest, `deepest` (its largest
    /// ln(D/2R⁰), order), NaN where no order rose above its seed (every order levels: which
    /// one "got deepest" would be only the lowest walked); a seed already visible (`target` =
    /// ln(d_visible/2R⁰) ≤ 0) is visible at once, as order `lowest`.
    pub(crate) fn of_walk(
        first: Option<(f64, u32)>,
        deepest: (f64, u32),
        target: f64,
        tread_life_km: f64,
        lowest: u32,
    ) -> Self {
        let (distance_to_visible_km, order) = match first {
            _ if target <= 0.0 => (0.0, lowest as f64),
            Some((km, n)) => (km, n as f64),
            None if deepest.0 <= 0.0 => (f64::INFINITY, f64::NAN),
            None => (f64::INFINITY, deepest.1 as f64),
        };
        LifeAnswer {
            answer: WearAnswer {
                polygon_order_wear: order,
                distance_to_visible_km,
                tread_life_km,
            },
            peak_share_of_visible: if first.is_some() || target <= 0.0 {
                1.0
            } else {
                (deepest.0 - target).exp()
            },
        }
    }
}

impl WheelGrowth {
    /// Where each pole of the tread's transfer resonates, in orders: ω = x V/r_B at the pole's
    /// frequency |Im s|.
    fn resonance_orders(&self) -> impl Iterator<Item = f64> + '_ {
        self.response
            .transfer
            .terms
            .iter()
            .map(|t| t.pole.im.abs() * self.r_b / self.speed_mps)
    }

    /// The wheel's wear answer under `c` over the tread's life
    /// (MODEL.md#the-estimator-over-the-treads-life): every order that ν passes, integrated
    /// from the seed over the drifting tread frequency, until it is visible or the tire is worn
    /// out.
    pub fn life_answer(&self, c: &FittedConstants) -> LifeAnswer {
        let answer = self.aged(c).life(c, Nodes::Adaptive);
        self.in_time(vec![answer]).remove(0)
    }

    /// [`WheelGrowth::life_answer`] with Ḡ(x) at the `nodes` given. Order n's x = n·f₀/f runs
    /// from n down to n·f₀/f_end, at the distance s(x) = w(x/n)/ẇ (w the worn depth at which
    /// f₀/f = x/n). Ḡ is linear between the nodes and the linear loop is affine in it, so
    /// ln D_n at a node is closed-form: base·s + Re(through · ∫Ḡ ds), the integral from the
    /// nodes' moments ([`TransferNodes`]); the locked print by the trapezoid rule in s. ln D is
    /// taken only on the segments where it can rise.
    fn life(&self, c: &FittedConstants, nodes: Nodes) -> LifeAnswer {
        let orders = self.life_orders();
        let at = self.life_nodes(&orders, c.speed_spread_kmh / 3.6, nodes);
        self.life_from(&orders, &at, c)
    }

    /// `answers`, or unknown ones where the wheel's wall-clock limit passed while they were
    /// walked (a walk that finds it passed stops: what it gives is not an answer).
    pub(super) fn in_time(&self, answers: Vec<LifeAnswer>) -> Vec<LifeAnswer> {
        match self.out_of_time() {
            None => answers,
            Some(_) => vec![LifeAnswer::UNKNOWN; answers.len()],
        }
    }

    /// [`WheelGrowth::life_answer`] under each set of `sets`, each answer with every order's
    /// largest ln(D/2R⁰)
    /// over the life (orders from `.0`; [`WheelGrowth::life_walk`]): what the saturated level
    /// screens its orders with.
    pub(super) fn life_answers_and_peaks(
        &self,
        sets: &[FittedConstants],
    ) -> (u32, Vec<(LifeAnswer, Vec<f64>)>) {
        let orders = self.life_orders();
        let answers = per_spread(
            sets,
            |spread_mps| self.life_nodes(&orders, spread_mps, Nodes::Adaptive),
            |at, c| {
                let mut peaks = Vec::with_capacity(orders.fixed.len());
                let answer = self.life_walk(&orders, at, c, Some(&mut peaks));
                (answer, peaks)
            },
        );
        (orders.lo, answers)
    }

    /// What the answer over the tread's life takes from the wheel alone: the tread's drift, the
    /// orders ν passes, each with its zone transfer H_w(n), forcing e_n and tongue.
    fn life_orders(&self) -> LifeOrders {
        let drift = TreadDrift::of(&self.params, &self.patch);
        let (lo, hi) = passed_orders(self.nu(), drift.at_end());
        self.life_orders_over(drift, lo, hi)
    }

    /// Each order's largest ln(D/2R⁰) over the life on the plain walk
    /// ([`WheelGrowth::life_answers_and_peaks`]), for the orders `lo..=hi` alone (any orders,
    /// not only those ν passes) under each set of `sets`, all of the speed spread
    /// `spread_mps` \[m/s\]: what screens the saturated level's legs of orders beyond the plain
    /// walk's (the nodes of Ḡ laid over these orders alone).
    pub(super) fn life_peaks_over(
        &self,
        lo: u32,
        hi: u32,
        spread_mps: f64,
        sets: &[&FittedConstants],
    ) -> Vec<Vec<f64>> {
        let orders = self.life_orders_over(TreadDrift::of(&self.params, &self.patch), lo, hi);
        let at = self.life_nodes(&orders, spread_mps, Nodes::Adaptive);
        sets.iter()
            .map(|c| {
                let mut peaks = Vec::with_capacity(orders.fixed.len());
                self.life_walk(&orders, &at, c, Some(&mut peaks));
                peaks
            })
            .collect()
    }

    /// [`WheelGrowth::life_orders`] of the orders `lo..=hi` on the tread's `drift`.
    fn life_orders_over(&self, drift: TreadDrift, lo: u32, hi: u32) -> LifeOrders {
        let end = drift.at_end();
        // Each order's zone transfer H_w(n), forcing e_n, and tongue (centre and half-width,
        // m/s): the tongue at x: a worn tread's ν is ν₀·f/f₀, so order n locks as the new
        // tire's order x does, in a band of speeds around V ν/x, ±V δ_L/x (δ_L of order n). The
        // uniform mean over it is the same at every x: the band of ω = x V/r_B it spans does not
        // move.
        let fixed = (lo..=hi)
            .zip(self.feedback.zones_and_forcings(lo))
            .map(|(n, (zone, forcing))| {
                (
                    zone,
                    forcing,
                    self.tongue_mps(n as f64, forcing, self.seed_m),
                )
            })
            .collect();
        LifeOrders {
            slope: drift.slope_coefficients(),
            drift,
            end,
            lo,
            hi,
            fixed,
            tongue_means: std::cell::OnceCell::new(),
        }
    }

    /// The nodes of Ḡ(x) over `orders`' span for a spread of `spread_mps` \[m/s\], laid as
    /// `nodes` asks.
    fn life_nodes(&self, orders: &LifeOrders, spread_mps: f64, nodes: Nodes) -> LifeNodes {
        let transfer = TransferNodes::new(
            self,
            orders.lo as f64 * orders.end,
            orders.hi as f64,
            spread_mps,
            nodes,
        );
        LifeNodes {
            spread_mps,
            // 1/x at the nodes (every order's tongue is read there).
            per_x: transfer.x.iter().map(|x| 1.0 / x).collect(),
            transfer,
            tongue_nodes: std::cell::OnceCell::new(),
        }
    }

    /// The answer under `c` from the wheel's `orders` and the nodes `at` of its spread.
    fn life_from(&self, orders: &LifeOrders, at: &LifeNodes, c: &FittedConstants) -> LifeAnswer {
        self.life_walk(orders, at, c, None)
    }

    /// [`WheelGrowth::life_from`], and where `peaks` is given, each order's largest
    /// ln(D/2R⁰) over the life into it (from `orders.lo`; at least the target where it is
    /// visible): every order is then walked to its own polygon or the tire's end, not only to
    /// an earlier order's polygon. The answer is the same.
    fn life_walk(
        &self,
        orders: &LifeOrders,
        at: &LifeNodes,
        c: &FittedConstants,
        mut peaks: Option<&mut Vec<f64>>,
    ) -> LifeAnswer {
        let share = c.wear_share_straight;
        let other_per_share =
            self.position_rate(c.wear_rate_driven_factor) * self.feedback.local_per_m;
        let wear_m_per_m = self.tread_wear_with(c);
        let tread_life = tread_life_km(&self.params, wear_m_per_m * MM_PER_1000KM_PER_M_PER_M);
        let target = self.print_log_ratio;
        let spread_mps = at.spread_mps;
        let LifeOrders {
            drift,
            slope,
            end,
            lo,
            hi,
            fixed,
            tongue_means,
        } = orders;
        let (end, lo, hi) = (*end, *lo, *hi);
        let LifeNodes {
            transfer,
            per_x,
            tongue_nodes,
            ..
        } = at;
        let life_m = drift.usable_m / wear_m_per_m;
        let nu = self.nu();
        let v = self.speed_mps;
        let mut first: Option<(f64, u32)> = None;
        let mut deepest = (f64::NEG_INFINITY, lo);
        // The tongue's uniform means, for the widest tongue of these orders (a vibrating
        // wheel under a spread).
        let tongue_mean = |order: f64, centre_mps: f64, half_mps: f64| {
            tongue_means
                .get_or_init(|| {
                    let widest = (lo..=hi)
                        .zip(fixed)
                        .map(|(n, &(_, _, (_, half_mps)))| half_mps * n as f64 / v)
                        .fold(0.0, f64::max);
                    self.response
                        .transfer
                        .tongue_means(self.r_b, v, self.response.nu, widest)
                })
                .at(order, centre_mps, half_mps)
        };
        for (n, &(zone, forcing, (centre_mps, half_mps))) in (lo..=hi).zip(fixed) {
            // Past the wheel's wall-clock limit no answer is given (the callers ask
            // out_of_time): the walk stops.
            if self.deadline.passed() {
                break;
            }
            let order = n as f64;
            let order_loop = self.order_loop(zone, forcing, share, other_per_share);
            let (centre_at_n, half_at_n) = (centre_mps * order, half_mps * order);
            let over_tongue = (half_mps > 0.0 && spread_mps > 0.0)
                .then(|| tongue_mean(order, centre_mps, half_mps));
            // Where the band's nearest edge is t deviations from V, its share of the spread is
            // below its width times the density there, 2δ/(σ√2π)·e^{−t²/2}: the locked print is
            // left out beyond the t at which that, over the whole life, moves ln D by less than
            // NEGLIGIBLE_LOCKED_LOG (everywhere, if it does at t = 0 at the widest band).
            let lock_within_sd = match over_tongue {
                Some(g) => {
                    let widest = 2.0 * half_at_n / (order * end);
                    let bound = widest / (spread_mps * (2.0 * std::f64::consts::PI).sqrt())
                        * (order_loop.locked_per_m - order_loop.linear_per_m(g)).abs()
                        * life_m;
                    (bound >= NEGLIGIBLE_LOCKED_LOG)
                        .then(|| (2.0 * (bound / NEGLIGIBLE_LOCKED_LOG).ln()).sqrt())
                }
                None => (half_mps > 0.0).then_some(f64::INFINITY),
            };
            // The locked print's part of β at x: over the share of the spread in the tongue,
            // the locked print instead of the loop's own mean over the band.
            let locked_per_m = |x: f64, g: Complex64, j: Option<usize>| {
                let Some(t) = lock_within_sd else {
                    return 0.0;
                };
                let per_x = j.map_or_else(|| 1.0 / x, |j| per_x[j]);
                let (centre, half) = (centre_at_n * per_x, half_at_n * per_x);
                if (centre - v).abs() - half > t * spread_mps {
                    return 0.0;
                }
                let eta = half / spread_mps;
                let locked_share = match j {
                    // At a node, the spread's density at the tongue's centre is the same for
                    // every order.
                    Some(j) if spread_mps > 0.0 && eta <= NARROW_BAND_DEVIATIONS => tongue_nodes
                        .get_or_init(|| {
                            transfer
                                .x
                                .iter()
                                .map(|&x| NarrowBand::at((v * nu / x - v) / spread_mps))
                                .collect()
                        })[j]
                        .share(eta),
                    _ => band_share(centre, half, v, spread_mps),
                };
                if locked_share > NEGLIGIBLE_LOCKED_SHARE {
                    let in_band = order_loop.linear_per_m(over_tongue.unwrap_or(g));
                    locked_share * (order_loop.locked_per_m - in_band)
                } else {
                    0.0
                }
            };
            let (per_order, per_wear) = (1.0 / order, 1.0 / wear_m_per_m);
            let distance_m = |x: f64| drift.worn_at(x * per_order) * per_wear;
            // The loop through the tread, ∫ Re(through · Ḡ) ds from x back to n, is
            // Re(through · ∫_x^n Ḡ(x′) (−dw/dx′) dx′)/ẇ = Re(Σ_m c_m (M_m(n) − M_m(x))), with
            // dw/dx = Σ_m e_m x^m/n^{m+1}: c_m = −through · e_m/(n^{m+1} ẇ).
            let mut weight = [Complex64::new(0.0, 0.0); WORN_DEGREE];
            let mut power = per_order;
            for (c, &e) in weight.iter_mut().zip(slope) {
                *c = order_loop.through_per_m * (-e * power * per_wear);
                power *= per_order;
            }
            let weighted = |m: &Moments| {
                weight
                    .iter()
                    .zip(m)
                    .fold(0.0, |acc, (c, m)| acc + (c * m).re)
            };
            let (g_start, moments_start) = transfer.point(order);
            let at_start = weighted(&moments_start);
            let x_end = order * end;
            let (g_end, moments_end) = transfer.point(x_end);
            // The nodes strictly between n·f₀/f_end and n, from n down, then the end.
            let mut inside = transfer.x.partition_point(|&x| x <= x_end)
                ..transfer.x.partition_point(|&x| x < order);
            // With no locked print on this order, ln D can rise only on a segment with an end
            // where the linear loop's rate is not negative (a rising one). The walk starts at
            // the node above the highest rising node and stops at the node below the lowest:
            // outside them ln D falls, and neither peaks nor reaches the visible depth. An order
            // with no rising point has no walk (its peak stays at the seed). (Where the print
            // counts, its part of ln D is summed node by node: every node is walked.)
            let mut resume = None;
            let mut to_end = true;
            if lock_within_sd.is_none() {
                let rises = |g: Complex64| order_loop.linear_per_m(g) >= 0.0;
                let (start_rises, end_rises) = (rises(g_start), rises(g_end));
                let highest = inside.clone().rev().find(|&j| rises(transfer.g[j]));
                let lowest =
                    highest.and_then(|top| (inside.start..=top).find(|&j| rises(transfer.g[j])));
                if !start_rises && !end_rises && highest.is_none() {
                    if 0.0 > deepest.0 {
                        deepest = (0.0, n);
                    }
                    if let Some(peaks) = peaks.as_deref_mut() {
                        peaks.push(0.0);
                    }
                    continue;
                }
                if !start_rises {
                    resume = match highest {
                        Some(top) => (top + 1 < inside.end).then_some(top + 1),
                        // Only the end rises: the walk's one segment is from the lowest node.
                        None => (!inside.is_empty()).then_some(inside.start),
                    };
                }
                if let Some(j) = resume {
                    inside.end = j;
                }
                if !end_rises {
                    match lowest {
                        Some(bottom) if bottom > inside.start => {
                            inside.start = bottom - 1;
                            to_end = false;
                        }
                        Some(_) => {}
                        // Only the start rises: the walk's one segment is to the highest node.
                        None => {
                            if let Some(top) = inside.clone().next_back() {
                                inside.start = top;
                                to_end = false;
                            }
                        }
                    }
                }
            }
            let path = inside
                .rev()
                .map(|j| (transfer.x[j], transfer.g[j], Some(j)))
                .chain(to_end.then_some((x_end, g_end, None)));
            let moments_of = |j: Option<usize>| j.map_or(moments_end, |j| transfer.moments[j]);
            let distance_of = |x: f64| if x == x_end { life_m } else { distance_m(x) };
            // ln D at a node where the distance is `s`, the locked print's part `locked_log`.
            let log_at = |s: f64, j: Option<usize>, locked_log: f64| {
                order_loop.base_per_m * s + (at_start - weighted(&moments_of(j))) + locked_log
            };
            // Walk the nodes, taking ln D only where it can rise: on a segment where the
            // linear loop's rate (linear in x between the nodes, Ḡ being so) and the locked
            // print's (by the trapezoid rule) are both negative at the ends, ln D falls, so it
            // neither peaks nor reaches the visible depth there. The distance is read where it is
            // needed (lazily at the previous node).
            let mut prev = match resume {
                Some(j) => Prev {
                    x: transfer.x[j],
                    j: Some(j),
                    s: None,
                    log: None,
                    linear: order_loop.linear_per_m(transfer.g[j]),
                    locked: 0.0,
                    locked_log: 0.0,
                },
                None => Prev {
                    x: order,
                    j: None,
                    s: Some(0.0),
                    log: Some(0.0),
                    linear: order_loop.linear_per_m(g_start),
                    locked: locked_per_m(order, g_start, None),
                    locked_log: 0.0,
                },
            };
            let mut peak = 0.0_f64;
            for (x, g, j) in path {
                let linear = order_loop.linear_per_m(g);
                let locked = locked_per_m(x, g, j);
                let may_rise = linear.max(prev.linear) + locked.max(prev.locked) >= 0.0;
                let locks = locked != 0.0 || prev.locked != 0.0;
                let mut s = None;
                if may_rise || locks || first.is_some() {
                    let s_before = *prev.s.get_or_insert_with(|| distance_of(prev.x));
                    // Past an earlier order's polygon this one can only come later.
                    if peaks.is_none() && first.is_some_and(|(m, _)| s_before > m) {
                        break;
                    }
                    s = Some(distance_of(x));
                }
                let mut locked_log = prev.locked_log;
                if let (true, Some(s), Some(s_before)) = (locks, s, prev.s) {
                    locked_log += 0.5 * (prev.locked + locked) * (s - s_before);
                }
                let mut log = None;
                if let (true, Some(s), Some(s_before)) = (may_rise, s, prev.s) {
                    let next = log_at(s, j, locked_log);
                    let before = *prev
                        .log
                        .get_or_insert_with(|| log_at(s_before, prev.j, prev.locked_log));
                    if next >= target && target > 0.0 {
                        let at_m = s_before + (s - s_before) * (target - before) / (next - before);
                        if first.is_none_or(|(m, _)| at_m < m) {
                            first = Some((at_m, n));
                        }
                        peak = peak.max(next);
                        break;
                    }
                    peak = peak.max(next);
                    log = Some(next);
                }
                prev = Prev {
                    x,
                    j,
                    s,
                    log,
                    linear,
                    locked,
                    locked_log,
                };
            }
            if peak > deepest.0 {
                deepest = (peak, n);
            }
            if let Some(peaks) = peaks.as_deref_mut() {
                peaks.push(peak);
            }
        }
        LifeAnswer::of_walk(
            first.map(|(m, n)| (m * 1e-3, n)),
            deepest,
            target,
            tread_life,
            lo,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::tire::contact_patch;

    /// The table's end is the ageing law's f/f₀ ≈ √((h₀/h)/(c + (1 − c) h/h₀)) (the bending
    /// term under 0.6%), for the carcass shares of its bound and the 1/h law (c = 0); a new
    /// tread does not drift; the worn depth read from its polynomial is within 10⁻⁶ of the
    /// usable depth of the ageing law's own (measured: 2.5·10⁻⁷ at c = 0.3) (at depths between the table's points too), and the
    /// slope the orders' integrals weigh Ḡ with is its derivative.
    #[test]
    fn the_drift_follows_the_ageing_tread() {
        for (c, mu) in [
            (0.0, 0.0),
            (0.3, 0.0),
            (0.5, 0.0),
            (0.7, 0.0),
            (0.5, 0.3),
            (0.3, 0.7),
        ] {
            let p = Params {
                carcass_share: c,
                belt_mass_share: mu,
                ..crate::wear::physics::fitted::pinned_params()
            };
            let patch = contact_patch(&p).unwrap();
            let drift = TreadDrift::of(&p, &patch);
            let usable = p.usable_wear_m();
            let h = (p.tread_height - usable) / p.tread_height;
            // The mass's fall (the belt's share of it not wearing) over the compliance's.
            let law = ((1.0 / (mu + (1.0 - mu) * h)) / (c + (1.0 - c) * h)).sqrt();
            let end = 1.0 / drift.at_end();
            assert!(
                (end / law - 1.0).abs() < 0.01,
                "c = {c}: {end} against {law}"
            );
            assert_eq!(drift.ratio[0], 1.0);
            // Monotone: the tread only stiffens and lightens as it wears.
            assert!(drift.ratio.windows(2).all(|w| w[1] < w[0]), "c = {c}");
            // f₀/f at the worn depth w, from the ageing law itself.
            let frequency = |h: f64| {
                let b = worn_tread_block(&p, &patch, h);
                (b.stiffness_n_per_m / b.mass_kg).sqrt()
            };
            let ratio = |w: f64| frequency(p.tread_height) / frequency(p.tread_height - w);
            let mut worst: f64 = 0.0;
            for k in 0..=100 {
                let w = usable * k as f64 / 100.0;
                worst = worst.max((drift.worn_at(ratio(w)) - w).abs() / usable);
            }
            assert!(worst < 1e-6, "c = {c}: {worst}");
            assert_eq!(drift.worn_at(1.5), 0.0);
            assert_eq!(drift.worn_at(0.5 * drift.at_end()), usable);
            // dw(x/n)/dx = Σ e_m x^m/n^{m+1} against a central difference, at n = 20.
            let (e, n) = (drift.slope_coefficients(), 20.0);
            for k in 1..10 {
                let x = n * (1.0 - (1.0 - drift.at_end()) * k as f64 / 10.0);
                let step = 1e-4;
                let difference =
                    (drift.worn_at((x + step) / n) - drift.worn_at((x - step) / n)) / (2.0 * step);
                let series: f64 = (0..WORN_DEGREE)
                    .map(|m| e[m] * x.powi(m as i32) / n.powi(m as i32 + 1))
                    .sum();
                assert!(
                    (series / difference - 1.0).abs() < 1e-6,
                    "c = {c}, x = {x}: {series} {difference}"
                );
            }
        }
    }
}

#[cfg(test)]
mod table_tests {
    use super::*;
    use crate::classify::budget::Meter;
    use crate::classify::ClassifierOptions;
    use crate::evaluate::{calibrate_wear, solve_wheel};
    use crate::model::{Variant, Wheel};
    use crate::wear::{WearInputs, WearSettings};

    /// A wheel's closed loop at a highway point (140 km/h 0.35°: the follower vibrates).
    fn growth(speed_kmh: f64, toe_deg: f64, wheel: Wheel) -> (WheelGrowth, bool) {
        let opts = ClassifierOptions::default();
        let base = crate::wear::physics::fitted::pinned_params();
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        let p = Params {
            speed_kmh,
            toe_deg,
            ..base
        };
        let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
        let g = WheelGrowth::new(
            &WearInputs {
                params: &p,
                model: &w.model,
                verdict: &w.verdict,
                settings: &WearSettings::default(),
                calibration: &cal,
            },
            &Meter::new(opts.budget),
        )
        .unwrap();
        (g, w.verdict.class.vibrates())
    }

    /// The estimate (what explore writes) is the saturated answer over the tread's life under
    /// the sample's own constants, with the new tire's growth of its order in the growth columns
    /// (none where every order levels) and the answer's peak share (at φ_s = 0.28, σ_V = 10
    /// km/h, where the follower at 120 km/h and 0.45° gets a polygon).
    #[test]
    fn the_estimate_is_the_saturated_answer() {
        let opts = ClassifierOptions::default();
        let base = Params {
            wear_share_straight: 0.28,
            speed_spread_kmh: 10.0,
            ..crate::wear::physics::fitted::pinned_params()
        };
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        let mut finite = 0;
        for (speed_kmh, toe_deg) in [(120.0, 0.45), (110.0, 0.6), (80.0, 0.3)] {
            let p = Params {
                speed_kmh,
                toe_deg,
                ..base
            };
            for wheel in Wheel::BOTH {
                let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
                let at = || {
                    let settings = WearSettings::default();
                    let inputs = WearInputs {
                        params: &p,
                        model: &w.model,
                        verdict: &w.verdict,
                        settings: &settings,
                        calibration: &cal,
                    };
                    let g = WheelGrowth::new(&inputs, &Meter::new(opts.budget)).unwrap();
                    (crate::wear::estimate(&inputs, &Meter::new(opts.budget)), g)
                };
                let (e, g) = at();
                let whole = g.saturated_answer(&FittedConstants::of(&p));
                let life = whole.answer;
                let here = format!("{speed_kmh} km/h {toe_deg}° {wheel}");
                // How near the deepest order came is the life answer's, 1 where visible.
                assert_eq!(
                    e.peak_share_of_visible.to_bits(),
                    whole.peak_share_of_visible.to_bits(),
                    "{here}"
                );
                assert!(
                    (e.peak_share_of_visible == 1.0) == life.distance_to_visible_km.is_finite()
                        && e.peak_share_of_visible > 0.0,
                    "{here}: {}",
                    e.peak_share_of_visible
                );
                assert_eq!(
                    e.distance_to_visible_km.to_bits(),
                    life.distance_to_visible_km.to_bits(),
                    "{here}"
                );
                assert_eq!(
                    e.polygon_order_dominant.to_bits(),
                    life.polygon_order_wear.to_bits(),
                    "{here}"
                );
                if life.polygon_order_wear.is_nan() {
                    // Every order levels from its seed: no order, no growth.
                    assert!(
                        e.growth_rate_per_1000km.is_nan() && e.orders.is_empty(),
                        "{here}"
                    );
                    assert!(life.distance_to_visible_km.is_infinite(), "{here}");
                } else {
                    let order = g.order(life.polygon_order_wear as u32);
                    assert_eq!(
                        e.growth_rate_per_1000km, order.growth_rate_per_1000km,
                        "{here}"
                    );
                    assert_eq!(e.orders, vec![order], "{here}");
                }
                if life.distance_to_visible_km.is_finite() {
                    finite += 1;
                }
            }
        }
        assert!(finite >= 1, "no polygon over the tread's life");
    }

    /// The nodes' Ḡ (the far poles through their Chebyshev fit) is every pole's sum at the
    /// node within 10⁻⁶ of the largest |Ḡ|, and their moments are the integrals of x^m Ḡ (Ḡ
    /// linear between the nodes) by a fine trapezoid within 10⁻⁶, for a vibrating and a stable
    /// wheel at spreads of 2–10 km/h.
    #[test]
    fn the_nodes_are_the_transfer_and_its_moments() {
        let mut fitted = 0;
        for (speed, toe, wheel) in [
            (140.0, 0.35, Wheel::Follower),
            (110.0, 0.45, Wheel::Follower),
        ] {
            let (g, _) = growth(speed, toe, wheel);
            for spread_kmh in [2.0, 5.0, 10.0] {
                let spread = spread_kmh / 3.6;
                let (lo, hi) = (10.0, 30.0);
                let nodes = TransferNodes::new(&g, lo, hi, spread, Nodes::Adaptive);
                let transfer = &g.response.transfer;
                let direct: Vec<Complex64> = nodes
                    .x
                    .iter()
                    .map(|&x| transfer.mean_over_speed(x, g.r_b, g.speed_mps, spread))
                    .collect();
                let largest = direct.iter().map(|d| d.norm()).fold(0.0, f64::max);
                for (k, (a, b)) in nodes.g.iter().zip(&direct).enumerate() {
                    assert!(
                        (a - b).norm() <= 1e-6 * largest,
                        "{speed} km/h, {spread_kmh} km/h, node {k}: {a} {b}"
                    );
                }
                fitted += usize::from(nodes.g != direct);
                // The moments at the last node against a fine trapezoid of x^m Ḡ.
                let last = nodes.x.len() - 1;
                for m in 0..WORN_DEGREE {
                    let mut sum = Complex64::new(0.0, 0.0);
                    for k in 1..=last {
                        let (a, b) = (nodes.x[k - 1], nodes.x[k]);
                        let steps = 200;
                        for i in 0..steps {
                            let (t0, t1) = (i as f64 / steps as f64, (i + 1) as f64 / steps as f64);
                            let at = |t: f64| {
                                let x = a + (b - a) * t;
                                (nodes.g[k - 1] * (1.0 - t) + nodes.g[k] * t) * x.powi(m as i32)
                            };
                            sum += (at(t0) + at(t1)) * (0.5 * (b - a) / steps as f64);
                        }
                    }
                    let got = nodes.moments[last][m];
                    assert!(
                        (got - sum).norm() <= 1e-6 * sum.norm(),
                        "moment {m}: {got} {sum}"
                    );
                }
            }
        }
        // The fit was used (somewhere it differs from the direct sum in its last digits).
        assert!(fitted > 0);
    }

    /// The tongue's means from [`TongueMeans`] (far poles as one series in λ²) are the
    /// transfer's uniform means over the band, within 10⁻⁹ relative, at every order a
    /// vibrating wheel's answer over its life takes and half-widths up to the widest.
    #[test]
    fn the_tongue_means_are_the_band_means() {
        let (g, vibrates) = growth(140.0, 0.35, Wheel::Follower);
        assert!(vibrates);
        let (v, nu) = (g.speed_mps, g.response.nu);
        let widest = 0.3;
        let means = g.response.transfer.tongue_means(g.r_b, v, nu, widest);
        for n in 8..30 {
            let order = n as f64;
            for lambda in [1e-3, 0.01, 0.1, widest] {
                let (centre, half) = (v * nu / order, v * lambda / order);
                let want =
                    g.response
                        .transfer
                        .mean_over_band(order, g.r_b, centre - half, centre + half);
                let got = means.at(order, centre, half);
                assert!(
                    (got - want).norm() <= 1e-9 * want.norm(),
                    "order {n}, λ {lambda}: {got} {want}"
                );
            }
        }
    }

    /// The adaptive nodes of Ḡ(x) (and the locked print left out where it cannot count) give the
    /// integral over a uniform grid of 0.02 order: at highway points with stable and vibrating
    /// wheels, both positions, spreads of 0.5–10 km/h, the same polygon within 1.5% in
    /// distance, or the same peak within 2% where none is visible (a case on the edge,
    /// visible by one and not by the other, only where the other's peak is at least 0.9 of the
    /// visible depth). Measured: 0.6% and 0.8% at most.
    #[test]
    fn the_adaptive_nodes_give_the_fine_integral() {
        let opts = ClassifierOptions::default();
        let base = crate::wear::physics::fitted::pinned_params();
        let cal = calibrate_wear(&base, Variant::SlidingShare, &opts).unwrap();
        let settings = WearSettings::default();
        let (mut visible, mut vibrating) = (0, 0);
        for (speed_kmh, toe_deg) in [
            (80.0, 0.3),
            (100.0, 0.45),
            (110.0, 0.45),
            (125.0, 0.3),
            (140.0, 0.35),
            (115.0, 0.6),
        ] {
            for wheel in Wheel::BOTH {
                let p = Params {
                    speed_kmh,
                    toe_deg,
                    ..base
                };
                let w = solve_wheel(p, Variant::SlidingShare, wheel, &opts);
                vibrating += usize::from(w.verdict.class.vibrates());
                let g = WheelGrowth::new(
                    &WearInputs {
                        params: &p,
                        model: &w.model,
                        verdict: &w.verdict,
                        settings: &settings,
                        calibration: &cal,
                    },
                    &Meter::new(opts.budget),
                )
                .unwrap();
                for (phi, spread) in [
                    (0.12, 5.0),
                    (0.25, 5.0),
                    (0.28, 10.0),
                    (0.25, 2.0),
                    (0.25, 0.5),
                ] {
                    let c = FittedConstants {
                        wear_share_straight: phi,
                        speed_spread_kmh: spread,
                        wear_rate_driven_factor: 1.75,
                        ..FittedConstants::of(&g.params)
                    };
                    let (t, d) = (g.life(&c, Nodes::Adaptive), g.life(&c, Nodes::UniformFine));
                    let at = format!("{speed_kmh} km/h {toe_deg} deg {wheel} {c:?}: {t:?} {d:?}");
                    let (st, sd) = (
                        t.answer.distance_to_visible_km,
                        d.answer.distance_to_visible_km,
                    );
                    match (st.is_finite(), sd.is_finite()) {
                        (true, true) => {
                            visible += 1;
                            assert!((st / sd - 1.0).abs() < 0.015, "{at}");
                            assert_eq!(t.answer.polygon_order_wear, d.answer.polygon_order_wear);
                        }
                        (false, false) => assert!(
                            (t.peak_share_of_visible / d.peak_share_of_visible - 1.0).abs() < 0.02,
                            "{at}"
                        ),
                        _ => assert!(
                            t.peak_share_of_visible.min(d.peak_share_of_visible) >= 0.9,
                            "{at}"
                        ),
                    }
                }
            }
        }
        assert!(visible >= 5, "only {visible} visible cases");
        assert!(vibrating >= 2, "only {vibrating} vibrating wheels");
    }
}
