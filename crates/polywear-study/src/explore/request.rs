//! An explore run as asked for, resolved into a [`RunPlan`]: the study (the file, the one
//! recorded in the output directory for `--resume`, or the built-in one), its parameters,
//! samples, seed, shard, wear stage and output directory, every value checked before any work;
//! and the resume rules: a resumed run takes its recorded values as defaults and refuses a
//! value that contradicts them.

use std::path::{Path, PathBuf};

use polywear_core::classify::WheelBudget;
use polywear_core::wear::{WearPower, WearSettings, WearZone};

use super::recorded_run::{changed_lines, param_changes, RecordedRun};
use super::{ExploreError, RunPlan, Shard};
use crate::param_sources::{param_file, refuse_file_overlap, refuse_reserved_names, Refusal};
use crate::refusal::Contradiction;
use crate::study::{Study, DEFAULT_STUDY};
use polywear_core::params::axle::Drivetrain;

/// What `explore` is asked: every field as given, `None` where not given.
#[derive(Debug, Clone, Default)]
pub struct ExploreRequest {
    /// The study file; `None`: the recorded one on resume, else the built-in default.
    pub study: Option<PathBuf>,
    /// Base samples; `None`: the recorded or the study's.
    pub samples: Option<u64>,
    /// Seed; `None`: the recorded or the study's.
    pub seed: Option<u64>,
    /// Output directory; `None`: `data/explore_<study>_seed<seed>`.
    pub out: Option<PathBuf>,
    /// Continue the run recorded in `out`.
    pub resume: bool,
    /// Evaluate only this shard; `None`: the recorded one, else the whole run.
    pub shard: Option<Shard>,
    /// A `--params` file.
    pub params: Option<PathBuf>,
    /// Run implausible values anyway.
    pub accept_implausible: bool,
    /// Leave the wear stage out.
    pub no_wear: bool,
    /// The wear zone, over the study's.
    pub wear_zone: Option<WearZone>,
    /// Which friction power wears the tread, over the study's.
    pub wear_power: Option<WearPower>,
    /// Which axle is driven, over the study's `drivetrain`
    /// (MODEL.md#the-car-axles-and-drivetrain).
    pub drivetrain: Option<Drivetrain>,
}

impl ExploreRequest {
    /// `--resume --out DIR` continues the run recorded there: its study, parameters, samples,
    /// seed and shard are the defaults, and a flag that contradicts them is refused. A manifest
    /// this build cannot read back (damaged, or from a version that recorded less) is left to
    /// `prepare_output`, which says how the directory differs from this run; a run on a retired
    /// wear answer is refused here, since that is the whole story, not how its recorded
    /// parameters differ from today's defaults.
    fn recorded_run(&self) -> Result<Option<(PathBuf, RecordedRun)>, Refusal> {
        match (&self.out, self.resume) {
            (Some(dir), true) => match RecordedRun::read(dir) {
                Ok(run) => Ok(run.map(|run| (dir.clone(), run))),
                Err(e) if e.retired_level => Err(Refusal::RetiredRun(e)),
                Err(_) => Ok(None),
            },
            _ => Ok(None),
        }
    }

    /// The study's text and where it came from (quoted in refusals): the file, the one
    /// recorded in `--resume --out DIR`, or the built-in one.
    fn study_source(
        &self,
        recorded: Option<&(PathBuf, RecordedRun)>,
    ) -> Result<(String, String), Refusal> {
        Ok(match (&self.study, recorded) {
            (Some(path), _) => (
                crate::safe_read::read_text(path, crate::safe_read::Limit::Text).map_err(
                    |source| Refusal::Unreadable {
                        by: "study",
                        source,
                    },
                )?,
                path.display().to_string(),
            ),
            (None, Some((dir, run))) => (
                run.study.clone(),
                format!("the study recorded in {}", dir.display()),
            ),
            (None, None) => (
                DEFAULT_STUDY.to_string(),
                "built-in default study".to_string(),
            ),
        })
    }

    /// The run asked for: the study (the file, the one recorded in `--resume --out DIR`, or
    /// the built-in one), its base parameters, samples, seed, shard and output directory.
    /// `budget` applies the caller's work limits to the study's; its error, and every
    /// [`Refusal`] (through `From`), is the caller's error type `E`.
    pub fn plan<E: From<Refusal>>(
        &self,
        budget: &dyn Fn(WheelBudget) -> Result<WheelBudget, E>,
    ) -> Result<(RunPlan, Vec<String>), E> {
        let args = self;
        let mut notes = Vec::new();
        let recorded = args.recorded_run()?;
        let (source, origin) = args.study_source(recorded.as_ref())?;
        // A resumed run's values were judged when it started.
        let accept = args.accept_implausible || recorded.is_some();
        let (base, named) = match (&args.params, &recorded) {
            // The recorded values already hold the study's fixed ones, which parsing sets again.
            (None, Some((_, run))) => (run.params, Vec::new()),
            _ => param_file(args.params.as_deref(), accept)?,
        };
        // A relative `[operating_points]` file is found beside the study file (for a recorded
        // study, where the run found it).
        let study_dir = match (&args.study, &recorded) {
            (Some(path), _) => path.parent().map(Path::to_path_buf).unwrap_or_default(),
            (None, Some((_, run))) => run.operating_points_dir.clone().unwrap_or_default(),
            (None, None) => PathBuf::new(),
        };
        let in_study = |e| Refusal::study(&origin, e);
        let mut study = Study::parse_at(&source, base, &study_dir).map_err(in_study)?;
        if let Some((dir, run)) = &recorded {
            check_against_recorded(args, &study, dir, run)?;
        }
        notes.extend(check_new_inputs(
            args,
            &study,
            &named,
            (&origin, &study_dir),
            accept,
        )?);
        study.wear = wear_settings(args, &study, recorded.as_ref().map(|(_, run)| run))?;
        notes.extend(overridden_wear_keys(args, &study, &origin));
        if let Some(asked) = args.drivetrain {
            if let Some((_, run)) = &recorded {
                let was = run.params.drivetrain;
                if was != asked {
                    return Err(Refusal::ResumeDrivetrain { asked, was }.into());
                }
            }
            if study.base.drivetrain != asked {
                notes.push(format!(
                    "note: --drivetrain {asked} replaces {origin}'s drivetrain = {}",
                    study.base.drivetrain
                ));
            }
            study.base.drivetrain = asked;
        }
        let wear = RunPlan::wear_stage(&study).map_err(|source| Refusal::RunWearStage {
            by: origin.clone(),
            source: Box::new(source),
        })?;
        let asked = budget(study.budget)?;
        notes.extend(overridden_budget_keys(&study, &asked, &origin));
        study.budget = asked;
        let recorded_samples = recorded
            .as_ref()
            .map(|(_, run)| run.samples / study.evaluations(1));
        let base_samples = args.samples.or(recorded_samples).unwrap_or(study.samples);
        study
            .check_samples(base_samples)
            .map_err(|e| Refusal::study(format!("{origin}: --samples {base_samples}"), e))?;
        // A Saltelli design needs k + 2 evaluations per base sample.
        let samples = study.evaluations(base_samples);
        let seed = args
            .seed
            .or(recorded.as_ref().map(|(_, run)| run.seed))
            .unwrap_or(study.seed);
        study
            .check_scenarios(seed, samples)
            .and_then(|()| study.check_scenario_rules(accept))
            .map_err(in_study)?;
        let out_dir = args
            .out
            .clone()
            .unwrap_or_else(|| default_out_dir(&study, seed));
        let recorded_shard = recorded.as_ref().map(|(_, run)| run.shard);
        let plan = RunPlan {
            study,
            seed,
            samples,
            shard: args.shard.or(recorded_shard).unwrap_or(Shard::WHOLE),
            out_dir,
            resume: args.resume,
            command: crate::provenance::command_line(),
            wear,
        };
        Ok((plan, notes))
    }
}

/// The study's values against their plausible ranges (unless `accept`), a `--params` file that
/// sets what the study sets too, passed-through columns named as output columns; and, before
/// any work, how a computed weight is made.
fn check_new_inputs(
    args: &ExploreRequest,
    study: &Study,
    named: &[polywear_core::params::ParamId],
    (origin, study_dir): (&str, &Path),
    accept: bool,
) -> Result<Vec<String>, Refusal> {
    if !accept {
        study
            .check_plausible()
            .map_err(|e| Refusal::study(origin, e))?;
    }
    refuse_file_overlap(named, args.params.as_deref(), study, origin)?;
    let Some(op) = &study.operating_points else {
        return Ok(Vec::new());
    };
    refuse_reserved_names(
        op.pass_through.iter().map(|c| c.name.as_str()),
        &op.path,
        "`operating_points.pass_through`",
        &["sample_id", "operating_point_row"],
    )?;
    Ok(op
        .weight_computed
        .iter()
        .map(|how| crate::operating_points::computed_weight_note(&study_dir.join(&op.file), how))
        .collect())
}

/// The run's wear stage: `--no-wear`, or `--wear-zone` and `--wear-power`
/// over the study's wear settings; a resumed run keeps the stage it started with, and a flag
/// that contradicts it is refused.
fn wear_settings(
    args: &ExploreRequest,
    study: &Study,
    recorded: Option<&RecordedRun>,
) -> Result<Option<WearSettings>, Refusal> {
    let flags = asked_flags(args);
    let any_flag = args.wear_zone.is_some() || args.wear_power.is_some();
    let asked = match (args.no_wear, any_flag) {
        (true, _) => Some(None),
        (false, false) => None,
        (false, true) if study.wear.is_none() && recorded.is_none() => {
            return Err(Refusal::WearFlagsWithoutWear { flags })
        }
        (false, true) => {
            let base = recorded
                .and_then(|r| r.wear)
                .or(study.wear)
                .unwrap_or_default();
            Some(Some(WearSettings {
                zone: args.wear_zone.unwrap_or(base.zone),
                power: args.wear_power.unwrap_or(base.power),
            }))
        }
    };
    let Some(run) = recorded else {
        return Ok(asked.unwrap_or(study.wear));
    };
    match asked {
        Some(w) if w != run.wear => {
            let flag = if args.no_wear {
                "--no-wear".to_string()
            } else {
                flags
            };
            Err(Refusal::ResumeWear {
                flag,
                was: run.wear,
            })
        }
        _ => Ok(run.wear),
    }
}

/// One line for each of the study's wear settings a flag replaces ("no silent override": the
/// flag wins, and the run says so).
fn overridden_wear_keys(args: &ExploreRequest, study: &Study, origin: &str) -> Vec<String> {
    let flags = [
        ("wear_zone", args.wear_zone.map(|z| z.to_string())),
        ("wear_power", args.wear_power.map(|p| p.to_string())),
    ];
    flags
        .into_iter()
        .filter_map(|(key, flag)| {
            let (flag, theirs) = (flag?, study.key_text(key)?);
            (flag != theirs).then(|| {
                format!(
                    "note: --{} {flag} overrides {origin}'s {key} = \"{theirs}\"",
                    key.replace('_', "-")
                )
            })
        })
        .collect()
}

/// One line for each of the study's work limits the budget flags replace.
fn overridden_budget_keys(study: &Study, asked: &WheelBudget, origin: &str) -> Vec<String> {
    let mut notes = Vec::new();
    if let Some(theirs) = study.key_text("max_rhs_evals") {
        if asked.max_rhs_evals != study.budget.max_rhs_evals {
            notes.push(format!(
                "note: --max-rhs-evals {} overrides {origin}'s max_rhs_evals = {theirs}",
                asked.max_rhs_evals
            ));
        }
    }
    if let Some(theirs) = study.key_text("max_wheel_seconds") {
        if asked.max_wheel_seconds != study.budget.max_wheel_seconds {
            notes.push(format!(
                "note: --max-wheel-seconds {} overrides {origin}'s max_wheel_seconds = {theirs}",
                polywear_core::wording::plain(asked.max_wheel_seconds, 12)
            ));
        }
    }
    notes
}

/// The wear flags given, as typed: "--wear-zone Z", "--wear-power P".
fn asked_flags(args: &ExploreRequest) -> String {
    let mut f = Vec::new();
    if let Some(z) = args.wear_zone {
        f.push(format!("--wear-zone {z}"));
    }
    if let Some(p) = args.wear_power {
        f.push(format!("--wear-power {p}"));
    }
    f.join(" ")
}

/// Refuses a flag of `--resume --out DIR` that contradicts the run recorded in DIR, showing
/// both values; repeating the recorded value is accepted.
fn check_against_recorded(
    args: &ExploreRequest,
    study: &Study,
    dir: &Path,
    run: &RecordedRun,
) -> Result<(), Refusal> {
    let refuse = |what| Refusal::Contradicts {
        dir: dir.to_path_buf(),
        what,
    };
    if let Some(path) = &args.study {
        if study.source != run.study {
            return Err(refuse(Contradiction::Study {
                path: path.clone(),
                lines: changed_lines(&run.study, &study.source),
            }));
        }
    }
    if let Some(seed) = args.seed.filter(|s| *s != run.seed) {
        return Err(refuse(Contradiction::Seed {
            given: seed,
            run: run.seed,
        }));
    }
    if let Some(n) = args
        .samples
        .filter(|n| study.evaluations(*n) != run.samples)
    {
        return Err(refuse(Contradiction::Samples {
            given: n,
            run: run.samples / study.evaluations(1),
        }));
    }
    if let Some(s) = args.shard.filter(|s| *s != run.shard) {
        return Err(refuse(Contradiction::Shard {
            given: s,
            run: run.shard,
        }));
    }
    if let Some(path) = &args.params {
        if study.base != run.params {
            return Err(refuse(Contradiction::Params {
                path: path.clone(),
                changes: param_changes(&run.params, &study.base),
            }));
        }
    }
    Ok(())
}

/// The closing report of a shard that owns no chunk: `_report/report.md` says it holds no
/// rows; returns its path.
pub fn empty_shard_report(plan: &RunPlan) -> Result<PathBuf, ExploreError> {
    let dir = plan.out_dir.join("_report");
    let failed = |path: &Path, e: std::io::Error| ExploreError::OutputDir {
        dir: path.to_path_buf(),
        message: e.to_string(),
    };
    crate::safe_write::create_dir(&dir).map_err(|e| failed(&dir, e))?;
    let text = format!(
        "# Shard {k}/{n} of study `{name}`: no rows\n\nThis shard holds no rows: the run has {chunks} \
         chunk(s) of {size} samples ({samples} samples), fewer than the {n} shards, and shard k \
         owns the chunks whose index is k mod {n}. Nothing is missing; analyse all shards together \
         (`polywear analyze <shard directories>`).\n",
        k = plan.shard.index,
        n = plan.shard.count,
        name = plan.study.name,
        chunks = plan.n_chunks(),
        size = plan.study.chunk_size,
        samples = plan.samples,
    );
    let path = dir.join("report.md");
    crate::safe_write::write_file(&path, text.as_bytes()).map_err(|e| failed(&path, e))?;
    Ok(path)
}

/// Below this `chunk_size` explore warns: each chunk costs a file and three fsyncs.
pub(crate) const CHUNK_SIZE_WARN: u64 = 64;

/// The warning for a small `chunk_size`, with its measured cost (docs/book/src/maintainers/benchmarks.md#fsync).
pub fn chunk_size_warning(chunk_size: u64) -> Option<String> {
    (chunk_size < CHUNK_SIZE_WARN).then(|| {
        format!(
            "warning: chunk_size = {chunk_size} is below {CHUNK_SIZE_WARN}: every chunk is a file with three fsyncs, and analyze opens each; on 2,000 samples of the default study (2 cores) chunk_size 1 made explore {} and analyze {} slower than the default 4096; keep it in the thousands",
            CHUNK_1_EXPLORE_SLOWER, CHUNK_1_ANALYZE_SLOWER
        )
    })
}

/// Measured side by side (docs/book/src/reference/guarantees.md#what-is-guaranteed): explore and analyze of 2,000 samples of
/// the default study at chunk_size 1 against 4096.
const CHUNK_1_EXPLORE_SLOWER: &str = "about 30x";
/// See [`CHUNK_1_EXPLORE_SLOWER`].
const CHUNK_1_ANALYZE_SLOWER: &str = "about 9x";

/// Default output directory for a study and seed.
pub fn default_out_dir(study: &Study, seed: u64) -> PathBuf {
    Path::new("data").join(format!("explore_{}_seed{seed}", study.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_chunk_size_is_warned_about_with_its_cost() {
        assert!(chunk_size_warning(4096).is_none());
        assert!(chunk_size_warning(64).is_none());
        let w = chunk_size_warning(1).unwrap();
        assert!(w.contains("chunk_size = 1") && w.contains("30x"), "{w}");
    }
}
