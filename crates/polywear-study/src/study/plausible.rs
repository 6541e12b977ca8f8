//! A study's values against the parameters' plausible ranges (MODEL.md#parameter-table): its
//! fixed values, the bounds its distributions can reach, and every row of its
//! `[operating_points]` file. A drawn distribution is judged by its hard bounds (a uniform's or
//! truncated normal's `min` and `max`, every level) and, where it has none, by its centre (a
//! normal's `mean`, a lognormal's `median`): an unbounded tail always reaches past a plausible
//! range, and the accepted range already bounds it (`TailOutOfRange`).

use super::{DrawnParam, Study, StudyError};
use polywear_core::params::ParamError;
use polywear_core::sampling::distribution::Distribution;

impl Study {
    /// Refuses the first implausible value the study gives, naming its key (`params.NAME`,
    /// `params.NAME.min`, `params.NAME.levels[2]`) or the operating-point file's row and column.
    /// Nothing is refused when the study says `accept_implausible = true`.
    pub fn check_plausible(&self) -> Result<(), StudyError> {
        if self.accept_implausible {
            return Ok(());
        }
        for &id in &self.fixed {
            id.spec()
                .check_plausible(self.base[id])
                .map_err(|source| StudyError::Param {
                    key: format!("params.{id}"),
                    source,
                })?;
        }
        for d in &self.drawn {
            d.check_plausible()?;
        }
        if let Some(op) = &self.operating_points {
            op.check_plausible()
                .map_err(|e| StudyError::OperatingPoints(e.to_string()))?;
        }
        Ok(())
    }
}

impl DrawnParam {
    /// The values that judge the distribution, each with the key it is written under.
    pub(super) fn judged_values(&self) -> Vec<(String, f64)> {
        let key = |field: &str| format!("params.{}.{field}", self.param);
        match &self.dist {
            Distribution::Uniform { min, max, .. }
            | Distribution::TruncatedNormal { min, max, .. } => {
                vec![(key("min"), *min), (key("max"), *max)]
            }
            Distribution::Normal { mean, .. } => vec![(key("mean"), *mean)],
            Distribution::LogNormal { median, .. } => vec![(key("median"), *median)],
            Distribution::Levels(levels) => levels
                .iter()
                .enumerate()
                .map(|(i, x)| (key(&format!("levels[{i}]")), *x))
                .collect(),
        }
    }

    /// Refuses a distribution whose hard bounds, or whose centre where it has no bounds, are
    /// implausible (see the module docs).
    pub fn check_plausible(&self) -> Result<(), StudyError> {
        for (key, x) in self.judged_values() {
            self.param
                .spec()
                .check_plausible(x)
                .map_err(|source: ParamError| StudyError::Param { key, source })?;
        }
        Ok(())
    }
}
