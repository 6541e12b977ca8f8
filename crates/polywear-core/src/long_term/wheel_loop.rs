//! Level A, the long-term loop (MODEL.md#the-long-term-loop): the tread ODE integrated over a
//! few revolutions at a fixed worn profile, the wear of one mean revolution scaled up to a step
//! of distance, the profile updated, and again, until a polygon is visible or the distance asked
//! is run.
//!
//! State: the depth d(θ) on M cells ([`Profile`]), the tread height h and the ODE state, which
//! each window starts from where the last one ended. A step visits the speeds of the usage
//! ([`Leg`]) in proportion to distance, one chunk per speed, the profile updated after each, so
//! that an order meets the alternation of lock and drift it meets on the road. Each chunk:
//!
//! 1. integrates N_skip + N_in revolutions with ε(t) of the profile ([`super::window`]);
//! 2. means the measured revolutions with the weights that cancel the drifting prints of an
//!    unlocked cycle exactly (`super::lock::revolution_weights`): the plain mean leaves C_N(δ)
//!    of the print, which the scaling would multiply by thousands of revolutions;
//! 3. lays that revolution's energy onto the cells, each element by its own pressure
//!    ([`DepositPlan`], one energy sample per cell), adds the wear that is not straight running,
//!    (1 − φ_s)w′_pos per element by its pressure (w′_pos the position's even-wear rate), and
//!    scales both by chunk/(2π r_B) revolutions;
//! 4. lowers h by the mean of all the wear (the tread's real height loss); the tread block is
//!    rebuilt at the worn height with the carcass in series ([`WheelModel::build_worn`]).
//!
//! The run ends where a polygon is visible, where the tread has lost its usable depth
//! ([`Params::usable_wear_m`]: the tyre is worn out before a polygon), or at the distance asked.
//!
//! The step is the smallest of Δs_max, a tenth of the time in which the fastest harmonic doubles
//! (0.1 |R|/|dR/ds| and 0.2/|β|) and 1 µm of profile change, never below Δs_min; a step after
//! which a speed's lock flag or its nearest order changed is redone at half the length, down to
//! Δs_min, so that a tongue's edge is not jumped over. The redone step starts from the state the
//! first try started from, and its windows are taken as the first try measured them, laid again
//! for the shorter distance, not integrated again (the later legs' windows saw the earlier legs'
//! wear laid for the longer step: a difference of the step's own first order). Until the run passes the distance where the
//! change was seen, a step takes at most half the way there, so that the redos close in on the
//! change as a bisection does instead of stepping over it again at the rule's length.

use super::deposit::{check_samples, other_wear_m_per_m, DepositPlan};
use super::edge::{bracketed_step_m, signature, EdgeSides, Signature};
use super::first_step::FIRST_SKIP_REVS;
pub use super::first_step::{
    first_step_tread_s, slowest_cruise_kmh, FIRST_STEP_REVS, MAX_FIRST_STEP_TREAD_S,
};
use super::lock::{is_locked, revolution_weights, rotation_number, window_revs, WINDOW_REVS};
use super::profile::{harmonics_of, Profile};
use super::step_rule::{harmonic_rates, next_step_m};
use super::wheel_wear::pick_profiles;
pub use super::wheel_wear::{
    measured_growth_per_m, profile_harmonics, HistoryPoint, RunEnd, WheelWear, LINEAR_REGIME_SEEDS,
};
use super::window::{integrate_window, EpsilonTable, WindowRequest};
use crate::model::{Variant, Wheel, WheelModel};
use crate::params::Params;
use crate::solver::IntegrationError;
use crate::wear::physics::calibration::position_rate_m_per_m;
use crate::wear::physics::feedback::Feedback;
pub use crate::wear::physics::feedback::FEEDBACK_ORDERS;
use crate::wear::physics::slip::{SlipPower, WearPower};
use crate::wear::physics::zone::WearZone;
pub use crate::wear::response::legs::{cruise_legs, cycle_legs, Leg, SPEED_NODES};
use crate::wear::WearError;

mod steps;
use steps::{step_after, step_to_take_m, LoopRecord};

/// Profile cells M of the shipped loop (1.95 mm each at r_B = 0.317 m, under a quarter of the
/// trailing zone's length).
pub(crate) const CELLS: usize = 1024;
/// A window cycles (has a rotation number) when |v| reaches this share of U = V sin α.
const CYCLING_SHARE_OF_U: f64 = 0.1;
/// The tread model is rebuilt at a speed once h has moved this much since \[m\].
const HEIGHT_REBUILD_M: f64 = 1e-5;
/// Table points of ε per revolution per feedback order.
const TABLE_POINTS_PER_ORDER: usize = 8;
/// Most steps a run may take (a guard against a step rule that stalls).
const MAX_STEPS: usize = 20_000;
/// Most integration steps one window may take.
const MAX_WINDOW_STEPS: usize = 50_000_000;

/// How the loop runs (the physics constants are parameters; these are the numerics and the
/// run's length).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct LoopSettings {
    /// Profile cells M.
    pub cells: usize,
    /// Energy samples per revolution, a whole multiple of `cells` (each laid at its interval's
    /// centre angle: fewer print their comb onto the profile, [`super::deposit::check_samples`],
    /// MODEL.md#the-long-term-loop).
    pub samples_per_rev: usize,
    /// Distance to run \[km\].
    pub distance_km: f64,
    /// Largest step Δs_max \[km\].
    pub max_step_km: f64,
    /// Smallest step Δs_min \[km\] (also the first step).
    pub min_step_km: f64,
    /// Revolutions integrated and not measured after each profile update, N_skip.
    pub skip_revs: usize,
    /// Whether the tread height falls with the wear (the tread block stiffens and lightens,
    /// MODEL.md#the-ageing-tread); the worn depth that ends the tyre's life is counted either way.
    pub update_tread_height: bool,
    /// Relative tolerance of the windows' integration.
    pub rtol: f64,
    /// Seed of the seed profile's phases.
    pub seed: u64,
    /// Where the friction power wears the tread.
    pub zone: WearZone,
    /// Which friction power wears it (the driving wheel's slip power counted or not).
    pub power: WearPower,
    /// Stop once a polygon is visible (else run the whole distance, or until the tyre is worn
    /// out).
    pub stop_at_visible: bool,
    /// Most RHS evaluations one wheel's run may take over all its windows: a backstop beside
    /// the refusal of a too slow usage before any work ([`MAX_FIRST_STEP_TREAD_S`]); a run
    /// over it fails its wheel with reason `budget exceeded`. The default is 30 times what
    /// the default point's 60,000 km take (33 million on the follower).
    pub max_rhs_evals: u64,
}

impl Default for LoopSettings {
    fn default() -> Self {
        LoopSettings {
            cells: CELLS,
            samples_per_rev: CELLS,
            distance_km: 60_000.0,
            max_step_km: 500.0,
            min_step_km: 20.0,
            skip_revs: 2,
            update_tread_height: true,
            rtol: 1e-7,
            seed: 1,
            zone: WearZone::DEFAULT,
            power: WearPower::DEFAULT,
            stop_at_visible: true,
            max_rhs_evals: 1_000_000_000,
        }
    }
}

impl LoopSettings {
    /// The default [`LoopSettings::max_rhs_evals`] of a run driven at `speed_nodes` speeds:
    /// the default's share per speed of [`SPEED_NODES`] kept, since every speed integrates its
    /// own windows over its share of the distance, so a run's cost grows with its speeds (at
    /// 40, 115 km/h, 0.60° and σ_V = 5 km/h, the follower spent 1e9 by 21,256 km of the
    /// 40,200 its tire lasts). At most [`SPEED_NODES`] speeds keep the default.
    pub fn default_max_rhs_evals_for(speed_nodes: usize) -> u64 {
        let per_default = speed_nodes.max(SPEED_NODES) as f64 / SPEED_NODES as f64;
        (LoopSettings::default().max_rhs_evals as f64 * per_default).round() as u64
    }
}

/// What the loop needs about one wheel.
#[derive(Debug, Clone, Copy)]
pub struct LoopInputs<'a> {
    /// The wheel's parameters (the speed is each leg's; the tread height is the new tyre's, and
    /// its usable depth ends the run).
    pub params: &'a Params,
    /// Which wheel.
    pub wheel: Wheel,
    /// Friction variant.
    pub variant: Variant,
    /// The run's abradability γ \[m³/J\] (for the φ_s of `params`).
    pub gamma_m3_per_j: f64,
    /// The usage.
    pub legs: &'a [Leg],
    /// The state (z, y, v) to start from: a point of the cycle the classifier found where the
    /// wheel vibrates; `None` starts at the equilibrium of the first leg.
    pub start: Option<[f64; 3]>,
}

/// The tread model of one leg at one tread height.
struct LegModel {
    height_m: f64,
    params: Params,
    model: WheelModel,
    feedback: Feedback,
    period_s: f64,
    /// The driving wheel's slip power at this leg (none for the follower).
    slip: SlipPower,
}

/// Everything that a redo restores.
#[derive(Clone)]
struct RunState {
    profile: Profile,
    height_m: f64,
    /// The mean depth worn off the tread so far \[m\] (whether or not h follows it).
    worn_m: f64,
    /// The ODE state each leg's last window ended in (`None`: not visited yet).
    x: Vec<Option<[f64; 3]>>,
    /// The state the last window ended in, whichever leg it was.
    last_x: [f64; 3],
    distance_m: f64,
    rho: Vec<f64>,
    energy_j: f64,
    straight_volume_m3: f64,
    history_len: usize,
}

/// What one leg's window measured at a step's profile, kept so that a step redone at a shorter
/// length lays it again instead of integrating the same window twice.
#[derive(Clone)]
struct Measured {
    /// The wear rate per cell \[m/m\] (straight running and the rest).
    rate_m_per_m: Vec<f64>,
    /// The mean revolution's straight-running friction energy \[J\].
    energy_per_rev_j: f64,
    /// The depth it wears summed over the cells, per revolution \[m\].
    straight_depth_per_rev_m: f64,
    /// One cell's area of the tread band \[m²\].
    cell_area_m2: f64,
    /// The distance of one revolution 2π r_B \[m\].
    rev_m: f64,
    /// The state (z, y, v) the window ended in.
    end: [f64; 3],
    rho: f64,
    locked: bool,
}

/// A step's distance-weighted wear rate per cell \[m/m\], each leg's ρ and lock flag, and what
/// each leg's window measured.
type StepRates = (Vec<f64>, Vec<f64>, Vec<bool>, Vec<Measured>);

/// One wheel's run.
struct Run<'a> {
    inputs: LoopInputs<'a>,
    settings: &'a LoopSettings,
    models: Vec<Option<LegModel>>,
    state: RunState,
    rhs_evals: u64,
}

impl<'a> Run<'a> {
    /// The model of leg `i` at the run's current tread height (rebuilt once h has moved).
    fn leg_model(&mut self, i: usize) -> Result<&LegModel, WearError> {
        let h = self.state.height_m;
        let stale = match &self.models[i] {
            Some(m) => (m.height_m - h).abs() > HEIGHT_REBUILD_M,
            None => true,
        };
        if stale {
            let speed_kmh = self.inputs.legs[i].speed_kmh;
            let new = Params {
                speed_kmh,
                ..*self.inputs.params
            };
            // The worn tread block (its carcass in series), and the feedback at the worn height.
            let params = Params {
                tread_height: h,
                ..new
            };
            let model = WheelModel::build_worn(&new, h, self.inputs.wheel, self.inputs.variant)
                .map_err(|e| self.failure(speed_kmh, e.to_string()))?;
            let feedback = Feedback::new(&params, &model, self.settings.zone);
            let period_s = 1.0 / model.ode.linear_stability().eig_freq_hz;
            let slip = SlipPower::of(&params, &model, self.settings.power);
            self.models[i] = Some(LegModel {
                height_m: h,
                params,
                model,
                feedback,
                period_s,
                slip,
            });
        }
        Ok(self.models[i].as_ref().expect("built above"))
    }

    fn over_budget(&self) -> String {
        format!(
            "budget exceeded (max_rhs_evals = {} for the loop; {} RHS evaluations spent)",
            self.settings.max_rhs_evals, self.rhs_evals
        )
    }

    fn failure(&self, speed_kmh: f64, reason: String) -> WearError {
        WearError::Loop {
            speed_kmh,
            distance_km: self.state.distance_m / 1e3,
            reason,
        }
    }

    /// Drives leg `i` for `chunk_m` metres at the current profile and lays its wear; with
    /// `measured`, lays what an earlier window at this same state measured instead of
    /// integrating again (a step redone at a shorter length).
    fn chunk(
        &mut self,
        i: usize,
        chunk_m: f64,
        measured: Option<&Measured>,
    ) -> Result<Measured, WearError> {
        let m = match measured {
            Some(m) => m.clone(),
            None => self.measure(i)?,
        };
        let revs_driven = chunk_m / m.rev_m;
        self.state.energy_j += m.energy_per_rev_j * revs_driven;
        self.state.straight_volume_m3 += m.straight_depth_per_rev_m * m.cell_area_m2 * revs_driven;
        for (d, r) in self.state.profile.depth_m.iter_mut().zip(&m.rate_m_per_m) {
            *d += r * chunk_m;
        }
        let rate = &m.rate_m_per_m;
        let worn_m = rate.iter().sum::<f64>() / rate.len() as f64 * chunk_m;
        self.state.worn_m += worn_m;
        if self.settings.update_tread_height {
            self.state.height_m -= worn_m;
        }
        self.state.x[i] = Some(m.end);
        self.state.last_x = m.end;
        self.state.rho[i] = m.rho;
        Ok(m)
    }

    /// Integrates leg `i`'s window at the current profile and state: its mean revolution laid
    /// onto the cells as a wear rate, its ρ and lock flag, and the state it ends in.
    fn measure(&mut self, i: usize) -> Result<Measured, WearError> {
        let (settings, gamma) = (self.settings, self.inputs.gamma_m3_per_j);
        let prev_rho = self.state.rho[i];
        // A leg's first visit starts where the last window ended and settles onto its own
        // cycle; later visits go on from the leg's own state, so that no window measures the
        // slow relaxation of a cycle from another speed (which is not fixed to the tyre, and
        // which the scaling would multiply).
        let start_x = self.state.x[i];
        let first = start_x.is_none();
        let radius = self.state.profile.radius_m();
        let orders = FEEDBACK_ORDERS.min(radius.len() / 2 - 1);
        let harmonics = harmonics_of(&radius, orders);
        let lm = self.leg_model(i)?;
        let (p, fb, ode, period_s, slip) =
            (lm.params, lm.feedback, lm.model.ode, lm.period_s, lm.slip);
        let width_m = lm.model.patch.width_m;
        let table = EpsilonTable::new(&fb, &harmonics, TABLE_POINTS_PER_ORDER * orders);
        // The run's work budget covers every window: the last one gets what is left of it
        // (12 RHS evaluations a DOP853 step).
        let left = settings.max_rhs_evals.saturating_sub(self.rhs_evals);
        if left == 0 {
            return Err(self.failure(p.speed_kmh, self.over_budget()));
        }
        let max_steps = MAX_WINDOW_STEPS.min((left / 12).max(1) as usize);
        let revs = if first {
            WINDOW_REVS.1
        } else {
            window_revs(prev_rho)
        };
        let window = integrate_window(&WindowRequest {
            ode: &ode,
            epsilon: &table,
            rotation_hz: WheelModel::rotation_hz(&p),
            start: start_x.unwrap_or(self.state.last_x),
            skip_revs: if first {
                FIRST_SKIP_REVS
            } else {
                settings.skip_revs
            },
            revs,
            samples_per_rev: settings.samples_per_rev,
            rtol: settings.rtol,
            period_s,
            max_steps,
        })
        .map_err(|e| match e {
            IntegrationError::TooManySteps { .. } if max_steps < MAX_WINDOW_STEPS => {
                self.failure(p.speed_kmh, self.over_budget())
            }
            e => self.failure(p.speed_kmh, e.to_string()),
        })?;
        self.rhs_evals += window.rhs_evals as u64;
        let cycling = window.peak_v_mps > CYCLING_SHARE_OF_U * ode.u_mps;
        let t_rev = 1.0 / WheelModel::rotation_hz(&p);
        let rho = if cycling {
            rotation_number(&window.crossings_s, t_rev)
        } else {
            f64::NAN
        };
        let weights = revolution_weights(window.energy_j.len(), rho);
        let samples = settings.samples_per_rev;
        let mut mean_j = vec![0.0; samples];
        for (w, rev) in weights.iter().zip(&window.energy_j) {
            for (m, e) in mean_j.iter_mut().zip(rev) {
                *m += w * e;
            }
        }
        // The driving wheel's slip power in the same zone (MODEL.md#the-driving-wheels-slip-power).
        slip.add_to_revolution(&mut mean_j, &table, t_rev);
        let plan = DepositPlan::new(
            &fb.zone,
            p.r_b,
            width_m,
            &radius,
            fb.local_per_m,
            samples,
            0.5,
        );
        let per_rev_m = plan.lay(gamma, &mean_j);
        let rev_m = std::f64::consts::TAU * p.r_b;
        let other_rate = (1.0 - p.wear_share_straight)
            * position_rate_m_per_m(&p, self.inputs.wheel, settings.power);
        let other = other_wear_m_per_m(&radius, fb.local_per_m, other_rate);
        let rate_m_per_m = per_rev_m
            .iter()
            .zip(&other)
            .map(|(d, o)| d / rev_m + o)
            .collect();
        Ok(Measured {
            rate_m_per_m,
            energy_per_rev_j: mean_j.iter().sum::<f64>(),
            straight_depth_per_rev_m: per_rev_m.iter().sum::<f64>(),
            cell_area_m2: width_m * rev_m / radius.len() as f64,
            rev_m,
            end: window.end,
            rho,
            locked: cycling && is_locked(rho),
        })
    }

    /// One step of `step_m` over every leg; returns the distance-weighted wear rate per cell,
    /// each leg's (ρ, lock flag) and what its window measured. With `measured` (a step redone
    /// from the same state) the legs lay that again and integrate nothing.
    fn step(&mut self, step_m: f64, measured: Option<&[Measured]>) -> Result<StepRates, WearError> {
        let legs = self.inputs.legs;
        let mut rate = vec![0.0; self.state.profile.cells()];
        let (mut rho, mut locked) = (Vec::new(), Vec::new());
        let mut kept = Vec::with_capacity(legs.len());
        for (i, leg) in legs.iter().enumerate() {
            let c = self.chunk(i, leg.share * step_m, measured.map(|m| &m[i]))?;
            for (r, c) in rate.iter_mut().zip(&c.rate_m_per_m) {
                *r += leg.share * c;
            }
            rho.push(c.rho);
            locked.push(c.locked);
            kept.push(c);
        }
        self.state.distance_m += step_m;
        Ok((rate, rho, locked, kept))
    }
}

impl<'a> Run<'a> {
    /// The run at distance 0: the seeded profile, the first leg's model and equilibrium (or
    /// the given start), the first history point, and the tread band's area \[m²\].
    fn start(
        inputs: &LoopInputs<'a>,
        settings: &'a LoopSettings,
        orders: usize,
    ) -> Result<(Self, HistoryPoint, f64), WearError> {
        let p = inputs.params;
        let seed_m = p.seed_runout_um * 1e-6;
        let profile = Profile::seeded(settings.cells, seed_m, settings.seed);
        let mut run = Run {
            inputs: *inputs,
            settings,
            models: (0..inputs.legs.len()).map(|_| None).collect(),
            state: RunState {
                profile,
                height_m: p.tread_height,
                worn_m: 0.0,
                x: vec![None; inputs.legs.len()],
                last_x: [0.0; 3],
                distance_m: 0.0,
                rho: vec![f64::NAN; inputs.legs.len()],
                energy_j: 0.0,
                straight_volume_m3: 0.0,
                history_len: 1,
            },
            rhs_evals: 0,
        };
        let first_model = run.leg_model(0)?;
        let band_area_m2 = first_model.model.patch.width_m * std::f64::consts::TAU * p.r_b;
        run.state.last_x = inputs
            .start
            .unwrap_or_else(|| first_model.model.ode.equilibrium());
        let (depths, _, _) = harmonic_rates(&run.state.profile, &vec![0.0; settings.cells], orders);
        let start = HistoryPoint {
            distance_km: 0.0,
            tread_height_m: p.tread_height,
            depths_m: depths,
            depth_rate_m_per_m: vec![0.0; orders],
            growth_per_m: vec![0.0; orders],
            rho: vec![f64::NAN; inputs.legs.len()],
            locked: vec![false; inputs.legs.len()],
        };
        Ok((run, start, band_area_m2))
    }
}

/// Each leg's wear rate per cell \[m/m\] of a step's windows.
fn rates_of(measured: &[Measured]) -> Vec<&[f64]> {
    measured.iter().map(|m| &m.rate_m_per_m[..]).collect()
}

/// The history point of a step accepted from `before` to `after` under the wear rate
/// `rate_m_per_m` per cell: the depths at its end, and the rates at its start.
fn history_point(
    before: &RunState,
    after: &RunState,
    rate_m_per_m: &[f64],
    orders: usize,
    rho: Vec<f64>,
    locked: Vec<bool>,
) -> HistoryPoint {
    let (_, d_rate, beta) = harmonic_rates(&before.profile, rate_m_per_m, orders);
    HistoryPoint {
        distance_km: after.distance_m / 1e3,
        tread_height_m: after.height_m,
        depths_m: after.profile.depths_m(orders),
        depth_rate_m_per_m: d_rate,
        growth_per_m: beta,
        rho,
        locked,
    }
}

/// Runs the long-term loop for one wheel. `progress` is told each accepted step's distance
/// \[km\] (from any thread).
pub fn run_wheel(
    inputs: &LoopInputs<'_>,
    settings: &LoopSettings,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<WheelWear, WearError> {
    let p = inputs.params;
    check_samples(settings.samples_per_rev, settings.cells).map_err(|e| WearError::Loop {
        speed_kmh: inputs.legs.first().map_or(p.speed_kmh, |l| l.speed_kmh),
        distance_km: 0.0,
        reason: e.to_string(),
    })?;
    let seed_m = p.seed_runout_um * 1e-6;
    let orders = FEEDBACK_ORDERS.min(settings.cells / 2 - 1);
    let (mut run, start, band_area_m2) = Run::start(inputs, settings, orders)?;
    let mut record = LoopRecord::new(start, &run.state);
    let total_m = settings.distance_km * 1e3;
    let min_step_m = settings.min_step_km * 1e3;
    let mut step_m = min_step_m;
    // The state before the last accepted step, its length, the signature it was taken at and
    // what its windows measured.
    let mut last: Option<(RunState, f64, Signature, Vec<Measured>)> = None;
    // A redo's windows, measured at the very state it restarts from.
    let mut remeasured: Option<Vec<Measured>> = None;
    // The distance at which a window last saw the signature change, ahead of the run, and the
    // resolution that change needs.
    let mut edge: Option<(f64, f64)> = None;
    let shares: Vec<f64> = inputs.legs.iter().map(|l| l.share).collect();
    let usable_m = p.usable_wear_m();
    // The mean wear rate of the last accepted step \[m/m\].
    let mut wear_rate_m_per_m = 0.0f64;
    while run.state.distance_m < total_m * (1.0 - 1e-12) && record.steps < MAX_STEPS {
        let this_m = step_to_take_m(
            step_m,
            &run.state,
            total_m,
            usable_m,
            wear_rate_m_per_m,
            &mut edge,
        );
        let before = run.state.clone();
        let (rate, rho, locked, measured) = run.step(this_m, remeasured.take().as_deref())?;
        let sig = signature(&rho, &locked);
        if let Some((prev_state, prev_m, prev_sig, prev_measured)) = last.take() {
            let half = 0.5 * prev_m;
            let resolution_m = if prev_sig == sig {
                f64::INFINITY
            } else {
                let sides = EdgeSides {
                    shares: &shares,
                    signatures: [&prev_sig, &sig],
                    rates_m_per_m: [rates_of(&prev_measured), rates_of(&measured)],
                    profile: &before.profile,
                    seed_depth_m: 2.0 * seed_m,
                };
                sides.resolution_m(min_step_m)
            };
            if half >= resolution_m * (1.0 - 1e-12) {
                // The previous step changed a lock flag or an order, and the change is not yet
                // placed as finely as its print needs: redo it at half length, laying again
                // what its windows measured at the same state.
                edge = Some((before.distance_m, resolution_m));
                run.state = prev_state;
                record.history.truncate(run.state.history_len);
                record
                    .profiles
                    .retain(|(km, _)| *km <= run.state.distance_m / 1e3);
                step_m = half;
                remeasured = Some(prev_measured);
                record.redone += 1;
                continue;
            }
        }
        let point = history_point(&before, &run.state, &rate, orders, rho, locked);
        (step_m, wear_rate_m_per_m) = step_after(&point, &rate, settings);
        record.accept(point, &before, &mut run.state, this_m, p);
        progress(this_m / 1e3);
        last = Some((before, this_m, sig, measured));
        if (record.visible.is_some() && settings.stop_at_visible) || record.worn_out_km.is_some() {
            break;
        }
    }
    let distance_m = run.state.distance_m;
    Ok(WheelWear {
        wheel: inputs.wheel,
        legs: inputs.legs.to_vec(),
        profiles: pick_profiles(record.profiles, 5),
        visible: record.visible,
        worn_out_km: record.worn_out_km,
        energy_j: run.state.energy_j,
        straight_volume_m3: run.state.straight_volume_m3,
        band_area_m2,
        even_wear_m_per_m: run.state.straight_volume_m3 / (band_area_m2 * distance_m.max(1e-300)),
        seed_m,
        rhs_evals: run.rhs_evals,
        steps: record.steps,
        redone: record.redone,
        end_states: run.state.x.clone(),
        history: record.history,
    })
}
