//! An [`crate::analysis::outcome::OutcomeAnswer`] in words, one writer for vibration and for
//! wear: the terminal's lines per wheel and per paired comparison, and the report's
//! occurrence and paired tables. The counts' own words come from [`CountWords`].

use std::fmt::Write as _;

use super::words::{paired_cells, pct};
use crate::analysis::counts::{ClassCounts, RiskCounts, WithinCounts};
use crate::analysis::outcome::Occurrence;
use crate::analysis::paired::Paired;
use polywear_core::classify::Class;
use polywear_core::model::Wheel;
use polywear_core::params::axle::Drivetrain;
use polywear_core::wording::km;

/// How an outcome's counts read.
pub(super) trait CountWords: RiskCounts {
    /// The counts behind a probability, for the terminal: "3 of 10 classified; 0 failed, 0 no
    /// traction".
    fn behind(&self) -> String;
    /// The report table's header cells of the counts, with their alignment row.
    fn header() -> (&'static str, &'static str);
    /// The report table's cells of the counts, in the header's order.
    fn cells(&self) -> String;
}

impl CountWords for ClassCounts {
    fn behind(&self) -> String {
        format!(
            "{} of {} classified; {} failed, {} no traction",
            self.vibrating(),
            self.classified(),
            self.failed(),
            self.no_traction()
        )
    }
    fn header() -> (&'static str, &'static str) {
        (
            "classified | vibrating | P(vibration) | 95% Wilson interval | stable | limit cycle | bistable | no traction | failed",
            "---:|---:|---:|---|---:|---:|---:|---:|---:",
        )
    }
    fn cells(&self) -> String {
        let (lo, hi) = self.wilson();
        format!(
            "{} | {} | {} | {} – {} | {} | {} | {} | {} | {}",
            self.classified(),
            self.vibrating(),
            pct(self.p()),
            pct(lo),
            pct(hi),
            self.get(Class::Stable),
            self.get(Class::LimitCycle),
            self.get(Class::Bistable),
            self.no_traction(),
            self.failed()
        )
    }
}

impl CountWords for WithinCounts {
    fn behind(&self) -> String {
        format!(
            "{} of {} with a distance; {} unknown",
            self.within, self.known, self.unknown
        )
    }
    fn header() -> (&'static str, &'static str) {
        (
            "wheels with a distance | visible polygon | P(wear) | 95% Wilson interval | unknown",
            "---:|---:|---:|---|---:",
        )
    }
    fn cells(&self) -> String {
        let (lo, hi) = self.wilson();
        format!(
            "{} | {} | {} | {} – {} | {}",
            self.known,
            self.within,
            pct(self.p()),
            pct(lo),
            pct(hi),
            self.unknown
        )
    }
}

/// " within 40,000 km" after a wheel's name, where the row has a distance (NaN: none).
fn within_words(within_km: f64, width: usize) -> String {
    if within_km.is_nan() {
        String::new()
    } else {
        format!(" within {:>width$}", km(within_km))
    }
}

/// The terminal's line per variant, wheel (and distance): the probability, its Wilson
/// interval and the counts behind it.
pub(super) fn occurrence_lines<C: CountWords>(
    lines: &mut Vec<String>,
    rows: &[(f64, &Occurrence<C>)],
    drivetrain: Drivetrain,
) {
    for (within_km, o) in rows {
        let (lo, hi) = o.counts.wilson();
        lines.push(format!(
            "  {:>8} {:>15}{}: {:>7.3}%  [{:.3}%, {:.3}%]  ({})",
            o.variant,
            drivetrain.words(o.wheel),
            within_words(*within_km, 10),
            100.0 * o.p(),
            100.0 * lo,
            100.0 * hi,
            o.counts.behind()
        ));
    }
}

/// The terminal's line per paired comparison: its counts and McNemar's p-value.
pub(super) fn paired_lines(lines: &mut Vec<String>, rows: &[(f64, &Paired)]) {
    for (within_km, p) in rows {
        lines.push(format!(
            "  {:>8} paired{}: {}; McNemar p = {}",
            p.variant,
            within_words(*within_km, 10),
            p.counts_text(),
            p.mcnemar_text()
        ));
    }
}

/// The report's table of the probability per variant, wheel (and distance, where
/// `with_km`).
pub(super) fn occurrence_table<C: CountWords>(
    s: &mut String,
    rows: &[(f64, &Occurrence<C>)],
    with_km: bool,
    drivetrain: Drivetrain,
) {
    let (head, align) = C::header();
    let (kh, ka) = if with_km {
        (" within |", "---:|")
    } else {
        ("", "")
    };
    let _ = writeln!(s, "| variant | wheel |{kh} {head} |");
    let _ = writeln!(s, "|---|---|{ka}{align}|");
    for (within_km, o) in rows {
        let k = if with_km {
            format!(" {} |", km(*within_km))
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "| {} | {} |{k} {} |",
            o.variant,
            drivetrain.words(o.wheel),
            o.counts.cells()
        );
    }
}

/// The report's table of the paired comparisons per variant (and distance, where `with_km`);
/// `unknown` names the samples left out ("a wheel unclassified", "a wheel unknown").
pub(super) fn paired_table(
    s: &mut String,
    rows: &[(f64, &Paired)],
    with_km: bool,
    unknown: &str,
    drivetrain: Drivetrain,
) {
    let follower = drivetrain.words(Wheel::Follower);
    let driving = drivetrain.words(Wheel::Driving);
    let (kh, ka) = if with_km {
        (" within |", "---:|")
    } else {
        ("", "")
    };
    let _ = writeln!(
        s,
        "| variant |{kh} pairs | only {follower} | only {driving} | both | neither | {unknown} | McNemar p-value |"
    );
    let _ = writeln!(s, "|---|{ka}---:|---:|---:|---:|---:|---:|---:|");
    for (within_km, p) in rows {
        let k = if with_km {
            format!(" {} |", km(*within_km))
        } else {
            String::new()
        };
        let _ = writeln!(s, "| {} |{k} {} |", p.variant, paired_cells(p));
    }
}
