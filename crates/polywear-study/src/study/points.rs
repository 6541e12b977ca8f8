//! A study's `[operating_points]` section: the file it names, read and checked against the
//! rest of the study (see [`crate::operating_points`]).

use std::path::Path;

use super::schema::OperatingPointsSection;
use super::{DrawnParam, Sampler, Study, StudyError};
use crate::operating_points::OperatingPoints;
use polywear_core::params::{ParamId, Params};
use polywear_core::sampling::design::Design;

/// Reads `[operating_points]`'s file and checks it against the rest of the study. Refused: a
/// design other than random (stratifying axes says nothing about drawing rows), and a parameter
/// both in the file and in `[params]` (drawn or `fixed`: the file's value would silently
/// replace it).
pub(super) fn operating_points(
    section: &OperatingPointsSection,
    base: &Params,
    drawn: &[DrawnParam],
    fixed: &[ParamId],
    design: Design,
    dir: &Path,
) -> Result<OperatingPoints, StudyError> {
    if design != Design::Random {
        return Err(StudyError::OperatingPoints(format!(
            "`design` = \"{design}\" cannot draw measured operating points: rows are drawn at random in proportion to their weights, which the stratified axes of a `{design}` design cannot express; use design = \"random\""
        )));
    }
    if section.file.trim().is_empty() {
        return Err(StudyError::OperatingPoints(
            "`operating_points.file` is empty; accepted: a CSV or Parquet file, relative to the study's folder".into(),
        ));
    }
    let cross = drawn
        .iter()
        .any(|d| ParamId::CROSS_RULES.contains(&d.param));
    let pass_through = section.pass_through.clone().unwrap_or_default();
    let op = OperatingPoints::load(
        &section.file,
        section.weight.as_deref(),
        &pass_through,
        dir,
        base,
        cross,
    )
    .map_err(|e| StudyError::OperatingPoints(e.to_string()))?;
    if cross {
        check_rows_against_draws(&op, base, drawn)?;
    }
    for name in &op.names {
        let how = if drawn.iter().any(|d| d.param.name() == *name) {
            "drawn"
        } else if fixed.iter().any(|f| f.name() == *name) {
            "fixed"
        } else {
            continue;
        };
        return Err(StudyError::OperatingPoints(format!(
            "{}: column `{name}` is also {how} in [params] (`params.{name}`); a parameter comes from the file or from [params], not both",
            op.path.display()
        )));
    }
    Ok(op)
}

/// Refuses a row of the file that a draw can push across an ordering rule (μ_s ≤ μ_m,
/// n_d ≤ n_w): each row with the drawn parameters at their worst bounds must hold.
fn check_rows_against_draws(
    op: &OperatingPoints,
    base: &Params,
    drawn: &[DrawnParam],
) -> Result<(), StudyError> {
    use super::schema::{value_range, ORDERED_PAIRS};
    use polywear_core::wording::plain;
    for (i, row) in op.values.iter().enumerate() {
        let mut p = *base;
        for (name, v) in op.names.iter().zip(row) {
            let id: ParamId = name
                .parse()
                .expect("an operating-point column is a parameter");
            p[id] = *v;
        }
        for rule in &ORDERED_PAIRS {
            let (small, large, why) = (rule.small, rule.large, rule.why);
            let ((_, small_max), small_drawn) = value_range(&p, drawn, small);
            let ((large_min, _), large_drawn) = value_range(&p, drawn, large);
            if (small_drawn || large_drawn) && rule.broken(small_max, large_min) {
                return Err(StudyError::OperatingPoints(format!(
                    "{}, row {}: with the draws of [params], {small} reaches {} and {large} falls to {}: samples drawing this row would fail ({why})",
                    op.path.display(),
                    i + 1,
                    plain(small_max, 6),
                    plain(large_min, 6)
                )));
            }
        }
    }
    Ok(())
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
        let (mut p, mut values) = self.design_sample(index);
        let Some(op) = &self.study.operating_points else {
            return (p, values, None);
        };
        let row = op.draw(&self.streams, index);
        for (&id, v) in self.op_params.iter().zip(&op.values[row]) {
            p[id] = *v;
            values.push(*v);
        }
        (p, values, Some(row))
    }
}
