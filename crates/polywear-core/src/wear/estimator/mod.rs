//! Level B, the per-sample estimator (MODEL.md#the-per-sample-estimator): for one wheel after
//! its verdict, the closed-loop growth rate of every profile order near the tread frequency,
//! averaged over the speed spread; the order that grows fastest, and the distance at which it
//! becomes visible.
//!
//! A profile harmonic R_n forces ε = Re\[e_n R_n e^{inΩt}\] (step 12); the tread's power
//! answers with δP/P̄ = G(iω_n) ε at ω_n = nΩ, which the zone lays back onto order n through
//! conj(H_w(n)); each element also wears in proportion to its own pressure. Per metre:
//!
//! ```text
//! β_n = −w′ Re[κ(1 − |H_w|²) + G(iω_n) conj(H_w) e_n]
//!       − w′_x [κ(1 − |H_w|²) + G_x Re(conj(H_w) e_n)] − (1 − φ_s) w′_pos κ,
//! ```
//!
//! w′_x the driving wheel's slip power's even wear and G_x its response, w′_pos the position's
//! even-wear rate (MODEL.md#the-driving-wheels-slip-power).
//!
//! G is the equilibrium's transfer for a stable wheel (no integration) and the cycle's periodic
//! linearisation for a vibrating one (one period read off shooting's last iteration: 17 RHS
//! evaluations).
//! Over the speed spread the wheel's linearisation at the sample's speed is kept and ω_n moves
//! with the speed: the mean over the normal spread is then exact pole by pole.

use super::WearError;
use crate::classify::budget::{Deadline, Meter};
use crate::classify::{Class, WheelVerdict};
use crate::model::{ModelFailure, WheelModel};
use crate::numeric::Complex64;
use crate::params::Params;
use crate::wear::physics::calibration::{
    driven_position, position_rate_m_per_m, wear_rate_ref_m_per_m, Calibration,
};
use crate::wear::physics::cycle::{SampledCycle, SAMPLES_PER_PERIOD};
use crate::wear::physics::feedback::Feedback;
use crate::wear::physics::fitted::{FittedConstants, LifeAnswer};
use crate::wear::physics::law::{
    even_wear_m_per_m, MM_PER_1000KM_PER_M_PER_M, PER_1000KM_PER_PER_M,
};
use crate::wear::physics::slip::{SlipPower, WearPower};
use crate::wear::physics::zone::WearZone;
use crate::wear::response::normal_form::ForcedHopf;
use crate::wear::response::periodic::CycleResponse;
use crate::wear::response::transfer::{equilibrium_expansion, Linearisation, PoleExpansion};

mod life;
mod lock_band;
mod narrow_band;
mod orders;
mod settings;
pub use life::{
    answer_saturated_per_step, DepthLock, LifeProfile, PiecewiseRate, SaturatedSteps, SpeedTerm,
    LIFE_PROFILE_INTERVALS, SATURATED_SPEED_LEGS, SLIDING_MODULATION_MAX,
};
use narrow_band::{band_share, NarrowBand, NARROW_BAND_DEVIATIONS};
pub(crate) use orders::per_spread;
use orders::{OrderFixed, OrderLoop, SpreadTerms};
pub use settings::{retired_level, WearProblem, WearSettings, SHIPPED_LEVEL};

/// A share of the spread inside the tongue below which the locked print is left out (its
/// effect on β̄ is below this share of the locked growth).
const NEGLIGIBLE_LOCKED_SHARE: f64 = 1e-6;

/// Orders evaluated on either side of ν: ⌊ν⌋ − this … ⌈ν⌉ + this.
pub(crate) const ORDERS_AROUND_NU: u32 = 2;

/// The closed-loop growth of one profile order.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct OrderGrowth {
    /// The order n (sides of the polygon).
    pub order: u32,
    /// δ_n = ν − n \[revolutions⁻¹\].
    pub detuning_rev: f64,
    /// β̄_n, the growth rate over the speed spread \[1/1000 km\] (> 0: grows).
    pub growth_rate_per_1000km: f64,
    /// The part of β̄_n that passes through the tread's dynamics, −w′ Re\[Ḡ conj(H_w) e_n\]
    /// \[1/1000 km\]: what the patch filter acts on twice.
    pub regenerative_per_1000km: f64,
    /// Half-width of the speed band around the order's lock where a vibrating wheel's cycle
    /// locks to a seed-sized polygon \[km/h\] (0 for a stable wheel).
    pub lock_halfwidth_kmh: f64,
    /// The share of the speed spread inside that band, where the order grows by the locked
    /// print instead of the linear loop.
    pub locked_share: f64,
}

/// The estimator's figures for one wheel (MODEL.md#wear-columns); NaN where undefined.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WearAnswer {
    /// w′ at the point \[mm/1000 km\] (φ_s·w′₀ at the reference point).
    pub wear_even_mm_per_1000km: f64,
    /// The order with the largest β̄_n; over the tread's life, the order visible first (or the
    /// deepest). NaN where undefined.
    pub polygon_order_dominant: f64,
    /// Its detuning δ = ν − n.
    pub detuning_rev: f64,
    /// Its β̄_n \[1/1000 km\].
    pub growth_rate_per_1000km: f64,
    /// Distance to a polygon of depth d_visible peak-to-valley, cruising at this point with
    /// this speed spread \[km\]; +inf if every order levels out (over the tread's life: if
    /// none is visible before the tire is worn out).
    pub distance_to_visible_km: f64,
    /// Over the tread's life, how deep the deepest order got before the tire was worn out, as
    /// a share of d_visible (1 where a polygon is visible): how near a wheel without one came.
    /// NaN on the new tire's level, whose orders grow without end or level out from the seed.
    pub peak_share_of_visible: f64,
    /// φ_s used.
    pub wear_calibration_share: f64,
    /// λ_lev = w′ κ, the levelling of straight running \[1/1000 km\].
    pub levelling_per_1000km: f64,
    /// λ_other = (1 − φ_s) w′₀ κ, the levelling of all other wear \[1/1000 km\].
    pub levelling_other_per_1000km: f64,
    /// The position's whole even wear at the point \[mm/1000 km\]: w′ and the rest of the
    /// position's wear, (1 − φ_s) w′_pos; the tread's mean depth falls at this rate
    /// (MODEL.md#the-ageing-tread).
    pub tread_wear_mm_per_1000km: f64,
    /// Every order evaluated, lowest first.
    pub orders: Vec<OrderGrowth>,
    /// Why the figures are NaN; empty otherwise.
    pub reason: String,
}

impl WearAnswer {
    /// The answer of a wheel with no figures.
    pub fn undefined(share: f64, reason: String) -> Self {
        let nan = f64::NAN;
        WearAnswer {
            wear_even_mm_per_1000km: nan,
            polygon_order_dominant: nan,
            detuning_rev: nan,
            growth_rate_per_1000km: nan,
            distance_to_visible_km: nan,
            peak_share_of_visible: nan,
            wear_calibration_share: share,
            levelling_per_1000km: nan,
            levelling_other_per_1000km: nan,
            tread_wear_mm_per_1000km: nan,
            orders: Vec::new(),
            reason,
        }
    }
}

/// How the wheel answers ε: its transfer as poles, its power, ν, and the phase coupling.
#[derive(Debug, Clone, PartialEq)]
struct Response {
    transfer: PoleExpansion,
    mean_power_w: f64,
    nu: f64,
    phase_coupling_s: f64,
    power_harmonic_rel: f64,
    /// The direction of 2P̂₁ĝ₋₁/P̄ (the product is free of the cycle's time origin): where the
    /// locked print lies against the forcing (0 for a stable tread).
    print_direction: Complex64,
    /// The cycle's forced Hopf normal form (None for a stable tread).
    hopf: Option<ForcedHopf>,
}

fn response(inputs: &WearProblem, meter: &Meter) -> Result<Response, WearError> {
    let (p, v) = (&inputs.params, inputs.verdict);
    let model = inputs
        .model
        .as_ref()
        .map_err(|f| WearError::NoModel(f.to_string()))?;
    let ode = &model.ode;
    let r = match v.class {
        Class::Stable => {
            let lin = Linearisation::at(ode, &ode.equilibrium());
            let transfer = equilibrium_expansion(ode, &lin).ok_or(WearError::NoEigenbasis)?;
            Response {
                transfer,
                mean_power_w: lin.power_w,
                nu: v.eig_freq_hz / WheelModel::rotation_hz(p),
                phase_coupling_s: 0.0,
                power_harmonic_rel: 0.0,
                print_direction: Complex64::new(0.0, 0.0),
                hopf: None,
            }
        }
        Class::LimitCycle | Class::Bistable => {
            let cycle = SampledCycle::of(ode, v, SAMPLES_PER_PERIOD, meter)?;
            let r = CycleResponse::of(ode, &cycle)?;
            Response {
                hopf: ForcedHopf::of(&r),
                transfer: r.transfer,
                mean_power_w: r.mean_power_w,
                nu: v.polygon_order,
                phase_coupling_s: r.phase_coupling_s,
                power_harmonic_rel: r.power_harmonic_rel,
                print_direction: unit(r.power_harmonic * r.phase_coupling),
            }
        }
        Class::NoTraction | Class::Failed | Class::Standstill => {
            return Err(WearError::NoModel(format!("{}: {}", v.class, v.reason)))
        }
    };
    if r.nu.is_finite() && r.nu > 0.0 && r.mean_power_w > 0.0 {
        Ok(r)
    } else {
        Err(WearError::NoModel(format!(
            "no tread frequency or no power (ν = {}, P̄ = {} W)",
            r.nu, r.mean_power_w
        )))
    }
}

/// z/|z| (0 for z = 0).
fn unit(z: Complex64) -> Complex64 {
    let norm = z.norm();
    if norm > 0.0 {
        z / norm
    } else {
        Complex64::new(0.0, 0.0)
    }
}

/// The orders evaluated around ν: ⌊ν⌋ − 2 … ⌈ν⌉ + 2, from 1 up.
pub fn orders_around(nu: f64) -> std::ops::RangeInclusive<u32> {
    let lo = (nu.floor() - ORDERS_AROUND_NU as f64).max(1.0) as u32;
    let hi = (nu.ceil() + ORDERS_AROUND_NU as f64).max(lo as f64) as u32;
    lo..=hi
}

/// One wheel's closed loop, ready to give the growth of any order: its response to ε, its even
/// wear and the feedback at its operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelGrowth {
    response: Response,
    feedback: Feedback,
    /// w′ per unit φ_s \[m/m\] (γ ∝ φ_s): the lateral power's.
    even_per_share: f64,
    /// The driving wheel's slip power's w′ per unit φ_s \[m/m\] (0 for the follower).
    slip_even_per_share: f64,
    /// G_x, the slip power's response to ε (quasi-static).
    slip_gain: f64,
    /// w′_pos κ \[1/m\]: λ_other per unit (1 − φ_s), w′_pos the position's even-wear rate.
    other_per_share: f64,
    /// w′_pos \[m/m\], the position's even-wear rate.
    position_rate_m_per_m: f64,
    /// Whether w′_pos is k_d w′₀ (the driving wheel under the slip reading), not w′₀.
    driven_position: bool,
    /// The sample's parameters, for the seed, the visible depth and the usable tread.
    params: Params,
    speed_mps: f64,
    r_b: f64,
    seed_m: f64,
    visible_m: f64,
    /// ln(d_visible / 2R⁰), the locked print's logarithm (kept: the band asks it per set).
    print_log_ratio: f64,
    share: f64,
    spread_mps: f64,
    /// The contact patch, whose tread block ages in the answer over the tread's life (its
    /// drift is built there, off the new tire's path).
    patch: crate::model::ContactPatch,
    /// The wheel's wall-clock limit (the meter's it was built with): every walk polls it, and
    /// an answer given after it passed is unknown, with its reason ([`WheelGrowth::out_of_time`]).
    deadline: Deadline,
}

impl WheelGrowth {
    /// The loop of one wheel (see [`WearProblem::solve`] for what it costs).
    pub fn new(inputs: &WearProblem, meter: &Meter) -> Result<Self, WearError> {
        let p = &inputs.params;
        let response = response(inputs, meter)?;
        let model = inputs
            .model
            .as_ref()
            .map_err(|f| WearError::NoModel(f.to_string()))?;
        let feedback = Feedback::new(p, model, inputs.settings.zone);
        let gamma_per_share = inputs.calibration.gamma_m3_per_j(&Params {
            wear_share_straight: 1.0,
            ..*p
        });
        let even_per_share = even_wear_m_per_m(
            gamma_per_share,
            response.mean_power_w,
            model.patch.width_m,
            p.speed_mps(),
            p.r_b,
        );
        let slip = SlipPower::of(p, model, inputs.settings.power);
        let slip_even_per_share = even_wear_m_per_m(
            gamma_per_share,
            slip.power_w,
            model.patch.width_m,
            p.speed_mps(),
            p.r_b,
        );
        let position_rate = position_rate_m_per_m(p, model.wheel, inputs.settings.power);
        Ok(WheelGrowth {
            other_per_share: position_rate * feedback.local_per_m,
            position_rate_m_per_m: position_rate,
            driven_position: driven_position(model.wheel, inputs.settings.power),
            params: *p,
            response,
            feedback,
            even_per_share,
            slip_even_per_share,
            slip_gain: slip.gain,
            speed_mps: p.speed_mps(),
            r_b: p.r_b,
            seed_m: p.seed_runout_um * 1e-6,
            visible_m: p.visible_depth_mm * 1e-3,
            print_log_ratio: print_log_ratio(p),
            share: p.wear_share_straight,
            spread_mps: p.speed_spread_kmh / 3.6,
            patch: model.patch,
            deadline: meter.deadline(),
        })
    }

    /// The wheel without a wall-clock limit: for a caller that keeps it and asks it many
    /// answers over minutes (the calibration's fit), whose own budget is its design's size.
    pub fn untimed(mut self) -> Self {
        self.deadline = Deadline::never();
        self
    }

    /// Why the wheel's answers are unknown, once its wall-clock limit (`max_wheel_seconds`)
    /// has passed: a walk that finds it passed stops, and every answer given after it is
    /// replaced by this reason, never by a figure walked only in part.
    pub fn out_of_time(&self) -> Option<String> {
        self.deadline.passed().then(|| self.deadline.reason())
    }

    /// The wheel with its tread ageing as `c` says (its carcass and belt shares,
    /// MODEL.md#the-ageing-tread): only the drift of the tread frequency over the life reads
    /// them, so the new tire's closed loop is kept and only the parameters change.
    pub(crate) fn aged(&self, c: &FittedConstants) -> std::borrow::Cow<'_, WheelGrowth> {
        if c.ages_as(&self.params) {
            return std::borrow::Cow::Borrowed(self);
        }
        let mut aged = self.clone();
        aged.params.carcass_share = c.carcass_share;
        aged.params.belt_mass_share = c.belt_mass_share;
        std::borrow::Cow::Owned(aged)
    }

    /// `answer` of each group of `sets` that ages the tread alike, on the wheel aged so
    /// ([`WheelGrowth::aged`]), its answers back in the order of `sets`: what every answer over
    /// the tread's life under many sets is made of (a group shares its drift, and within it the
    /// speed spread's nodes, [`per_spread`]).
    pub(crate) fn per_ageing<A>(
        &self,
        sets: &[FittedConstants],
        answer: impl Fn(&WheelGrowth, &[FittedConstants]) -> Vec<A>,
    ) -> Vec<A> {
        let key = |c: &FittedConstants| (c.carcass_share.to_bits(), c.belt_mass_share.to_bits());
        let mut groups: Vec<((u64, u64), Vec<usize>)> = Vec::new();
        for (k, c) in sets.iter().enumerate() {
            match groups.iter_mut().find(|(g, _)| *g == key(c)) {
                Some((_, members)) => members.push(k),
                None => groups.push((key(c), vec![k])),
            }
        }
        let mut out: Vec<Option<A>> = (0..sets.len()).map(|_| None).collect();
        for (_, members) in groups {
            let group: Vec<FittedConstants> = members.iter().map(|&k| sets[k]).collect();
            let g = self.aged(&group[0]);
            for (k, a) in members.into_iter().zip(answer(&g, &group)) {
                out[k] = Some(a);
            }
        }
        out.into_iter()
            .map(|a| a.expect("one answer per set"))
            .collect()
    }

    /// ν = f/f_rot.
    pub fn nu(&self) -> f64 {
        self.response.nu
    }

    /// |P₁|/P̄ of the wheel's cycle, what it prints every revolution onto an order it is locked
    /// to (MODEL.md#growth-of-a-vibrating-wheel); 0 for a stable tread.
    pub fn cycle_power_harmonic_rel(&self) -> f64 {
        self.response.power_harmonic_rel
    }

    /// The even wear w′ at the sample's φ_s \[m/m\]: the lateral power's and the slip
    /// power's.
    pub fn even_wear_m_per_m(&self) -> f64 {
        self.share * (self.even_per_share + self.slip_even_per_share)
    }

    /// κ = k_t/p₀ \[1/m\].
    pub fn local_per_m(&self) -> f64 {
        self.feedback.local_per_m
    }

    /// The growth of order `order` at the sample's φ_s and speed spread.
    pub fn order(&self, order: u32) -> OrderGrowth {
        self.order_with(order, self.share, self.spread_mps)
    }

    /// The wheel's answers under every set of `sets`, as [`WearProblem::solve`] gives a sample whose
    /// constants are the set's ([`WheelGrowth::saturated_answers_with`]); unknown past the
    /// wheel's wall-clock limit.
    pub fn answers_on(&self, sets: &[FittedConstants]) -> Vec<LifeAnswer> {
        let answers = self.saturated_answers_with(sets);
        if self.out_of_time().is_some() {
            return vec![LifeAnswer::UNKNOWN; sets.len()];
        }
        answers
    }

    /// w′_pos with the driven axle's rate `wear_rate_driven_factor` \[m/m\]: the position's
    /// even-wear rate, k_d w′₀ for a driving wheel under the slip reading, w′₀ otherwise.
    fn position_rate(&self, wear_rate_driven_factor: f64) -> f64 {
        if self.driven_position {
            wear_rate_driven_factor * wear_rate_ref_m_per_m(&self.params)
        } else {
            wear_rate_ref_m_per_m(&self.params)
        }
    }

    /// The tread's whole even wear under `c` \[m/m\]: w′ at its φ_s and the rest of the
    /// position's wear, (1 − φ_s) w′_pos; the tread's mean depth falls at this rate
    /// (MODEL.md#the-ageing-tread).
    fn tread_wear_with(&self, c: &FittedConstants) -> f64 {
        let share = c.wear_share_straight;
        let even = share * (self.even_per_share + self.slip_even_per_share);
        even + (1.0 - share) * self.position_rate(c.wear_rate_driven_factor)
    }

    /// λ_other per unit (1 − φ_s) \[1/1000 km\] with the driven axle's rate
    /// `wear_rate_driven_factor`: w′_pos κ, w′_pos = k_d w′₀ for a driving wheel under the slip
    /// reading, w′₀ otherwise. With no speed spread β_n is φ_s β_n(φ_s = 1) minus (1 − φ_s)
    /// times this, for every order (a drive cycle's band uses it).
    pub fn other_levelling_per_1000km(&self, wear_rate_driven_factor: f64) -> f64 {
        self.position_rate(wear_rate_driven_factor)
            * self.feedback.local_per_m
            * PER_1000KM_PER_PER_M
    }

    /// The growth of order `order` with φ_s = `share` and a speed spread of `spread_mps`
    /// \[m/s\]: β_n = φ_s·B_n(σ_V) − (1 − φ_s) w′₀ κ, B_n the loop at φ_s = 1, over the share
    /// of the spread where a vibrating wheel's cycle is not locked to a seed-sized polygon of
    /// this order; where it is, the order grows by the locked print
    /// (MODEL.md#growth-of-a-vibrating-wheel).
    pub fn order_with(&self, order: u32, share: f64, spread_mps: f64) -> OrderGrowth {
        self.order_at(order, share, spread_mps, self.other_per_share)
    }

    /// [`WheelGrowth::order_with`] with λ_other per unit (1 − φ_s) = `other_per_share` \[1/m\]
    /// (it moves with the position's even-wear rate, k_d for a driving wheel).
    fn order_at(
        &self,
        order: u32,
        share: f64,
        spread_mps: f64,
        other_per_share: f64,
    ) -> OrderGrowth {
        let terms = self.spread_terms(&self.order_fixed(order), spread_mps);
        self.order_from(&terms, share, other_per_share)
    }

    /// What order `order`'s growth takes from the wheel alone: the zone's transfer, the
    /// forcing and the tongue (its uniform mean kept once asked for).
    fn order_fixed(&self, order: u32) -> OrderFixed {
        let n = order as f64;
        let forcing = self.feedback.forcing_per_radius(n);
        // The cycle locks to a seed-sized polygon in a band of speeds around V_n.
        let (lock_speed_mps, lock_mps) = self.tongue_mps(n, forcing, self.seed_m);
        OrderFixed {
            order,
            zone: self.feedback.zone.transfer(n, self.r_b),
            forcing,
            lock_speed_mps,
            lock_mps,
            over_tongue: std::cell::OnceCell::new(),
        }
    }

    /// What order `f.order`'s growth takes from a speed spread of `spread_mps` \[m/s\],
    /// before φ_s and λ_other enter: the forcing's normal mean over the spread, the share of
    /// the spread inside the tongue and, where that share counts, the forcing's uniform mean
    /// over the tongue.
    fn spread_terms(&self, f: &OrderFixed, spread_mps: f64) -> SpreadTerms {
        let n = f.order as f64;
        let r = &self.response;
        let mean = r
            .transfer
            .mean_over_speed(n, self.r_b, self.speed_mps, spread_mps);
        let v = self.speed_mps;
        let locked_share = band_share(f.lock_speed_mps, f.lock_mps, v, spread_mps);
        let over_tongue = (locked_share > NEGLIGIBLE_LOCKED_SHARE && spread_mps > 0.0).then(|| {
            *f.over_tongue.get_or_init(|| {
                r.transfer.mean_over_band(
                    n,
                    self.r_b,
                    f.lock_speed_mps - f.lock_mps,
                    f.lock_speed_mps + f.lock_mps,
                )
            })
        });
        SpreadTerms {
            order: f.order,
            zone: f.zone,
            forcing: f.forcing,
            mean,
            lock_mps: f.lock_mps,
            locked_share,
            over_tongue,
        }
    }

    /// Order `t.order`'s growth at φ_s = `share` and λ_other per unit (1 − φ_s) =
    /// `other_per_share` \[1/m\], from its spread's terms.
    fn order_from(&self, t: &SpreadTerms, share: f64, other_per_share: f64) -> OrderGrowth {
        let order_loop = self.order_loop(t.zone, t.forcing, share, other_per_share);
        let beta = order_loop.growth_per_m(t.mean, t.locked_share, t.over_tongue);
        OrderGrowth {
            order: t.order,
            detuning_rev: self.response.nu - t.order as f64,
            growth_rate_per_1000km: beta * PER_1000KM_PER_PER_M,
            regenerative_per_1000km: order_loop.through_tread_per_m(t.mean) * PER_1000KM_PER_PER_M,
            lock_halfwidth_kmh: t.lock_mps * 3.6,
            locked_share: t.locked_share,
        }
    }

    /// The closed loop of an order whose wear zone has the transfer `zone` (H_w) and whose
    /// forcing is `forcing` (e_n), at φ_s = `share` and λ_other per unit (1 − φ_s) =
    /// `other_per_share` \[1/m\]: what stays fixed while the tread's transfer Ḡ moves (with
    /// the speed spread, or with the tread's age).
    fn order_loop(
        &self,
        zone: Complex64,
        forcing: Complex64,
        share: f64,
        other_per_share: f64,
    ) -> OrderLoop {
        let even = share * self.even_per_share;
        let other = (1.0 - share) * other_per_share;
        let slip = self.slip_per_m(zone, forcing, share);
        OrderLoop {
            base_per_m: -even * self.feedback.local_per_m * (1.0 - zone.norm_sqr()) - other - slip,
            through_per_m: -even * zone.conj() * forcing,
            // |H_w| as √|H_w|², not `norm`'s hypot: every order of the answer over the tread's life
            // asks it, and the values are far from overflow.
            locked_per_m: self.locked_print_per_m(even, zone.norm_sqr().sqrt()) - other - slip,
        }
    }

    /// The slip power's part of β for an order of zone transfer `zone` and forcing `forcing`
    /// at φ_s = `share` \[1/m\]: its wear shared by pressure within the zone levels by
    /// κ(1 − |H_w|²), and its zone total follows the profile's ε with G_x (at the frozen slip
    /// ratio) through conj(H_w) e_n, as the lateral power does with G
    /// (MODEL.md#the-driving-wheels-slip-power). Positive: it levels.
    fn slip_per_m(&self, zone: Complex64, forcing: Complex64, share: f64) -> f64 {
        let even = share * self.slip_even_per_share;
        if even == 0.0 {
            return 0.0;
        }
        let through = (zone.conj() * forcing).re * self.slip_gain;
        even * (self.feedback.local_per_m * (1.0 - zone.norm_sqr()) + through)
    }
}

impl WearProblem<'_> {
    /// Solves one wheel's wear problem (MODEL.md#the-per-sample-estimator): the order visible
    /// first over the tread's life, each speed's print saturated, and its distance there (the
    /// growth columns then the new tire's growth of that order; NaN where no order rises above its
    /// seed over the life, every order levelling). Adds no RHS evaluation to a stable wheel; a
    /// vibrating one spends, at each sample of its cycle, one evaluation of the vector field and
    /// its Jacobian that the linearisation reads too, and one at the period's end (17, the period
    /// read off shooting's last iteration), or integrates the period again where the classifier
    /// kept no iteration (about 165), charged to `meter`. A wheel without a model, or whose cycle
    /// cannot be integrated, gets NaN with the reason.
    pub fn solve(&self, meter: &Meter) -> WearAnswer {
        let p = &self.params;
        let share = p.wear_share_straight;
        let growth = match WheelGrowth::new(self, meter) {
            Ok(g) => g,
            Err(e) => return WearAnswer::undefined(share, e.to_string()),
        };
        // The order visible first over the tread's life (or the deepest), with the new tire's
        // growth of it in the growth columns. No order rose above its seed (NaN): none is the
        // wear's order, and no order's growth fills the growth columns.
        let life = growth.saturated_answer(&FittedConstants::of(p));
        let order = life.polygon_order_wear;
        let top = (!order.is_nan()).then(|| growth.order(order as u32));
        let (orders, distance_km, peak_share): (Vec<OrderGrowth>, f64, f64) = (
            top.into_iter().collect(),
            life.distance_to_visible_km,
            life.peak_share_of_visible,
        );
        if let Some(reason) = growth.out_of_time() {
            return WearAnswer::undefined(share, reason);
        }
        let even = growth.even_wear_m_per_m();
        WearAnswer {
            wear_even_mm_per_1000km: even * MM_PER_1000KM_PER_M_PER_M,
            polygon_order_dominant: top.map_or(f64::NAN, |t| t.order as f64),
            detuning_rev: top.map_or(f64::NAN, |t| t.detuning_rev),
            growth_rate_per_1000km: top.map_or(f64::NAN, |t| t.growth_rate_per_1000km),
            distance_to_visible_km: distance_km,
            peak_share_of_visible: peak_share,
            wear_calibration_share: share,
            levelling_per_1000km: even * growth.local_per_m() * PER_1000KM_PER_PER_M,
            levelling_other_per_1000km: (1.0 - share)
                * growth.other_per_share
                * PER_1000KM_PER_PER_M,
            tread_wear_mm_per_1000km: (even + (1.0 - share) * growth.position_rate_m_per_m)
                * MM_PER_1000KM_PER_M_PER_M,
            orders,
            reason: String::new(),
        }
    }
}

/// The cruising distance until the position's whole even wear, `tread_wear_mm_per_1000km`,
/// leaves the worn-out depth \[km\] (MODEL.md#the-ageing-tread).
pub fn tread_life_km(p: &Params, tread_wear_mm_per_1000km: f64) -> f64 {
    p.usable_wear_m() * 1e3 / tread_wear_mm_per_1000km * 1000.0
}

/// ln(d_visible / 2R⁰): how many e-foldings an order grows from the seed's peak-to-valley
/// 2R⁰ to the visible depth (MODEL.md#growth-of-an-order); every answer over the tread's life
/// reads its crossing of this.
pub fn print_log_ratio(p: &Params) -> f64 {
    (p.visible_depth_mm * 1e-3 / (2.0 * (p.seed_runout_um * 1e-6))).ln()
}

/// s* = ln(d_visible / (2R⁰)) / β \[km\] for a growing order (0 if the seed is already
/// visible), +inf for one that levels out or has no seed to grow from.
pub fn distance_to_visible_km(p: &Params, growth_per_1000km: f64) -> f64 {
    if growth_per_1000km.is_nan() {
        return f64::NAN;
    }
    let seed_mm = 2.0 * p.seed_runout_um * 1e-3;
    if growth_per_1000km <= 0.0 || seed_mm <= 0.0 {
        return f64::INFINITY;
    }
    ((p.visible_depth_mm / seed_mm).ln().max(0.0) / growth_per_1000km) * 1000.0
}

#[cfg(test)]
mod bounds_tests;
