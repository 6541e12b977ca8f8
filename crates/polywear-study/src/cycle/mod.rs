//! Drive cycles: a speed trace (`time_s`, `speed_kmh`, optionally any parameter per step) whose
//! every step is classified for both wheels as if the operating point were held (quasi-static:
//! MODEL.md#step-1-deflection to #step-9-attractor at each step's parameters). Standstill
//! (0 km/h) is a step of its own: no sliding, no tread dynamics, not vibrating.
//!
//! Quasi-static validity. The tread answers a change of operating point within its time
//! constant τ = 1/|Re λ| (λ the leading eigenvalue at the equilibrium,
//! MODEL.md#step-8-linear-stability). The speed's change moves Re λ; the time it takes to move
//! Re λ by its own size is
//! T = |Re λ| / |d(Re λ)/dt|. The quasi-static verdict holds at a step when τ ≤ T, i.e. when
//! |d(Re λ)/dt| ≤ (Re λ)²: the tread settles before its stability has changed appreciably. It
//! fails near every crossing of a Hopf boundary (Re λ → 0), where the tread lags the speed (a
//! delayed bifurcation). d(Re λ)/dt is the central difference over the neighbouring steps
//! (one-sided at the ends and next to steps without a tread ODE); steps without a tread ODE
//! (standstill, no traction, failed) are not assessed and count as holding.

mod input;
pub mod request;
pub mod structures;
pub mod summary;
pub mod wear;

use std::path::PathBuf;

use crate::table_input::{NumericTable, TableError};
use polywear_core::classify::{Class, ClassifierOptions};
use polywear_core::ensemble::{self, Control};
use polywear_core::evaluate::{self, PointProblem, WearStage};
use polywear_core::model::Variant;
use polywear_core::params::{ParamError, ParamId, Params};
use polywear_core::records::WheelRecord;
use polywear_core::wording::{plain, thousands};

/// Why a drive cycle is refused (before any work, naming the file, row and column) or its
/// outputs are not written.
#[derive(Debug, thiserror::Error)]
pub enum CycleError {
    /// The file cannot be read as a table of numbers.
    #[error(transparent)]
    Table(#[from] TableError),
    /// `time_s` or `speed_kmh` is missing.
    #[error("{}: no column `{name}` (columns: {}); a cycle needs `time_s` and `speed_kmh`", path.display(), columns.join(", "))]
    MissingColumn {
        /// The cycle file.
        path: PathBuf,
        /// The missing column.
        name: &'static str,
        /// The columns it has.
        columns: Vec<String>,
    },
    /// A column that is no parameter.
    #[error("{}: column `{name}` (column {number}) is neither `time_s` nor a parameter of `polywear params`{}", path.display(), did_you_mean(name))]
    UnknownColumn {
        /// The cycle file.
        path: PathBuf,
        /// The column's name.
        name: String,
        /// Its position, counted from 1.
        number: usize,
    },
    /// The toe-in per step given another way than the angle.
    #[error("{}: column `{name}` (column {number}): a cycle gives the toe-in per step as `toe_deg`, the per-wheel angle (toe_deg = atan(toe_mm / rim_diameter_mm), or toe_total_deg / 2); for the whole cycle, `--set {name}=...` reads it as typed", path.display())]
    ToeColumn {
        /// The cycle file.
        path: PathBuf,
        /// The column's name.
        name: String,
        /// Its position, counted from 1.
        number: usize,
    },
    /// A shared column beside an axle's own column of the same quantity (`toe_deg` and
    /// `toe_rear_deg`).
    #[error("{}: {source}", path.display())]
    AxleColumns {
        /// The cycle file.
        path: PathBuf,
        /// Which keys.
        source: ParamError,
    },
    /// A single row: no step duration.
    #[error("{}: one step only; a cycle needs at least two (the time between steps sets their durations)", path.display())]
    OneStep {
        /// The cycle file.
        path: PathBuf,
    },
    /// A time not after the previous row's.
    #[error("{at}: time_s = {} does not follow the previous row's {} (times must increase)", plain(*time_s, 12), plain(*previous_s, 12))]
    TimeNotIncreasing {
        /// File, row and column.
        at: String,
        /// The row's time \[s\].
        time_s: f64,
        /// The previous row's time \[s\].
        previous_s: f64,
    },
    /// A negative speed.
    #[error("{at}: speed_kmh = {} is negative; accepted 0 (standstill) or {range}", plain(*speed_kmh, 12))]
    NegativeSpeed {
        /// File, row and column.
        at: String,
        /// The speed given \[km/h\].
        speed_kmh: f64,
        /// The speed's accepted range.
        range: String,
    },
    /// Times so far apart that a step's duration, the cycle's length or its distance is not a
    /// finite number.
    #[error("{}: the cycle's {what} is not finite (times and their differences must stay below about 1e300 s; {})", path.display(), plain(*value, 6))]
    NotFiniteSum {
        /// The cycle file.
        path: PathBuf,
        /// Which sum: a step's duration, the total time or the distance.
        what: &'static str,
        /// Its value (inf).
        value: f64,
    },
    /// More steps × tire structures than `STEP_EVALUATIONS_MAX`.
    #[error("{}: {} steps x {} tire structure(s) = {} step evaluations; accepted at most {} (every step's records stay in memory until the files are written: about 3 KB a step, 7 KB with the wear stage): draw fewer --structure-samples, or resample the cycle to fewer steps", path.display(), thousands(*steps as f64), thousands(*structures as f64), thousands(*steps as f64 * *structures as f64), thousands(STEP_EVALUATIONS_MAX as f64))]
    TooMuchWork {
        /// The cycle file.
        path: PathBuf,
        /// Its steps.
        steps: u64,
        /// The tire structures asked for.
        structures: u64,
    },
    /// A constant of the tire's life that changes from step to step.
    #[error("{at}: `{name}` = {} differs from the first step's {}: it is a constant of the tire's whole life (the lifetime verdict reads it once), so a cycle gives it one value: a column constant over the cycle, or `--set {name}=...`", plain(*value, 12), plain(*first, 12))]
    VaryingLifeConstant {
        /// File, row and column.
        at: String,
        /// The parameter.
        name: &'static str,
        /// The first step's value.
        first: f64,
        /// This step's.
        value: f64,
    },
    /// A parameter a drive cycle does not use.
    #[error("{}: column `{name}`: {why}; leave it out", path.display())]
    UnusedColumn {
        /// The cycle file.
        path: PathBuf,
        /// The column.
        name: &'static str,
        /// Why the cycle does not use it.
        why: &'static str,
    },
    /// A value outside its parameter's range, or a step whose parameters do not fit together.
    #[error("{at}: {source}")]
    Param {
        /// File and row (and column for one cell).
        at: String,
        /// The parameter's refusal.
        source: ParamError,
    },
}

/// "; did you mean `speed_kmh`?" for a misspelt parameter name, or nothing.
fn did_you_mean(name: &str) -> String {
    polywear_core::params::suggest_name(name)
        .map(|n| format!("; did you mean `{n}`?"))
        .unwrap_or_default()
}

/// Consecutive steps classified in order by one worker, each starting its shooting from the
/// previous step's cycle (the neighbouring step's cycle is close: the speed changes little in
/// one step). Blocks are fixed, so the rows do not depend on the number of threads.
pub(crate) const BLOCK_STEPS: usize = 32;

/// Blocks classified at once before their profiles over the tread's life are summed into their
/// structures' (in block order, so the sums do not depend on the number of threads): each block
/// holds two profiles of [`wear::CYCLE_ORDERS_MAX`] × (LIFE_PROFILE_INTERVALS + 1) numbers
/// (66 KB each), so a batch holds about 8 MB whatever the cycle's length.
const BATCH_BLOCKS: usize = 64;

/// Most step evaluations (steps × tire structures) one run accepts. Every step's two records stay
/// in memory until the files are written (2.9 GB measured at a million steps; with the wear
/// stage, its growth of each order and the calibration band's, 1.32 GB at 200,000 steps), so a larger run is refused before any work instead
/// of exhausting the memory hours in. A million steps is 11.6 days of driving logged at 1 Hz.
pub(crate) const STEP_EVALUATIONS_MAX: u64 = 1_000_000;

/// The parameters a cycle's lifetime verdict reads once for the tire's whole life
/// (MODEL.md#along-a-drive-cycle): the steps share one tread, so its depths, its seed, what
/// counts as visible and the fitted constants that share its even wear cannot change from step
/// to step. A column of one of them must hold one value, which the whole life then takes.
pub(crate) const LIFE_CONSTANTS: [ParamId; 9] = [
    ParamId::WearShareStraight,
    ParamId::WearRateDrivenFactor,
    ParamId::WearRateRef,
    ParamId::SeedRunoutUm,
    ParamId::VisibleDepthMm,
    ParamId::LimitDepthMm,
    ParamId::TreadDepthNewMm,
    ParamId::TreadDepthWornOutMm,
    ParamId::CarcassShare,
];

/// Why a drive cycle does not use `speed_spread_kmh`: its speeds are its spread.
pub const NO_SPREAD: &str = "a drive cycle does not use the speed spread: its steps' speeds are its spread (MODEL.md#along-a-drive-cycle)";

/// A checked drive cycle.
#[derive(Debug, Clone)]
pub struct DriveCycle {
    /// The file the cycle was read from.
    pub path: PathBuf,
    /// FNV-1a 64 of the file's bytes (recorded in the outputs' metadata).
    pub hash: String,
    /// Time of each step \[s\], strictly increasing.
    pub time_s: Vec<f64>,
    /// Vehicle speed at each step \[km/h\].
    pub speed_kmh: Vec<f64>,
    /// Parameters given per step (other than the speed), in file order.
    pub names: Vec<ParamId>,
    /// `values[i][j]`: step i's value of `names[j]`.
    pub values: Vec<Vec<f64>>,
    table: NumericTable,
}

impl DriveCycle {
    /// Refuses a run over `structures` tire structures whose step evaluations exceed
    /// `STEP_EVALUATIONS_MAX`, before any work.
    pub fn check_work(&self, structures: u64) -> Result<(), CycleError> {
        let steps = self.len() as u64;
        if steps.saturating_mul(structures) > STEP_EVALUATIONS_MAX {
            return Err(CycleError::TooMuchWork {
                path: self.path.clone(),
                steps,
                structures,
            });
        }
        Ok(())
    }

    /// Number of time steps.
    pub fn len(&self) -> usize {
        self.time_s.len()
    }

    /// Whether the cycle has no step.
    pub fn is_empty(&self) -> bool {
        self.time_s.is_empty()
    }

    /// Whether step `i` is standstill (speed 0).
    pub fn standstill(&self, i: usize) -> bool {
        self.speed_kmh[i] == 0.0
    }

    /// The cycle as the long-term loop's legs (MODEL.md#the-long-term-loop): `nodes` speeds,
    /// each an equal share of the distance at the distance-weighted quantiles; with the
    /// cycle's length \[km\]. No legs where every step stands still.
    pub fn wear_legs(&self, nodes: usize) -> (Vec<polywear_core::long_term::wheel_loop::Leg>, f64) {
        let distances_m: Vec<f64> = self
            .step_durations_s()
            .iter()
            .zip(&self.speed_kmh)
            .map(|(dt, v)| dt * v / 3.6)
            .collect();
        let legs =
            polywear_core::long_term::wheel_loop::cycle_legs(&self.speed_kmh, &distances_m, nodes);
        (legs, distances_m.iter().sum::<f64>() / 1e3)
    }

    /// The distance covered at each step \[km\]: its speed held for its duration.
    pub fn step_km(&self) -> Vec<f64> {
        self.step_durations_s()
            .iter()
            .zip(&self.speed_kmh)
            .map(|(dt, v)| v * dt / 3600.0)
            .collect()
    }

    /// How long each step holds \[s\]: until the next step; the last step as long as the one
    /// before it (a logger's sample holds until the next). With steps of equal length every
    /// step weighs the same, and the time shares are shares of steps.
    pub fn step_durations_s(&self) -> Vec<f64> {
        let t = &self.time_s;
        let n = t.len();
        (0..n)
            .map(|i| {
                if i + 1 < n {
                    t[i + 1] - t[i]
                } else {
                    t[n - 1] - t[n - 2]
                }
            })
            .collect()
    }

    /// The parameter set of step `i` on top of `base`: the step's columns, then its speed (a
    /// standstill step keeps `base`'s speed; it is never classified).
    pub fn step_params(&self, base: &Params, i: usize) -> Params {
        let mut p = *base;
        for (&id, v) in self.names.iter().zip(&self.values[i]) {
            p[id] = *v;
        }
        if !self.standstill(i) {
            p.speed_kmh = self.speed_kmh[i];
        }
        p
    }

    /// `base` with the cycle's columns of `LIFE_CONSTANTS` (each one value over the cycle):
    /// the parameters of the tire's whole life, which its lifetime verdict reads (the seed, the
    /// visible depth, the usable tread, the fitted constants), as every step reads them.
    pub fn whole_life(&self, base: &Params) -> Params {
        let mut p = *base;
        for (k, &id) in self.names.iter().enumerate() {
            if LIFE_CONSTANTS.contains(&id) {
                p[id] = self.values[0][k];
            }
        }
        p
    }
}

/// One wheel at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepWheel {
    /// The wheel's record, with the explorer's columns.
    pub record: WheelRecord,
    /// τ = 1/|Re λ| \[s\] (NaN without a tread ODE).
    pub tread_time_constant_s: f64,
    /// T = |Re λ| / |d(Re λ)/dt| \[s\] (infinite where Re λ does not change; NaN without an ODE).
    pub stability_change_time_s: f64,
    /// τ ≤ T (true where not assessed).
    pub quasi_static: bool,
}

impl StepWheel {
    /// The vehicle stands still at this step (speed 0, class `standstill`): not vibrating, not
    /// classified.
    pub fn standstill(&self) -> bool {
        self.record.class == Class::Standstill
    }

    /// In self-excited vibration at this step (a limit cycle or bistable, never at standstill).
    pub fn vibrates(&self) -> bool {
        self.record.class.vibrates()
    }
}

/// One tire structure's cycle, classified: both wheels at every step (follower then driving
/// per step; `[step][wheel]`) and, where the wear stage answers over the tread's life, each
/// wheel's profiles summed over the steps by distance.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassifiedCycle {
    /// Both wheels at every step.
    pub steps: Vec<[StepWheel; 2]>,
    /// Per wheel, the steps' profiles over the tread's life ([`wear::CycleLife`]); None
    /// without the wear stage.
    pub life: [Option<wear::CycleLife>; 2],
}

/// Classifies both wheels at every step of `cycle` on top of `base`. See [`classify_cycles`].
pub fn classify_cycle(
    cycle: &DriveCycle,
    base: &Params,
    variant: Variant,
    opts: &ClassifierOptions,
    wear: Option<&WearStage>,
) -> ClassifiedCycle {
    classify_cycles(
        cycle,
        std::slice::from_ref(base),
        variant,
        opts,
        wear,
        &|_| {},
    )
    .pop()
    .expect("one base")
}

/// [`classify_cycle`] for each of several parameter bases (tire structures), in their order.
/// Blocks of `BLOCK_STEPS` steps of every base run in parallel on the current rayon pool,
/// 64 blocks at a time; within a block each wheel starts from its own cycle at the
/// previous step, and a step with the same parameters as the previous one takes its verdict.
/// With `wear`, every step also runs the wear stage (its columns in the records, each order's
/// growth and, over the tread's life, its profile for [`wear::CycleLife`]). `progress` hears
/// the steps of each block as it finishes (from the
/// worker threads).
pub fn classify_cycles(
    cycle: &DriveCycle,
    bases: &[Params],
    variant: Variant,
    opts: &ClassifierOptions,
    wear: Option<&WearStage>,
    progress: &(dyn Fn(u64) + Sync),
) -> Vec<ClassifiedCycle> {
    let n = cycle.len();
    let per_base = n.div_ceil(BLOCK_STEPS);
    let jobs: Vec<(usize, usize)> = (0..bases.len())
        .flat_map(|k| (0..per_base).map(move |b| (k, b)))
        .collect();
    let km = cycle.step_km();
    let with_wear = wear.is_some();
    let mut rows: Vec<Vec<[StepRow; 2]>> = bases.iter().map(|_| Vec::with_capacity(n)).collect();
    let mut life: Vec<[wear::CycleLife; 2]> = bases
        .iter()
        .map(|_| [wear::CycleLife::default(), wear::CycleLife::default()])
        .collect();
    for batch in jobs.chunks(BATCH_BLOCKS) {
        let block = |j: usize| {
            let (k, b) = batch[j];
            let block = classify_block(cycle, &km, &bases[k], variant, opts, wear, b);
            progress(block.0.len() as u64);
            block
        };
        let done = ensemble::solve(batch.len(), block, &Control::QUIET).all();
        for (&(k, _), (block_rows, block_life)) in batch.iter().zip(done) {
            rows[k].extend(block_rows);
            for w in 0..2 {
                life[k][w].merge(&block_life[w]);
            }
        }
    }
    rows.into_iter()
        .zip(life)
        .map(|(records, life)| {
            let mut steps: Vec<[StepWheel; 2]> = records
                .into_iter()
                .map(|pair| {
                    pair.map(|(record, _)| StepWheel {
                        record,
                        tread_time_constant_s: f64::NAN,
                        stability_change_time_s: f64::NAN,
                        quasi_static: true,
                    })
                })
                .collect();
            for w in 0..2 {
                assess_quasi_static(&cycle.time_s, &mut steps, w);
            }
            ClassifiedCycle {
                steps,
                life: life.map(|l| with_wear.then_some(l)),
            }
        })
        .collect()
}

/// The records of block `b`, in step order, and each wheel's profiles over the tread's life
/// summed over the block's steps by their distance `km`. Each step is one point of the one road
/// ([`polywear_core::evaluate::solve`]); each wheel starts its shooting from its own cycle at the
/// previous step (the driving wheel without one from the follower's at this step).
fn classify_block(
    cycle: &DriveCycle,
    km: &[f64],
    base: &Params,
    variant: Variant,
    opts: &ClassifierOptions,
    wear: Option<&WearStage>,
    b: usize,
) -> (Vec<[StepRow; 2]>, [wear::CycleLife; 2]) {
    let lo = b * BLOCK_STEPS;
    let hi = (lo + BLOCK_STEPS).min(cycle.len());
    let mut out: Vec<[StepRow; 2]> = Vec::with_capacity(hi - lo);
    let mut life: [wear::CycleLife; 2] = [wear::CycleLife::default(), wear::CycleLife::default()];
    // The previous step's profiles, for a repeated step: the rows do not keep them (66 KB a
    // wheel; the block's sums are what the cycle reads).
    let mut last_life: [Option<polywear_core::wear::LifeProfile>; 2] = [None, None];
    let mut hints = vec![None, None];
    let mut previous: Option<Params> = None;
    for (i, &step_km) in km.iter().enumerate().take(hi).skip(lo) {
        let mut p = cycle.step_params(base, i);
        if cycle.standstill(i) {
            p.speed_kmh = 0.0;
            previous = None;
        } else if previous == Some(p) {
            let same = out.last().expect("a previous step").clone();
            for (w, last) in last_life.iter().enumerate() {
                life[w].add_step(last.as_ref(), step_km, p.speed_kmh);
            }
            out.push(same);
            continue;
        } else {
            previous = Some(p);
        }
        let problem = PointProblem::new(p, std::slice::from_ref(&variant), opts)
            .with_wear(wear)
            .with_previous(&hints);
        let solution = evaluate::solve(&problem);
        if !cycle.standstill(i) {
            hints = solution.hints();
        }
        let growth = |w: &evaluate::WheelSolution| match wear {
            Some(stage) if !cycle.standstill(i) => wear::step_life(&p, w, stage, opts),
            _ => None,
        };
        let [mut f, mut d]: [StepRow; 2] = solution
            .wheels
            .into_iter()
            .map(|w| {
                let g = growth(&w);
                (w.record, g)
            })
            .collect::<Vec<_>>()
            .try_into()
            .expect("two wheels");
        last_life = [f.1.take(), d.1.take()];
        for (w, last) in last_life.iter().enumerate() {
            life[w].add_step(last.as_ref(), step_km, p.speed_kmh);
        }
        out.push([f, d]);
    }
    (out, life)
}

/// One wheel's row at one step and its profile over the tread's life ([`wear::step_life`]).
type StepRow = (WheelRecord, Option<polywear_core::wear::LifeProfile>);

/// Fills τ, T and the quasi-static flag of wheel `w` at every step (see the module docs).
fn assess_quasi_static(time_s: &[f64], steps: &mut [[StepWheel; 2]], w: usize) {
    let re: Vec<Option<f64>> = steps
        .iter()
        .map(|s| {
            let x = s[w].record.eig_re_max;
            (!s[w].standstill() && x.is_finite()).then_some(x)
        })
        .collect();
    let n = re.len();
    for i in 0..n {
        let Some(r) = re[i] else { continue };
        let before = (i > 0)
            .then(|| re[i - 1])
            .flatten()
            .map(|x| (x, time_s[i - 1]));
        let after = (i + 1 < n)
            .then(|| re[i + 1])
            .flatten()
            .map(|x| (x, time_s[i + 1]));
        let rate = match (before, after) {
            (Some((a, ta)), Some((b, tb))) => (b - a) / (tb - ta),
            (Some((a, ta)), None) => (r - a) / (time_s[i] - ta),
            (None, Some((b, tb))) => (b - r) / (tb - time_s[i]),
            (None, None) => 0.0,
        };
        let s = &mut steps[i][w];
        s.tread_time_constant_s = 1.0 / r.abs();
        s.stability_change_time_s = if rate == 0.0 {
            f64::INFINITY
        } else {
            r.abs() / rate.abs()
        };
        s.quasi_static = s.tread_time_constant_s <= s.stability_change_time_s;
    }
}

#[cfg(test)]
mod tests;
