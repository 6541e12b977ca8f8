//! Which of a fleet's operating points are risky: for a study with `[operating_points]`, each
//! row of the file with its P(vibration) per wheel (Wilson interval), its share of the weight
//! (hours, distance, or equal rows) and its share of the fleet's risk, the rows sorted by that
//! share.
//!
//! Samples draw rows in proportion to their weight, so the run's P(vibration) is already the
//! weighted one: P = Σ_r w_r P_r / Σ_r w_r. A row's share of the fleet's risk is its term of
//! that sum, w_r P_r / Σ w P, per wheel and for both wheels together; the shares of a wheel add
//! up to 1.

use std::collections::BTreeMap;

use super::counts::ClassCounts;
use super::inputs::RunInfo;
use super::outcome::RowCounts;
use polywear_core::model::{Variant, Wheel};

/// What the weight of an operating point measures, from the study's `weight`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum WeightKind {
    /// Hours driven there (a column named `hours`, or `weight_kind = "hours"`).
    Hours(String),
    /// Distance driven there (a column named `km`, or `weight_kind = "km"`).
    Km(String),
    /// Another column, whose meaning the study does not say.
    Column(String),
    /// No weight column: every row is equally likely.
    EqualRows,
}

impl WeightKind {
    /// The kind from the recorded weight column and, where the run records one, its declared
    /// kind (`hours` or `km`); without a declared kind the column's name says it.
    pub fn of(column: Option<&str>, kind: Option<&str>) -> WeightKind {
        let Some(column) = column else {
            return WeightKind::EqualRows;
        };
        match kind.unwrap_or(column) {
            "hours" => WeightKind::Hours(column.to_string()),
            "km" => WeightKind::Km(column.to_string()),
            _ => WeightKind::Column(column.to_string()),
        }
    }

    /// How the headline is weighted, in words, to follow "P(vibration) is": "weighted by hours
    /// driven at each operating point (column `hours`)".
    pub fn words(&self) -> String {
        match self {
            WeightKind::Hours(c) => {
                format!("weighted by hours driven at each operating point (column `{c}`)")
            }
            WeightKind::Km(c) => {
                format!("weighted by distance driven at each operating point (column `{c}`)")
            }
            WeightKind::Column(c) => format!("weighted by column `{c}` of the operating points"),
            WeightKind::EqualRows => {
                "weighted equally over the operating points (no weight column)".to_string()
            }
        }
    }

    /// The weight's name in a table heading: "hours", "distance", the column, or "rows".
    pub fn short(&self) -> &str {
        match self {
            WeightKind::Hours(_) => "hours",
            WeightKind::Km(_) => "distance",
            WeightKind::Column(c) => c,
            WeightKind::EqualRows => "rows",
        }
    }
}

/// One operating point of the file, for one variant.
#[derive(Debug, Clone, PartialEq)]
pub struct FleetRow {
    /// The friction variant.
    pub variant: Variant,
    /// The row of the file, counted from 1 (as error messages and `operating_point_row` count).
    pub row: u64,
    /// The row's values of [`Fleet::columns`] (empty when the study cannot be read back).
    pub values: Vec<f64>,
    /// Its weight over the total weight (NaN when the study cannot be read back).
    pub weight_share: f64,
    /// Rows per class of the follower.
    pub follower: ClassCounts,
    /// Rows per class of the driving wheel.
    pub driving: ClassCounts,
    /// Its share of the fleet's risk per wheel: follower, driving.
    pub risk_share: [f64; 2],
    /// Its share of the fleet's risk of both wheels together (the sort key).
    pub risk_share_both: f64,
}

impl FleetRow {
    /// The counts of `wheel`.
    pub fn counts(&self, wheel: Wheel) -> &ClassCounts {
        match wheel {
            Wheel::Follower => &self.follower,
            Wheel::Driving => &self.driving,
        }
    }
}

/// The per-row answer of a fleet run.
#[derive(Debug, Clone, PartialEq)]
pub struct Fleet {
    /// The operating-point file as the study names it.
    pub file: String,
    /// Its parameter columns, in file order.
    pub columns: Vec<String>,
    /// What the weights measure.
    pub weight: WeightKind,
    /// Every row drawn at least once, per variant, sorted by variant then by
    /// [`FleetRow::risk_share_both`] (largest first; rows without a verdict last).
    pub rows: Vec<FleetRow>,
    /// Rows of the file with a positive weight that no sample drew.
    pub never_drawn: u64,
}

/// The per-row table of a run with `[operating_points]`, from the vibration answer's counts
/// per row ([`crate::analysis::outcome::OutcomeAnswer::fleet`]); None for other runs.
pub(crate) fn fleet(per_row: &[RowCounts], info: &RunInfo) -> Option<Fleet> {
    let record = info.operating_points.as_ref()?;
    let op = info
        .study
        .as_ref()
        .and_then(|s| s.operating_points.as_ref());
    // Shares relative to the largest weight, so that weights near the largest float sum
    // without overflow.
    let largest = op.map_or(f64::NAN, |o| {
        o.weights.iter().fold(0.0f64, |m, w| m.max(*w))
    });
    let total_weight: f64 = op.map_or(f64::NAN, |o| o.weights.iter().map(|w| w / largest).sum());
    let mut out: Vec<FleetRow> = per_row
        .iter()
        .map(
            |&RowCounts {
                 variant,
                 row,
                 counts: [follower, driving],
             }| {
                let i = (row - 1) as usize;
                let values = op
                    .and_then(|o| o.values.get(i).cloned())
                    .unwrap_or_default();
                let weight_share = op
                    .and_then(|o| o.weights.get(i))
                    .map_or(f64::NAN, |w| w / largest / total_weight);
                FleetRow {
                    variant,
                    row,
                    values,
                    weight_share,
                    follower,
                    driving,
                    risk_share: [f64::NAN; 2],
                    risk_share_both: f64::NAN,
                }
            },
        )
        .collect();
    risk_shares(&mut out);
    let drawn_rows = |v: Variant| out.iter().filter(|r| r.variant == v).count() as u64;
    let positive = op.map_or(0, |o| o.weights.iter().filter(|w| **w > 0.0).count() as u64);
    let never_drawn = info
        .variants
        .first()
        .map_or(0, |v| positive.saturating_sub(drawn_rows(*v)));
    Some(Fleet {
        file: record.file.clone(),
        columns: record.columns.clone(),
        weight: WeightKind::of(record.weight.as_deref(), None),
        rows: out,
        never_drawn,
    })
}

/// Each row's term of the weighted P(vibration) over the sum of the terms, per variant and
/// wheel and for both wheels together; then the rows sorted by the latter. A row without a
/// classified sample has no term (NaN) and adds nothing to the sums.
fn risk_shares(rows: &mut [FleetRow]) {
    let term = |r: &FleetRow, w: Wheel| {
        let p = r.counts(w).p();
        if p.is_finite() {
            r.weight_share * p
        } else {
            0.0
        }
    };
    let mut sums: BTreeMap<Variant, [f64; 2]> = BTreeMap::new();
    for r in rows.iter() {
        let s = sums.entry(r.variant).or_default();
        s[0] += term(r, Wheel::Follower);
        s[1] += term(r, Wheel::Driving);
    }
    for r in rows.iter_mut() {
        let s = sums[&r.variant];
        let share = |t: f64, total: f64| if total > 0.0 { t / total } else { f64::NAN };
        let (f, d) = (term(r, Wheel::Follower), term(r, Wheel::Driving));
        let known = r.follower.classified() + r.driving.classified() > 0;
        r.risk_share = [share(f, s[0]), share(d, s[1])];
        r.risk_share_both = if known {
            share(f + d, s[0] + s[1])
        } else {
            f64::NAN
        };
    }
    rows.sort_by(|a, b| {
        let key = |r: &FleetRow| {
            if r.risk_share_both.is_finite() {
                r.risk_share_both
            } else {
                f64::NEG_INFINITY
            }
        };
        a.variant
            .cmp(&b.variant)
            .then(key(b).total_cmp(&key(a)))
            .then(a.row.cmp(&b.row))
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_core::classify::Class;

    fn counts(vibrating: u64, stable: u64) -> ClassCounts {
        let mut c = ClassCounts::default();
        c.add(Class::LimitCycle, vibrating);
        c.add(Class::Stable, stable);
        c
    }

    fn row(r: u64, weight_share: f64, f: (u64, u64), d: (u64, u64)) -> FleetRow {
        FleetRow {
            variant: Variant::SlidingShare,
            row: r,
            values: vec![],
            weight_share,
            follower: counts(f.0, f.1),
            driving: counts(d.0, d.1),
            risk_share: [f64::NAN; 2],
            risk_share_both: f64::NAN,
        }
    }

    #[test]
    fn risk_shares_are_the_terms_of_the_weighted_probability() {
        // Row 1: 10% of the hours, always vibrating; row 2: 90%, vibrating a tenth of the time.
        let mut rows = vec![
            row(1, 0.1, (50, 0), (0, 50)),
            row(2, 0.9, (10, 90), (10, 90)),
            row(3, 0.0, (0, 0), (0, 0)),
        ];
        risk_shares(&mut rows);
        // Both wheels: 0.1 of 0.28 against 0.18 of 0.28, so row 2 leads; row 3, never
        // classified, comes last without a share.
        assert_eq!(rows.iter().map(|r| r.row).collect::<Vec<_>>(), [2, 1, 3]);
        let (r2, r1, r3) = (&rows[0], &rows[1], &rows[2]);
        assert!((r2.risk_share_both - 0.18 / 0.28).abs() < 1e-12);
        assert!((r1.risk_share_both - 0.1 / 0.28).abs() < 1e-12);
        assert!(r3.risk_share_both.is_nan());
        // Weighted P(follower) = 0.1 + 0.09 = 0.19: row 1 holds 0.1 / 0.19 of it.
        assert!((r1.risk_share[0] - 0.1 / 0.19).abs() < 1e-12);
        assert!((r2.risk_share[0] - 0.09 / 0.19).abs() < 1e-12);
        // The driving wheel vibrates only on row 2.
        assert_eq!(r1.risk_share[1], 0.0);
        assert!((r2.risk_share[1] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_weight_kind_comes_from_the_declared_kind_or_the_column() {
        assert_eq!(
            WeightKind::of(Some("hours"), None),
            WeightKind::Hours("hours".into())
        );
        assert_eq!(
            WeightKind::of(Some("dist"), Some("km")),
            WeightKind::Km("dist".into())
        );
        assert_eq!(
            WeightKind::of(Some("trips"), None),
            WeightKind::Column("trips".into())
        );
        assert_eq!(WeightKind::of(None, None), WeightKind::EqualRows);
        assert!(WeightKind::of(Some("hours"), None)
            .words()
            .contains("hours driven"));
    }
}
