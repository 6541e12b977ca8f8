//! One drive-cycle run, checked before any work (MODEL.md#along-a-drive-cycle): the cycle file,
//! the parameters given for the whole cycle, the tire structures of a study, the wear stage and
//! the calibration band's sets, built from plain values. The command line only fills
//! [`CycleInput`] from its flags and says the notes; a script builds the same run without it.

use std::path::Path;

use polywear_core::classify::{ClassifierOptions, WheelBudget};
use polywear_core::evaluate::WearStage;
use polywear_core::model::Variant;
use polywear_core::params::{ParamId, Params};
use polywear_core::wear::{FittedConstants, WearSettings};

use super::structures::{draw_structures, study_metadata, CommandLine, Structures};
use super::{classify_cycles, ClassifiedCycle, DriveCycle};
use crate::calibration_band::CalibrationBand;
use crate::param_sources::Refusal;
use crate::provenance::run_metadata;
use crate::study::Study;

/// The most memory the wear stage's speed bins may take, over every structure and both wheels
/// (each bin one 66 KB profile a wheel: WLTC's 846 bins of 0.1 km/h are 112 MB a structure).
pub const SATURATED_BINS_MAX_BYTES: u64 = 4 << 30;

/// What a cycle run is given, as plain values (the flags of `polywear cycle`).
#[derive(Debug, Clone, Copy)]
pub struct CycleInput<'a> {
    /// The drive cycle file (CSV or Parquet: `time_s`, `speed_kmh`, any parameter per step).
    pub cycle: &'a Path,
    /// The friction variant of both wheels.
    pub variant: Variant,
    /// Parameters for the whole cycle by name (`--set`), the toe-in also as `toe_mm` or
    /// `toe_total_deg`.
    pub set: &'a [(String, f64)],
    /// A parameter file (`--params`), applied first.
    pub params: Option<&'a Path>,
    /// Run values outside their plausible ranges anyway.
    pub accept_implausible: bool,
    /// A study and how many tire structures to draw from it (`--study`,
    /// `--structure-samples`).
    pub study: Option<(&'a Path, u64)>,
    /// Which axle is driven (`--drivetrain`; MODEL.md#the-car-axles-and-drivetrain); `None`:
    /// front-wheel drive, the default.
    pub drivetrain: Option<polywear_core::params::axle::Drivetrain>,
}

/// One cycle run, checked: the cycle, variant, options, tire structures and the outputs'
/// metadata.
pub struct CycleRequest {
    /// The drive cycle, read and checked.
    pub cycle: DriveCycle,
    /// The friction variant of both wheels.
    pub variant: Variant,
    /// The classifier's options, the work budget the study's or the caller's.
    pub opts: ClassifierOptions,
    /// The nominal tire (`--params` and `--set`), on which the wear stage is calibrated.
    pub base: Params,
    /// The tire structures driven: the nominal tire alone without a study.
    pub structures: Structures,
    /// The study the structures were drawn from.
    pub study: Option<Study>,
    /// Written into every output file (version, command, parameters, variant, cycle, study).
    pub metadata: Vec<(String, String)>,
}

/// A checked request with its wear stage and calibration band: what [`CyclePlan::classify`]
/// runs.
pub struct CyclePlan {
    /// The checked request, its metadata naming the wear stage and the band.
    pub request: CycleRequest,
    /// The wear stage (MODEL.md#polygonal-wear), calibrated on the nominal tire; None without it.
    pub wear: Option<WearStage>,
    /// The calibrated sets each structure's distance to a visible polygon is also evaluated
    /// under (MODEL.md#the-calibration-band); empty for none.
    pub band_sets: Vec<FittedConstants>,
}

impl CycleRequest {
    /// Every input checked before any work: the cycle (its size and plausibility), the typed
    /// values (toe-in forms as angles), the parameter file, the study's structures and each
    /// step's parameters together. `budget` sets the work limits on the defaults, then on the
    /// study's; `note` hears each note as it is made, so that one said before a refusal is
    /// said.
    pub fn new<E: From<Refusal>>(
        input: &CycleInput<'_>,
        budget: &dyn Fn(WheelBudget) -> Result<WheelBudget, E>,
        note: &dyn Fn(&str),
    ) -> Result<Self, E> {
        let mut opts = ClassifierOptions {
            budget: budget(WheelBudget::default())?,
            ..ClassifierOptions::default()
        };
        let refuse = Refusal::Cycle;
        let cycle = DriveCycle::read(input.cycle).map_err(refuse)?;
        cycle
            .check_work(input.study.map_or(1, |(_, k)| k))
            .map_err(refuse)?;
        if !input.accept_implausible {
            cycle.check_plausible().map_err(refuse)?;
        }
        let accept = input.accept_implausible;
        let rim = crate::toe_input::rim_diameter_mm(input.params, input.set, accept)?;
        let (set, toe_notes) = crate::toe_input::set_as_angles(input.set, rim, accept)?;
        toe_notes.iter().for_each(|n| note(n));
        let (line, notes) = CommandLine::read(input.params, &set, accept, &cycle)?;
        notes.iter().for_each(|n| note(n));
        let mut base = line.file;
        for t in &line.set {
            if t.id == ParamId::SpeedSpreadKmh {
                return Err(Refusal::CycleSpread { id: t.id }.into());
            }
            base.try_set(t.id, t.value).map_err(Refusal::from)?;
        }
        if let Some(d) = input.drivetrain {
            base.drivetrain = d;
        }
        let mut metadata = run_metadata(&base, input.variant);
        metadata.push(("cycle".into(), input.cycle.display().to_string()));
        metadata.push(("cycle_hash".into(), cycle.hash.clone()));
        let (structures, study) = match input.study {
            Some((path, k)) => {
                let (s, study, notes) = draw_structures(&line, path, k, &cycle)?;
                notes.iter().for_each(|n| note(n));
                // The study's work limits, unless the caller says otherwise.
                opts.budget = budget(study.budget)?;
                metadata.extend(study_metadata(&study, k, &s.names));
                (s, Some(study))
            }
            None => (nominal_structure(base), None),
        };
        // Every step's parameters fit together on the first base (rules tying several
        // parameters: mu_s <= mu_m, n_driven <= n_wheels), before any work.
        cycle.check_steps(&structures.bases[0]).map_err(refuse)?;
        Ok(CycleRequest {
            cycle,
            variant: input.variant,
            opts,
            base,
            structures,
            study,
            metadata,
        })
    }

    /// The request with its wear stage (`wear`: its settings, None to leave it out) and the
    /// band's sets (`band`: the sets and their source, as [`CalibrationBand::asked`] gives
    /// them; used only with the wear stage), each named in the metadata. Refused: a stage that
    /// cannot be calibrated, and speed bins over [`SATURATED_BINS_MAX_BYTES`].
    pub fn prepare(
        mut self,
        wear: Option<WearSettings>,
        band: Option<(CalibrationBand, String)>,
    ) -> Result<CyclePlan, Refusal> {
        let wear = match wear {
            None => None,
            Some(settings) => Some(
                WearStage::for_run(
                    &self.base,
                    self.variant,
                    settings,
                    &ClassifierOptions::default(),
                )
                .map_err(Refusal::CycleWearStage)?,
            ),
        };
        if let Some(stage) = &wear {
            self.check_bins()?;
            let stage = serde_json::to_string(stage).expect("json");
            self.metadata.push(("wear".into(), stage));
        }
        let band_sets = match (&wear, band) {
            (Some(_), Some((band, source))) => {
                let said = format!("{} sets from {source}", band.sets.len());
                self.metadata.push(("calibration_band".into(), said));
                band.sets.iter().map(|s| s.constants()).collect()
            }
            _ => Vec::new(),
        };
        Ok(CyclePlan {
            request: self,
            wear,
            band_sets,
        })
    }

    /// Refuses structures whose speed bins would take more than [`SATURATED_BINS_MAX_BYTES`].
    fn check_bins(&self) -> Result<(), Refusal> {
        let per_wheel = super::wear::saturated_bins_bytes(&self.cycle);
        let bases = self.structures.bases.len() as u64;
        let bytes = 2 * bases * per_wheel;
        if bytes <= SATURATED_BINS_MAX_BYTES {
            return Ok(());
        }
        let most = SATURATED_BINS_MAX_BYTES / (2 * per_wheel).max(1);
        Err(Refusal::CycleBins {
            structures: bases,
            bytes,
            bytes_per_structure: 2 * per_wheel,
            most,
        })
    }
}

impl CyclePlan {
    /// The step evaluations the run takes: steps × tire structures.
    pub fn steps_to_do(&self) -> u64 {
        let r = &self.request;
        r.cycle.len() as u64 * r.structures.bases.len() as u64
    }

    /// Classifies every structure along the cycle ([`classify_cycles`]) on the current rayon
    /// pool; `progress` hears the steps done.
    pub fn classify(&self, progress: &(dyn Fn(u64) + Sync)) -> Vec<ClassifiedCycle> {
        let r = &self.request;
        classify_cycles(
            &r.cycle,
            &r.structures.bases,
            r.variant,
            &r.opts,
            self.wear.as_ref(),
            progress,
        )
    }
}

/// The one structure of a run without a study: the nominal tire.
fn nominal_structure(base: Params) -> Structures {
    Structures {
        names: Vec::new(),
        values: vec![Vec::new()],
        bases: vec![base],
        fleet_rows: None,
        said: Vec::new(),
    }
}
