//! The calibration band in words (MODEL.md#the-calibration-band): beside each wear figure's
//! sampling interval, its range over the calibrated sets of fitted constants, and the report's
//! section that says what the band is and which set gives each end.

use polywear_core::wording::{capitalise, markdown_text};
use std::fmt::Write as _;

use crate::analysis::band::{BandRange, CalibrationBand, PairedBand};
use crate::analysis::Analysis;
use polywear_core::model::Wheel;
use polywear_core::wording::km;

/// "calibration band 6.1–11.8%" for a probability.
pub(crate) fn percent(r: &BandRange) -> String {
    format!("calibration band {:.1}–{:.1}%", 100.0 * r.lo, 100.0 * r.hi)
}

/// "calibration band −11.0 to −54.0 points" for a difference of probabilities.
pub(crate) fn points(r: &BandRange) -> String {
    let p = |x: f64| {
        let t = format!("{:+.1}", 100.0 * x);
        if t == "+0.0" || t == "-0.0" {
            "0.0".to_string()
        } else {
            t.replace('-', "−")
        }
    };
    format!("calibration band {} to {} points", p(r.lo), p(r.hi))
}

/// Which wheel is more exposed across the band, in words that name a wheel only where the sign
/// holds under every set.
pub(crate) fn paired_words(p: &PairedBand, sets: usize) -> String {
    let r = &p.follower_minus_driving;
    // As finely as the smaller end needs to read as not zero.
    let by = |a: f64, b: f64| {
        let digits = if a.abs().min(b.abs()) < 0.001 { 3 } else { 1 };
        format!("by {:.digits$} to {:.digits$} points", 100.0 * a, 100.0 * b)
    };
    match p.holds() {
        Some(Wheel::Follower) => format!(
            "the follower is more exposed under all {sets} calibrated sets ({})",
            by(r.lo, r.hi)
        ),
        Some(Wheel::Driving) => format!(
            "the driving wheel is more exposed under all {sets} calibrated sets ({})",
            by(-r.hi, -r.lo)
        ),
        // One wheel ahead under some sets and behind under none: the others are ties (both
        // figures the same, mostly 0 under the sets of lowest φ_s), said as such rather than as
        // a set that reverses the sign.
        None if p.driving_ahead == 0 && p.follower_ahead > 0 => format!(
            "the follower is ahead under {} and behind under none of the {sets} calibrated sets (tied under {}: both wheels' figures equal)",
            p.follower_ahead,
            sets.saturating_sub(p.follower_ahead)
        ),
        None if p.follower_ahead == 0 && p.driving_ahead > 0 => format!(
            "the driving wheel is ahead under {} and behind under none of the {sets} calibrated sets (tied under {}: both wheels' figures equal)",
            p.driving_ahead,
            sets.saturating_sub(p.driving_ahead)
        ),
        None => format!(
            "which wheel is more exposed depends on the calibrated set (follower ahead under {}, driving wheel under {}, tied under {} of {sets}): no wheel is named",
            p.follower_ahead,
            p.driving_ahead,
            sets.saturating_sub(p.follower_ahead + p.driving_ahead)
        ),
    }
}

/// What the band is, in one sentence: how many sets, their constants' ranges, the method and
/// the file, the subsample, and where the calibration's accepted region lies (the file's own
/// words, the finding an engineer quotes beside the band).
pub(crate) fn about(b: &CalibrationBand) -> String {
    let region = if b.region.is_empty() {
        String::new()
    } else {
        format!("; the calibration's finding: {}", b.region)
    };
    format!(
        "{} calibrated sets ({}; {}, {}), re-evaluated on {} of the run's samples{region}",
        b.sets.len(),
        b.constants_words(),
        b.method,
        b.source,
        b.samples
    )
}

/// The summary's line where the run has no band.
pub(crate) const NO_BAND: &str = "no calibration band in this run (explore wrote none: `--calibration-band off`, or an older polywear): the intervals are sampling only; the fitted constants' own uncertainty is not in them";

/// The report's section: what the band is, the headline's and the scenarios' bands with the
/// sets at their ends, and which wheel is more exposed where the sign holds.
pub(crate) fn section(s: &mut String, a: &Analysis) {
    let Some(w) = &a.wear else { return };
    let _ = writeln!(s, "### The calibration band\n");
    let Some(b) = &a.band else {
        let _ = writeln!(s, "> {}.\n", capitalise(NO_BAND));
        return;
    };
    let _ = writeln!(
        s,
        "The wear answer rests on five constants fitted to field facts, not measured: φ_s \
         (`wear_share_straight`), σ_V (`speed_spread_kmh`), the driven axle's wear rate k_d \
         (`wear_rate_driven_factor`, a published range) and the ageing tread's carcass and belt \
         shares c and μ_b (`carcass_share`, `belt_mass_share`, bounded by judgement). The field \
         facts do not fix them to a point: {}. Each figure below is the run's, moved by each set's difference from the \
         run's own constants on the same samples; its range over the sets is the calibration \
         band, beside the 95% Wilson interval (sampling only). The band's rows: `{}` \
         (MODEL.md#the-calibration-band).\n",
        markdown_text(&about(b)),
        b.file
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().to_string())
    );
    let _ = writeln!(
        s,
        "| variant | wheel | within | P(visible polygon) | calibration band | lowest under | highest under |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---|---|");
    for (within_km, o) in w.occurrence_rows() {
        if let Some(r) = b.occurrence_of(o.variant, o.wheel, within_km) {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {:.2}% | {:.1}–{:.1}% | `{}` | `{}` |",
                o.variant,
                o.wheel,
                km(within_km),
                100.0 * o.p(),
                100.0 * r.lo,
                100.0 * r.hi,
                r.lo_set,
                r.hi_set
            );
        }
    }
    let _ = writeln!(s);
    for p in &b.paired {
        let _ = writeln!(
            s,
            "- Within {} (`{}`): {}.",
            km(p.within_km),
            p.variant,
            paired_words(p, b.sets.len())
        );
    }
    if !b.scenarios.is_empty() {
        let _ = writeln!(s, "\nThe scenarios' effects across the band:\n");
        for e in &b.scenarios {
            let _ = writeln!(
                s,
                "- `{}`, {} ({}): {} (lowest under `{}`, highest under `{}`).",
                e.scenario,
                e.wheel,
                e.variant,
                points(&e.range),
                e.range.lo_set,
                e.range.hi_set
            );
        }
    }
    let _ = writeln!(s);
}

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_core::model::Variant;

    fn paired(lo: f64, hi: f64, follower_ahead: usize, driving_ahead: usize) -> PairedBand {
        PairedBand {
            variant: Variant::SlidingShare,
            within_km: 40_000.0,
            follower_minus_driving: BandRange {
                lo,
                lo_set: "a".into(),
                hi,
                hi_set: "b".into(),
            },
            follower_ahead,
            driving_ahead,
        }
    }

    /// A band whose sets put one wheel ahead or tie, never behind, says so; only a band whose
    /// sets reverse the sign names no wheel; a sign held by every set names it.
    #[test]
    fn ties_are_not_called_a_reversal() {
        let words = paired_words(&paired(0.0, 0.016, 78, 0), 96);
        assert_eq!(
            words,
            "the follower is ahead under 78 and behind under none of the 96 calibrated sets (tied under 18: both wheels' figures equal)"
        );
        let words = paired_words(&paired(-0.02, 0.0, 0, 5), 96);
        assert!(
            words.starts_with("the driving wheel is ahead under 5 and behind under none"),
            "{words}"
        );
        let words = paired_words(&paired(-0.01, 0.02, 60, 30), 96);
        assert!(
            words.contains("follower ahead under 60, driving wheel under 30, tied under 6 of 96")
                && words.ends_with("no wheel is named"),
            "{words}"
        );
        let words = paired_words(&paired(0.01, 0.02, 96, 0), 96);
        assert!(
            words.starts_with("the follower is more exposed under all 96"),
            "{words}"
        );
    }
}
