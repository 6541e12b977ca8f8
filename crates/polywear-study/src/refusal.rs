//! Why an input is refused before any work (printed as `error: …`, exit 2): a typed error whose
//! variants carry what the message names (the flag, key or file a value was given by, the
//! parameter, the value, the range) and whose text says what is accepted instead.
//!
//! The families: a parameter's value refused where it was given ([`Refusal::Param`]); a file
//! that cannot be read ([`Refusal::Unreadable`]) or a study that is refused
//! ([`Refusal::Study`]); two places setting one parameter ([`Conflict`]); a resumed run
//! contradicted ([`Contradiction`]); a study whose design or draws cannot serve the command;
//! and `optimize`'s problem (its constraints, [`ConstraintError`], and boxes, [`VaryError`]).

use std::path::PathBuf;

use polywear_core::params::{ParamError, ParamId};
use polywear_core::wear::{WearError, WearSettings};
use polywear_core::wording::plain;

use crate::explore::recorded_run::{shell_word, ManifestReadError};
use crate::explore::{ExploreError, Shard};
use crate::operating_points::OperatingPointsError;
use crate::optimize::objective::ObjectiveError;
use crate::safe_read::ReadError;
use crate::study::{BrokenRule, StudyError};

/// An input refused before any work: the message names the flag or key, the value and the
/// accepted range (printed as `error: …`, exit 2).
#[derive(Debug, thiserror::Error)]
pub enum Refusal {
    /// A parameter's value (or name) refused, with how it was given: a flag (`--toe 0.15`,
    /// `--set toe_deg`, `--vary toe_deg`), a file's key (`--params FILE: \`params.toe_deg\``)
    /// or a file's row (`points.csv, row 3`).
    #[error("{by}: {source}")]
    Param {
        /// How the value was given.
        by: String,
        /// Why it was refused.
        source: ParamError,
    },
    /// Parameters that do not fit together (μ_s above μ_m), or a value refused that names its
    /// parameter itself.
    #[error(transparent)]
    Params(#[from] ParamError),
    /// A per-wheel toe angle outside its plausible range, in the words it was typed in (a toe
    /// in mm or a total toe, with its conversion), not as a bare `toe_deg`.
    #[error(
        "{by}: implausible for a road tire (plausible toe_deg {} deg per wheel) (if it is meant, --accept-implausible runs it anyway)",
        ParamId::ToeDeg.spec().plausible_text()
    )]
    ImplausibleToe {
        /// How the toe was given.
        by: String,
        /// The per-wheel angle it converts to \[deg\].
        deg: f64,
    },
    /// A file that cannot be read, named with what gave it (`--params`, `--study`, `study`).
    #[error("{by} {source}")]
    Unreadable {
        /// The flag or word that gave the file.
        by: &'static str,
        /// Why it cannot be read (naming the file).
        source: ReadError,
    },
    /// A study, or a `--params` file read by the study's rules, refused: `by` says where it
    /// came from, with the flag concerned (`--study FILE`, `FILE: --samples 10`).
    #[error("{by}: {source}")]
    Study {
        /// Where the study came from, and the flag concerned.
        by: String,
        /// Why it was refused.
        source: Box<StudyError>,
    },
    /// The wear stage of an explore run cannot be set up for its study.
    #[error("{by}: {source}")]
    RunWearStage {
        /// Where the study came from.
        by: String,
        /// Why.
        source: Box<ExploreError>,
    },
    /// `optimize`'s wear stage cannot be calibrated.
    #[error("the wear stage: {0}")]
    WearStage(#[source] WearError),
    /// A drive cycle's file refused (its columns, steps, values or work).
    #[error(transparent)]
    Cycle(#[from] crate::cycle::CycleError),
    /// The speed spread set for a drive cycle, whose steps' speeds are its spread.
    #[error("--set {id}: {}; leave it out", crate::cycle::NO_SPREAD)]
    CycleSpread {
        /// The parameter (`speed_spread_kmh`).
        id: ParamId,
    },
    /// A drive cycle's wear stage that cannot be calibrated.
    #[error("the wear stage: {0} (leave it out with --no-wear)")]
    CycleWearStage(#[source] WearError),
    /// A drive cycle's speed bins over the memory limit for that many tire structures.
    #[error(
        "--structure-samples: {structures} structures would hold {:.1} GiB of speed bins on this cycle ({:.0} MB a structure); accepted: at most {most} structures, or --no-wear",
        *bytes as f64 / (1u64 << 30) as f64,
        *bytes_per_structure as f64 / 1e6
    )]
    CycleBins {
        /// The structures asked for.
        structures: u64,
        /// The bins' bytes for all of them.
        bytes: u64,
        /// The bins' bytes for one structure.
        bytes_per_structure: u64,
        /// The most structures within the limit.
        most: u64,
    },
    /// The calibration band a command's `--calibration-band` names, unreadable or not a band.
    #[error(transparent)]
    BandFile(#[from] crate::calibration_band::BandFileError),
    /// A sample count for the band given with the band off.
    #[error(
        "--band-samples {samples}: the calibration band is off (--calibration-band off), so it would not be used; leave it out"
    )]
    BandSamplesWithBandOff {
        /// The count given.
        samples: u64,
    },
    /// A file of points refused (its columns, a value, the weight).
    #[error(transparent)]
    Points(#[from] OperatingPointsError),
    /// A file of points with no parameter column.
    #[error(
        "{}: no parameter column (columns: {}); name parameters of `polywear params`, e.g. speed_kmh,toe_deg",
        path.display(),
        columns.join(", ")
    )]
    NoParameterColumn {
        /// The file.
        path: PathBuf,
        /// The columns it has.
        columns: Vec<String>,
    },
    /// A column carried into the output (passed through, or the weight) whose name an output
    /// column of polywear has.
    #[error(
        "{}: column `{column}`, which {key} names, is also an output column of polywear; rename it in the file",
        file.display()
    )]
    ReservedColumn {
        /// The file.
        file: PathBuf,
        /// The column.
        column: String,
        /// The key or flag that names it.
        key: String,
    },
    /// Two places set one parameter.
    #[error(transparent)]
    Conflict(#[from] Conflict),
    /// A flag of `--resume --out DIR` that contradicts the run recorded in DIR.
    #[error(
        "--resume --out {d}: {what}{}leave it out to continue the run as it started (`polywear explore --resume --out {d}`), or choose another --out for a new run",
        what.separator(),
        d = shell_word(&dir.display().to_string())
    )]
    Contradicts {
        /// The run's directory.
        dir: PathBuf,
        /// What contradicts it.
        what: Contradiction,
    },
    /// A wear flag of `--resume` that contradicts the wear stage the run started with.
    #[error(
        "--resume: {flag} contradicts the run, which started with {}; leave it out to continue the run as it started, or choose another --out for a new run",
        started_with(was)
    )]
    ResumeWear {
        /// The flags as typed.
        flag: String,
        /// The run's wear stage (`None`: none).
        was: Option<WearSettings>,
    },
    /// `--resume` with a `--drivetrain` other than the run's.
    #[error(
        "--resume: --drivetrain {asked} contradicts the run, which started with drivetrain = {was}; leave it out to continue the run as it started, or choose another --out for a new run"
    )]
    ResumeDrivetrain {
        /// The drivetrain asked for.
        asked: polywear_core::params::axle::Drivetrain,
        /// The run's.
        was: polywear_core::params::axle::Drivetrain,
    },
    /// `--resume` of a run answered on a retired wear level.
    #[error("--resume: {0}")]
    RetiredRun(#[source] ManifestReadError),
    /// Wear flags for a study that leaves the wear stage out.
    #[error(
        "{flags}: the study sets `wear = false`, which leaves the wear stage out; remove it from the study, or leave {flags} out"
    )]
    WearFlagsWithoutWear {
        /// The flags as typed (`--wear-zone Z --wear-power P`).
        flags: String,
    },
    /// `optimize` over a study with a saltelli design.
    #[error(
        "{origin}: `design` = \"saltelli\" draws blocks for Sobol indices, not a fleet's samples; accepted: a study with design random, lhs, sobol or grid"
    )]
    SaltelliFleet {
        /// Where the study came from.
        origin: String,
    },
    /// `cycle --study` with a saltelli design.
    #[error(
        "{origin}: a saltelli design's rows are arranged for Sobol indices, not a sample of tire structures; use random, lhs or sobol"
    )]
    SaltelliStructures {
        /// Where the study came from.
        origin: String,
    },
    /// `cycle --study` with a study that draws no structure parameter.
    #[error(
        "{origin}: the study draws no tire-structure, friction or vehicle parameter, so every structure sample would be the same"
    )]
    NoStructureDrawn {
        /// Where the study came from.
        origin: String,
    },
    /// A chart's band from a study that draws nothing besides the operating point and the axes.
    #[error(
        "--study {}: draws no parameter besides the operating point and the chart's axes; the band needs distributions of tire-structure, friction or vehicle parameters",
        study.display()
    )]
    NoBandDrawn {
        /// The study file.
        study: PathBuf,
    },
    /// A wear objective or constraint in a build whose rows have no wear distance.
    #[error(
        "--objective wear: this build's rows have no `distance_to_visible_km` (the wear stage's distance to a visible polygon), so there is no risk of wear to minimise; accepted here: --objective vibration"
    )]
    NoWearColumns,
    /// A wear objective or constraint over a study with `wear = false`.
    #[error(
        "--objective wear: the study sets `wear = false`, so its rows have no distance to a visible polygon; remove it, or use --objective vibration"
    )]
    WearObjectiveWithoutWear,
    /// A calibration band asked for by name where it cannot apply.
    #[error("--calibration-band {band}: {why}; leave the flag out or give --calibration-band off")]
    BandMisfit {
        /// The band's file, or the shipped band's name.
        band: String,
        /// Why it cannot apply.
        why: BandMisfit,
    },
    /// A `--constraint` refused.
    #[error("--constraint `{text}`: {why}")]
    Constraint {
        /// The constraint as typed.
        text: String,
        /// Why.
        why: ConstraintError,
    },
    /// `--vary` given more than twice.
    #[error("--vary is given {0} times; accepted: one or two parameters")]
    VaryCount(usize),
    /// `--vary` naming one parameter twice.
    #[error("--vary names {0} twice; accepted: two different parameters")]
    VaryTwice(ParamId),
    /// A `--vary` box refused.
    #[error("{by}: {why}")]
    Vary {
        /// The box as typed (`--vary toe_deg=0..0.5`).
        by: String,
        /// Why.
        why: Box<VaryError>,
    },
}

impl Refusal {
    /// The text of the file at `path`, within [`crate::safe_read::Limit::Text`], or
    /// [`Refusal::Unreadable`] naming `by`, the flag or word that gave the file.
    pub(crate) fn read_text(by: &'static str, path: &std::path::Path) -> Result<String, Refusal> {
        crate::safe_read::read_text(path, crate::safe_read::Limit::Text)
            .map_err(|source| Refusal::Unreadable { by, source })
    }

    /// [`Refusal::Study`]: `source`, refused in the study (or `--params` file) that `by` names.
    pub fn study(by: impl Into<String>, source: StudyError) -> Refusal {
        Refusal::Study {
            by: by.into(),
            source: Box::new(source),
        }
    }
}

/// Two places that set one parameter (the one-place rule of [`crate::param_sources`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Conflict {
    /// Typed twice on the command line.
    #[error("`{id}` is given twice on the command line ({first} and {second}); give it once")]
    TypedTwice {
        /// The parameter.
        id: ParamId,
        /// The first typing (`--toe 0.1`).
        first: String,
        /// The second.
        second: String,
    },
    /// Typed on the command line and varied by the command itself (a sweep, a chart's axis).
    #[error("{by} sets `{id}`, which {owner} varies; leave {by} out")]
    Varied {
        /// How it was typed.
        by: String,
        /// The parameter.
        id: ParamId,
        /// What varies it (`the sweep`, `the chart's x axis`).
        owner: String,
    },
    /// Set by a `--params` file and by a study (or its operating-point file).
    #[error(
        "--params {} sets `{id}`, and {origin} {there}; a parameter comes from one file: remove it from one of them",
        params.display()
    )]
    StudyFile {
        /// The `--params` file.
        params: PathBuf,
        /// The parameter.
        id: ParamId,
        /// Where the study came from.
        origin: String,
        /// How the study sets it (`fixes it (\`params.toe_deg\`)`).
        there: String,
    },
    /// Set by a `--params` file and by a column of a file of points.
    #[error(
        "--params {} sets `{id}`, which {} gives per point (column `{id}`); a parameter comes from one file: remove it from one of them",
        params.display(),
        points.display()
    )]
    PointColumn {
        /// The `--params` file.
        params: PathBuf,
        /// The parameter.
        id: ParamId,
        /// The file of points.
        points: PathBuf,
    },
    /// Set on the command line and by a column of the cycle file.
    #[error(
        "{by} sets `{id}`, which {} gives at every step (its column `{id}`); a parameter comes from one place: leave it out of {by} or drop the column",
        cycle.display()
    )]
    CycleColumn {
        /// How it was given (`--set NAME=V`, `--params FILE`).
        by: String,
        /// The parameter.
        id: ParamId,
        /// The cycle file.
        cycle: PathBuf,
    },
    /// The speed typed for a cycle, which gives it at every step.
    #[error("--set speed_kmh: the cycle gives the speed at every step (its `speed_kmh` column)")]
    CycleSpeed,
    /// Set by `--set` or the cycle file and by the cycle's `--study`.
    #[error(
        "{by} sets `{id}`, which {origin} {}; a parameter comes from one place, not both",
        how.words(*id)
    )]
    StudySets {
        /// How it was given (`--set NAME=V`, `CYCLE (a column)`).
        by: String,
        /// The parameter.
        id: ParamId,
        /// Where the study came from.
        origin: String,
        /// How the study sets it.
        how: StudySetting,
    },
    /// Set on the command line and drawn by a chart's band study.
    #[error(
        "{by} sets `{id}`, which --study {} draws per structure for the band; a parameter is drawn or set, not both",
        study.display()
    )]
    BandDrawn {
        /// How it was given.
        by: String,
        /// The parameter.
        id: ParamId,
        /// The study file.
        study: PathBuf,
    },
}

/// How a cycle's study sets a parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StudySetting {
    /// Drawn per structure sample.
    Draws,
    /// A column of its `[operating_points]` file.
    PerVehicle,
    /// A fixed value (`params.NAME`).
    Fixes,
}

impl StudySetting {
    /// The words after "which STUDY", for parameter `id`.
    pub fn words(self, id: ParamId) -> String {
        match self {
            StudySetting::Draws => "draws per structure sample".into(),
            StudySetting::PerVehicle => {
                "gives per vehicle (a column of its [operating_points] file)".into()
            }
            StudySetting::Fixes => format!("fixes (`params.{}`)", id.name()),
        }
    }
}

/// What of `--resume --out DIR` contradicts the run recorded there.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Contradiction {
    /// The study file differs from the run's.
    #[error(
        "{} differs from the run's study in these lines (- the run's, + the file's):\n    {}\n",
        path.display(),
        lines.join("\n    ")
    )]
    Study {
        /// The study file given.
        path: PathBuf,
        /// The lines that differ (`- ` the run's, `+ ` the file's).
        lines: Vec<String>,
    },
    /// `--seed`.
    #[error("--seed {given} contradicts the run's seed {run}")]
    Seed {
        /// As given.
        given: u64,
        /// The run's.
        run: u64,
    },
    /// `--samples` (base samples).
    #[error("--samples {given} contradicts the run's {run} samples")]
    Samples {
        /// As given.
        given: u64,
        /// The run's.
        run: u64,
    },
    /// `--shard`.
    #[error("--shard {given} contradicts the run's shard {run}")]
    Shard {
        /// As given.
        given: Shard,
        /// The run's.
        run: Shard,
    },
    /// `--params`, whose values differ from the run's.
    #[error(
        "--params {} contradicts the run's values ({changes}, now from the file)",
        path.display()
    )]
    Params {
        /// The file given.
        path: PathBuf,
        /// The values that differ, in words.
        changes: String,
    },
}

impl Contradiction {
    /// What joins the contradiction to the advice after it: nothing after the study's lines
    /// (they end the line), else `; `.
    fn separator(&self) -> &'static str {
        match self {
            Contradiction::Study { .. } => "",
            _ => "; ",
        }
    }
}

/// The wear stage a run started with, in words.
fn started_with(was: &Option<WearSettings>) -> String {
    was.map_or("no wear stage (--no-wear)".to_string(), |w| {
        format!(
            "the wear stage with --wear-zone {} --wear-power {}",
            w.zone, w.power
        )
    })
}

/// Why `optimize`'s calibration band cannot apply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum BandMisfit {
    /// Nothing weighs wear, and the sets move only the wear answer.
    #[error(
        "neither the objective nor a constraint weighs wear, and the calibrated sets move only the wear answer"
    )]
    NoWear,
    /// A varied parameter is one of the sets' constants.
    #[error(
        "--vary {0} varies a constant the calibrated sets fix (each set would overwrite every setting)"
    )]
    VariesConstant(ParamId),
}

/// The forms `--constraint` accepts, said after a constraint that cannot be read.
const CONSTRAINT_FORMS: &str = "accepted: NAME<=V or NAME>=V, NAME a varied parameter (pressure_kpa>=230) or a risk, wear or vibration, optionally of a wheel (vibration:driving<=0.3)";

/// Why a `--constraint` is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConstraintError {
    /// Neither `<=` nor `>=`.
    #[error("no <= or >=; {forms}", forms = CONSTRAINT_FORMS)]
    NoBound,
    /// The bound is not a finite number.
    #[error("`{value}` is not a finite number; {forms}", forms = CONSTRAINT_FORMS)]
    NotANumber {
        /// The bound as typed.
        value: String,
    },
    /// An unknown wheel after the risk.
    #[error("{0}; {forms}", forms = CONSTRAINT_FORMS)]
    Wheel(ObjectiveError),
    /// A risk bounded outside \[0, 1\].
    #[error("a risk is a probability, {value} is not in [0, 1]; {forms}", forms = CONSTRAINT_FORMS)]
    NotAProbability {
        /// The bound.
        value: f64,
    },
    /// Neither a risk nor a parameter.
    #[error("{0}; {forms}", forms = CONSTRAINT_FORMS)]
    Name(ParamError),
    /// A bound on a parameter not varied.
    #[error("{0} is not varied; accepted: a bound on a --vary parameter, or on wear or vibration")]
    NotVaried(ParamId),
    /// A bound that leaves no box.
    #[error("leaves an empty box for {0}; accepted: a bound inside the --vary range")]
    EmptyBox(ParamId),
}

/// Why a `--vary` box is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum VaryError {
    /// A shared key varied where the study gives an axle its own value of it, which no wheel
    /// then reads (MODEL.md#the-car-axles-and-drivetrain).
    #[error(
        "the study gives this quantity per axle (`params.{own}`), so the shared {param} is read by no wheel there; vary the axles' keys"
    )]
    PerAxle {
        /// The shared parameter varied.
        param: ParamId,
        /// The axle's own parameter the study gives.
        own: ParamId,
    },
    /// A whole-number parameter whose box holds no whole setting.
    #[error(
        "{param} is a whole number and the box holds no whole setting between its ends; accepted: whole ends LO < HI, e.g. {param}=2..8"
    )]
    NoWholeSetting {
        /// The parameter.
        param: ParamId,
    },
    /// A setting that takes a value outside its plausible range.
    #[error("the setting {param} = {}: {source}", plain(*value, 12))]
    Implausible {
        /// The parameter.
        param: ParamId,
        /// The setting.
        value: f64,
        /// Why.
        source: ParamError,
    },
    /// A corner of the box that breaks a cross-parameter rule.
    #[error("the setting {param} = {} {}", plain(*value, 12), rule.words())]
    BreaksRule {
        /// The parameter.
        param: ParamId,
        /// The setting.
        value: f64,
        /// The rule, and how it is broken.
        rule: BrokenRule,
    },
    /// An end outside the parameter's accepted range.
    #[error("the box is outside the accepted range: {0}")]
    OutsideRange(#[source] ParamError),
    /// An end that takes a sample outside the accepted range.
    #[error(
        "the box is outside the accepted range for the study's samples: a setting is the centre of {param}'s distribution, every sample moved with it; {source}"
    )]
    OutsideForSamples {
        /// The parameter.
        param: ParamId,
        /// Why.
        source: StudyError,
    },
}
