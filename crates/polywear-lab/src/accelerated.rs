//! The accelerated-wear oracle (MODEL.md#the-accelerated-oracle): the same physics as the
//! long-term loop by another road, with nothing averaged and nothing scaled. The abradability
//! is multiplied by A, the tread ODE runs on continuously, and the profile is updated after
//! every single revolution by what that revolution wore (A times the real wear of one
//! revolution). Over N revolutions the profile then travels as the real one does over A·N
//! revolutions, as long as a revolution's print stays small against the profile (A·D₁ ≪ R),
//! so its growth divided by A is the growth per distance the loop and the estimator predict.
//!
//! It shares the loop's building blocks (the window's integration, the deposit, the seed)
//! and none of its decisions: no revolution weights, no step rule, no redo, no scaling.

use polywear_core::long_term::deposit::{check_samples, other_wear_m_per_m, DepositPlan};
use polywear_core::long_term::profile::{harmonics_of, Profile};
use polywear_core::long_term::window::{integrate_window, EpsilonTable, WindowRequest};
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::numeric::Complex64;
use polywear_core::params::Params;
use polywear_core::wear::physics::calibration::position_rate_m_per_m;
use polywear_core::wear::physics::feedback::Feedback;
use polywear_core::wear::physics::slip::SlipPower;
use polywear_core::wear::physics::slip::WearPower;
use polywear_core::wear::physics::zone::WearZone;
use polywear_core::wear::WearError;

/// How the oracle runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OracleSettings {
    /// The acceleration A of the wear.
    pub acceleration: f64,
    /// Revolutions integrated before the first wear is laid (onto the cycle).
    pub warmup_revs: usize,
    /// Revolutions with wear.
    pub revs: usize,
    /// Profile cells.
    pub cells: usize,
    /// Energy samples per revolution, a whole multiple of `cells`
    /// ([`polywear_core::long_term::deposit::check_samples`]).
    pub samples_per_rev: usize,
    /// Orders that act back through ε and are recorded, 1 ..= this.
    pub orders: usize,
    /// Relative tolerance of the integration.
    pub rtol: f64,
    /// Seed of the seed profile's phases.
    pub seed: u64,
    /// Where the friction power wears the tread.
    pub zone: WearZone,
    /// Which friction power wears it (the driving wheel's slip power counted or not).
    pub power: WearPower,
}

impl Default for OracleSettings {
    fn default() -> Self {
        OracleSettings {
            acceleration: 1e3,
            warmup_revs: 10,
            revs: 1000,
            cells: 1024,
            samples_per_rev: 1024,
            orders: 128,
            rtol: 1e-7,
            seed: 1,
            zone: WearZone::DEFAULT,
            power: WearPower::DEFAULT,
        }
    }
}

/// What the oracle measured.
#[derive(Debug, Clone, PartialEq)]
pub struct OracleRun {
    /// The harmonics R_n \[m\] of orders 1 ..= `orders` after each revolution with wear (the
    /// first row is the seed).
    pub harmonics: Vec<Vec<Complex64>>,
    /// The distance one revolution stands for, A·2π r_B \[m\].
    pub metres_per_rev: f64,
    /// The depth profile at the end \[m\].
    pub profile: Profile,
}

impl OracleRun {
    /// β_n \[1/m of real distance\] between revolutions `from` and `to`:
    /// ln(D_n(to)/D_n(from)) / ((to − from)·A·2π r_B).
    pub fn growth_per_m(&self, order: u32, from: usize, to: usize) -> f64 {
        let n = order as usize - 1;
        (self.harmonics[to][n].norm() / self.harmonics[from][n].norm()).ln()
            / ((to - from) as f64 * self.metres_per_rev)
    }
}

/// Runs the oracle for `wheel` at `p` (its speed and tread height held) with abradability
/// `gamma_m3_per_j` (before the acceleration), from `start` (z, y, v) or the equilibrium.
pub fn run_oracle(
    p: &Params,
    wheel: Wheel,
    variant: Variant,
    gamma_m3_per_j: f64,
    start: Option<[f64; 3]>,
    s: &OracleSettings,
) -> Result<OracleRun, WearError> {
    let fail = |reason: String| WearError::Loop {
        speed_kmh: p.speed_kmh,
        distance_km: 0.0,
        reason,
    };
    check_samples(s.samples_per_rev, s.cells).map_err(|e| fail(e.to_string()))?;
    let model = WheelModel::build(p, wheel, variant).map_err(|e| fail(e.to_string()))?;
    let fb = Feedback::new(p, &model, s.zone);
    let rotation_hz = WheelModel::rotation_hz(p);
    let period_s = 1.0 / model.ode.linear_stability().eig_freq_hz;
    let rev_m = std::f64::consts::TAU * p.r_b;
    let other_m_per_rev = (1.0 - p.wear_share_straight)
        * position_rate_m_per_m(p, wheel, s.power)
        * rev_m
        * s.acceleration;
    let slip = SlipPower::of(p, &model, s.power);
    let mut profile = Profile::seeded(s.cells, p.seed_runout_um * 1e-6, s.seed);
    let mut x = start.unwrap_or_else(|| model.ode.equilibrium());
    let depths = |pr: &Profile| pr.harmonics(s.orders);
    let mut rows = vec![depths(&profile)];
    for rev in 0..s.warmup_revs + s.revs {
        let radius = profile.radius_m();
        let table = EpsilonTable::new(&fb, &harmonics_of(&radius, s.orders), 8 * s.orders);
        let w = integrate_window(&WindowRequest {
            ode: &model.ode,
            epsilon: &table,
            rotation_hz,
            start: x,
            skip_revs: 0,
            revs: 1,
            samples_per_rev: s.samples_per_rev,
            rtol: s.rtol,
            period_s,
            max_steps: 10_000_000,
        })
        .map_err(|e| fail(e.to_string()))?;
        x = w.end;
        if rev < s.warmup_revs {
            continue;
        }
        let plan = DepositPlan::new(
            &fb.zone,
            p.r_b,
            model.patch.width_m,
            &radius,
            fb.local_per_m,
            s.samples_per_rev,
            0.5,
        );
        // The driving wheel's slip power, as the loop lays it.
        let mut energy = w.energy_j[0].clone();
        slip.add_to_revolution(&mut energy, &table, 1.0 / rotation_hz);
        let worn = plan.lay(gamma_m3_per_j * s.acceleration, &energy);
        let other = other_wear_m_per_m(&radius, fb.local_per_m, other_m_per_rev);
        for ((d, a), b) in profile.depth_m.iter_mut().zip(&worn).zip(&other) {
            *d += a + b;
        }
        rows.push(depths(&profile));
    }
    Ok(OracleRun {
        harmonics: rows,
        metres_per_rev: rev_m * s.acceleration,
        profile,
    })
}
