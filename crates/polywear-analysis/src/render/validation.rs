//! The fast classifier against the brute-force reference (`polywear validate`), in words.

use polywear_study::validation::{median, Comparison, HOPF_BAND};

/// What `validate` prints: agreement of the classes outside the Hopf band, the limit cycles'
/// figures within 1%, every disagreement, and the cost per wheel of each.
pub fn report_lines(rows: &[Comparison]) -> Vec<String> {
    let mut lines = Vec::new();
    let compared: Vec<&Comparison> = rows.iter().filter(|r| r.compared()).collect();
    let agree = compared.iter().filter(|r| r.classes_agree()).count();
    let cycles: Vec<&&Comparison> = compared
        .iter()
        .filter(|r| r.classes_agree() && r.fast.class.vibrates())
        .collect();
    let worst = cycles
        .iter()
        .map(|r| r.worst_relative_error())
        .fold(0.0, f64::max);
    let within = cycles
        .iter()
        .filter(|r| r.worst_relative_error() < 0.01)
        .count();
    lines.push(format!(
        "wheels evaluated:                      {}",
        rows.len()
    ));
    lines.push(format!(
        "outside the Hopf band (|Re λ| >= {HOPF_BAND}): {} ({} limit cycles by the reference)",
        compared.len(),
        compared
            .iter()
            .filter(|r| r.reference.class.vibrates())
            .count()
    ));
    lines.push(format!(
        "class agreement there:                 {agree} / {}",
        compared.len()
    ));
    lines.push(format!(
        "limit cycles with amp_y, amp_v, freq within 1%: {within} / {} (worst {:.3}%)",
        cycles.len(),
        100.0 * worst
    ));
    for r in compared.iter().filter(|r| !r.classes_agree()) {
        lines.push(format!(
            "  DISAGREE #{} {} {}: fast {} ({}), reference {} (re {:.4})",
            r.index,
            r.wheel,
            r.variant,
            r.fast.class.as_str(),
            r.fast.reason,
            r.reference.class.as_str(),
            r.fast.eig_re_max
        ));
    }
    let stat = |f: &dyn Fn(&Comparison) -> f64, sel: &dyn Fn(&Comparison) -> bool| {
        median(rows.iter().filter(|r| sel(r)).map(f).collect())
    };
    let all = |_: &Comparison| true;
    let lc = |r: &Comparison| r.fast.class.vibrates();
    lines.push(String::new());
    lines.push("cost per wheel (median, single thread)      fast classifier    brute-force reference   ratio".to_string());
    for (label, sel) in [
        ("all wheels", &all as &dyn Fn(&Comparison) -> bool),
        ("limit cycles only", &lc),
    ] {
        let (fu, ru) = (stat(&|r| r.fast_us, sel), stat(&|r| r.reference_us, sel));
        let (fe, re) = (
            stat(&|r| r.fast.rhs_evals as f64, sel),
            stat(&|r| r.reference.rhs_evals as f64, sel),
        );
        lines.push(format!(
            "  {label:<20} time [µs]         {fu:>12.1}    {ru:>18.1}   {:>8.0}x",
            ru / fu
        ));
        lines.push(format!(
            "  {label:<20} RHS evaluations   {fe:>12.0}    {re:>18.0}   {:>8.0}x",
            re / fe.max(1.0)
        ));
    }
    lines
}
