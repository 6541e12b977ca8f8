//! `polywear optimize`: the setting of one or two parameters, within a box, that minimises the
//! risk of polygonal wear (or of vibration, or a weighted sum) over a study's samples.
//!
//! A *setting* of a parameter the study fixes is its value (`set`). For a drawn parameter it
//! moves the distribution so that its centre is the value and keeps the fleet's spread: every
//! sample's value moves by the same amount (`shift`; the centre is a uniform's midpoint, a
//! normal's or truncated normal's mean, the mean of levels or of an operating-point column),
//! or, for a lognormal, is scaled by the same factor (`scale`; the centre is its median). Every
//! setting is evaluated on the same samples (common random numbers), so two settings differ
//! only by the setting. The search ([`search`]) is a coarse grid refined where it matters; the
//! objective ([`objective`]) comes with its 95% interval, and the result says how flat the
//! optimum is: the settings whose objective lies within the best's interval.

pub mod evaluate;
pub mod input;
pub mod objective;
mod request;
pub mod search;

pub use request::ProblemSpec;

use crate::calibration_band::CalibrationBand;
use crate::study::{Change, ParamChange, Study, StudyError};
use objective::{Estimate, Objective, Outcomes, Term, WheelChoice};
use polywear_core::classify::ClassifierOptions;
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::params::ParamId;
use polywear_core::sampling::distribution::Distribution;
use search::{Evaluated, SearchOptions};

/// How a setting of a parameter changes the study's samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SettingKind {
    /// The study fixes the parameter: the setting is its value.
    Set,
    /// Drawn: every sample moves by (setting − centre).
    Shift {
        /// The distribution's centre.
        centre: f64,
    },
    /// Drawn lognormal: every sample is scaled by setting / median.
    Scale {
        /// The distribution's median.
        median: f64,
    },
}

/// One varied parameter and its range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// The parameter.
    pub param: ParamId,
    /// The box's lower end (a setting).
    pub lo: f64,
    /// Its upper end.
    pub hi: f64,
    /// What a setting does to the samples.
    pub kind: SettingKind,
}

impl Axis {
    /// The axis of `param` over [lo, hi] in `study`, its kind from how the study gives it.
    pub fn new(study: &Study, param: ParamId, lo: f64, hi: f64) -> Axis {
        let kind = match study.drawn.iter().find(|d| d.param == param) {
            Some(d) => match &d.dist {
                Distribution::LogNormal { median, .. } => SettingKind::Scale { median: *median },
                dist => SettingKind::Shift {
                    centre: centre(dist),
                },
            },
            None => match column_mean(study, param) {
                Some(centre) => SettingKind::Shift { centre },
                None => SettingKind::Set,
            },
        };
        Axis {
            param,
            lo,
            hi,
            kind,
        }
    }

    /// The setting at unit coordinate `u`. A whole-number parameter (a count of wheels) takes
    /// whole values only, or, drawn, moves its samples by whole steps: the nearest such setting
    /// inside the box, so that no setting evaluates 3.75 wheels.
    pub fn value(&self, u: f64) -> f64 {
        let raw = if u >= 1.0 {
            self.hi
        } else {
            self.lo + u * (self.hi - self.lo)
        };
        if !self.param.spec().integer {
            return raw;
        }
        let offset = match self.kind {
            SettingKind::Set => 0.0,
            SettingKind::Shift { centre } => centre,
            SettingKind::Scale { .. } => return raw,
        };
        let mut v = offset + (raw - offset).round();
        if v < self.lo {
            v += 1.0;
        }
        if v > self.hi {
            v -= 1.0;
        }
        v
    }

    /// Whether every setting of the box is a whole step of a whole-number parameter: the box
    /// holds at least one, and a fixed one's ends are whole.
    pub fn whole_steps_fit(&self) -> bool {
        if !self.param.spec().integer {
            return true;
        }
        let (lo, hi) = (self.value(0.0), self.value(1.0));
        let inside = (self.lo..=self.hi).contains(&lo) && (self.lo..=self.hi).contains(&hi);
        match self.kind {
            SettingKind::Set => inside && self.lo.fract() == 0.0 && self.hi.fract() == 0.0,
            _ => inside,
        }
    }

    /// The first lattice index of `lattice` steps whose setting equals index `k`'s (a whole-number
    /// parameter has fewer settings than lattice points: each is evaluated once).
    pub fn canonical_index(&self, k: i64, lattice: i64) -> i64 {
        let at = |k: i64| self.value(k as f64 / lattice as f64);
        let v = at(k);
        let (mut lo, mut hi) = (0, k);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if at(mid) < v {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        lo
    }

    /// The change a setting makes to every sample.
    pub fn change(&self, setting: f64) -> ParamChange {
        let change = match self.kind {
            SettingKind::Set => Change::Set(setting),
            SettingKind::Shift { centre } => Change::Shift(setting - centre),
            SettingKind::Scale { median } => Change::Scale(setting / median),
        };
        ParamChange {
            param: self.param,
            change,
        }
    }

    /// What a setting means for this parameter, in words.
    pub fn meaning(&self) -> String {
        match self.kind {
            SettingKind::Set => format!("{}: the value every sample takes", self.param),
            SettingKind::Shift { centre } => format!(
                "{}: the centre of its distribution (now {}), every sample moved by the same amount",
                self.param,
                polywear_core::wording::plain(centre, 6)
            ),
            SettingKind::Scale { median } => format!(
                "{}: the median of its lognormal distribution (now {}), every sample scaled by the same factor",
                self.param,
                polywear_core::wording::plain(median, 6)
            ),
        }
    }

    /// Refuses a box end that takes any of the run's samples outside the parameter's accepted
    /// range (the change is monotone in the setting, so the two ends decide).
    pub fn check(
        &self,
        study: &Study,
        seed: u64,
        samples: u64,
        key: &str,
    ) -> Result<(), StudyError> {
        for end in [self.lo, self.hi] {
            study.check_change(key, self.change(end), seed, samples)?;
        }
        Ok(())
    }
}

/// The centre of a location family: midpoint, mean, or mean of the levels.
fn centre(dist: &Distribution) -> f64 {
    match dist {
        Distribution::Uniform { min, max, .. } => 0.5 * (min + max),
        Distribution::Normal { mean, .. } | Distribution::TruncatedNormal { mean, .. } => *mean,
        Distribution::LogNormal { median, .. } => *median,
        Distribution::Levels(levels) => levels.iter().sum::<f64>() / levels.len() as f64,
    }
}

/// The weighted mean of an operating-point column, when the study draws `param` from one.
fn column_mean(study: &Study, param: ParamId) -> Option<f64> {
    let op = study.operating_points.as_ref()?;
    let j = op.names.iter().position(|n| *n == param.name())?;
    // Relative to the largest weight, so that weights near the largest float sum without
    // overflow.
    let largest = op.weights.iter().fold(0.0f64, |m, w| m.max(*w));
    let total: f64 = op.weights.iter().map(|w| w / largest).sum();
    Some(
        op.values
            .iter()
            .zip(&op.weights)
            .map(|(row, w)| row[j] * (w / largest))
            .sum::<f64>()
            / total,
    )
}

/// A bound a setting must meet: on a risk (its estimate), as `--constraint vibration:driving<=0.3`
/// writes it.
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// The risk.
    pub term: Term,
    /// On which wheel.
    pub wheel: WheelChoice,
    /// At most (true) or at least (false).
    pub at_most: bool,
    /// The bound, as a probability.
    pub bound: f64,
    /// The constraint as given.
    pub text: String,
}

impl Constraint {
    /// The objective whose estimate the constraint bounds.
    pub fn objective(&self) -> Objective {
        Objective {
            terms: vec![(1.0, self.term)],
            wheel: self.wheel,
        }
    }

    /// Whether `e` meets it.
    pub fn holds(&self, e: &Estimate) -> bool {
        if self.at_most {
            e.value <= self.bound
        } else {
            e.value >= self.bound
        }
    }
}

/// What `optimize` is asked, checked: built by [`Problem::new`] from a [`ProblemSpec`].
#[derive(Debug, Clone)]
#[non_exhaustive]
pub struct Problem {
    /// The study whose samples every setting is evaluated on.
    pub study: Study,
    /// The seed of its draws.
    pub seed: u64,
    /// Samples per setting.
    pub samples: u64,
    /// The friction variant both wheels are evaluated under.
    pub variant: Variant,
    /// One or two varied parameters.
    pub axes: Vec<Axis>,
    /// What is minimised.
    pub objective: Objective,
    /// Bounds on risks a setting must meet.
    pub constraints: Vec<Constraint>,
    /// A visible polygon counts when it appears within this distance \[km\].
    pub within_km: f64,
    /// How far the search refines.
    pub search: SearchOptions,
    /// The classifier's options (the study's work budget).
    pub classifier: ClassifierOptions,
    /// The wear stage, when the objective or a constraint weighs wear.
    pub wear: Option<polywear_core::evaluate::WearStage>,
    /// Every constraint as given, the bounds on varied parameters included (in the metadata).
    pub given_constraints: Vec<String>,
    /// The calibrated sets every setting's wear answer is also evaluated under, on the same
    /// samples (None: the run's constants alone).
    pub band: Option<ProblemBand>,
    /// Why the default band was left out, where it would otherwise have applied.
    pub band_note: Option<String>,
}

/// The calibrated sets of an optimisation (MODEL.md#the-calibration-band) and where they come
/// from.
#[derive(Debug, Clone)]
pub struct ProblemBand {
    /// The sets.
    pub sets: CalibrationBand,
    /// A file's path, or [`crate::calibration_band::SHIPPED_NAME`].
    pub source: String,
    /// Asked for by name (refused where it cannot apply), not by default (then left out, with
    /// a note where it would have moved the wear answer).
    pub given: bool,
    /// Samples the sets are evaluated on: all of them where the run has at most this many,
    /// else a subsample, each set's objective then the run's own on every sample plus the
    /// set's paired difference on the subsample (a control variate).
    pub samples: u64,
}

/// Samples optimize evaluates the calibrated sets on by default: a fifth of its default
/// 10,000, the paired differences between a set and the run's own constants varying far less
/// than either.
pub const DEFAULT_BAND_SAMPLES: u64 = 2_000;

/// A setting's objective under one calibrated set, on the same samples.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetEstimate {
    /// The objective.
    pub objective: Estimate,
    /// Whether every constraint holds under the set.
    pub feasible: bool,
}

impl Problem {
    /// The box of axis `k` widened on its `lower` (or upper) side, for an optimum on that edge:
    /// by the box's own width, halved until every sample stays in the parameter's accepted
    /// range and the setting in its plausible one (unless the study accepts implausible
    /// values), the new end rounded to 3 digits where that still fits; None where that side
    /// cannot move.
    pub fn widened(&self, k: usize, lower: bool) -> Option<(f64, f64)> {
        let a = self.axes[k];
        let s = a.param.spec();
        let fits = |lo: f64, hi: f64| {
            let end = if lower { lo } else { hi };
            let plausible = self.study.accept_implausible || s.check_plausible(end).is_ok();
            let wider = Axis { lo, hi, ..a };
            let in_range = match a.kind {
                SettingKind::Set => s.check(end).is_ok(),
                _ => wider
                    .check(&self.study, self.seed, self.samples, "")
                    .is_ok(),
            };
            plausible && in_range && s.check(end).is_ok()
        };
        let mut step = a.hi - a.lo;
        for _ in 0..30 {
            let (lo, hi) = if lower {
                (a.lo - step, a.hi)
            } else {
                (a.lo, a.hi + step)
            };
            if fits(lo, hi) {
                let end = if lower { lo } else { hi };
                // Three digits, rounded into the box so that the rounding cannot leave it.
                let unit = 10f64.powf(end.abs().log10().floor() - 2.0);
                let rounded = if lower {
                    (end / unit).ceil() * unit
                } else {
                    (end / unit).floor() * unit
                };
                let inward = rounded.is_finite() && (rounded >= end) == lower;
                let (rlo, rhi) = if lower { (rounded, hi) } else { (lo, rounded) };
                let moved = if lower { rlo < a.lo } else { rhi > a.hi };
                return Some(if inward && moved && fits(rlo, rhi) {
                    (rlo, rhi)
                } else {
                    (lo, hi)
                });
            }
            step /= 2.0;
        }
        None
    }

    /// Where the nominal tire (the study's median values) changes stability along the first
    /// axis, per wheel: the sign changes of max Re λ (MODEL.md#step-8-linear-stability) on a
    /// scan of 400 steps, each placed by linear interpolation.
    pub fn nominal_stability_changes(&self) -> Vec<(Wheel, f64)> {
        let a = &self.axes[0];
        let mut base = self.study.base;
        for d in &self.study.drawn {
            base[d.param] = d.dist.quantile(0.5);
        }
        const SCAN: usize = 400;
        let mut changes = Vec::new();
        for wheel in Wheel::BOTH {
            let re: Vec<(f64, f64)> = (0..=SCAN)
                .map(|i| {
                    let x = a.value(i as f64 / SCAN as f64);
                    let mut p = base;
                    p[a.param] = x;
                    let re = WheelModel::build(&p, wheel, self.variant)
                        .map_or(f64::NAN, |m| m.ode.linear_stability().eig_re_max);
                    (x, re)
                })
                .collect();
            for w in re.windows(2) {
                let ((x0, r0), (x1, r1)) = (w[0], w[1]);
                if r0.is_finite() && r1.is_finite() && (r0 > 0.0) != (r1 > 0.0) {
                    changes.push((wheel, x0 + (x1 - x0) * r0 / (r0 - r1)));
                }
            }
        }
        changes
    }
}

/// One evaluated setting.
#[derive(Debug, Clone)]
pub struct Setting {
    /// The value of each varied parameter, in axis order.
    pub values: Vec<f64>,
    /// Where it lies in the unit box.
    pub unit: Vec<f64>,
    /// The refinement level it was added at.
    pub level: usize,
    /// The objective.
    pub objective: Estimate,
    /// Each constraint's estimate, in order.
    pub constrained: Vec<Estimate>,
    /// Whether every constraint holds.
    pub feasible: bool,
    /// Every sample's outcomes, in sample order.
    pub outcomes: Vec<Outcomes>,
    /// The objective under each calibrated set, in the band's order (empty without a band).
    pub band: Vec<SetEstimate>,
}

/// The search's result.
#[derive(Debug, Clone)]
pub struct Solution {
    /// Every setting evaluated, in order.
    pub settings: Vec<Setting>,
    /// The best feasible setting, if any.
    pub best: Option<usize>,
    /// Each setting minus the best on the same samples, with its 95% interval (NaN without a
    /// best).
    pub vs_best: Vec<(f64, f64, f64)>,
}

impl Solution {
    /// The feasible settings whose objective lies within the best's 95% interval: how flat the
    /// optimum is.
    pub fn within_best(&self) -> Vec<usize> {
        let Some(b) = self.best else {
            return Vec::new();
        };
        let high = self.settings[b].objective.high;
        (0..self.settings.len())
            .filter(|&i| {
                let s = &self.settings[i];
                s.feasible && s.objective.value <= high
            })
            .collect()
    }

    /// The best feasible setting under each calibrated set, among the settings evaluated (the
    /// search refines around the run's own optimum), ties to the first as
    /// [`search::best`]'s; empty without a band.
    pub fn band_optima(&self) -> Vec<Option<usize>> {
        let sets = self.settings.first().map_or(0, |s| s.band.len());
        (0..sets)
            .map(|k| {
                (0..self.settings.len())
                    .filter(|&i| {
                        let e = &self.settings[i].band[k];
                        e.feasible && e.objective.value.is_finite()
                    })
                    .min_by(|&a, &b| {
                        let v = |i: usize| self.settings[i].band[k].objective.value;
                        v(a).total_cmp(&v(b)).then(a.cmp(&b))
                    })
            })
            .collect()
    }

    /// The axes on whose edge the best setting lies: (axis index, "lower" or "upper").
    pub fn on_edge(&self) -> Vec<(usize, &'static str)> {
        match self.best {
            Some(b) => self.edges_of(b),
            None => Vec::new(),
        }
    }

    /// The axes on whose edge setting `i` lies: (axis index, "lower" or "upper").
    pub fn edges_of(&self, i: usize) -> Vec<(usize, &'static str)> {
        let unit = &self.settings[i].unit;
        unit.iter()
            .enumerate()
            .filter_map(|(k, &u)| match u {
                u if u <= 0.0 => Some((k, "lower")),
                u if u >= 1.0 => Some((k, "upper")),
                _ => None,
            })
            .collect()
    }
}

/// Turns the search's evaluations back into settings (the order is the same).
pub(crate) fn collect(
    points: &[Evaluated],
    mut settings: Vec<Setting>,
    objective: &Objective,
) -> Solution {
    for (s, p) in settings.iter_mut().zip(points) {
        s.level = p.level;
    }
    let best = search::best(points);
    let vs_best = match best {
        Some(b) => settings
            .iter()
            .map(|s| objective.paired_difference(&s.outcomes, &settings[b].outcomes))
            .collect(),
        None => vec![(f64::NAN, f64::NAN, f64::NAN); settings.len()],
    };
    Solution {
        settings,
        best,
        vs_best,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_setting_sets_a_fixed_parameter_and_moves_a_drawn_ones_centre() {
        let study = Study::parse(
            r#"[params]
               toe_deg = { dist = "uniform", min = 0.2, max = 0.4 }
               g_mod = { dist = "lognormal", median = 1e6, sigma = 0.05 }
               load_n = 4500"#,
        )
        .unwrap();
        let toe = Axis::new(&study, ParamId::ToeDeg, 0.1, 0.5);
        assert_eq!(
            toe.kind,
            SettingKind::Shift {
                centre: 0.30000000000000004
            }
        );
        let c = toe.change(0.1);
        assert!(
            matches!(c.change, Change::Shift(d) if (d + 0.2).abs() < 1e-15),
            "{c:?}"
        );
        let g = Axis::new(&study, ParamId::GMod, 0.5e6, 2e6);
        assert_eq!(g.change(2e6).change, Change::Scale(2.0));
        let load = Axis::new(&study, ParamId::LoadN, 3000.0, 5000.0);
        assert_eq!(load.kind, SettingKind::Set);
        assert_eq!(load.change(3500.0).change, Change::Set(3500.0));
        assert_eq!(
            (load.value(0.0), load.value(0.5), load.value(1.0)),
            (3000.0, 4000.0, 5000.0)
        );
    }
}
