//! The long-term loop's answer in words (MODEL.md#the-long-term-loop): the verdict of each
//! wheel (a polygon visible, the tyre worn out before one, or none in the distance run) and the
//! loop's, the tread's and the estimator's figures, as `polywear wear` prints them.

use polywear_core::long_term::{LongTermProblem, LongTermSolution, WheelLongTerm};
use polywear_core::model::WheelModel;
use polywear_core::params::Params;
use polywear_core::wear::long_term::RunEnd;
use polywear_core::wording::plain;

/// The verdict of one wheel in words.
fn verdict_words(o: &WheelLongTerm, p: &Params, distance_km: f64) -> String {
    let run = match &o.run {
        Ok(r) => r,
        Err(e) => return format!("{}: no wear figures ({e})", o.wheel),
    };
    let lock = match (run.locked_speed_kmh(), &o.tongue) {
        (Some(v), Ok(Some(t))) => format!(
            "locked at {} km/h; its tongue spans {}±{} km/h",
            plain(v, 4),
            if t.at_bound { "at least " } else { "" },
            plain(t.halfwidth_kmh, 2)
        ),
        (Some(v), Err(e)) => format!(
            "locked at {} km/h; its tongue not measured: {e}",
            plain(v, 4)
        ),
        (Some(v), Ok(None)) => format!("locked at {} km/h", plain(v, 4)),
        (None, _) => "vibration not locked".into(),
    };
    let n = run.dominant_order();
    match run.ended() {
        RunEnd::Visible { order, km } => format!(
            "{}: a{} {order}-sided polygon becomes visible after {} km ({lock})",
            o.wheel,
            if order == 8 || order == 11 || order == 18 {
                "n"
            } else {
                ""
            },
            thousands(km)
        ),
        RunEnd::WornOut { km } => format!(
            "{}: tire worn out before a polygon, after {} km ({} mm of usable tread gone; the deepest order, {n}, {} µm peak-to-valley) ({lock})",
            o.wheel,
            thousands(km),
            plain(p.usable_wear_m() * 1e3, 4),
            plain(run.end().depths_m[n as usize - 1] * 1e6, 2)
        ),
        RunEnd::Distance => {
            let s = run.distance_to_visible_km(p.visible_depth_mm * 1e-3);
            if s.is_infinite() {
                format!(
                    "{}: no polygon in {} km, every order levels out ({lock})",
                    o.wheel,
                    thousands(distance_km)
                )
            } else {
                format!(
                    "{}: no polygon in {} km; order {n} still grows and would be visible after about {} km ({lock})",
                    o.wheel,
                    thousands(distance_km),
                    thousands(s)
                )
            }
        }
    }
}

/// A distance in words: to the km below 1,000 km, to 100 km above, with thousands separators.
fn thousands(km: f64) -> String {
    polywear_core::wording::thousands(if km < 1e3 {
        km
    } else {
        (km / 100.0).round() * 100.0
    })
}

/// What the first line says beside the problem: the usage in words, and the run's time.
pub struct Header<'a> {
    /// "cruising at 100 km/h, speed spread 5 km/h, ..." or the cycle driven.
    pub usage: &'a str,
    /// Wall time of the run \[s\].
    pub secs: f64,
}

/// The long-term loop's answer in lines, as `polywear wear` prints it: the run, both wheels'
/// verdicts in one line, then per wheel the loop's figures, its tread, and with `estimate` the
/// per-sample estimator's.
pub fn lines(
    problem: &LongTermProblem,
    solution: &LongTermSolution,
    head: &Header<'_>,
    estimate: bool,
) -> Vec<String> {
    let mut out = Vec::new();
    let p = &problem.params;
    let settings = &problem.settings;
    let wheels = &solution.wheels;
    let secs = head.secs;
    out.push(format!(
        "{} (wear zone {}, phi_s = {}, seed run-out {} um, visible at {} mm); {:.1} s",
        head.usage,
        settings.zone,
        plain(p.wear_share_straight, 4),
        plain(p.seed_runout_um, 4),
        plain(p.visible_depth_mm, 4),
        secs
    ));
    let words: Vec<String> = wheels
        .iter()
        .map(|w| verdict_words(w, p, settings.distance_km))
        .collect();
    out.push(words.join("; "));
    for w in wheels {
        let f = w.figures(p);
        // The growth from the seed (the estimator's figure) and over the last step, which can
        // differ in sign once the tread has worn and ν has moved.
        let at_end = w.run.as_ref().map_or(f64::NAN, |r| {
            r.end().growth_per_m[f.dominant_order as usize - 1] * 1e6
        });
        out.push(format!(
            "  {}: loop      dominant order {}, growth {} per 1000 km from the seed, {} at the end, distance {} km",
            w.wheel,
            plain(f.dominant_order, 4),
            plain(f.growth_rate_per_1000km, 3),
            plain(at_end, 3),
            plain(f.distance_to_visible_km.round(), 8)
        ));
        if w.run.is_ok() {
            let f_rot = WheelModel::rotation_hz(p);
            out.push(format!(
                "  {}: tread     height {} -> {} mm, frequency {} -> {} Hz, nu {} -> {}{}",
                w.wheel,
                plain(p.tread_height * 1e3, 4),
                plain(f.tread_height_end_mm, 3),
                plain(f.tread_freq_start_hz, 4),
                plain(f.tread_freq_end_hz, 4),
                plain(f.tread_freq_start_hz / f_rot, 4),
                plain(f.tread_freq_end_hz / f_rot, 4),
                if f.worn_out_km.is_nan() {
                    String::new()
                } else {
                    format!(", worn out at {} km", plain(f.worn_out_km.round(), 8))
                }
            ));
        }
        if estimate {
            out.push(match &w.solution.wear {
                Some(e) => format!(
                    "  {}: estimate  dominant order {}, growth {} per 1000 km, distance {} km{}",
                    w.wheel,
                    plain(e.polygon_order_dominant, 4),
                    plain(e.growth_rate_per_1000km, 3),
                    plain(e.distance_to_visible_km.round(), 8),
                    if e.reason.is_empty() {
                        String::new()
                    } else {
                        format!(" ({})", e.reason)
                    }
                ),
                None => format!("  {}: estimate  none", w.wheel),
            });
        }
    }
    out
}
