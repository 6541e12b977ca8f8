//! Calibration: fits chosen parameters to target observations (Hopf onset values of any axis,
//! linear vibration frequency), by Levenberg–Marquardt on log-parameters with an optional prior
//! that pulls toward the starting values, and reports the fit's sensitivities.
//!
//! Targets come from a TOML file (`studies/paper_targets.toml` holds the paper's); the fitted
//! values are written as a parameter file that `simulate`, `bifurcation` and `explore` read with
//! `--params FILE`.

use crate::bifurcation::eig_re;
use crate::model::{Variant, Wheel, WheelModel};
use crate::numeric::brent;
use crate::params::{spec, Params, Provenance, SPECS};

/// What a target observes.
#[derive(Debug, Clone, PartialEq)]
pub enum Observable {
    /// The value of `param` in [from, to] where Re λ changes sign (a Hopf point).
    Hopf {
        param: &'static str,
        from: f64,
        to: f64,
    },
    /// The linear vibration frequency |Im λ|/2π [Hz] at a point given by `at`.
    Frequency { at: Vec<(&'static str, f64)> },
}

/// One observation to match.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    pub name: String,
    pub observable: Observable,
    pub wheel: Wheel,
    pub variant: Variant,
    pub value: f64,
    pub weight: f64,
}

/// A calibration problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub fit: Vec<&'static str>,
    /// Log-space standard deviation of the prior around the starting values (None: no prior).
    pub prior_sigma: Option<f64>,
    pub start: Params,
    pub targets: Vec<Target>,
}

/// The tire-structure and friction parameters MODEL.md marks as decoded or reconstructed: the
/// default set to fit (the operating point is what targets vary; vehicle parameters do not act
/// on the follower).
pub fn default_fit() -> Vec<&'static str> {
    use crate::params::Group;
    SPECS
        .iter()
        .filter(|s| matches!(s.group, Group::TireStructure | Group::Friction))
        .filter(|s| {
            matches!(
                s.provenance,
                Provenance::Decoded | Provenance::Reconstructed
            )
        })
        .filter(|s| s.default > 0.0)
        .map(|s| s.name)
        .collect()
}

fn num(v: &toml::Value, key: &str) -> Result<f64, String> {
    match v {
        toml::Value::Float(x) if x.is_finite() => Ok(*x),
        toml::Value::Integer(i) => Ok(*i as f64),
        _ => Err(format!("`{key}` must be a finite number")),
    }
}

fn param_name(v: &str, key: &str) -> Result<&'static str, String> {
    spec(v)
        .map(|s| s.name)
        .ok_or_else(|| format!("`{key}`: unknown parameter `{v}`"))
}

/// Parses a targets file.
pub fn parse_problem(text: &str) -> Result<Problem, String> {
    let t: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| format!("malformed TOML: {}", e.to_string().trim()))?;
    for k in t.keys() {
        if !["fit", "prior_sigma", "params", "target", "description"].contains(&k.as_str()) {
            return Err(format!(
                "unknown key `{k}`; accepted: description, fit, prior_sigma, params, target"
            ));
        }
    }
    let fit = match t.get("fit") {
        None => default_fit(),
        Some(v) => {
            let arr = v
                .as_array()
                .ok_or("`fit` must be an array of parameter names")?;
            let mut out = Vec::new();
            for (i, x) in arr.iter().enumerate() {
                let name = x.as_str().ok_or(format!("`fit[{i}]` must be a string"))?;
                out.push(param_name(name, &format!("fit[{i}]"))?);
            }
            if out.is_empty() {
                return Err("`fit` must name at least one parameter".into());
            }
            out
        }
    };
    let prior_sigma = match t.get("prior_sigma") {
        None => None,
        Some(v) => {
            let s = num(v, "prior_sigma")?;
            if s <= 0.0 {
                return Err("`prior_sigma` must be positive".into());
            }
            Some(s)
        }
    };
    let mut start = Params::default();
    if let Some(p) = t.get("params") {
        let p = p.as_table().ok_or("`params` must be a table")?;
        for (k, v) in p {
            start
                .set(k, num(v, &format!("params.{k}"))?)
                .map_err(|e| format!("`params.{k}`: {e}"))?;
        }
        start.validate().map_err(|e| format!("`params`: {e}"))?;
    }
    for n in &fit {
        if start.get(n).is_none_or(|v| v <= 0.0) {
            return Err(format!(
                "`fit`: `{n}` starts at 0 and cannot be fitted in log space"
            ));
        }
    }
    let arr = t
        .get("target")
        .and_then(|v| v.as_array())
        .ok_or("no [[target]] entries")?;
    let mut targets = Vec::new();
    for (i, v) in arr.iter().enumerate() {
        let key = format!("target[{i}]");
        let tt = v.as_table().ok_or(format!("`{key}` must be a table"))?;
        let get = |k: &str| tt.get(k).ok_or(format!("`{key}` needs `{k}`"));
        let kind = get("kind")?
            .as_str()
            .ok_or(format!("`{key}.kind` must be a string"))?;
        let observable = match kind {
            "hopf" => {
                let param = param_name(
                    get("param")?
                        .as_str()
                        .ok_or(format!("`{key}.param` must be a string"))?,
                    &format!("{key}.param"),
                )?;
                let (from, to) = (
                    num(get("from")?, &format!("{key}.from"))?,
                    num(get("to")?, &format!("{key}.to"))?,
                );
                let s = spec(param).expect("known");
                for x in [from, to] {
                    s.check(x).map_err(|e| format!("`{key}`: {e}"))?;
                }
                if from >= to {
                    return Err(format!("`{key}`: from = {from} must be below to = {to}"));
                }
                Observable::Hopf { param, from, to }
            }
            "frequency" => {
                let mut at = Vec::new();
                if let Some(a) = tt.get("at") {
                    for (k, x) in a.as_table().ok_or(format!("`{key}.at` must be a table"))? {
                        let n = param_name(k, &format!("{key}.at"))?;
                        let x = num(x, &format!("{key}.at.{k}"))?;
                        spec(n)
                            .expect("known")
                            .check(x)
                            .map_err(|e| format!("`{key}.at`: {e}"))?;
                        at.push((n, x));
                    }
                }
                Observable::Frequency { at }
            }
            other => {
                return Err(format!(
                    "`{key}.kind` = \"{other}\" is unknown; accepted: hopf, frequency"
                ))
            }
        };
        let wheel = match tt.get("wheel") {
            Some(w) => w
                .as_str()
                .ok_or(format!("`{key}.wheel` must be a string"))?
                .parse()
                .map_err(|e| format!("`{key}.wheel`: {e}"))?,
            None => Wheel::Follower,
        };
        let variant = match tt.get("variant") {
            Some(w) => w
                .as_str()
                .ok_or(format!("`{key}.variant` must be a string"))?
                .parse()
                .map_err(|e| format!("`{key}.variant`: {e}"))?,
            None => Variant::Paper,
        };
        let value = num(get("value")?, &format!("{key}.value"))?;
        if value == 0.0 {
            return Err(format!("`{key}.value` must not be 0 (errors are relative)"));
        }
        let weight = match tt.get("weight") {
            Some(w) => num(w, &format!("{key}.weight"))?,
            None => 1.0,
        };
        if weight < 0.0 {
            return Err(format!("`{key}.weight` must not be negative"));
        }
        let name = tt
            .get("name")
            .and_then(|n| n.as_str())
            .map(String::from)
            .unwrap_or_else(|| format!("{kind} {i}"));
        targets.push(Target {
            name,
            observable,
            wheel,
            variant,
            value,
            weight,
        });
    }
    Ok(Problem {
        fit,
        prior_sigma,
        start,
        targets,
    })
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
            let mut q = *p;
            for (k, x) in at {
                *q.get_mut(k).expect("known") = *x;
            }
            WheelModel::build(&q, t.wheel, t.variant)
                .map_or(f64::NAN, |m| m.ode.linear_stability().eig_freq_hz)
        }
    }
}

/// The fitted parameters and how well they do.
#[derive(Debug, Clone)]
pub struct Fit {
    pub params: Params,
    /// (name, start value, fitted value)
    pub fitted: Vec<(&'static str, f64, f64)>,
    /// (target name, target value, model at start, model at fit)
    pub residuals: Vec<(String, f64, f64, f64)>,
    /// d ln(model_i) / d ln(param_j) at the fit, targets × fitted parameters.
    pub sensitivity: Vec<Vec<f64>>,
    pub cost: f64,
    pub evaluations: usize,
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

/// Fits the problem by Levenberg–Marquardt in log-parameters.
pub fn calibrate(problem: &Problem) -> Fit {
    let x0: Vec<f64> = problem
        .fit
        .iter()
        .map(|n| problem.start.get(n).expect("known").ln())
        .collect();
    let (x, fx, evaluations) = levenberg_marquardt(|x| residuals(problem, x, &x0), &x0, 200);
    let params = with_log(&problem.start, &problem.fit, &x);
    let fitted = problem
        .fit
        .iter()
        .zip(&x0)
        .zip(&x)
        .map(|((n, a), b)| (*n, a.exp(), b.exp()))
        .collect();
    let residuals = problem
        .targets
        .iter()
        .map(|t| {
            (
                t.name.clone(),
                t.value,
                observe(t, &problem.start),
                observe(t, &params),
            )
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
                    let mp = observe(t, &with_log(&problem.start, &problem.fit, &xp));
                    let mm = observe(t, &with_log(&problem.start, &problem.fit, &xm));
                    (mp.ln() - mm.ln()) / (2.0 * h)
                })
                .collect()
        })
        .collect();
    Fit {
        params,
        fitted,
        residuals,
        sensitivity,
        cost: fx,
        evaluations,
    }
}

/// The fitted values as a parameter file (`--params FILE`).
pub fn parameter_file(fit: &Fit, source: &str) -> String {
    let mut s = format!(
        "# polywear parameter file, written by `polywear calibrate` (polywear {}) from {source}.\n\
         # Fit cost (weighted squared relative errors + prior): {:.6e}\n[params]\n",
        env!("CARGO_PKG_VERSION"),
        fit.cost
    );
    for (name, start, value) in &fit.fitted {
        s.push_str(&format!("{name} = {value:e}   # start {start:e}\n"));
    }
    s
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
