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

use crate::bifurcation::eig_re;
use crate::classify::{classify_point, ClassifierOptions};
use crate::model::{Variant, Wheel, WheelModel};
use crate::numeric::brent;
use crate::params::{spec, ParamError, ParamSpec, Params, Provenance, SPECS};
use crate::toml_input::{self, Section, TomlError};

/// What a target observes.
#[derive(Debug, Clone, PartialEq)]
pub enum Observable {
    /// The value of `param` in [from, to] where Re λ changes sign (a Hopf point).
    Hopf {
        /// The parameter swept.
        param: &'static str,
        /// Start of the searched range.
        from: f64,
        /// End of the searched range.
        to: f64,
    },
    /// The linear vibration frequency |Im λ|/2π \[Hz\] at a point given by `at`.
    Frequency {
        /// The point: (parameter, value) pairs applied on top of the parameters.
        at: Vec<(&'static str, f64)>,
    },
    /// The limit-cycle amplitude (half peak-to-peak of y) of the target's wheel divided by that
    /// of `relative_to`, at the point `at` (0 where the target's wheel is stable).
    AmplitudeRatio {
        /// The point: (parameter, value) pairs applied on top of the parameters.
        at: Vec<(&'static str, f64)>,
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
    /// Relative error up to which the target counts as met (reported, not enforced).
    pub tolerance: f64,
}

/// A calibration problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// Parameters fitted continuously (in log space).
    pub fit: Vec<&'static str>,
    /// Log-space standard deviation of the prior around the starting values (None: no prior).
    pub prior_sigma: Option<f64>,
    /// Starting values of every parameter.
    pub start: Params,
    /// The observations to match.
    pub targets: Vec<Target>,
    /// Parameters restricted to a few values each (e.g. a decoded constant's lost-digit
    /// alternatives); every combination is tried. Not fitted continuously.
    pub choices: Vec<(&'static str, Vec<f64>)>,
}

/// The tire-structure and friction parameters MODEL.md#constants marks as decoded or reconstructed:
/// the default set to fit (the operating point is what targets vary; vehicle parameters do not act
/// on the follower).
pub fn default_fit() -> Vec<&'static str> {
    use crate::params::Group;
    SPECS
        .iter()
        .filter(|s| matches!(s.group, Group::TireStructure | Group::Friction))
        .filter(|s| {
            matches!(
                s.provenance,
                Provenance::Decoded | Provenance::Reconstructed | Provenance::Fitted
            )
        })
        .filter(|s| s.default > 0.0)
        .map(|s| s.name)
        .collect()
}

/// A targets-file problem, with the key it concerns.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TargetsError {
    /// Syntax, unknown or missing keys, values of the wrong type.
    #[error(transparent)]
    Input(#[from] TomlError),
    /// An unknown parameter name, or a value outside its parameter's accepted range.
    #[error("`{key}`: {source}")]
    Param {
        /// The key, in full.
        key: String,
        /// Why it was refused.
        source: ParamError,
    },
    /// A setting outside its accepted range.
    #[error("`{key}` = {value} is outside its accepted range {range}")]
    OutOfRange {
        /// The key, in full.
        key: String,
        /// The value given.
        value: f64,
        /// The accepted range.
        range: &'static str,
    },
    /// A `choices` list without values.
    #[error("`{key}` must hold at least one value")]
    NoValues {
        /// The key, in full.
        key: String,
    },
    /// `choices` would try too many combinations.
    #[error("`choices` make {0} combinations; accepted at most 4096")]
    TooManyCombinations(usize),
    /// A parameter named twice in one list.
    #[error("`{key}` names `{name}` twice")]
    Repeated {
        /// The list's key.
        key: String,
        /// The parameter named twice.
        name: &'static str,
    },
    /// An empty list of parameters.
    #[error("`{0}` must name at least one parameter")]
    NoneNamed(String),
    /// A parameter both fitted and restricted to choices.
    #[error(
        "`{0}` is both in `fit` (continuous) and in `choices` (discrete); name it in one only"
    )]
    FitAndChoice(&'static str),
    /// A fitted parameter that starts at 0 (log space cannot move it).
    #[error("`fit`: `{0}` starts at 0 and cannot be fitted in log space")]
    ZeroStart(&'static str),
    /// The file has no `[[target]]`.
    #[error("no [[target]] entries")]
    NoTargets,
    /// A target kind that does not exist.
    #[error("`{key}.kind` = \"{kind}\" is unknown; accepted: hopf, frequency, amplitude_ratio")]
    UnknownKind {
        /// The target's key.
        key: String,
        /// The kind given.
        kind: String,
    },
    /// A Hopf target whose range is empty.
    #[error("`{key}`: from = {from} must be below to = {to}")]
    Unordered {
        /// The target's key.
        key: String,
        /// Start of the range.
        from: f64,
        /// End of the range.
        to: f64,
    },
    /// An amplitude ratio of a wheel to itself.
    #[error("`{key}`: `relative_to` must name the other wheel than `wheel` = {wheel}")]
    SameWheel {
        /// The target's key.
        key: String,
        /// The wheel named twice.
        wheel: Wheel,
    },
    /// A target value of 0 (errors are relative to it).
    #[error("`{key}.value` must not be 0 (errors are relative)")]
    ZeroValue {
        /// The target's key.
        key: String,
    },
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
}

/// A parameter name at `key`.
fn param_name(name: &str, key: &str) -> Result<&'static ParamSpec, TargetsError> {
    spec(name).ok_or_else(|| TargetsError::Param {
        key: key.to_string(),
        source: ParamError::Unknown {
            name: name.to_string(),
        },
    })
}

/// `value` checked against parameter `s`'s accepted range, errors under `key`.
fn in_range(s: &ParamSpec, value: f64, key: &str) -> Result<f64, TargetsError> {
    s.check(value).map_err(|source| TargetsError::Param {
        key: key.to_string(),
        source,
    })?;
    Ok(value)
}

const TOP_KEYS: &[&str] = &[
    "description",
    "fit",
    "prior_sigma",
    "params",
    "choices",
    "target",
];
const TARGET_KEYS: &[&str] = &[
    "name",
    "kind",
    "param",
    "from",
    "to",
    "at",
    "wheel",
    "relative_to",
    "variant",
    "value",
    "weight",
    "tolerance",
];

/// An operating point `at = { name = value, ... }` of target `t`.
fn point(t: &Section) -> Result<Vec<(&'static str, f64)>, TargetsError> {
    let mut at = Vec::new();
    if let Some(v) = t.get("at") {
        let path = t.key("at");
        let a = Section::of(v, &path, "a table")?;
        for (k, x) in a.table {
            let s = param_name(k, &path)?;
            let x = toml_input::finite(x, &a.key(k))?;
            at.push((s.name, in_range(s, x, &path)?));
        }
    }
    Ok(at)
}

/// A positive-or-zero (`open` = false) or positive (`open` = true) number at `field`.
fn non_negative(
    t: &Section,
    field: &str,
    default: f64,
    open: bool,
    range: &'static str,
) -> Result<f64, TargetsError> {
    let value = t.opt(field, toml_input::finite)?.unwrap_or(default);
    if value < 0.0 || (open && value == 0.0) {
        return Err(TargetsError::OutOfRange {
            key: t.key(field),
            value,
            range,
        });
    }
    Ok(value)
}

fn parse_target(i: usize, v: &toml::Value) -> Result<Target, TargetsError> {
    let key = format!("target[{i}]");
    let t = Section::of(v, &key, "a table")?;
    t.deny_unknown(TARGET_KEYS)?;
    let kind = t.req("kind", toml_input::text)?;
    let wheel = t
        .opt("wheel", toml_input::parsed)?
        .unwrap_or(Wheel::Follower);
    let observable = match kind {
        "hopf" => {
            let s = param_name(t.req("param", toml_input::text)?, &t.key("param"))?;
            let from = in_range(s, t.req("from", toml_input::finite)?, &key)?;
            let to = in_range(s, t.req("to", toml_input::finite)?, &key)?;
            if from >= to {
                return Err(TargetsError::Unordered { key, from, to });
            }
            Observable::Hopf {
                param: s.name,
                from,
                to,
            }
        }
        "frequency" => Observable::Frequency { at: point(&t)? },
        "amplitude_ratio" => {
            let relative_to = t
                .opt("relative_to", toml_input::parsed)?
                .unwrap_or(Wheel::Follower);
            if relative_to == wheel {
                return Err(TargetsError::SameWheel { key, wheel });
            }
            Observable::AmplitudeRatio {
                at: point(&t)?,
                relative_to,
            }
        }
        other => {
            return Err(TargetsError::UnknownKind {
                key: key.clone(),
                kind: other.to_string(),
            })
        }
    };
    let variant = t
        .opt("variant", toml_input::parsed)?
        .unwrap_or(Variant::DEFAULT);
    let value = t.req("value", toml_input::finite)?;
    if value == 0.0 {
        return Err(TargetsError::ZeroValue { key });
    }
    let weight = non_negative(&t, "weight", 1.0, false, "[0, inf)")?;
    let tolerance = non_negative(&t, "tolerance", 0.1, true, "(0, inf) (relative error)")?;
    let name = match t.opt("name", toml_input::text)? {
        Some(n) => n.to_string(),
        None => format!("{kind} {i}"),
    };
    Ok(Target {
        name,
        observable,
        wheel,
        variant,
        value,
        weight,
        tolerance,
    })
}

/// A list of distinct parameter names at `key`.
fn name_list(v: &toml::Value, key: &str) -> Result<Vec<&'static str>, TargetsError> {
    let mut out: Vec<&'static str> = Vec::new();
    for (i, x) in toml_input::array(v, key, "an array of parameter names")?
        .iter()
        .enumerate()
    {
        let k = format!("{key}[{i}]");
        let name = param_name(toml_input::text(x, &k)?, &k)?.name;
        if out.contains(&name) {
            return Err(TargetsError::Repeated {
                key: key.to_string(),
                name,
            });
        }
        out.push(name);
    }
    if out.is_empty() {
        return Err(TargetsError::NoneNamed(key.to_string()));
    }
    Ok(out)
}

/// `[params]`: the starting values, on top of the defaults.
fn parse_start(top: &Section) -> Result<Params, TargetsError> {
    let mut start = Params::default();
    if let Some(v) = top.get("params") {
        let p = Section::of(v, "params", "a table")?;
        for (k, v) in p.table {
            let key = p.key(k);
            let x = toml_input::finite(v, &key)?;
            start
                .set(k, x)
                .map_err(|source| TargetsError::Param { key, source })?;
        }
        start.validate().map_err(|source| TargetsError::Param {
            key: "params".into(),
            source,
        })?;
    }
    Ok(start)
}

/// `[choices]`: each a parameter restricted to a few values.
fn parse_choices(top: &Section) -> Result<Vec<(&'static str, Vec<f64>)>, TargetsError> {
    let mut choices = Vec::new();
    if let Some(c) = top.get("choices") {
        let c = Section::of(c, "choices", "a table")?;
        for (k, v) in c.table {
            let key = c.key(k);
            let s = param_name(k, &key)?;
            let arr = toml_input::array(v, &key, "an array of numbers")?;
            if arr.is_empty() {
                return Err(TargetsError::NoValues { key });
            }
            let vals = arr
                .iter()
                .enumerate()
                .map(|(i, x)| {
                    let k = format!("{key}[{i}]");
                    in_range(s, toml_input::finite(x, &k)?, &k)
                })
                .collect::<Result<Vec<f64>, _>>()?;
            choices.push((s.name, vals));
        }
    }
    let combos: usize = choices.iter().map(|(_, v)| v.len()).product();
    if combos > 4096 {
        return Err(TargetsError::TooManyCombinations(combos));
    }
    Ok(choices)
}

/// Parses a targets file; every problem is refused with the key it concerns.
pub fn parse_problem(text: &str) -> Result<Problem, TargetsError> {
    let table = toml_input::parse(text)?;
    let top = Section::top(&table);
    top.deny_unknown(TOP_KEYS)?;
    top.opt("description", toml_input::text)?;
    let prior_sigma = match top.opt("prior_sigma", toml_input::finite)? {
        Some(value) if value <= 0.0 => {
            return Err(TargetsError::OutOfRange {
                key: "prior_sigma".into(),
                value,
                range: "(0, inf)",
            })
        }
        s => s,
    };
    let start = parse_start(&top)?;
    let choices = parse_choices(&top)?;
    let fit = match top.get("fit") {
        None => default_fit()
            .into_iter()
            .filter(|n| !choices.iter().any(|(c, _)| c == n))
            .collect(),
        Some(v) => name_list(v, "fit")?,
    };
    if let Some((n, _)) = choices.iter().find(|(c, _)| fit.contains(c)) {
        return Err(TargetsError::FitAndChoice(n));
    }
    if let Some(n) = fit.iter().find(|n| start.get(n).is_none_or(|v| v <= 0.0)) {
        return Err(TargetsError::ZeroStart(n));
    }
    let targets = top
        .get("target")
        .and_then(|v| v.as_array())
        .ok_or(TargetsError::NoTargets)?
        .iter()
        .enumerate()
        .map(|(i, v)| parse_target(i, v))
        .collect::<Result<Vec<_>, _>>()?;
    if targets.is_empty() {
        return Err(TargetsError::NoTargets);
    }
    Ok(Problem {
        fit,
        prior_sigma,
        start,
        targets,
        choices,
    })
}

/// `p` with a target's `at` values set (the point where it is observed).
fn at_point(p: &Params, at: &[(&'static str, f64)]) -> Params {
    let mut q = *p;
    for (k, x) in at {
        *q.get_mut(k).expect("known") = *x;
    }
    q
}

/// The model's value of a target's observable (NaN when undefined, e.g. no Hopf point in range).
pub fn observe(t: &Target, p: &Params) -> f64 {
    match &t.observable {
        Observable::Hopf { param, from, to } => {
            // Scan for the first sign change, then Brent.
            let n = 48;
            let f = |x: f64| eig_re(p, param, x, t.wheel, t.variant);
            let mut prev = (*from, f(*from));
            for i in 1..=n {
                let x = from + (to - from) * i as f64 / n as f64;
                let fx = f(x);
                if prev.1.is_finite() && fx.is_finite() && (prev.1 < 0.0) != (fx < 0.0) {
                    return brent(f, prev.0, x, 1e-9 * x.abs().max(1e-12), 200).unwrap_or(f64::NAN);
                }
                prev = (x, fx);
            }
            f64::NAN
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
                let (_, v) = classify_point(&q, wheel, t.variant, &opts);
                match v.class {
                    crate::classify::Class::Stable => 0.0,
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
    pub fitted: Vec<(&'static str, f64, f64)>,
    /// (name, chosen value) for each parameter restricted by `choices`.
    pub chosen: Vec<(&'static str, f64)>,
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

fn with_log(start: &Params, fit: &[&'static str], x: &[f64]) -> Params {
    let mut p = *start;
    for (name, xi) in fit.iter().zip(x) {
        *p.get_mut(name).expect("known") = xi.exp();
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

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// Levenberg–Marquardt on a residual vector, with central-difference Jacobians.
/// Returns (x, cost = Σ r², evaluations).
pub fn levenberg_marquardt(
    f: impl Fn(&[f64]) -> Option<Vec<f64>>,
    x0: &[f64],
    max_iter: usize,
) -> (Vec<f64>, f64, usize) {
    let n = x0.len();
    let mut x = x0.to_vec();
    let mut r = f(&x).expect("the starting point is valid");
    let mut cost = sum_sq(&r);
    let mut evals = 1;
    let mut lambda = 1e-3;
    let h = 1e-5;
    for _ in 0..max_iter {
        let mut jac = nalgebra::DMatrix::<f64>::zeros(r.len(), n);
        for j in 0..n {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[j] += h;
            xm[j] -= h;
            evals += 2;
            if let (Some(rp), Some(rm)) = (f(&xp), f(&xm)) {
                for i in 0..r.len() {
                    jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * h);
                }
            }
        }
        let jt = jac.transpose();
        let jtj = &jt * &jac;
        let g = &jt * nalgebra::DVector::from_column_slice(&r);
        let mut improved = false;
        for _ in 0..20 {
            let mut a = jtj.clone();
            for k in 0..n {
                a[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(step) = a.lu().solve(&(-&g)) else {
                lambda *= 10.0;
                continue;
            };
            let xn: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            evals += 1;
            match f(&xn) {
                Some(rn) if sum_sq(&rn) < cost => {
                    x = xn;
                    r = rn;
                    cost = sum_sq(&r);
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = true;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !improved || cost < 1e-24 || g.norm() < 1e-14 {
            break;
        }
    }
    (x, cost, evals)
}

/// Every combination of the choices, in a fixed order.
fn combinations(choices: &[(&'static str, Vec<f64>)]) -> Vec<Vec<(&'static str, f64)>> {
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
    use rayon::prelude::*;
    let combos = combinations(&problem.choices);
    let runs: Vec<_> = combos
        .par_iter()
        .filter_map(|combo| {
            let mut start = problem.start;
            for (n, v) in combo {
                *start.get_mut(n).expect("known") = *v;
            }
            start.validate().ok()?;
            let sub = Problem {
                start,
                ..problem.clone()
            };
            let x0: Vec<f64> = sub
                .fit
                .iter()
                .map(|n| sub.start.get(n).expect("known").ln())
                .collect();
            residuals(&sub, &x0, &x0)?;
            let (x, cost, evals) = levenberg_marquardt(|x| residuals(&sub, x, &x0), &x0, 200);
            Some((combo.clone(), start, x0, x, cost, evals))
        })
        .collect();
    let evaluations = runs.iter().map(|r| r.5).sum();
    let (chosen, start, x0, x, cost, _) = runs
        .into_iter()
        .min_by(|a, b| a.4.total_cmp(&b.4))
        .unwrap_or_else(|| {
            let x0: Vec<f64> = problem
                .fit
                .iter()
                .map(|n| problem.start.get(n).expect("known").ln())
                .collect();
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

/// The fitted values as a parameter file (`--params FILE`). Refused when a value is not finite
/// or out of range (a diverged fit), so that no unusable file is ever written.
pub fn parameter_file(fit: &Fit, source: &str) -> Result<String, ParamFileError> {
    fit.params.validate().map_err(ParamFileError::Diverged)?;
    if !fit.cost.is_finite() {
        return Err(ParamFileError::NonFiniteCost);
    }
    let mut s = format!(
        "# polywear parameter file, written by `polywear calibrate` (polywear {}) from {source}.\n\
         # Fit cost (weighted squared relative errors + prior): {:.6e}\n[params]\n",
        env!("CARGO_PKG_VERSION"),
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
    fn levenberg_marquardt_finds_the_rosenbrock_minimum() {
        let f = |x: &[f64]| Some(vec![1.0 - x[0], 10.0 * (x[1] - x[0] * x[0])]);
        let (x, fx, _) = levenberg_marquardt(f, &[-1.2, 1.0], 500);
        assert!(
            fx < 1e-16 && (x[0] - 1.0).abs() < 1e-7 && (x[1] - 1.0).abs() < 1e-7,
            "{x:?} {fx}"
        );
    }

    #[test]
    fn default_fit_is_the_decoded_and_reconstructed_structure_and_friction() {
        let f = default_fit();
        assert!(f.contains(&"g_mod") && f.contains(&"c_brush") && f.contains(&"v_s"));
        assert!(!f.contains(&"speed_kmh") && !f.contains(&"r_b") && !f.contains(&"f0"));
    }
}
