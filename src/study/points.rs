//! A study's `[operating_points]` section: the file it names, read and checked against the
//! rest of the study (see [`crate::operating_points`]).

use std::path::Path;

use super::{DrawnParam, Sampler, Study, StudyError};
use crate::operating_points::OperatingPoints;
use crate::params::{ParamId, Params};
use crate::sampling::design::Design;
use crate::toml_input::{self, Section};

/// Reads `[operating_points]` (`file`, optional `weight`) and its file. Refused: a design other
/// than random (stratifying axes says nothing about drawing rows), and a parameter both in the
/// file and in `[params]` (drawn or fixed: the file's value would silently replace it).
pub(super) fn parse_operating_points(
    top: &Section,
    base: &Params,
    drawn: &[DrawnParam],
    design: Design,
    dir: &Path,
) -> Result<Option<OperatingPoints>, StudyError> {
    let Some(v) = top.get("operating_points") else {
        return Ok(None);
    };
    let t = Section::of(v, "operating_points", "a table")?;
    t.deny_unknown(&["file", "weight"])?;
    let file = t.req("file", toml_input::text)?;
    let weight = t.opt("weight", toml_input::text)?;
    if design != Design::Random {
        return Err(StudyError::OperatingPoints(format!(
            "`design` = \"{design}\" cannot draw measured operating points: rows are drawn at random in proportion to their weights, which the stratified axes of a `{design}` design cannot express; use design = \"random\""
        )));
    }
    let cross = drawn
        .iter()
        .any(|d| ParamId::CROSS_RULES.contains(&d.param));
    let op = OperatingPoints::load(file, weight, dir, base, cross)
        .map_err(|e| StudyError::OperatingPoints(e.to_string()))?;
    let named = top.get("params").and_then(|p| p.as_table());
    for name in &op.names {
        if let Some(how) = named
            .and_then(|p| p.get(*name))
            .map(|v| match v.is_table() {
                true if drawn.iter().any(|d| d.param.name() == *name) => "drawn",
                _ => "fixed",
            })
        {
            return Err(StudyError::OperatingPoints(format!(
                "{}: column `{name}` is also {how} in [params] (`params.{name}`); a parameter comes from the file or from [params], not both",
                op.path.display()
            )));
        }
    }
    Ok(Some(op))
}

impl Study {
    /// Names of a sample's values: the drawn parameters, then the operating-point columns.
    pub fn value_names(&self) -> Vec<&'static str> {
        let op = self.operating_points.iter().flat_map(|o| o.names.iter());
        self.drawn
            .iter()
            .map(|d| d.param.name())
            .chain(op.copied())
            .collect()
    }
}

impl Sampler<'_> {
    /// [`Sampler::sample`], with the operating-point row the sample drew (0-based), if any; the
    /// values are in [`Study::value_names`] order.
    pub fn sample_with_row(&self, index: u64) -> (Params, Vec<f64>, Option<usize>) {
        let (mut p, mut values) = self.sample(index);
        let Some(op) = &self.study.operating_points else {
            return (p, values, None);
        };
        let row = op.draw(&self.streams, index);
        for (name, v) in op.names.iter().zip(&op.values[row]) {
            *p.get_mut(name)
                .expect("operating-point columns are parameter names") = *v;
            values.push(*v);
        }
        (p, values, Some(row))
    }
}
