//! The rule that a parameter is set in one place (the brief's "nothing is silent"): the
//! defaults, then a `--params` file, then the values typed on the command line, each source
//! remembered so that a command which sets a parameter itself (a sweep, a chart's axis, a
//! study, a cycle's column) refuses or notes the overlap. Every command resolves its
//! parameters here; the command line only turns its flags into the typed list.

use std::path::{Path, PathBuf};

use polywear_core::params::axle::check_one_place;
use polywear_core::params::{ParamId, Params};
use polywear_core::wording::plain;

use crate::safe_read::{self, Limit};
use crate::study::{read_param_file_keys, Study};

pub use crate::refusal::{Conflict, Refusal};

/// A value typed on the command line: the parameter, its words (`--toe 0.15`) and its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Typed {
    /// The parameter.
    pub id: ParamId,
    /// How it was typed, quoted in messages.
    pub by: String,
    /// The value, in the parameter's unit.
    pub value: f64,
}

/// The parameters of a command, and where the explicitly given ones came from.
#[derive(Debug, Clone)]
pub struct ParamSources {
    /// Defaults, then the `--params` file, then the typed values; validated.
    pub params: Params,
    /// The `--params` file and the parameters it names.
    pub file: Option<(PathBuf, Vec<ParamId>)>,
    /// The parameters typed on the command line, each with its words (`--toe 0.15`).
    pub typed: Vec<(ParamId, String)>,
}

impl ParamSources {
    /// Defaults, then the file, then `typed`, each checked before any work. A parameter typed
    /// twice is refused as ambiguous; a typed value replacing the file's is returned as a
    /// note; implausible values are refused unless `accept_implausible`.
    pub fn resolve(
        file: Option<&Path>,
        typed: Vec<Typed>,
        accept_implausible: bool,
    ) -> Result<(Self, Vec<String>), Refusal> {
        let (mut p, named) = param_file(file, accept_implausible)?;
        let file_values = p;
        for (k, t) in typed.iter().enumerate() {
            if let Some(first) = typed[..k].iter().find(|f| f.id == t.id) {
                return Err(Conflict::TypedTwice {
                    id: t.id,
                    first: first.by.clone(),
                    second: t.by.clone(),
                }
                .into());
            }
            let refuse = |source| Refusal::Param {
                by: t.by.clone(),
                source,
            };
            p.try_set(t.id, t.value).map_err(refuse)?;
            if !accept_implausible {
                t.id.spec().check_plausible(t.value).map_err(refuse)?;
            }
        }
        let file = file.map(|path| (path.to_path_buf(), named));
        let notes = match &file {
            Some((path, names)) => replaced_notes(&typed, names, &file_values, path),
            None => Vec::new(),
        };
        let given: Vec<ParamId> = typed
            .iter()
            .map(|t| t.id)
            .chain(file.iter().flat_map(|(_, names)| names.iter().copied()))
            .collect();
        check_one_place(&given, "the parameters given (flags, --set and --params)")?;
        p.validate()?;
        let sources = ParamSources {
            params: p,
            file,
            typed: typed.into_iter().map(|t| (t.id, t.by)).collect(),
        };
        Ok((sources, notes))
    }

    /// Where parameter `id` was given explicitly (`--toe 0.15`, `--params FILE`), if it was.
    pub fn given_by(&self, id: ParamId) -> Option<String> {
        if let Some((_, by)) = self.typed.iter().find(|(t, _)| *t == id) {
            return Some(by.clone());
        }
        let (path, names) = self.file.as_ref()?;
        names
            .contains(&id)
            .then(|| format!("--params {}", path.display()))
    }

    /// A parameter that `owner` (a sweep, a chart's axis) varies itself: typed on the command
    /// line too it is refused as ambiguous; a `--params` file's value is replaced, and the
    /// returned note says so.
    pub fn owned_by(&self, id: ParamId, owner: &str) -> Result<Option<String>, Refusal> {
        if let Some((_, by)) = self.typed.iter().find(|(t, _)| *t == id) {
            return Err(Conflict::Varied {
                by: by.clone(),
                id,
                owner: owner.to_string(),
            }
            .into());
        }
        Ok(self.given_by(id).map(|by| {
            format!(
                "note: {owner} replaces {id} = {} of {by}",
                plain(self.params[id], 12)
            )
        }))
    }
}

/// The notes for typed values that replace a `--params` file's: "note: --toe 0.2 replaces
/// toe_deg = 0.15 of --params FILE".
pub(crate) fn replaced_notes(
    typed: &[Typed],
    named: &[ParamId],
    file_values: &Params,
    file: &Path,
) -> Vec<String> {
    typed
        .iter()
        .filter(|t| named.contains(&t.id) && file_values[t.id] != t.value)
        .map(|t| {
            format!(
                "note: {} replaces {} = {} of --params {}",
                t.by,
                t.id,
                plain(file_values[t.id], 12),
                file.display()
            )
        })
        .collect()
}

/// Refuses a per-wheel toe angle `deg` outside the plausible range, in the words it was typed
/// in (`by`: the flag or key, with its conversion), not as a bare `toe_deg`.
pub(crate) fn check_plausible_toe(deg: f64, by: &str) -> Result<(), Refusal> {
    let spec = ParamId::ToeDeg.spec();
    if spec.plausible.is_none_or(|q| q.contains(deg)) {
        return Ok(());
    }
    Err(Refusal::ImplausibleToe {
        by: by.to_string(),
        deg,
    })
}

/// The defaults with the `--params` file applied, and the parameters the file names; a value
/// outside its plausible range is refused unless `accept_implausible`.
pub fn param_file(
    path: Option<&Path>,
    accept_implausible: bool,
) -> Result<(Params, Vec<ParamId>), Refusal> {
    let Some(path) = path else {
        return Ok((Params::default(), Vec::new()));
    };
    let text = safe_read::read_text(path, Limit::Text).map_err(|source| Refusal::Unreadable {
        by: "--params",
        source,
    })?;
    let by = format!("--params {}", path.display());
    let (p, keys) =
        read_param_file_keys(&Params::default(), &text).map_err(|e| Refusal::study(&by, e))?;
    if !accept_implausible {
        for (id, key) in &keys {
            let by = format!("{by}: `{key}`");
            // A toe-in typed in mm or as total toe (its key is not the parameter's) is refused
            // in those words.
            if *key != format!("params.{id}") {
                check_plausible_toe(p[*id], &by)?;
                continue;
            }
            id.spec()
                .check_plausible(p[*id])
                .map_err(|source| Refusal::Param { by, source })?;
        }
    }
    Ok((p, keys.into_iter().map(|(id, _)| id).collect()))
}

/// Refuses a column carried into the output (passed through, or the weight) whose name an
/// output column of polywear has (`class`, `sample_id`, or one of `extra`): the output's
/// columns must be unique.
pub(crate) fn refuse_reserved_names<'a>(
    carried: impl IntoIterator<Item = &'a str>,
    file: &Path,
    key: &str,
    extra: &[&str],
) -> Result<(), Refusal> {
    let records = polywear_core::records::record_columns(&[]);
    for name in carried {
        if extra.contains(&name) || records.iter().any(|r| r.name == name) {
            return Err(Refusal::ReservedColumn {
                file: file.to_path_buf(),
                column: name.to_string(),
                key: key.to_string(),
            });
        }
    }
    Ok(())
}

/// Refuses a parameter that a `--params` file sets and a study (or its operating-point file)
/// sets too: two files for one value are ambiguous.
pub(crate) fn refuse_file_overlap(
    named: &[ParamId],
    params_path: Option<&Path>,
    study: &Study,
    origin: &str,
) -> Result<(), Refusal> {
    let Some(path) = params_path else {
        return Ok(());
    };
    for &id in named {
        if let Some(there) = study.sets(id) {
            return Err(Conflict::StudyFile {
                params: path.to_path_buf(),
                id,
                origin: origin.to_string(),
                there,
            }
            .into());
        }
    }
    let mut given = named.to_vec();
    given.extend(ParamId::ALL.iter().filter(|&&id| study.sets(id).is_some()));
    let place = format!("--params {} and {origin} together", path.display());
    check_one_place(&given, &place)?;
    Ok(())
}
