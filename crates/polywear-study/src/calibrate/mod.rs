//! Calibration: fits chosen parameters to target observations of either wheel under any variant
//! (Hopf points of any axis, linear vibration frequency, the driving-to-follower amplitude
//! ratio), by Levenberg–Marquardt on log-parameters with an optional prior that pulls toward the
//! starting values, and reports the fit's sensitivities. A decoded constant may be restricted to
//! its lost-digit alternatives (`[choices]`): every combination of choices is fitted and the best
//! kept, so that a fit never breaks a digit the paper shows.
//!
//! Targets come from a TOML file (`studies/paper_targets.toml` holds the paper's); the fitted
//! values are written as a parameter file that `simulate`, `bifurcation` and `explore` read with
//! `--params FILE`.

mod lm;
mod targets;

pub use lm::levenberg_marquardt;
pub use targets::{check_fit, parse_problem, TargetsError};

use crate::bifurcation::eig_re;
use polywear_core::classify::ClassifierOptions;
use polywear_core::ensemble::Control;
use polywear_core::model::{Variant, Wheel, WheelModel};
use polywear_core::numeric::sign_change_roots;
use polywear_core::params::{ParamError, ParamId, Params, Provenance};

/// What a target observes.
#[derive(Debug, Clone, PartialEq)]
pub enum Observable {
    /// The value of `param` in [from, to] where Re λ changes sign (a Hopf point).
    Hopf {
        /// The parameter swept.
        param: ParamId,
        /// Start of the searched range.
        from: f64,
        /// End of the searched range.
        to: f64,
    },
    /// The linear vibration frequency |Im λ|/2π \[Hz\] at a point given by `at`.
    Frequency {
        /// The point: (parameter, value) pairs applied on top of the parameters.
        at: Vec<(ParamId, f64)>,
    },
    /// The limit-cycle amplitude (half peak-to-peak of y) of the target's wheel divided by that
    /// of `relative_to`, at the point `at` (0 where the target's wheel is stable).
    AmplitudeRatio {
        /// The point: (parameter, value) pairs applied on top of the parameters.
        at: Vec<(ParamId, f64)>,
        /// The wheel whose amplitude is the denominator.
        relative_to: Wheel,
    },
}

/// One observation to match.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// How the fit table names the target.
    pub name: String,
    /// What is observed.
    pub observable: Observable,
    /// The wheel observed.
    pub wheel: Wheel,
    /// The friction variant of the model.
    pub variant: Variant,
    /// The observed value.
    pub value: f64,
    /// Weight of its relative error in the cost.
    pub weight: f64,
    /// Relative error up to which the target counts as met; a fit with a target not met writes
    /// no parameter file (unless asked to).
    pub tolerance: f64,
}

/// A calibration problem. Built and checked by [`parse_problem`] (targets,
/// parameters and their bounds), never from literal fields outside this crate.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct Problem {
    /// Parameters fitted continuously (in log space).
    pub fit: Vec<ParamId>,
    /// Log-space standard deviation of the prior around the starting values (None: no prior).
    pub prior_sigma: Option<f64>,
    /// Starting values of every parameter.
    pub start: Params,
    /// The observations to match.
    pub targets: Vec<Target>,
    /// Parameters restricted to a few values each (e.g. a decoded constant's lost-digit
    /// alternatives); every combination is tried. Not fitted continuously.
    pub choices: Vec<(ParamId, Vec<f64>)>,
}

impl Problem {
    /// The problem with `names` fitted instead of the file's `fit` (a command line's `--fit`),
    /// checked as the file's is ([`check_fit`]): a name that is no parameter, one named twice
    /// and one the file's `choices` restrict are refused, the refusal starting with the name
    /// for the caller to prefix with its flag. Empty `names` keep the file's.
    pub fn fit_instead(&mut self, names: &[String]) -> Result<(), FitNameError> {
        if names.is_empty() {
            return Ok(());
        }
        let mut fit: Vec<ParamId> = Vec::new();
        for n in names {
            let name: ParamId = n.trim().parse()?;
            if fit.contains(&name) {
                return Err(FitNameError::Twice(name));
            }
            if self.choices.iter().any(|(c, _)| *c == name) {
                return Err(FitNameError::Restricted(name));
            }
            fit.push(name);
        }
        self.fit = fit;
        Ok(check_fit(self)?)
    }
}

/// A name a command line's `--fit` gives refused ([`Problem::fit_instead`]); the message starts
/// with the name, for the caller to prefix with its flag.
#[derive(Debug, thiserror::Error)]
pub enum FitNameError {
    /// Not a parameter.
    #[error(transparent)]
    Unknown(#[from] ParamError),
    /// Named twice.
    #[error("`{0}` is named twice")]
    Twice(ParamId),
    /// Restricted by the file's `choices`.
    #[error("`{0}` is restricted by the file's `choices`; it cannot also be fitted")]
    Restricted(ParamId),
    /// Refused as the file's `fit` is.
    #[error(transparent)]
    Fit(#[from] TargetsError),
}

/// The tire-structure and friction parameters MODEL.md#constants marks as decoded or reconstructed:
/// the default set to fit (the operating point is what targets vary; vehicle parameters do not act
/// on the follower).
pub(crate) fn default_fit() -> Vec<ParamId> {
    use polywear_core::params::Group;
    ParamId::ALL
        .iter()
        .copied()
        .filter(|id| {
            let s = id.spec();
            matches!(s.group, Group::TireStructure | Group::Friction)
                && matches!(
                    s.provenance,
                    Provenance::Decoded | Provenance::Reconstructed | Provenance::Fitted
                )
                && s.default > 0.0
        })
        .collect()
}

/// Why no parameter file is written for a fit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamFileError {
    /// The fitted values lie outside their accepted ranges.
    #[error("the fit diverged and no parameter file is written: {0}")]
    Diverged(ParamError),
    /// The cost became NaN or infinite.
    #[error("the fit diverged (non-finite cost) and no parameter file is written")]
    NonFiniteCost,
    /// Targets the fit does not meet within their tolerance.
    #[error("{} of {total} targets not met, so no parameter file is written: {}", shortfalls.len(), shortfalls.join("; "))]
    NotMet {
        /// Why each unmet target is not met.
        shortfalls: Vec<String>,
        /// Targets of the fit.
        total: usize,
    },
}

/// `p` with a target's `at` values set (the point where it is observed).
fn at_point(p: &Params, at: &[(ParamId, f64)]) -> Params {
    let mut q = *p;
    for &(id, x) in at {
        q[id] = x;
    }
    q
}

/// The model's value of a target's observable (NaN when undefined, e.g. no Hopf point in range).
pub fn observe(t: &Target, p: &Params) -> f64 {
    match &t.observable {
        Observable::Hopf { param, from, to } => {
            // The first sign change on a scan of 48 intervals, then Brent.
            let n = 48;
            let f = |x: f64| eig_re(p, *param, x, t.wheel, t.variant);
            let scan = (0..=n).map(move |i| {
                let x = from + (to - from) * i as f64 / n as f64;
                (x, f(x))
            });
            let first = sign_change_roots(scan, f, |_, x1| 1e-9 * x1.abs().max(1e-12), 200).next();
            first.map_or(f64::NAN, |c| c.root.unwrap_or(f64::NAN))
        }
        Observable::Frequency { at } => {
            let q = at_point(p, at);
            WheelModel::build(&q, t.wheel, t.variant)
                .map_or(f64::NAN, |m| m.ode.linear_stability().eig_freq_hz)
        }
        Observable::AmplitudeRatio { at, relative_to } => {
            let q = at_point(p, at);
            let opts = ClassifierOptions::default();
            let amp = |wheel| {
                let v = polywear_core::evaluate::solve_wheel(q, t.variant, wheel, &opts).verdict;
                match v.class {
                    polywear_core::classify::Class::Stable => 0.0,
                    c if c.vibrates() => v.amp_y_m,
                    _ => f64::NAN,
                }
            };
            let reference = amp(*relative_to);
            if reference > 0.0 {
                amp(t.wheel) / reference
            } else {
                f64::NAN
            }
        }
    }
}

/// One target beside the model's value at the start and at the fit.
#[derive(Debug, Clone, PartialEq)]
pub struct TargetResult {
    /// The target's name.
    pub name: String,
    /// The wheel observed.
    pub wheel: Wheel,
    /// The friction variant of the model.
    pub variant: Variant,
    /// The observed value.
    pub value: f64,
    /// The model's value at the starting parameters.
    pub start: f64,
    /// The model's value at the fit.
    pub fitted: f64,
    /// Relative error up to which the target counts as met.
    pub tolerance: f64,
}

impl TargetResult {
    /// (model − target) / target at the fit; NaN where the model has no value.
    pub fn rel_error(&self) -> f64 {
        (self.fitted - self.value) / self.value
    }

    /// Within the target's tolerance.
    pub fn met(&self) -> bool {
        self.rel_error().abs() <= self.tolerance
    }

    /// Why the target is not met, for people; None when it is.
    pub fn shortfall(&self) -> Option<String> {
        if !self.fitted.is_finite() {
            Some(format!(
                "`{}` cannot be met: the fitted model has no such value (e.g. no Hopf point in the range)",
                self.name
            ))
        } else if !self.met() {
            Some(format!(
                "`{}` is not met: {:+.1}% off, tolerance {:.1}%",
                self.name,
                100.0 * self.rel_error(),
                100.0 * self.tolerance
            ))
        } else {
            None
        }
    }
}

/// The fitted parameters and how well they do.
#[derive(Debug, Clone)]
pub struct Fit {
    /// Every parameter at the fit.
    pub params: Params,
    /// (name, start value, fitted value)
    pub fitted: Vec<(ParamId, f64, f64)>,
    /// (name, chosen value) for each parameter restricted by `choices`.
    pub chosen: Vec<(ParamId, f64)>,
    /// Each target beside the model's values.
    pub targets: Vec<TargetResult>,
    /// d ln(model_i) / d ln(param_j) at the fit, targets × fitted parameters.
    pub sensitivity: Vec<Vec<f64>>,
    /// Sum of the squared weighted relative errors (and prior terms) at the fit.
    pub cost: f64,
    /// Model evaluations spent.
    pub evaluations: usize,
    /// Combinations of `choices` tried (1 without choices).
    pub combinations: usize,
}

fn with_log(start: &Params, fit: &[ParamId], x: &[f64]) -> Params {
    let mut p = *start;
    for (name, xi) in fit.iter().zip(x) {
        p[*name] = xi.exp();
    }
    p
}

/// Residuals: √w·(model − target)/target per target (1·√w where the model has no value), then
/// (x − x0)/σ per fitted parameter when there is a prior. None for an invalid parameter set.
fn residuals(problem: &Problem, x: &[f64], x0: &[f64]) -> Option<Vec<f64>> {
    let p = with_log(&problem.start, &problem.fit, x);
    p.validate().ok()?;
    let mut r: Vec<f64> = problem
        .targets
        .iter()
        .map(|t| {
            let m = observe(t, &p);
            let rel = if m.is_finite() {
                (m - t.value) / t.value
            } else {
                1.0
            };
            t.weight.sqrt() * rel
        })
        .collect();
    if let Some(s) = problem.prior_sigma {
        r.extend(x.iter().zip(x0).map(|(a, b)| (a - b) / s));
    }
    Some(r)
}

/// Every combination of the choices, in a fixed order.
fn combinations(choices: &[(ParamId, Vec<f64>)]) -> Vec<Vec<(ParamId, f64)>> {
    let mut out = vec![Vec::new()];
    for (name, vals) in choices {
        out = out
            .into_iter()
            .flat_map(|c| {
                vals.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((*name, *v));
                    c
                })
            })
            .collect();
    }
    out
}

/// Fits the problem by Levenberg–Marquardt in log-parameters, once per combination of
/// `choices` (in parallel), and keeps the combination with the lowest cost.
pub fn calibrate(problem: &Problem) -> Fit {
    let combos = combinations(&problem.choices);
    let fit_one = |k: usize| {
        let combo = &combos[k];
        let mut start = problem.start;
        for (n, v) in combo {
            start[*n] = *v;
        }
        start.validate().ok()?;
        let sub = Problem {
            start,
            ..problem.clone()
        };
        let x0: Vec<f64> = sub.fit.iter().map(|&n| sub.start[n].ln()).collect();
        residuals(&sub, &x0, &x0)?;
        let (x, cost, evals) = levenberg_marquardt(|x| residuals(&sub, x, &x0), &x0, 200);
        Some((combo.clone(), start, x0, x, cost, evals))
    };
    let runs: Vec<_> = polywear_core::ensemble::solve(combos.len(), fit_one, &Control::QUIET)
        .all()
        .into_iter()
        .flatten()
        .collect();
    let evaluations = runs.iter().map(|r| r.5).sum();
    let (chosen, start, x0, x, cost, _) = runs
        .into_iter()
        .min_by(|a, b| a.4.total_cmp(&b.4))
        .unwrap_or_else(|| {
            let x0: Vec<f64> = problem.fit.iter().map(|&n| problem.start[n].ln()).collect();
            (Vec::new(), problem.start, x0.clone(), x0, f64::NAN, 0)
        });
    let params = with_log(&start, &problem.fit, &x);
    let fitted = problem
        .fit
        .iter()
        .zip(&x0)
        .zip(&x)
        .map(|((n, a), b)| (*n, a.exp(), b.exp()))
        .collect();
    let targets = problem
        .targets
        .iter()
        .map(|t| TargetResult {
            name: t.name.clone(),
            wheel: t.wheel,
            variant: t.variant,
            value: t.value,
            start: observe(t, &problem.start),
            fitted: observe(t, &params),
            tolerance: t.tolerance,
        })
        .collect();
    let h = 1e-4;
    let sensitivity = problem
        .targets
        .iter()
        .map(|t| {
            (0..x.len())
                .map(|j| {
                    let (mut xp, mut xm) = (x.clone(), x.clone());
                    xp[j] += h;
                    xm[j] -= h;
                    let mp = observe(t, &with_log(&start, &problem.fit, &xp));
                    let mm = observe(t, &with_log(&start, &problem.fit, &xm));
                    (mp.ln() - mm.ln()) / (2.0 * h)
                })
                .collect()
        })
        .collect();
    Fit {
        params,
        fitted,
        chosen,
        targets,
        sensitivity,
        cost,
        evaluations,
        combinations: combos.len(),
    }
}

impl Fit {
    /// Refuses a fit with a target not met within its tolerance: its parameter file would not
    /// stand for the targets it claims to fit.
    pub fn check_met(&self) -> Result<(), ParamFileError> {
        let shortfalls: Vec<String> = self.targets.iter().filter_map(|t| t.shortfall()).collect();
        if shortfalls.is_empty() {
            return Ok(());
        }
        Err(ParamFileError::NotMet {
            shortfalls,
            total: self.targets.len(),
        })
    }
}

/// The fitted values as a parameter file (`--params FILE`). Refused when a value is not finite
/// or out of range (a diverged fit), so that no unusable file is ever written; whether every
/// target is met is [`Fit::check_met`]'s to say.
pub fn parameter_file(fit: &Fit, source: &str) -> Result<String, ParamFileError> {
    fit.params.validate().map_err(ParamFileError::Diverged)?;
    if !fit.cost.is_finite() {
        return Err(ParamFileError::NonFiniteCost);
    }
    let mut s = format!(
        "# polywear parameter file, written by `polywear calibrate` (polywear {}) from {source}.\n\
         # Fit cost (weighted squared relative errors + prior): {:.6e}\n[params]\n",
        crate::provenance::POLYWEAR_VERSION,
        fit.cost
    );
    for (name, start, value) in &fit.fitted {
        s.push_str(&format!("{name} = {value:e}   # fitted, start {start:e}\n"));
    }
    for (name, value) in &fit.chosen {
        s.push_str(&format!("{name} = {value:e}   # chosen among `choices`\n"));
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_fit_is_the_decoded_and_reconstructed_structure_and_friction() {
        let f = default_fit();
        assert!(
            f.contains(&ParamId::GMod) && f.contains(&ParamId::CBrush) && f.contains(&ParamId::VS)
        );
        assert!(
            !f.contains(&ParamId::SpeedKmh)
                && !f.contains(&ParamId::RB)
                && !f.contains(&ParamId::F0)
        );
    }
}
