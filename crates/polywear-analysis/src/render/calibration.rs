//! A calibration's fit in words (`polywear calibrate`): each target against the model at the
//! start and at the fit, the unmet ones, the fitted parameters and the sensitivities.

use std::fmt::Write as _;

use polywear_study::calibrate::{Fit, Problem};

/// The fit's first line: how many parameters were fitted to how many targets, in `secs`, with
/// how many cost evaluations, and the cost reached.
pub fn fit_heading(problem: &Problem, fit: &Fit, secs: f64) -> String {
    format!(
        "fitted {} parameters to {} targets in {secs:.1} s ({} cost evaluations), cost {:.4e}",
        fit.fitted.len(),
        problem.targets.len(),
        fit.evaluations,
        fit.cost
    )
}

/// The fit table: each target's value, the model's at the start and at the fit, and whether it
/// is met; then why each unmet target is not.
pub fn targets_text(fit: &Fit, out: &mut String) {
    let _ = writeln!(
        out,
        "\n{:<38} {:<9} {:<14} {:>11} {:>13} {:>13} {:>8}  met",
        "target", "wheel", "variant", "value", "model start", "model fit", "error"
    );
    for t in &fit.targets {
        let _ = writeln!(
            out,
            "{:<38} {:<9} {:<14} {:>11.5} {:>13.5} {:>13.5} {:>7.2}%  {}",
            t.name,
            t.wheel,
            t.variant,
            t.value,
            t.start,
            t.fitted,
            100.0 * t.rel_error(),
            if t.met() { "yes" } else { "NO" }
        );
    }
    let shortfalls: Vec<String> = fit.targets.iter().filter_map(|t| t.shortfall()).collect();
    if shortfalls.is_empty() {
        let _ = writeln!(out, "\nevery target is met within its tolerance");
    } else {
        let _ = writeln!(out);
        for s in &shortfalls {
            let _ = writeln!(out, "warning: {s}");
        }
    }
}

/// The chosen readings, the fitted parameters and the sensitivities at the fit.
pub fn parameters_text(fit: &Fit, out: &mut String) {
    if !fit.chosen.is_empty() {
        let _ = writeln!(
            out,
            "\nchosen among {} combinations of `choices`: {}",
            fit.combinations,
            fit.chosen
                .iter()
                .map(|(n, v)| format!("{n} = {v}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(
        out,
        "\n{:<14} {:>14} {:>14} {:>9}",
        "parameter", "start", "fitted", "change"
    );
    for (name, a, b) in &fit.fitted {
        let _ = writeln!(
            out,
            "{:<14} {a:>14.6e} {b:>14.6e} {:>8.2}%",
            name.name(),
            100.0 * (b - a) / a
        );
    }
    let _ = writeln!(
        out,
        "\nsensitivity d ln(target) / d ln(parameter) at the fit:"
    );
    let _ = write!(out, "{:<28}", "");
    for (name, _, _) in &fit.fitted {
        let _ = write!(out, " {:>10}", name.name());
    }
    let _ = writeln!(out);
    for (t, row) in fit.targets.iter().zip(&fit.sensitivity) {
        let _ = write!(out, "{:<28}", t.name);
        for v in row {
            let _ = write!(out, " {v:>10.3}");
        }
        let _ = writeln!(out);
    }
}
