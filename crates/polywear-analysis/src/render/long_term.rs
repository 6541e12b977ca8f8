//! The long-term loop's answer in words (MODEL.md#the-long-term-loop): the verdict of each
//! wheel (a polygon visible, the tyre worn out before one, or none in the distance run) and the
//! loop's, the tread's and the estimator's figures, as `polywear wear` prints them.

use polywear_core::long_term::wheel_loop::RunEnd;
use polywear_core::long_term::{LongTermProblem, LongTermSolution, WheelLongTerm};
use polywear_core::model::WheelModel;
use polywear_core::params::Params;
use polywear_core::wear::LifeAnswer;
use polywear_core::wording::plain;
use polywear_study::calibration_band::long_term::{LoopSets, SetRun};
use polywear_study::long_term_request::LongTermPlan;

/// The wheel by its axle and role: "rear (follower)" (MODEL.md#the-car-axles-and-drivetrain).
fn who(w: &WheelLongTerm) -> String {
    w.solution.record.axle.with_role(w.wheel)
}

/// The verdict of one wheel in words.
fn verdict_words(o: &WheelLongTerm, p: &Params, distance_km: f64) -> String {
    let run = match &o.run {
        Ok(r) => r,
        Err(e) => return format!("{}: no wear figures ({e})", who(o)),
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
            who(o),
            if order == 8 || order == 11 || order == 18 {
                "n"
            } else {
                ""
            },
            thousands(km)
        ),
        RunEnd::WornOut { km } => format!(
            "{}: tire worn out before a polygon, after {} km ({} mm of usable tread gone; the deepest order, {n}, {} µm peak-to-valley) ({lock})",
            who(o),
            thousands(km),
            plain(p.usable_wear_m() * 1e3, 4),
            plain(run.end().depths_m[n as usize - 1] * 1e6, 2)
        ),
        RunEnd::Distance => {
            let s = run.distance_to_visible_km(p.visible_depth_mm * 1e-3);
            let life = run.tread_life_km(p.usable_wear_m());
            if s.is_infinite() {
                format!(
                    "{}: no polygon in {} km, every order levels out ({lock})",
                    who(o),
                    thousands(distance_km)
                )
            } else if s > life {
                // No extrapolation past the tire's life: it wears out first.
                format!(
                    "{}: no polygon in {} km; order {n} still grows, but at its growth it would be visible only after about {} km, and the tire is worn out at about {} km at its wear so far ({lock})",
                    who(o),
                    thousands(distance_km),
                    thousands(s),
                    thousands(life)
                )
            } else {
                format!(
                    "{}: no polygon in {} km; order {n} still grows and would be visible after about {} km ({lock})",
                    who(o),
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
            who(w),
            plain(f.dominant_order, 4),
            plain(f.growth_rate_per_1000km, 3),
            plain(at_end, 3),
            plain(f.distance_to_visible_km.round(), 8)
        ));
        if w.run.is_ok() {
            let f_rot = WheelModel::rotation_hz(p);
            out.push(format!(
                "  {}: tread     height {} -> {} mm, frequency {} -> {} Hz, nu {} -> {}{}",
                who(w),
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
            let legs = problem.legs.len();
            let speeds = if legs == 1 {
                "the loop's one speed".to_string()
            } else {
                format!("each of the loop's {legs} speeds saturating on its own")
            };
            if problem.is_cruise() {
                let note = " (the one wear answer, the spread on the estimator's 40 legs)";
                out.push(life_line(&who(w), "estimate ", w.estimate.as_ref(), note));
                let check = format!(" ({speeds}: a check of the estimator's legs)");
                out.push(life_line(&who(w), "on legs  ", w.on_legs.as_ref(), &check));
            } else {
                // A drive cycle's answer is its speeds', not the point's.
                let note = format!(" (the one wear answer on the cycle's speeds: {speeds})");
                out.push(life_line(&who(w), "estimate ", w.estimate.as_ref(), &note));
            }
        }
    }
    out
}

/// One estimate's line over the tread's life: `label`, the answer, then `note`.
fn life_line(wheel: &str, label: &str, reading: Option<&LifeAnswer>, note: &str) -> String {
    match reading {
        Some(l) if l.distance_to_visible_km.is_finite() => format!(
            "  {wheel}: {label} order {}, distance {} km over the tread's life (the tire worn out at {} km){note}",
            plain(l.polygon_order_wear, 4),
            plain(l.distance_to_visible_km.round(), 8),
            plain(l.tread_life_km.round(), 8)
        ),
        // NaN order: no order rose above its seed (LifeAnswer::of_walk), so none is named.
        Some(l) if l.polygon_order_wear.is_nan() => format!(
            "  {wheel}: {label} none before the tire is worn out at {} km over the tread's life (every order stays below its seed run-out){note}",
            plain(l.tread_life_km.round(), 8),
        ),
        Some(l) => format!(
            "  {wheel}: {label} none before the tire is worn out at {} km over the tread's life (order {} deepest, at {} of the visible depth){note}",
            plain(l.tread_life_km.round(), 8),
            plain(l.polygon_order_wear, 4),
            plain(l.peak_share_of_visible, 2)
        ),
        None => format!("  {wheel}: {label} none"),
    }
}

/// One wheel's loop verdict as the band ranks it: the distance to a visible polygon (the
/// extrapolated one where the run ended with an order still growing; infinite where every
/// order levels out or the tire wore out first), the kind, and the verdict in short words.
pub(crate) struct BandVerdict {
    /// The key the band's ends are taken on \[km\] (NaN: no wear figures).
    pub km: f64,
    /// `visible`, `worn_out`, `none` or `no_figures`.
    pub kind: &'static str,
    /// The polygon's sides where one became visible (NaN otherwise).
    pub order: f64,
    /// Where the run ended: the visible polygon's or the tire's end \[km\] (the distance run
    /// otherwise).
    pub end_km: f64,
    /// The verdict in words.
    pub words: String,
}

/// [`BandVerdict`] of wheel `o` at parameters `p` over `distance_km`.
pub(crate) fn band_verdict(o: &WheelLongTerm, p: &Params, distance_km: f64) -> BandVerdict {
    let Ok(run) = &o.run else {
        return BandVerdict {
            km: f64::NAN,
            kind: "no_figures",
            order: f64::NAN,
            end_km: f64::NAN,
            words: "no wear figures".into(),
        };
    };
    match run.ended() {
        RunEnd::Visible { order, km } => BandVerdict {
            km,
            kind: "visible",
            order: order as f64,
            end_km: km,
            words: format!("a {order}-sided polygon after {} km", thousands(km)),
        },
        RunEnd::WornOut { km } => BandVerdict {
            km: f64::INFINITY,
            kind: "worn_out",
            order: f64::NAN,
            end_km: km,
            words: format!("worn out first, after {} km", thousands(km)),
        },
        RunEnd::Distance => {
            let s = run.distance_to_visible_km(p.visible_depth_mm * 1e-3);
            BandVerdict {
                km: s.max(distance_km),
                kind: "none",
                order: f64::NAN,
                end_km: distance_km,
                words: if s.is_finite() {
                    format!(
                        "none in {} km (about {} km at its growth)",
                        thousands(distance_km),
                        thousands(s)
                    )
                } else {
                    format!(
                        "none in {} km, every order levels out",
                        thousands(distance_km)
                    )
                },
            }
        }
    }
}

/// The loop's verdict under the calibrated sets run, per wheel, beside the run's own: its two
/// ends (the earliest polygon, the latest or none) and the sets that give them. `runs` holds
/// (set name, that set's solution); `of_sets` is how many sets the band has, `chosen` how the
/// ones run were chosen.
pub(crate) fn band_lines(
    problem: &LongTermProblem,
    runs: &[(&str, &LongTermSolution)],
    of_sets: usize,
    chosen: &str,
) -> Vec<String> {
    let distance = problem.settings.distance_km;
    let mut out = vec![format!(
        "calibration band: the loop run again under {} of the {of_sets} calibrated sets ({chosen})",
        runs.len()
    )];
    for (i, w) in polywear_core::model::Wheel::BOTH.iter().enumerate() {
        // The wheel by its axle under the problem's drivetrain: "rear (follower)".
        let wheel = problem.params.drivetrain.words(*w);
        let verdicts: Vec<(&str, BandVerdict)> = runs
            .iter()
            .map(|(name, s)| (*name, band_verdict(&s.wheels[i], &s.params, distance)))
            .filter(|(_, v)| !v.km.is_nan())
            .collect();
        // The earliest polygon first; among none, the tire's end (a shorter life first).
        let order = |a: &&(&str, BandVerdict), b: &&(&str, BandVerdict)| {
            a.1.km
                .total_cmp(&b.1.km)
                .then(a.1.end_km.total_cmp(&b.1.end_km))
        };
        let lowest = verdicts.iter().min_by(order);
        let highest = verdicts.iter().max_by(order);
        out.push(match (lowest, highest) {
            (Some(lo), Some(hi)) if lo.1.words == hi.1.words => format!(
                "  {wheel}: calibration band  {} under every set run",
                lo.1.words
            ),
            (Some(lo), Some(hi)) => format!(
                "  {wheel}: calibration band  {} ({}) to {} ({})",
                lo.1.words, lo.0, hi.1.words, hi.0
            ),
            _ => format!("  {wheel}: calibration band  no wear figures under any set run"),
        });
    }
    out
}

/// A whole run's band in words: `band_lines` under the sets the plan chose and ran (`runs`,
/// with how they were chosen), or the line that says the band is off and the verdict is the
/// run's own constants' alone (MODEL.md#the-calibration-band).
pub fn plan_band_lines(plan: &LongTermPlan, runs: Option<&[SetRun]>) -> Vec<String> {
    let (Some((band, source)), Some(runs)) = (&plan.band, runs) else {
        return vec![
            "calibration band: off (--calibration-band off): the verdict is the run's own constants' alone".into(),
        ];
    };
    let named: Vec<(&str, &LongTermSolution)> = runs
        .iter()
        .map(|r| (band.sets[r.set].id.as_str(), &r.solution))
        .collect();
    let chosen = match plan.band_sets {
        LoopSets::Ends => format!(
            "{source}: for each wheel the sets with the shortest and the longest per-sample wear answer here; the loop's own ends may lie at other sets, which --band-sets all checks"
        ),
        LoopSets::All => format!("{source}: every set"),
    };
    band_lines(&plan.problem, &named, band.sets.len(), &chosen)
}
