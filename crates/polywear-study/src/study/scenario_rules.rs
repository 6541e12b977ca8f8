//! Changed values through the checks every direct input gets: the plausible ranges
//! (MODEL.md#parameter-table) and the cross-parameter rules of `Params::validate`, before any
//! work, for a scenario's changes and for `optimize`'s settings alike. A change is applied to
//! the values that judge the baseline (its fixed values, its distributions' bounds or centres,
//! its operating points' extremes); every change is monotone (set, shift, positive scale, cap),
//! so the changed extremes bound the changed samples.

use super::schema::ORDERED_PAIRS;
use super::{ParamChange, Study, StudyError};
use polywear_core::params::{ParamError, ParamId};
use polywear_core::wording::plain;

/// A cross-parameter rule that a set of changes breaks for some sample.
#[derive(Debug, Clone, PartialEq)]
pub struct BrokenRule {
    /// The change that takes part in the rule (the first of the two parameters changed).
    pub change: ParamChange,
    /// The parameter that must not exceed the other.
    pub small: ParamId,
    /// The other.
    pub large: ParamId,
    /// The largest value `small` takes with the changes.
    pub small_max: f64,
    /// The smallest value `large` takes with them.
    pub large_min: f64,
    /// Why the rule holds, in words.
    pub why: &'static str,
    /// "at most" or "below".
    pub bound: &'static str,
}

impl BrokenRule {
    /// The rule and how it is broken, in words:
    /// `gives mu_s up to 0.9 and mu_m down to 0.76, and samples with ...`.
    pub fn words(&self) -> String {
        let (small, large) = (self.small, self.large);
        format!(
            "gives {small} up to {} and {large} down to {}, and samples with {small} above {large} would fail ({}); accepted: {small} {} {large} in every sample",
            plain(self.small_max, 6),
            plain(self.large_min, 6),
            self.why,
            self.bound,
        )
    }
}

impl Study {
    /// Refuses the first scenario whose changed values are implausible (unless
    /// `accept_implausible` or the study's `accept_implausible`) or break a cross-parameter rule
    /// for some sample, naming the scenario's key and what is accepted.
    pub fn check_scenario_rules(&self, accept_implausible: bool) -> Result<(), StudyError> {
        for s in &self.scenarios {
            for c in &s.changes {
                if let Some(own) = self.per_axle_beside(c.param) {
                    return Err(StudyError::DrawnRule(format!(
                        "`{}`: the study gives this quantity per axle (`params.{own}`), so the shared `{}` is read by no wheel; change the axles' keys",
                        s.key(c.param),
                        c.param
                    )));
                }
            }
            if !(accept_implausible || self.accept_implausible) {
                for c in &s.changes {
                    if let Err(source) = self.check_change_plausible(*c) {
                        return Err(StudyError::Param {
                            key: format!("{}.{}", s.key(c.param), c.change.kind()),
                            source,
                        });
                    }
                }
            }
            if let Some(b) = self.broken_rule(&s.changes) {
                return Err(StudyError::DrawnRule(format!(
                    "`{}` = {}: the scenario {}",
                    s.key(b.change.param),
                    b.change.change.text(),
                    b.words()
                )));
            }
        }
        Ok(())
    }

    /// An axle's own key of `shared`'s quantity that the study gives, when `shared` is a shared
    /// key (`toe_rear_deg` beside `toe_deg`; MODEL.md#the-car-axles-and-drivetrain).
    pub(crate) fn per_axle_beside(&self, shared: ParamId) -> Option<ParamId> {
        let q = shared.axle_quantity().filter(|q| q.shared == shared)?;
        [q.front, q.rear]
            .into_iter()
            .find(|&id| self.sets(id).is_some())
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

    /// Refuses `change` when it makes a value that judges its parameter implausible.
    pub fn check_change_plausible(&self, change: ParamChange) -> Result<(), ParamError> {
        for x in self.judged_values(change.param) {
            change
                .param
                .spec()
                .check_plausible(change.change.apply(x))?;
        }
        Ok(())
    }

    /// The values of `param` over the samples with `changes` applied.
    fn changed_range(&self, changes: &[ParamChange], param: ParamId) -> (f64, f64) {
        let range = self.value_range(param);
        let (lo, hi) = changes
            .iter()
            .filter(|c| c.param == param)
            .fold((range.lo, range.hi), |(lo, hi), c| {
                (c.change.apply(lo), c.change.apply(hi))
            });
        (lo.min(hi), lo.max(hi))
    }

    /// The first rule of `Params::validate` that orders two parameters which `changes` break
    /// for some sample; rules neither of whose parameters is changed are the baseline's, checked
    /// when the study is read.
    pub fn broken_rule(&self, changes: &[ParamChange]) -> Option<BrokenRule> {
        let changed = |p: ParamId| changes.iter().find(|c| c.param == p).copied();
        ORDERED_PAIRS.iter().find_map(|rule| {
            let change = changed(rule.small).or_else(|| changed(rule.large))?;
            let (_, small_max) = self.changed_range(changes, rule.small);
            let (large_min, _) = self.changed_range(changes, rule.large);
            rule.broken(small_max, large_min).then_some(BrokenRule {
                change,
                small: rule.small,
                large: rule.large,
                small_max,
                large_min,
                why: rule.why,
                bound: rule.bound_words(),
            })
        })
    }
}
