//! The report's wear answer, which leads the page: how likely a visible polygon is within each
//! distance per wheel, driving against follower (McNemar), what the distance means and which
//! constants are field-fitted (MODEL.md#calibration-to-the-field), where the wear risk lives
//! (risk maps beside the vibration maps), how fast polygons grow and their orders. Where the
//! wear answer and the paper's vibration answer disagree it says so first.

use std::fmt::Write as _;

use super::answer_words;
use super::words::{pct, rel};
use super::Figures;
use crate::analysis::paired::Paired;
use crate::analysis::rows::{SampleWeight, NEAR_MISS_SHARES};
use crate::analysis::wear_risk::{WearAnalysis, HEADLINE_WITHIN_KM, ORDERS_WITHIN_KM};
use crate::analysis::Analysis;
use polywear_core::model::{Variant, Wheel};
use polywear_core::params::axle::Drivetrain;
use polywear_core::params::ParamId;
use polywear_core::wording::plain;
use polywear_study::stats::format_p;

pub(crate) use polywear_core::wording::km;

/// The line a report without the wear stage carries instead of the wear answer.
pub(crate) const NO_WEAR_LINE: &str = "> The wear stage was left out of this run (`polywear explore --no-wear`, or `wear = false` in the study): there is no distance to a visible polygon, so this report answers for vibration only.";

/// The wear answer's sections, or `NO_WEAR_LINE` for a run without them.
pub(crate) fn section(s: &mut String, a: &Analysis, figures: &Figures) {
    let Some(w) = &a.wear else {
        let _ = writeln!(s, "{NO_WEAR_LINE}\n");
        return;
    };
    let _ = writeln!(s, "## The answer: polygonal wear\n");
    for variant in a.variants() {
        headline(s, a, w, variant);
    }
    meaning(s, a, w);
    occurrence_table(s, a, w);
    near_misses(s, w);
    paired_table(s, w, a.info.params.drivetrain);
    super::band::section(s, a);
    where_wear(s, a, figures);
    growth(s, w, figures);
}

/// The sentence a manager reads: which wheel wears polygonal, how likely within
/// [`HEADLINE_WITHIN_KM`], with its interval and McNemar's p; loud where the driving wheel is
/// not less exposed in wear although it is in vibration.
fn headline(s: &mut String, a: &Analysis, w: &WearAnalysis, variant: Variant) {
    let (Some(f), Some(d)) = (
        w.headline(variant, Wheel::Follower),
        w.headline(variant, Wheel::Driving),
    ) else {
        return;
    };
    let interval = |c: &crate::analysis::counts::WithinCounts, wheel: Wheel| {
        let (lo, hi) = c.wilson();
        let banded = a
            .band
            .as_ref()
            .and_then(|b| b.occurrence_of(variant, wheel, HEADLINE_WITHIN_KM))
            .map_or(String::new(), |r| format!("; {}", super::band::percent(r)));
        format!(
            "{} (95% interval {} – {}{banded})",
            pct(c.p()),
            pct(lo),
            pct(hi)
        )
    };
    let paired = w.paired_at(variant, HEADLINE_WITHIN_KM);
    // The wheels by axle and role, "rear (follower)" (MODEL.md#the-car-axles-and-drivetrain).
    let drivetrain = a.info.params.drivetrain;
    let (fw, dw) = (
        drivetrain.words(Wheel::Follower),
        drivetrain.words(Wheel::Driving),
    );
    let verdict = match paired {
        Some(p) if p.p_value < 0.05 && p.only_follower > p.only_driving => {
            format!("the {fw} wheel wears polygonal significantly more often than the {dw} one")
        }
        Some(p) if p.p_value < 0.05 && p.only_driving > p.only_follower => {
            format!("the {dw} wheel wears polygonal significantly more often than the {fw} one")
        }
        _ => "neither wheel wears polygonal significantly more often than the other".to_string(),
    };
    let _ = writeln!(
        s,
        "**Within {}, {} of {fw} wheels and {} of {dw} wheels get a visible polygon** \
         ({} mm peak-to-valley; `{variant}` variant). On the same samples {verdict}{}.\n",
        km(HEADLINE_WITHIN_KM),
        interval(&f.counts, Wheel::Follower),
        interval(&d.counts, Wheel::Driving),
        plain(w.visible_depth_mm, 3),
        paired.map_or(String::new(), |p| format!(
            " (McNemar p = {}: {} samples wear on the {fw} wheel only, {} on the {dw} wheel only)",
            p_text(p),
            p.only_follower,
            p.only_driving
        )),
    );
    if let Some(pb) = a.band.as_ref().and_then(|b| {
        b.paired_of(variant, HEADLINE_WITHIN_KM)
            .map(|p| (p, b.sets.len()))
    }) {
        let _ = writeln!(
            s,
            "Across the calibration band: {}.\n",
            super::band::paired_words(pb.0, pb.1)
        );
    }
    let vib = a.vibration.paired_of(variant);
    let driving_less_vibrating =
        vib.is_some_and(|p| p.p_value < 0.05 && p.only_follower > p.only_driving);
    let driving_less_wearing =
        paired.is_some_and(|p| p.p_value < 0.05 && p.only_follower > p.only_driving);
    if driving_less_vibrating && !driving_less_wearing {
        let v = vib.expect("checked above");
        let _ = writeln!(
            s,
            "> **The wear answer disagrees with the paper's vibration answer.** The driving wheel \
             vibrates less often than the follower ({} against {} of the samples, vibration \
             answer below), as the paper concludes, but it is **not less exposed to polygonal \
             wear**: {} against {} within {}. A stable tread grows polygons too, next to its \
             lightly damped resonance, and the driving wheel is stable more often; this is a \
             finding of the model, stated and not tuned away (MODEL.md#calibration-to-the-field). \
             Sueoka's field survey puts polygons on follower wheels.\n",
            pct(v.p_driving()),
            pct(v.p_follower()),
            pct(d.counts.p()),
            pct(f.counts.p()),
            km(HEADLINE_WITHIN_KM)
        );
    }
}

/// McNemar's p in words.
fn p_text(p: &Paired) -> String {
    if p.p_value.is_nan() {
        "n/a, no discordant pairs".into()
    } else {
        format!("{}, {}", format_p(p.p_value), p.method)
    }
}

/// What the distance means, which constants are field-fitted, how the samples are weighed and
/// which wheels are unknown.
fn meaning(s: &mut String, a: &Analysis, w: &WearAnalysis) {
    let drawn = |p: ParamId| a.info.drawn_names.contains(&p);
    let value = |p: ParamId, x: f64, unit: &str| {
        if drawn(p) {
            format!("drawn per sample (nominal {}{unit})", plain(x, 4))
        } else {
            format!("{}{unit}", plain(x, 4))
        }
    };
    let level_words =
        "**These distances are over the tread's life, each speed's print saturated**: every \
         order the tread frequency passes as the tread wears grows from the seed, the speed \
         spread driven on 40 legs and a deep order's print at each held to what sliding \
         friction can modulate (MODEL.md#the-forced-response-saturates), the one answer, which \
         agrees with the long-term loop (`polywear wear`). The five constants no measurement \
         fixes (φ_s, σ_V, k_d and the carcass and belt shares, which set how fast the tread \
         frequency drifts) are calibrated on these answers, and the calibration band is their \
         range (where the field's facts hold: the band's section).";
    let _ = writeln!(
        s,
        "**What the distance means.** A wheel's distance to a visible polygon is the distance it \
         runs **cruising at its sample's operating point, with the study's spread of the cruising \
         speed** (σ_V = {}, `speed_spread_kmh`), all its life; a wheel whose every order levels \
         out never gets one (+inf). A polygon counts as visible within a distance only if it \
         comes **before the tire is worn out** (`tread_life_km`: the position's whole even wear \
         down to the worn-out depth; a driven tire wears faster and is often replaced first), \
         the rows' `wear_outcome` \"visible\". **Constants are calibrated, not measured**: φ_s = {} \
         (`wear_share_straight`, the share of the even wear that straight running with toe \
         causes, to which the vibration couples), σ_V and three more. They are held to a highway \
         follower with excessive toe-in showing a polygon after 25,000–40,000 km, as Sueoka's \
         survey of passenger cars found, and to most tires never doing so (MODEL.md#calibration-to-the-field); \
         φ_s = 1 with no spread is the worst case. {level_words}\n",
        value(ParamId::SpeedSpreadKmh, w.speed_spread_kmh, " km/h"),
        value(ParamId::WearShareStraight, w.share_straight, ""),
    );
    if w.weight == SampleWeight::SpeedKmh {
        let _ = writeln!(
            s,
            "Wear is weighed by distance: the samples draw the operating points by hours driven, \
             so each counts in proportion to its speed (distance = hours × speed_kmh); the \
             intervals use the weighted samples' effective count.\n"
        );
    } else if a.fleet.is_some() {
        let _ = writeln!(
            s,
            "Wear is weighed by distance; the samples draw the operating points {}, so each \
             counts once.\n",
            a.fleet.as_ref().map_or(String::new(), |f| f.weight.words())
        );
    }
    let unknown = w.unknown();
    if unknown > 0 {
        let _ = writeln!(
            s,
            "> {unknown} {} no distance (NaN: failed, no traction, standstill, or a cycle the \
             estimator cannot close; `wear_reason` says why). They are counted on their own and \
             left out of every wear probability.\n",
            if unknown == 1 {
                "wheel has"
            } else {
                "wheels have"
            }
        );
    }
}

fn occurrence_table(s: &mut String, a: &Analysis, w: &WearAnalysis) {
    answer_words::occurrence_table(s, &w.occurrence_rows(), true, a.info.params.drivetrain);
    let _ = writeln!(
        s,
        "\nTables: `wear_occurrence.csv`, `wear_occurrence.parquet`{}.\n",
        if a.fleet.is_some() {
            "; per operating point: `wear_fleet_rows.csv`"
        } else {
            ""
        }
    );
}

/// How near the wheels without a visible polygon came, over the tread's life: the wheels whose
/// deepest order reached each share of the visible depth (`wear_peak_share_of_visible`). A
/// run on the new tire's level has no such column values and no section.
fn near_misses(s: &mut String, w: &WearAnalysis) {
    if w.near_misses.is_empty() {
        return;
    }
    let _ = writeln!(s, "### How near the others came\n");
    let _ = writeln!(
        s,
        "Over the tread's life each wheel's deepest order has a largest depth before the tire is \
         worn out (`wear_peak_share_of_visible`, as a share of the visible depth, {} mm): the \
         wheels that reached each share, among those with a value. A fleet far from the cliff \
         has few wheels in the middle columns; a small change of the constants or the operating \
         point moves the wheels near 100% across it.\n",
        plain(w.visible_depth_mm, 3)
    );
    let heads: Vec<String> = NEAR_MISS_SHARES
        .iter()
        .map(|&t| {
            if t >= 1.0 {
                "visible before worn out".to_string()
            } else {
                format!("≥ {:.0}%", 100.0 * t)
            }
        })
        .collect();
    let _ = writeln!(
        s,
        "| variant | wheel | wheels with a value | {} |",
        heads.join(" | ")
    );
    let _ = writeln!(s, "|---|---|---:|{}", "---:|".repeat(heads.len()));
    for m in &w.near_misses {
        let cells: Vec<String> = m
            .at_least
            .iter()
            .map(|&n| format!("{n} ({})", pct(n as f64 / m.known as f64)))
            .collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} |",
            m.variant,
            m.wheel,
            m.known,
            cells.join(" | ")
        );
    }
    let _ = writeln!(
        s,
        "\nTables: `wear_near_misses.csv`, `wear_near_misses.parquet`.\n"
    );
}

fn paired_table(s: &mut String, w: &WearAnalysis, drivetrain: Drivetrain) {
    let _ = writeln!(s, "### Driving vs follower in wear, on the same samples\n");
    answer_words::paired_table(s, &w.paired_rows(), true, "a wheel unknown", drivetrain);
    let _ = writeln!(
        s,
        "\nThe outcome is \"a visible polygon within the distance, before the tire is worn out\"; McNemar's test asks whether \
         the samples where only one wheel gets one split evenly. Tables: `wear_paired.csv`, \
         `wear_paired.parquet`.\n"
    );
}

fn where_wear(s: &mut String, a: &Analysis, figures: &Figures) {
    let _ = writeln!(s, "### Where polygonal wear lives\n");
    let _ = writeln!(
        s,
        "P(visible polygon within {}) per bin of each drawn parameter and over the risk maps' \
         cells, per wheel, with the nominal tire's Hopf curves (the stability boundaries) as on \
         the vibration maps; grey cells hold fewer than {} wheels with a distance. Tables: \
         `wear_conditional.csv`, `wear_riskmap_<x>_<y>.csv` (and `.parquet`).\n",
        km(HEADLINE_WITHIN_KM),
        a.options.min_count
    );
    for (_, f) in &figures.wear_conditional {
        let _ = writeln!(s, "![]({})\n", rel(f));
    }
    for f in &figures.wear_maps {
        let _ = writeln!(s, "![]({})\n", rel(&f.path));
    }
}

fn growth(s: &mut String, w: &WearAnalysis, figures: &Figures) {
    let _ = writeln!(
        s,
        "### How fast polygons grow, and how many sides they have\n"
    );
    let _ = writeln!(
        s,
        "Over every wheel with a figure: the growth rate of its dominant order (per 1000 km; \
         ≤ 0: it levels out; \"never\": every order levels out from its seed over the tread's \
         life, so no order is the wear's) and the finite distances to a visible polygon, beside \
         the share that never gets one (+inf). The distances are the point's, as if the tread never \
         ran out; the probabilities above count only those before the tire is worn out \
         (`tread_life_km`). Tables: `wear_severity.csv`, `wear_severity.parquet`.\n"
    );
    let _ = writeln!(
        s,
        "| variant | wheel | quantity | finite | never (+inf) | unknown | 5% | 25% | median | 75% | 95% |"
    );
    let _ = writeln!(s, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for v in &w.severity {
        let q = |x: f64| {
            if x.is_finite() {
                plain(x, 4)
            } else {
                "n/a".into()
            }
        };
        let unit = v.quantity.column.unit();
        let never = if v.quantity.log || v.spread.pos_inf > 0 {
            pct(v.share_inf())
        } else {
            "–".into()
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} [{}] | {} | {} | {} | {} | {} | {} | {} | {} |",
            v.variant,
            v.wheel,
            v.quantity.title,
            unit,
            v.spread.finite,
            never,
            v.spread.unknown,
            q(v.quantiles[0]),
            q(v.quantiles[1]),
            q(v.quantiles[2]),
            q(v.quantiles[3]),
            q(v.quantiles[4])
        );
    }
    let _ = writeln!(
        s,
        "\nThe dominant order (sides of the polygon) among the wheels with a visible polygon \
         within {}, per wheel. Tables: `wear_orders.csv`, `wear_orders.parquet`.\n",
        km(ORDERS_WITHIN_KM)
    );
    let _ = writeln!(
        s,
        "| variant | order | follower wheels | follower share | driving wheels | driving share |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|");
    let mut keys: Vec<(Variant, i64)> = w.orders.iter().map(|o| (o.variant, o.order)).collect();
    keys.sort();
    keys.dedup();
    let count = |v: Variant, wheel: Wheel, order: Option<i64>| -> u64 {
        w.orders
            .iter()
            .filter(|c| c.variant == v && c.wheel == wheel && order.is_none_or(|o| c.order == o))
            .map(|c| c.n)
            .sum()
    };
    for (v, order) in keys {
        let (nf, nd) = (
            count(v, Wheel::Follower, Some(order)),
            count(v, Wheel::Driving, Some(order)),
        );
        let share = |n: u64, wheel| pct(n as f64 / count(v, wheel, None) as f64);
        let _ = writeln!(
            s,
            "| {v} | {order} | {nf} | {} | {nd} | {} |",
            share(nf, Wheel::Follower),
            share(nd, Wheel::Driving)
        );
    }
    for (_, f) in &figures.wear_orders {
        let _ = writeln!(s, "\n![]({})", rel(f));
    }
    let _ = writeln!(s);
}
