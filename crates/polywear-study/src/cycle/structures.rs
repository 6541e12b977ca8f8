//! The tire structures a cycle is driven with (`polywear cycle --study`): the study's drawn
//! non-operating parameters on top of the command line's, each sample's parameter base and the
//! fleet rows drawn, refusing every parameter that two places set (the one-place rule of
//! [`crate::param_sources`]) before any work.

use std::path::{Path, PathBuf};

use polywear_core::params::{Group, ParamError, ParamId, Params};
use polywear_core::sampling::design::Design;
use polywear_core::wording::plain;

use super::DriveCycle;
use crate::param_sources::{
    param_file, refuse_file_overlap, refuse_reserved_names, replaced_notes, Refusal, Typed,
};
use crate::refusal::{Conflict, StudySetting};
use crate::study::Study;

/// What the command line gives: the `--params` file's values and names, and the typed values.
#[derive(Debug, Clone)]
pub struct CommandLine {
    /// The `--params` file, if any.
    pub params_file: Option<PathBuf>,
    /// The defaults with the file applied.
    pub file: Params,
    /// The parameters the file names.
    pub named: Vec<ParamId>,
    /// The values typed (`--set`).
    pub set: Vec<Typed>,
    /// Implausible values accepted.
    pub accept_implausible: bool,
}

impl CommandLine {
    /// Reads `--params` and the typed `--set` values, refusing before any work: the speed (the cycle gives it), a
    /// parameter set twice, one the cycle file gives per step (from `--set` or `--params`), and
    /// implausible values unless accepted. A `--set` value replacing the file's is noted.
    pub fn read(
        params_file: Option<&Path>,
        typed: &[(String, f64)],
        accept: bool,
        cycle: &DriveCycle,
    ) -> Result<(Self, Vec<String>), Refusal> {
        let (file, named) = param_file(params_file, accept)?;
        let mut notes = Vec::new();
        let params_by = || {
            format!(
                "--params {}",
                params_file.unwrap_or(Path::new("")).display()
            )
        };
        let mut set: Vec<Typed> = Vec::new();
        for (name, value) in typed {
            let by = format!("--set {name}={}", plain(*value, 12));
            let named_by = |source: ParamError| Refusal::Param {
                by: format!("--set {name}"),
                source,
            };
            let id: ParamId = name.parse().map_err(named_by)?;
            if id == ParamId::SpeedKmh {
                return Err(Conflict::CycleSpeed.into());
            }
            if let Some(first) = set.iter().find(|t| t.id == id) {
                return Err(Conflict::TypedTwice {
                    id,
                    first: first.by.clone(),
                    second: by,
                }
                .into());
            }
            id.spec().check(*value).map_err(named_by)?;
            if !accept {
                id.spec()
                    .check_plausible(*value)
                    .map_err(|source| Refusal::Param {
                        by: by.clone(),
                        source,
                    })?;
            }
            set.push(Typed {
                id,
                by,
                value: *value,
            });
        }
        let column = |id: ParamId| cycle.names.contains(&id);
        for (id, by) in set
            .iter()
            .map(|t| (t.id, t.by.clone()))
            .chain(named.iter().map(|&id| (id, params_by())))
        {
            if column(id) {
                return Err(Conflict::CycleColumn {
                    by,
                    id,
                    cycle: cycle.path.clone(),
                }
                .into());
            }
        }
        if named.contains(&ParamId::SpeedKmh) {
            notes.push(format!(
                "note: the cycle's speed replaces speed_kmh = {} of {}",
                plain(file.speed_kmh, 12),
                params_by()
            ));
        }
        if let Some(path) = params_file {
            notes.extend(replaced_notes(&set, &named, &file, path));
        }
        let line = CommandLine {
            params_file: params_file.map(Path::to_path_buf),
            file,
            named,
            set,
            accept_implausible: accept,
        };
        Ok((line, notes))
    }
}

/// The tire structures of `--study`: the drawn non-operating parameters (and a fleet's columns
/// other than the operating axes) with their values per sample, each sample's parameter base,
/// the fleet rows drawn, and the lines that say what the cycle takes from the study.
pub struct Structures {
    /// The parameters drawn per sample (the study's non-operating ones and a fleet's other columns).
    pub names: Vec<ParamId>,
    /// `values[k][j]`: sample k's value of `names[j]`.
    pub values: Vec<Vec<f64>>,
    /// Each sample's parameters: the study's base, its draws and the typed values.
    pub bases: Vec<Params>,
    /// The fleet row each sample drew, when the study has `[operating_points]`.
    pub fleet_rows: Option<Vec<usize>>,
    /// What the cycle takes from the study and what it does not, said before the results.
    pub said: Vec<String>,
}

/// Draws the structure samples of `--study` on top of the `--params` values, with `--set`
/// applied after the study's fixed values (a replaced fixed value is noted). With
/// `[operating_points]` each sample also draws a row, whose columns but the speed hold for the
/// whole cycle.
pub fn draw_structures(
    line: &CommandLine,
    path: &Path,
    k: u64,
    cycle: &DriveCycle,
) -> Result<(Structures, Study, Vec<String>), Refusal> {
    let origin = format!("--study {}", path.display());
    let source = Refusal::read_text("--study", path)?;
    let mut notes = Vec::new();
    let dir = path.parent().unwrap_or(Path::new(""));
    let study = Study::parse_at(&source, line.file, dir).map_err(|e| Refusal::study(&origin, e))?;
    if !(line.accept_implausible || study.accept_implausible) {
        study
            .check_plausible()
            .map_err(|e| Refusal::study(&origin, e))?;
    }
    refuse_file_overlap(&line.named, line.params_file.as_deref(), &study, &origin)?;
    if study.design == Design::Saltelli {
        return Err(Refusal::SaltelliStructures { origin });
    }
    study
        .check_samples(k)
        .map_err(|e| Refusal::study(format!("{origin}: --structure-samples"), e))?;
    let fleet = study.operating_points.as_ref();
    if let Some(op) = fleet {
        refuse_reserved_names(
            op.pass_through.iter().map(|c| c.name.as_str()),
            &op.path,
            "`operating_points.pass_through`",
            &[
                "sample_id",
                "operating_point_row",
                "step",
                "time_s",
                "step_duration_s",
                "tread_time_constant_s",
                "stability_change_time_s",
                "quasi_static",
            ],
        )?;
    }
    // The fleet's columns that hold for the whole cycle (the cycle gives the speed).
    let fleet_ids: Vec<ParamId> = fleet
        .iter()
        .flat_map(|op| op.names.iter())
        .map(|n| n.parse::<ParamId>().expect("a parameter column"))
        .filter(|&id| id != ParamId::SpeedKmh)
        .collect();
    let names: Vec<ParamId> = study
        .drawn
        .iter()
        .map(|d| d.param)
        .filter(|id| id.spec().group != Group::OperatingPoint)
        .chain(
            fleet_ids
                .iter()
                .copied()
                .filter(|id| !id.is_operating_axis()),
        )
        .collect();
    if names.is_empty() && fleet.is_none() {
        return Err(Refusal::NoStructureDrawn { origin });
    }
    notes.extend(refuse_study_overlaps(
        &study, &origin, line, cycle, &names, &fleet_ids,
    )?);
    let sampler = study.sampler(study.seed, k);
    let mut out = Structures {
        names,
        values: Vec::new(),
        bases: Vec::new(),
        fleet_rows: fleet.map(|_| Vec::new()),
        said: said_about_study(&study, (&origin, dir), k, cycle, line),
    };
    for i in 0..k {
        let (p, _, row) = sampler.sample_with_row(i);
        let mut b = study.base;
        for &id in out.names.iter().chain(&fleet_ids) {
            b[id] = p[id];
        }
        for t in &line.set {
            b.try_set(t.id, t.value)?;
        }
        out.values.push(out.names.iter().map(|&id| p[id]).collect());
        out.bases.push(b);
        if let (Some(rows), Some(r)) = (&mut out.fleet_rows, row) {
            rows.push(r);
        }
    }
    Ok((out, study, notes))
}

/// Refuses what the study sets and another place sets too: a drawn structure parameter or a
/// fleet column given by `--set` or the cycle file, a fixed value the cycle file gives per
/// step. A `--set` replacing one of the study's fixed values is noted.
fn refuse_study_overlaps(
    study: &Study,
    origin: &str,
    line: &CommandLine,
    cycle: &DriveCycle,
    names: &[ParamId],
    fleet_ids: &[ParamId],
) -> Result<Vec<String>, Refusal> {
    let cycle_by = format!("{} (a column)", cycle.path.display());
    let given = line
        .set
        .iter()
        .map(|t| (t.id, t.by.as_str()))
        .chain(cycle.names.iter().map(|&id| (id, cycle_by.as_str())));
    for (id, by) in given {
        let how = if names.contains(&id) && !fleet_ids.contains(&id) {
            StudySetting::Draws
        } else if fleet_ids.contains(&id) {
            StudySetting::PerVehicle
        } else if study.fixed.contains(&id) && by == cycle_by {
            StudySetting::Fixes
        } else {
            continue;
        };
        return Err(Conflict::StudySets {
            by: by.to_string(),
            id,
            origin: origin.to_string(),
            how,
        }
        .into());
    }
    let notes = line
        .set
        .iter()
        .filter(|t| study.fixed.contains(&t.id) && study.base[t.id] != t.value)
        .map(|t| {
            format!(
                "note: {} replaces {origin}'s `params.{}` = {}",
                t.by,
                t.id,
                plain(study.base[t.id], 12)
            )
        })
        .collect();
    Ok(notes)
}

/// The lines said before the results: which of the study's operating-point values the cycle
/// takes (a fleet's rows) and which it does not (the speed, drawn operating axes).
fn said_about_study(
    study: &Study,
    (origin, dir): (&str, &Path),
    k: u64,
    cycle: &DriveCycle,
    line: &CommandLine,
) -> Vec<String> {
    let mut said = Vec::new();
    let set_here = |id: ParamId| cycle.names.contains(&id) || line.set.iter().any(|s| s.id == id);
    if let Some(op) = &study.operating_points {
        let taken: Vec<&str> = op
            .names
            .iter()
            .copied()
            .filter(|n| *n != "speed_kmh")
            .collect();
        let by = match (&op.weight, &op.weight_computed) {
            (_, Some(how)) => format!("by km = {how}"),
            (Some(w), None) => format!("by its `{w}`"),
            (None, None) => "with equal weight".to_string(),
        };
        let speed = if op.names.contains(&"speed_kmh") {
            "; its `speed_kmh` column is not used: the cycle gives the speed"
        } else {
            ""
        };
        said.push(format!(
            "fleet: each of the {k} structure samples drives the cycle with one row of {} drawn {by} ({} from the row{speed})",
            dir.join(&op.file).display(),
            if taken.is_empty() { "no column".to_string() } else { taken.join(", ") }
        ));
    }
    if study.fixed.contains(&ParamId::SpeedKmh) {
        said.push(format!(
            "{origin}: its `params.speed_kmh` = {} is not used: the cycle gives the speed",
            plain(study.base.speed_kmh, 6)
        ));
    }
    let unused: Vec<ParamId> = study
        .drawn
        .iter()
        .map(|d| d.param)
        .filter(|id| id.is_operating_axis())
        .collect();
    if !unused.is_empty() {
        let held: Vec<String> = unused
            .iter()
            .filter(|&&id| id != ParamId::SpeedKmh && !set_here(id))
            .map(|&id| format!("{id} = {}", plain(study.base[id], 6)))
            .collect();
        let speed = if unused.contains(&ParamId::SpeedKmh) {
            "the cycle gives the speed"
        } else {
            ""
        };
        let held = match (speed.is_empty(), held.is_empty()) {
            (_, true) => speed.to_string(),
            (true, false) => format!("{} hold for the whole cycle", held.join(", ")),
            (false, false) => format!("{speed}, and {} hold for the whole cycle", held.join(", ")),
        };
        said.push(format!(
            "{origin}: its distributions of {} are not used: {held} (a study with [operating_points] gives load, pressure and toe-in per vehicle)",
            unused.iter().map(|id| id.name()).collect::<Vec<_>>().join(", "),
        ));
    }
    said
}

/// The study's keys in the outputs' metadata (and the fleet's file, when it gives the rows).
pub fn study_metadata(study: &Study, k: u64, names: &[ParamId]) -> Vec<(String, String)> {
    let mut m = vec![
        ("study_name".into(), study.name.clone()),
        ("study".into(), study.source.clone()),
        ("study_hash".into(), study.source_hash()),
        ("seed".into(), study.seed.to_string()),
        ("design".into(), study.design.as_str().into()),
        ("structure_samples".into(), k.to_string()),
        ("rng".into(), polywear_core::sampling::RNG_NAME.into()),
        (
            "drawn_names".into(),
            serde_json::to_string(names).expect("json"),
        ),
    ];
    if let Some(op) = &study.operating_points {
        m.push(("operating_points".into(), op.to_json().to_string()));
    }
    m
}
