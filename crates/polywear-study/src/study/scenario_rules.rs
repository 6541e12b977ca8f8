//! A scenario's changed values through the checks every direct input gets: the plausible ranges
//! (MODEL.md#parameter-table) and the cross-parameter rules of `Params::validate`, before any
//! work. A change is applied to the values that judge the baseline (its fixed values, its
//! distributions' bounds or centres, its operating points' extremes); every change is monotone
//! (set, shift, positive scale, cap), so the changed extremes bound the changed samples.

use super::schema::ORDERED_PAIRS;
use super::{Scenario, Study, StudyError};
use polywear_core::params::ParamId;
use polywear_core::wording::plain;

impl Study {
    /// Refuses the first scenario whose changed values are implausible (unless `accept_implausible`
    /// or the study's `accept_implausible`) or break a cross-parameter rule for some sample,
    /// naming the scenario's key and what is accepted.
    pub fn check_scenario_rules(&self, accept_implausible: bool) -> Result<(), StudyError> {
        for s in &self.scenarios {
            if !(accept_implausible || self.accept_implausible) {
                self.check_scenario_plausible(s)?;
            }
            self.check_scenario_cross_rules(s)?;
        }
        Ok(())
    }

    /// The values that judge `param` in the baseline, as the study's plausibility check judges
    /// them: a fixed value, a distribution's bounds or centre, an operating-point column's
    /// extremes.
    fn judged_values(&self, param: ParamId) -> Vec<f64> {
        if let Some(d) = self.drawn.iter().find(|d| d.param == param) {
            return d.judged_values().into_iter().map(|(_, x)| x).collect();
        }
        let range = self.value_range(param);
        vec![range.lo, range.hi]
    }

    fn check_scenario_plausible(&self, s: &Scenario) -> Result<(), StudyError> {
        for c in &s.changes {
            for x in self.judged_values(c.param) {
                let changed = c.change.apply(x);
                c.param
                    .spec()
                    .check_plausible(changed)
                    .map_err(|source| StudyError::Param {
                        key: format!("{}.{}", s.key(c.param), c.change.kind()),
                        source,
                    })?;
            }
        }
        Ok(())
    }

    /// The scenario's values of `param` over the samples: the baseline's, changed.
    fn scenario_range(&self, s: &Scenario, param: ParamId) -> (f64, f64) {
        let range = self.value_range(param);
        let (lo, hi) = s
            .changes
            .iter()
            .filter(|c| c.param == param)
            .fold((range.lo, range.hi), |(lo, hi), c| {
                (c.change.apply(lo), c.change.apply(hi))
            });
        (lo.min(hi), lo.max(hi))
    }

    fn check_scenario_cross_rules(&self, s: &Scenario) -> Result<(), StudyError> {
        // The rules of `Params::validate` that order two parameters, on the scenario's extremes
        // (the baseline's own are checked when the study is read).
        let changes = |p: ParamId| s.changes.iter().find(|c| c.param == p);
        for rule in &ORDERED_PAIRS {
            let (small, large) = (rule.small, rule.large);
            let change = match (changes(small), changes(large)) {
                (Some(c), _) | (None, Some(c)) => c,
                (None, None) => continue,
            };
            let (_, small_max) = self.scenario_range(s, small);
            let (large_min, _) = self.scenario_range(s, large);
            if !rule.broken(small_max, large_min) {
                continue;
            }
            return Err(StudyError::DrawnRule(format!(
                "`{}` = {}: the scenario gives {small} up to {} and {large} down to {}, and samples with {small} above {large} would fail ({}); accepted: {small} {} {large} in every sample",
                s.key(change.param),
                change.change.text(),
                plain(small_max, 6),
                plain(large_min, 6),
                rule.why,
                rule.bound_words(),
            )));
        }
        Ok(())
    }
}
