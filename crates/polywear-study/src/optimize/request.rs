//! `optimize`'s problem as asked and as checked: [`Problem::new`] refuses, before any work, a
//! box that takes a sample outside its accepted range, a constraint that names nothing varied
//! or leaves an empty box, and a wear objective the study cannot answer, so that a problem
//! built from Rust is checked as the command line's is.

use polywear_core::classify::ClassifierOptions;
use polywear_core::evaluate::WearStage;
use polywear_core::params::ParamId;
use polywear_core::sampling::design::Design;
use polywear_core::wear::FittedConstants;
use polywear_core::wording::plain;

use super::evaluate::wear_available;
use super::objective::{Objective, Term, WheelChoice};
use super::search::SearchOptions;
use super::{Axis, Constraint, Problem, ProblemBand, SettingKind};
use crate::provenance::run_metadata;
use crate::refusal::{BandMisfit, ConstraintError, Refusal, VaryError};
use crate::study::Study;

/// What `optimize` is asked, as typed.
#[derive(Debug, Clone)]
pub struct ProblemSpec {
    /// The study whose samples every setting is evaluated on (its work limits set).
    pub study: Study,
    /// Where the study came from, quoted in refusals.
    pub origin: String,
    /// The seed of its draws (`None`: the study's).
    pub seed: Option<u64>,
    /// Samples per setting.
    pub samples: u64,
    /// One or two varied parameters and their boxes.
    pub vary: Vec<(ParamId, f64, f64)>,
    /// The constraints as typed (`pressure_kpa>=230`, `vibration:driving<=0.3`).
    pub constraints: Vec<String>,
    /// What is minimised.
    pub objective: Objective,
    /// A visible polygon counts when it appears within this distance \[km\].
    pub within_km: f64,
    /// How far the search refines.
    pub search: SearchOptions,
    /// Box ends outside their plausible range accepted.
    pub accept_implausible: bool,
    /// The calibrated sets to evaluate every setting's wear answer under as well (None: the
    /// run's constants alone). Refused where nothing weighs wear, or where a varied parameter
    /// is one of the sets' constants.
    pub band: Option<ProblemBand>,
}

impl Problem {
    /// The checked problem of `spec`, with the wear stage calibrated when wear is weighed.
    pub fn new(spec: ProblemSpec) -> Result<Problem, Refusal> {
        let study = spec.study;
        let origin = spec.origin;
        if study.design == Design::Saltelli {
            return Err(Refusal::SaltelliFleet { origin });
        }
        study
            .check_samples(spec.samples)
            .map_err(|e| Refusal::study(format!("{origin}: --samples {}", spec.samples), e))?;
        let seed = spec.seed.unwrap_or(study.seed);
        // A front or rear wheel is the follower or the driving one under the study's drivetrain.
        let drivetrain = study.base.drivetrain;
        let mut objective = spec.objective;
        objective.wheel = objective.wheel.on(drivetrain);
        let mut axes = axes(&spec.vary, spec.accept_implausible, &study)?;
        let mut constraints = Vec::new();
        for c in &spec.constraints {
            match parse_constraint(c, objective.wheel)? {
                Bound::Risk(mut r) => {
                    r.wheel = r.wheel.on(drivetrain);
                    constraints.push(r)
                }
                Bound::Param(id, at_most, v) => narrow(&mut axes, id, at_most, v, c)?,
            }
        }
        let wear = objective.uses_wear() || constraints.iter().any(|c| c.term == Term::Wear);
        if wear && !wear_available() {
            return Err(Refusal::NoWearColumns);
        }
        let settings = match (wear, study.wear) {
            (false, _) => None,
            (true, Some(s)) => Some(s),
            (true, None) => return Err(Refusal::WearObjectiveWithoutWear),
        };
        let (band, band_note) = match spec.band {
            Some(band) => match band_misfit(wear, &axes) {
                None => (Some(band), None),
                Some(why) if band.given => {
                    return Err(Refusal::BandMisfit {
                        band: band.source,
                        why,
                    })
                }
                // The default band where nothing weighs wear: nothing to say.
                Some(_) if !wear => (None, None),
                Some(why) => (
                    None,
                    Some(format!(
                        "the calibration band is left out: {why}; the optimum is the run's constants' alone, with its sampling interval only"
                    )),
                ),
            },
            None => (None, None),
        };
        for (a, given) in axes.iter().zip(&spec.vary) {
            check_axis(a, &study, seed, spec.samples, given)?;
        }
        let accept = spec.accept_implausible || study.accept_implausible;
        check_settings(&axes, &study, &spec.search, accept, &spec.vary)?;
        let classifier = ClassifierOptions {
            budget: study.budget,
            ..ClassifierOptions::default()
        };
        let wear = settings
            .map(|s| WearStage::for_run(&study.base, study.variants[0], s, &classifier))
            .transpose()
            .map_err(Refusal::WearStage)?;
        Ok(Problem {
            variant: study.variants[0],
            classifier,
            wear,
            study,
            seed,
            samples: spec.samples,
            axes,
            objective,
            constraints,
            within_km: spec.within_km,
            search: spec.search,
            given_constraints: spec.constraints,
            band,
            band_note,
        })
    }
    /// The metadata of every output file: the run, the objective, the box, the search.
    pub fn metadata(&self) -> Vec<(String, String)> {
        let problem = self;
        let study = &problem.study;
        let mut m = run_metadata(&study.base, problem.variant);
        let json = |v: serde_json::Value| v.to_string();
        m.extend([
            ("study_name".into(), study.name.clone()),
            ("study".into(), study.source.clone()),
            ("study_hash".into(), study.source_hash()),
            ("seed".into(), problem.seed.to_string()),
            ("samples".into(), problem.samples.to_string()),
            ("design".into(), study.design.as_str().into()),
            ("rng".into(), polywear_core::sampling::RNG_NAME.into()),
            ("drawn".into(), json(study.drawn_json())),
            ("objective".into(), problem.objective.text()),
            ("within_km".into(), plain(problem.within_km, 12)),
            (
                "box".into(),
                json(serde_json::Value::Array(
                    problem
                        .axes
                        .iter()
                        .map(|a| {
                            serde_json::json!({
                                "name": a.param.name(), "lo": a.lo, "hi": a.hi, "setting": a.meaning()
                            })
                        })
                        .collect(),
                )),
            ),
            ("constraints".into(), json(problem.given_constraints.clone().into())),
            (
                "calibration_band".into(),
                match &problem.band {
                    Some(b) => json(serde_json::json!({
                        "source": b.source,
                        "method": b.sets.method,
                        "samples": b.samples.min(problem.samples),
                        "sets": b.sets.sets.iter().map(|c| serde_json::json!({
                            "id": c.id,
                            "nominal": c.nominal,
                            "wear_share_straight": c.wear_share_straight,
                            "speed_spread_kmh": c.speed_spread_kmh,
                            "wear_rate_driven_factor": c.wear_rate_driven_factor,
                        })).collect::<Vec<_>>(),
                    })),
                    None => "off".into(),
                },
            ),
            (
                "search".into(),
                json(serde_json::json!({
                    "grid": problem.search.grid, "levels": problem.search.levels, "keep": problem.search.keep
                })),
            ),
        ]);
        m
    }
}

/// Why a band cannot apply, if it cannot: it needs a wear answer to move, and a box that
/// leaves the sets' constants alone (a set would overwrite every setting of a varied φ_s, σ_V
/// or k_d).
fn band_misfit(wear: bool, axes: &[Axis]) -> Option<BandMisfit> {
    if !wear {
        return Some(BandMisfit::NoWear);
    }
    axes.iter()
        .find(|a| FittedConstants::PARAMS.contains(&a.param))
        .map(|a| BandMisfit::VariesConstant(a.param))
}

/// One `--constraint`: a bound on a varied parameter, or on a risk.
enum Bound {
    Param(ParamId, bool, f64),
    Risk(Constraint),
}

fn parse_constraint(s: &str, wheel: WheelChoice) -> Result<Bound, Refusal> {
    let refuse = |why| Refusal::Constraint {
        text: s.to_string(),
        why,
    };
    let (name, at_most, value) = if let Some((n, v)) = s.split_once("<=") {
        (n, true, v)
    } else if let Some((n, v)) = s.split_once(">=") {
        (n, false, v)
    } else {
        return Err(refuse(ConstraintError::NoBound));
    };
    let value: f64 = value
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| {
            refuse(ConstraintError::NotANumber {
                value: value.trim().to_string(),
            })
        })?;
    let name = name.trim();
    let (term, wheel) = match name.split_once(':') {
        Some((t, w)) => (
            t.trim(),
            w.parse::<WheelChoice>()
                .map_err(|e| refuse(ConstraintError::Wheel(e)))?,
        ),
        None => (name, wheel),
    };
    if let Ok(term) = term.parse::<Term>() {
        if !(0.0..=1.0).contains(&value) {
            return Err(refuse(ConstraintError::NotAProbability { value }));
        }
        return Ok(Bound::Risk(Constraint {
            term,
            wheel,
            at_most,
            bound: value,
            text: s.to_string(),
        }));
    }
    let id: ParamId = name.parse().map_err(|e| refuse(ConstraintError::Name(e)))?;
    Ok(Bound::Param(id, at_most, value))
}

/// The axes of `--vary`: one or two distinct parameters.
fn axes(
    vary: &[(ParamId, f64, f64)],
    accept_implausible: bool,
    study: &Study,
) -> Result<Vec<Axis>, Refusal> {
    if vary.len() > 2 {
        return Err(Refusal::VaryCount(vary.len()));
    }
    if let [a, b] = vary {
        if a.0 == b.0 {
            return Err(Refusal::VaryTwice(a.0));
        }
    }
    for given in vary {
        if let Some(own) = study.per_axle_beside(given.0) {
            return Err(Refusal::Vary {
                by: vary_key(given),
                why: Box::new(VaryError::PerAxle {
                    param: given.0,
                    own,
                }),
            });
        }
    }
    if !(accept_implausible || study.accept_implausible) {
        for &(id, lo, hi) in vary {
            for v in [lo, hi] {
                id.spec()
                    .check_plausible(v)
                    .map_err(|source| Refusal::Param {
                        by: format!("--vary {id}"),
                        source,
                    })?;
            }
        }
    }
    Ok(vary
        .iter()
        .map(|&(id, lo, hi)| Axis::new(study, id, lo, hi))
        .collect())
}

/// A bound on a varied parameter narrows its box.
fn narrow(
    axes: &mut [Axis],
    id: ParamId,
    at_most: bool,
    v: f64,
    text: &str,
) -> Result<(), Refusal> {
    let Some(a) = axes.iter_mut().find(|a| a.param == id) else {
        return Err(Refusal::Constraint {
            text: text.to_string(),
            why: ConstraintError::NotVaried(id),
        });
    };
    if at_most {
        a.hi = a.hi.min(v);
    } else {
        a.lo = a.lo.max(v);
    }
    if a.lo >= a.hi {
        return Err(Refusal::Constraint {
            text: text.to_string(),
            why: ConstraintError::EmptyBox(id),
        });
    }
    Ok(())
}

/// `--vary NAME=LO..HI` as given.
fn vary_key(given: &(ParamId, f64, f64)) -> String {
    format!(
        "--vary {}={}..{}",
        given.0,
        plain(given.1, 12),
        plain(given.2, 12)
    )
}

/// Every setting the search can evaluate through the checks of a direct input, before any
/// work: a whole-number parameter on whole steps, each lattice point's values plausible
/// (unless `accept`), and no corner of the box breaking a cross-parameter rule (the changes
/// are monotone in the setting, so the corners decide for every point between).
fn check_settings(
    axes: &[Axis],
    study: &Study,
    search: &SearchOptions,
    accept: bool,
    given: &[(ParamId, f64, f64)],
) -> Result<(), Refusal> {
    let m = search.lattice();
    for (a, given) in axes.iter().zip(given) {
        let refuse = |why| Refusal::Vary {
            by: vary_key(given),
            why: Box::new(why),
        };
        if !a.whole_steps_fit() {
            return Err(refuse(VaryError::NoWholeSetting { param: a.param }));
        }
        if accept {
            continue;
        }
        let mut last = f64::NAN;
        for k in 0..=m {
            let v = a.value(k as f64 / m as f64);
            if v == last {
                continue;
            }
            last = v;
            study
                .check_change_plausible(a.change(v))
                .map_err(|source| {
                    refuse(VaryError::Implausible {
                        param: a.param,
                        value: v,
                        source,
                    })
                })?;
        }
    }
    let corners = 1usize << axes.len();
    for corner in 0..corners {
        let changes: Vec<_> = axes
            .iter()
            .enumerate()
            .map(|(i, a)| a.change(a.value(((corner >> i) & 1) as f64)))
            .collect();
        if let Some(b) = study.broken_rule(&changes) {
            let i = axes
                .iter()
                .position(|a| a.param == b.change.param)
                .unwrap_or(0);
            let setting = axes[i].value(((corner >> i) & 1) as f64);
            return Err(Refusal::Vary {
                by: vary_key(&given[i]),
                why: Box::new(VaryError::BreaksRule {
                    param: axes[i].param,
                    value: setting,
                    rule: b,
                }),
            });
        }
    }
    Ok(())
}

/// Refuses a box whose ends take any sample outside the parameter's accepted range.
fn check_axis(
    a: &Axis,
    study: &Study,
    seed: u64,
    samples: u64,
    given: &(ParamId, f64, f64),
) -> Result<(), Refusal> {
    let key = vary_key(given);
    let refuse = |why| Refusal::Vary {
        by: key.clone(),
        why: Box::new(why),
    };
    if let SettingKind::Set = a.kind {
        for end in [a.lo, a.hi] {
            a.param
                .spec()
                .check(end)
                .map_err(|e| refuse(VaryError::OutsideRange(e)))?;
        }
        return Ok(());
    }
    a.check(study, seed, samples, &key).map_err(|source| {
        refuse(VaryError::OutsideForSamples {
            param: a.param,
            source,
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::DEFAULT_STUDY;

    fn spec(vary: Vec<(ParamId, f64, f64)>, constraints: &[&str]) -> ProblemSpec {
        ProblemSpec {
            study: Study::parse(DEFAULT_STUDY).unwrap(),
            origin: "built-in default study".into(),
            seed: None,
            samples: 50,
            vary,
            constraints: constraints.iter().map(|c| c.to_string()).collect(),
            objective: Objective {
                terms: vec![(1.0, Term::Vibration)],
                wheel: WheelChoice::Follower,
            },
            within_km: 40_000.0,
            search: SearchOptions {
                grid: 3,
                levels: 1,
                keep: 1,
            },
            accept_implausible: false,
            band: None,
        }
    }

    #[test]
    fn a_problem_built_from_rust_is_checked_as_the_command_line_is() {
        let toe = (ParamId::ToeDeg, 0.25, 0.4);
        let ok = Problem::new(spec(vec![toe], &["toe_deg<=0.35"])).unwrap();
        assert_eq!(
            ok.axes[0].hi, 0.35,
            "a bound on a varied parameter narrows its box"
        );
        assert_eq!(ok.given_constraints, ["toe_deg<=0.35"]);
        let refused = |s: ProblemSpec| Problem::new(s).unwrap_err().to_string();
        assert!(refused(spec(vec![toe], &["load_n<=5000"])).contains("load_n is not varied"));
        assert!(refused(spec(vec![toe], &["toe_deg<=0.2"])).contains("empty box"));
        assert!(refused(spec(vec![toe, toe], &[])).contains("twice"));
        assert!(refused(spec(vec![toe], &["vibration<=2"])).contains("not in [0, 1]"));
        // A band needs a wear answer and a box that leaves its constants alone.
        let banded = |vary, terms| ProblemSpec {
            band: Some(ProblemBand {
                sets: crate::calibration_band::CalibrationBand::shipped(),
                source: "shipped".into(),
                given: true,
                samples: crate::optimize::DEFAULT_BAND_SAMPLES,
            }),
            objective: Objective {
                terms,
                wheel: WheelChoice::Follower,
            },
            ..spec(vary, &[])
        };
        assert!(refused(banded(vec![toe], vec![(1.0, Term::Vibration)]))
            .contains("neither the objective nor a constraint weighs wear"));
        let share = (ParamId::WearShareStraight, 0.1, 0.2);
        assert!(refused(banded(vec![share], vec![(1.0, Term::Wear)]))
            .contains("--vary wear_share_straight varies a constant the calibrated sets fix"));
        assert!(Problem::new(banded(vec![toe], vec![(1.0, Term::Wear)])).is_ok());
    }
}
