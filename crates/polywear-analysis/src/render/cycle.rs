//! The summary of a classified cycle in words: per wheel, the shares in vibration (with the 90%
//! interval over the tire structures when there are several), the dominant polygon order and
//! the distance to a visible polygon over a lifetime on the cycle.

use crate::figures::cycle::CycleRun;
use polywear_core::wear::estimator::print_log_ratio;
use polywear_core::wording::{plain, thousands};
use polywear_study::cycle::summary::{quantile, WheelSummary};
use polywear_study::cycle::wear::CycleWear;

/// The summary printed after a cycle: per wheel, the shares in vibration (with the 90% interval over the
/// structures when there are several) and the dominant polygon order, from `all`
/// ([`CycleRun::summaries`]).
pub fn summary_lines(
    run: &CycleRun<'_>,
    all: &[[WheelSummary; 2]],
    secs: f64,
    threads: usize,
) -> Vec<String> {
    let mut lines = Vec::new();
    let c = run.cycle;
    let dt = c.step_durations_s();
    let total_s: f64 = dt.iter().sum();
    let km: f64 = (0..c.len()).map(|i| c.speed_kmh[i] * dt[i] / 3600.0).sum();
    lines.push(format!(
        "{}: {} steps, {total_s:.0} s, {km:.2} km; {} structure(s) x 2 wheels classified in {secs:.2} s ({threads} threads), variant {}",
        c.path.display(),
        c.len(),
        run.steps.len(),
        run.variant.as_str()
    ));
    for w in 0..2 {
        let pick = |f: &dyn Fn(&WheelSummary) -> f64| {
            let mut xs: Vec<f64> = all.iter().map(|s| f(&s[w])).collect();
            xs.sort_by(f64::total_cmp);
            let mean = xs.iter().sum::<f64>() / xs.len() as f64;
            if xs.len() == 1 {
                format!("{:.1}%", 100.0 * mean)
            } else {
                let q = quantile;
                format!(
                    "{:.1}% (90% interval {:.1}-{:.1}%)",
                    100.0 * mean,
                    100.0 * q(&xs, 0.05),
                    100.0 * q(&xs, 0.95)
                )
            }
        };
        let mean = |f: &dyn Fn(&WheelSummary) -> f64| {
            all.iter().map(|s| f(&s[w])).sum::<f64>() / all.len() as f64
        };
        // Polygon orders: the mean share over the structures.
        let mut orders: std::collections::BTreeMap<i64, f64> = Default::default();
        for s in all {
            for (n, share) in &s[w].order_shares {
                *orders.entry(*n).or_default() += share / all.len() as f64;
            }
        }
        let top = orders
            .iter()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(n, share)| format!("mostly {n}-gon ({:.0}% of it)", 100.0 * share))
            .unwrap_or_else(|| "no vibration".into());
        lines.push(format!(
            "  {:>15}: in vibration {} of the time, {} of the distance; longest stretch {}{:.0} s / {:.2} km; {top}; quasi-static in doubt {:.1}% of the time",
            // The wheel by its axle and role, "rear (follower)", as its rows say.
            run.steps
                .first()
                .and_then(|s| s.first())
                .map_or_else(
                    || polywear_core::model::Wheel::BOTH[w].to_string(),
                    |step| step[w].record.axle.with_role(step[w].record.wheel)
                ),
            pick(&|s| s.time_share),
            pick(&|s| s.distance_share),
            if all.len() > 1 { "(mean) " } else { "" },
            mean(&|s| s.longest_vibration_s),
            mean(&|s| s.longest_vibration_km),
            100.0 * mean(&|s| s.not_quasi_static_share),
        ));
        // The seed's share of the visible depth, 2R⁰/d_visible: an order that never grows past
        // it levels out from the start.
        let seed_share = run
            .wear_bases
            .first()
            .map_or(f64::NAN, |p| (-print_log_ratio(p)).exp());
        if let Some(line) = wear_line(all, w, seed_share) {
            lines.push(format!("            {line}"));
        }
    }
    lines
}

/// A distance of the band in words: "never" for +inf.
fn shown_km(x: f64) -> String {
    if x.is_infinite() {
        "never".to_string()
    } else {
        format!("{} km", thousands(x))
    }
}

/// The polygon of a lifetime on the cycle, in words: the distance to a visible polygon (the
/// median and 90% interval over the structures when there are several) and its order; over the
/// tread's life, where none is visible, how near the deepest order came (`seed_share`, the
/// seed's share of the visible depth, is where every order starts).
fn wear_line(all: &[[WheelSummary; 2]], w: usize, seed_share: f64) -> Option<String> {
    let wear: Vec<CycleWear> = all.iter().filter_map(|s| s[w].wear).collect();
    if wear.is_empty() {
        return None;
    }
    let km = |x: f64| format!("{} km", thousands(x));
    let mut d: Vec<f64> = wear.iter().map(|c| c.distance_to_visible_km).collect();
    d.sort_by(f64::total_cmp);
    let q = quantile;
    let unknown = unknown_distance_note(&wear);
    // The level the cycle answered on (MODEL.md#along-a-drive-cycle): over the tread's life a
    // wheel has how near its deepest order came; as the new tire it has none.
    let over_life = wear.iter().any(|c| !c.peak_share_of_visible.is_nan());
    let no_figures = wear.iter().all(|c| c.distance_to_visible_km.is_nan());
    let life = if over_life {
        "driving this cycle all its life, its tread wearing"
    } else if no_figures {
        // Without a figure the level answered on cannot be told from the answers: none is said.
        "driving this cycle all its life"
    } else {
        "driving this cycle all its life, as the new tire"
    };
    if d.len() == 1 {
        let what = one_structure_polygon(wear[0], over_life, seed_share);
        let band = one_structure_band_note(&all[0][w]);
        return Some(format!("{life}: {what}{band}{unknown}"));
    }
    let never = d.iter().filter(|x| x.is_infinite()).count() as f64 / d.len() as f64;
    let shown = |x: f64| {
        if x.is_infinite() {
            "never".to_string()
        } else if x.is_nan() {
            "unknown".to_string()
        } else {
            km(x)
        }
    };
    let order = structures_order_note(&wear, over_life, seed_share);
    let band = median_band_note(all, w);
    Some(format!(
        "{life}: distance to a visible polygon {} (median over the structures; 90% interval {} to {}{band}); {}% of the structures {}{order}{unknown}",
        shown(q(&d, 0.5)),
        shown(q(&d, 0.05)),
        shown(q(&d, 0.95)),
        plain(100.0 * never, 3),
        if over_life {
            "show none before the tire is worn out"
        } else {
            "never show one"
        }
    ))
}

/// The note on the distance left out of the wear figures (failed steps or no traction): the
/// largest share over the structures, or nothing when every step has figures.
fn unknown_distance_note(wear: &[CycleWear]) -> String {
    let unknown = wear
        .iter()
        .map(|c| c.unknown_distance_share)
        .fold(0.0, f64::max);
    if unknown > 0.0 {
        format!(
            "; {}% of the distance has no wear figures (failed or no traction) and is left out",
            plain(100.0 * unknown, 2)
        )
    } else {
        String::new()
    }
}

/// The polygon of a lifetime on the cycle for a single structure, in words: when it becomes
/// visible and of what order, or, where it never does, why (the tread wears out first, or every
/// order levels out).
fn one_structure_polygon(c: CycleWear, over_life: bool, seed_share: f64) -> String {
    let km = |x: f64| format!("{} km", thousands(x));
    if c.distance_to_visible_km.is_nan() {
        "no wear figures at any step".to_string()
    } else if over_life
        && c.distance_to_visible_km.is_infinite()
        && c.peak_share_of_visible <= seed_share * (1.0 + 1e-9)
    {
        format!(
            "no polygon before the tire is worn out at {}: every order levels out from its seed as the tread wears",
            km(c.tread_life_km)
        )
    } else if over_life && c.distance_to_visible_km.is_infinite() {
        format!(
            "no polygon before the tire is worn out at {} (the deepest order, {:.0}, reached {}% of the visible depth)",
            km(c.tread_life_km),
            c.dominant_order,
            plain(100.0 * c.peak_share_of_visible, 2)
        )
    } else if over_life {
        format!(
            "a {:.0}-sided polygon becomes visible after {} (the tire is worn out at {})",
            c.dominant_order,
            km(c.distance_to_visible_km),
            km(c.tread_life_km)
        )
    } else if c.distance_to_visible_km.is_infinite() {
        format!(
            "no polygon ever: every order levels out (the slowest, order {:.0}, at {} per 1000 km)",
            c.dominant_order,
            plain(c.growth_rate_per_1000km, 3)
        )
    } else {
        format!(
            "a {:.0}-sided polygon becomes visible after {} (growth {} per 1000 km)",
            c.dominant_order,
            km(c.distance_to_visible_km),
            plain(c.growth_rate_per_1000km, 3)
        )
    }
}

/// The calibration band of a single structure's distance to a visible polygon, over the
/// calibrated sets' phi_s and k_d; nothing when the wheel has no band.
fn one_structure_band_note(s: &WheelSummary) -> String {
    s.distance_band_km().map_or(String::new(), |(lo, hi)| {
        format!(
            " (calibration band {} to {} over {} calibrated sets, their phi_s and k_d)",
            shown_km(lo),
            shown_km(hi),
            s.wear_band.len()
        )
    })
}

/// The polygon order named over several structures: over the tread's life the deepest order of
/// the wheels that grew past the seed (with the median peak share reached), as the new tire the
/// median fastest order.
fn structures_order_note(wear: &[CycleWear], over_life: bool, seed_share: f64) -> String {
    let q = quantile;
    let mut orders: Vec<f64> = wear
        .iter()
        .map(|c| c.dominant_order)
        .filter(|n| n.is_finite())
        .collect();
    orders.sort_by(f64::total_cmp);
    if over_life {
        // Over the tread's life the order named is the one visible first or, where none is,
        // the deepest: only wheels whose orders grew past the seed have one worth naming.
        let grown: Vec<&CycleWear> = wear
            .iter()
            .filter(|c| c.peak_share_of_visible > seed_share * (1.0 + 1e-9))
            .collect();
        let mut named: Vec<f64> = grown.iter().map(|c| c.dominant_order).collect();
        named.sort_by(f64::total_cmp);
        let mut peaks: Vec<f64> = wear.iter().map(|c| c.peak_share_of_visible).collect();
        peaks.sort_by(f64::total_cmp);
        match named.get(named.len() / 2) {
            None => "; every order levels out from its seed on every structure".to_string(),
            Some(n) => format!(
                "; the deepest order mostly {n:.0}, a median {}% of the visible depth reached",
                plain(100.0 * q(&peaks, 0.5), 2)
            ),
        }
    } else {
        orders.get(orders.len() / 2).map_or(String::new(), |n| {
            format!("; the fastest order mostly {n:.0}")
        })
    }
}

/// The calibration band of the median distance over several structures; nothing when the wheel
/// has no calibrated sets or no set has a median.
fn median_band_note(all: &[[WheelSummary; 2]], w: usize) -> String {
    let q = quantile;
    // The band of the median: the median over the structures under each set, its range.
    let sets = all[0][w].wear_band.len();
    (sets > 0)
        .then(|| {
            let medians: Vec<f64> = (0..sets)
                .map(|k| {
                    let mut d: Vec<f64> = all
                        .iter()
                        .filter_map(|s| s[w].wear_band.get(k))
                        .map(|c| c.distance_to_visible_km)
                        .collect();
                    d.sort_by(f64::total_cmp);
                    q(&d, 0.5)
                })
                .filter(|x| !x.is_nan())
                .collect();
            let lo = medians.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = medians.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (!medians.is_empty()).then(|| {
                format!(
                    "; the median's calibration band {} to {} over {sets} calibrated sets",
                    shown_km(lo),
                    shown_km(hi)
                )
            })
        })
        .flatten()
        .unwrap_or_default()
}
