//! A long-term run as an engineer asks for it (MODEL.md#the-long-term-loop), beside
//! [`crate::explore::ExploreRequest`]: `LongTermRequest` → [`LongTermRequest::plan`] →
//! [`LongTermPlan`] → [`LongTermPlan::solve`] → [`LongTermRun`]. The request names the point,
//! the usage (a cruise or a drive cycle's file), the distance, the loop's settings and the
//! calibration band; the plan is every input checked before any work (the band's every set
//! included: a set's wider spread can drive a leg the point's own does not) with the metadata
//! every output file records; the run is the loop on both wheels and under the band's chosen
//! sets. The command line keeps only its flags' names, which it puts on the errors.

use std::path::{Path, PathBuf};

use polywear_core::classify::ClassifierOptions;
use polywear_core::long_term::wheel_loop::{cruise_legs, Leg, LoopSettings};
use polywear_core::long_term::{self, LongTermError, LongTermProblem, LongTermSolution};
use polywear_core::model::Variant;
use polywear_core::params::Params;
use polywear_core::wear::WearSettings;
use polywear_core::wording::plain;

use crate::calibration_band::long_term::{self as band_loop, LoopSets, SetRun};
use crate::calibration_band::CalibrationBand;
use crate::cycle::{CycleError, DriveCycle};
use crate::provenance::run_metadata;

/// The speed nodes from which the loop's distance on a widely spread cycle has settled
/// (MODEL.md#along-a-drive-cycle: WLTC within 3% and 7% of 64 nodes on 40).
pub(crate) const SETTLED_CYCLE_NODES: usize = 40;

/// A long-term run as asked for: the checked values, not yet checked together.
#[derive(Debug, Clone)]
pub struct LongTermRequest {
    /// The point, its speed spread and fitted constants included.
    pub params: Params,
    /// The model variant.
    pub variant: Variant,
    /// A drive cycle (CSV or Parquet) driven again and again instead of cruising.
    pub cycle: Option<PathBuf>,
    /// Whether a cycle's implausible values are accepted.
    pub accept_implausible: bool,
    /// Speeds driven, equal shares of the distance.
    pub speed_nodes: usize,
    /// Distance to run \[km\].
    pub distance_km: f64,
    /// Seed of the new tyre's run-out phases.
    pub seed: u64,
    /// Where and which friction power wears the tread.
    pub reading: WearSettings,
    /// Most RHS evaluations of one wheel's loop.
    pub max_rhs_evals: u64,
    /// The calibrated sets and where they come from (none: off).
    pub band: Option<(CalibrationBand, String)>,
    /// Which of them the loop runs under.
    pub band_sets: LoopSets,
    /// The classifier's options (its budget).
    pub classifier: ClassifierOptions,
}

/// What a request cannot be run as.
#[derive(Debug, thiserror::Error)]
pub enum LongTermRequestError {
    /// The point, distance or legs are refused by the loop.
    #[error("{0}")]
    Problem(#[from] LongTermError),
    /// The cycle file cannot be read or is refused.
    #[error("{0}")]
    Cycle(#[from] CycleError),
    /// The cycle covers no distance.
    #[error("{path}: covers no distance (every step at standstill)")]
    CycleWithoutDistance {
        /// The cycle's file.
        path: PathBuf,
    },
    /// One of the calibration band's sets cannot be run at this point.
    #[error("{band}: set `{set}` (speed_spread_kmh = {}): {error}", plain(*speed_spread_kmh, 6))]
    BandSet {
        /// Where the band comes from.
        band: String,
        /// The set's id.
        set: String,
        /// Its speed spread \[km/h\].
        speed_spread_kmh: f64,
        /// Why the loop refuses it.
        error: LongTermError,
    },
}

/// Why a planned run gave no answer.
#[derive(Debug, thiserror::Error)]
pub enum LongTermRunError {
    /// The loop under the run's own constants (or the choice of the band's sets).
    #[error("{0}")]
    Own(#[from] LongTermError),
    /// The loop under one of the band's sets.
    #[error("the calibration band's runs: {0}")]
    Band(LongTermError),
}

/// A request checked: the problem, its usage in words, the metadata every output records, the
/// band, and notes for the reader.
#[derive(Debug, Clone)]
pub struct LongTermPlan {
    /// The loop's problem under the run's own constants.
    pub problem: LongTermProblem,
    /// The usage in words (the speeds driven).
    pub usage: String,
    /// What every output file of the run records.
    pub metadata: Vec<(String, String)>,
    /// The calibrated sets and where they come from (none: off).
    pub band: Option<(CalibrationBand, String)>,
    /// Which of them the loop runs under.
    pub band_sets: LoopSets,
    /// Things the reader should know that do not stop the run.
    pub notes: Vec<String>,
    /// A cruise's speed and nodes, whose legs follow a set's spread (none: a cycle's legs).
    cruise: Option<(f64, usize)>,
}

/// The loop under the run's own constants and under the band's chosen sets.
#[derive(Debug, Clone)]
pub struct LongTermRun {
    /// Both wheels under the run's own constants.
    pub solution: LongTermSolution,
    /// Each chosen set's run (none: the band is off).
    pub band_runs: Option<Vec<SetRun>>,
}

impl LongTermRequest {
    /// Checks every input before any work: the usage's legs, the loop's problem, and every
    /// set of the band at this point.
    pub fn plan(self) -> Result<LongTermPlan, LongTermRequestError> {
        let p = self.params;
        let mut notes = Vec::new();
        let mut metadata = run_metadata(&p, self.variant);
        let (legs, usage) = match &self.cycle {
            Some(path) => {
                let cycle = self.read_cycle(path, &mut notes)?;
                metadata.push(("cycle".into(), path.display().to_string()));
                cycle
            }
            None => (
                cruise_legs(p.speed_kmh, p.speed_spread_kmh, self.speed_nodes),
                cruise_words(&p, self.speed_nodes),
            ),
        };
        let settings = LoopSettings {
            distance_km: self.distance_km,
            seed: self.seed,
            zone: self.reading.zone,
            power: self.reading.power,
            max_rhs_evals: self.max_rhs_evals,
            ..LoopSettings::default()
        };
        metadata.extend(self.loop_metadata(&settings, &legs, &usage));
        let problem = LongTermProblem::new(p, self.variant, legs, settings, self.classifier)?;
        let plan = LongTermPlan {
            problem,
            usage,
            metadata,
            band: self.band,
            band_sets: self.band_sets,
            notes,
            cruise: self
                .cycle
                .is_none()
                .then_some((p.speed_kmh, self.speed_nodes)),
        };
        plan.check_band_sets()?;
        Ok(plan)
    }

    /// The cycle's speeds as legs of equal distance, refused as `polywear cycle` refuses it,
    /// and its usage in words; what it holds that the loop does not use goes to `notes`.
    fn read_cycle(
        &self,
        path: &Path,
        notes: &mut Vec<String>,
    ) -> Result<(Vec<Leg>, String), LongTermRequestError> {
        let cycle = DriveCycle::read(path)?;
        if !self.accept_implausible {
            cycle.check_plausible()?;
        }
        cycle.check_steps(&self.params)?;
        if !cycle.names.is_empty() {
            let names: Vec<&str> = cycle.names.iter().map(|id| id.name()).collect();
            notes.push(format!(
                "{}: its columns {} are not used by `wear`, which drives the point's own toe, load and pressure at the cycle's speeds",
                path.display(),
                names.join(", ")
            ));
        }
        let nodes = self.speed_nodes;
        let (legs, km) = cycle.wear_legs(nodes);
        if legs.is_empty() {
            return Err(LongTermRequestError::CycleWithoutDistance { path: path.into() });
        }
        if nodes < SETTLED_CYCLE_NODES {
            notes.push(format!(
                "--speed-nodes {nodes}: on a cycle of widely spread speeds the loop's distance settles only from about {SETTLED_CYCLE_NODES} speeds (WLTC: 12,700 km on 5, 22,700 on 40, 23,400 on 64; HWFET settles on 5); --speed-nodes {SETTLED_CYCLE_NODES} takes about 8 times the time (HWFET: 23 s on 5, 174 s on 40)"
            ));
        }
        let usage = format!(
            "driving the cycle {} ({km:.2} km) again and again, at {} of its speeds",
            path.display(),
            legs.len()
        );
        Ok((legs, usage))
    }

    /// The run's own keys after the shared ones: the wear reading, the loop's settings, the
    /// legs, the usage and the band.
    fn loop_metadata(
        &self,
        settings: &LoopSettings,
        legs: &[Leg],
        usage: &str,
    ) -> Vec<(String, String)> {
        vec![
            ("wear_zone".into(), self.reading.zone.as_str().into()),
            ("wear_power".into(), self.reading.power.as_str().into()),
            (
                "wear_loop".into(),
                serde_json::to_string(settings).expect("plain data"),
            ),
            (
                "legs".into(),
                serde_json::to_string(legs).expect("plain data"),
            ),
            ("usage".into(), usage.into()),
            (
                "calibration_band".into(),
                match &self.band {
                    Some((b, source)) => format!(
                        "{source}: {} sets; the loop run again under --band-sets {}",
                        b.sets.len(),
                        self.band_sets.as_str()
                    ),
                    None => "off".into(),
                },
            ),
        ]
    }
}

/// A cruise in words: its speed, spread and the speeds driven.
fn cruise_words(p: &Params, nodes: usize) -> String {
    format!(
        "cruising at {} km/h, speed spread {} km/h{}",
        plain(p.speed_kmh, 6),
        plain(p.speed_spread_kmh, 6),
        match (p.speed_spread_kmh > 0.0, nodes) {
            (false, _) => String::new(),
            (true, 1) => ", driven at the mean speed only".into(),
            (true, k) => format!(", driven at {k} of its speeds"),
        }
    )
}

impl LongTermPlan {
    /// The legs of the point with its fitted constants replaced by `q`'s: a cruise's follow
    /// `q`'s speed spread; a cycle's are the cycle's.
    pub fn legs_for(&self, q: &Params) -> Vec<Leg> {
        match self.cruise {
            Some((speed, nodes)) => cruise_legs(speed, q.speed_spread_kmh, nodes),
            None => self.problem.legs.clone(),
        }
    }

    /// Every set's run checked as the run's own is, before any work.
    fn check_band_sets(&self) -> Result<(), LongTermRequestError> {
        let Some((band, source)) = &self.band else {
            return Ok(());
        };
        for set in &band.sets {
            let q = set.constants().applied_to(&self.problem.params);
            LongTermProblem::new(
                q,
                self.problem.variant,
                self.legs_for(&q),
                self.problem.settings.clone(),
                self.problem.classifier,
            )
            .map_err(|error| LongTermRequestError::BandSet {
                band: source.clone(),
                set: set.id.clone(),
                speed_spread_kmh: set.speed_spread_kmh,
                error,
            })?;
        }
        Ok(())
    }

    /// Both wheels' loops under the run's own constants, then under the band's chosen sets.
    /// `progress` is told each accepted step's distance \[km\]; `more_runs` how many runs the
    /// band adds once its sets are chosen.
    pub fn solve(
        &self,
        progress: &(dyn Fn(f64) + Sync),
        more_runs: &dyn Fn(usize),
    ) -> Result<LongTermRun, LongTermRunError> {
        let solution = long_term::solve(&self.problem, progress)?;
        let band_runs = match &self.band {
            Some((band, _)) => {
                let sets = band_loop::chosen(band, self.band_sets, &self.problem, &solution)?;
                more_runs(sets.len());
                let legs = |q: &Params| self.legs_for(q);
                let runs = band_loop::run(band, &sets, &self.problem, &legs, progress)
                    .map_err(LongTermRunError::Band)?;
                Some(runs)
            }
            None => None,
        };
        Ok(LongTermRun {
            solution,
            band_runs,
        })
    }
}
