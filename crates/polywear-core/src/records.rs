//! One output row per wheel and operating point: the inputs, the static model (steps 1–7), the
//! linear stability (step 8) and the verdict (step 9). The first 24 columns carry exactly the
//! column names of `tests/data/points.csv`; the rest extend it.
//!
//! Every column is declared once, in `define_record!`'s table: name, unit, type and meaning.
//! The row type [`WheelRecord`], the typed column ids [`RecordColumn`], the column table
//! [`RECORD_COLUMNS`] (the Parquet and CSV writers, the `units` metadata, the analysis's column
//! names, the table in docs/book/src/reference/output-files.md#output-files) and [`record_columns`] all come from it.

use serde::Serialize;

use crate::classify::{Class, Method, WheelVerdict};
use crate::columns::Column;
use crate::model::{ModelFailure, Variant, Wheel, WheelModel};
use crate::params::axle::Axle;
use crate::params::Params;
use crate::wear::WearAnswer;

/// How a column is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColumnKind {
    /// A name (Parquet UTF-8 string).
    Str,
    /// A 64-bit float.
    F64,
    /// A 64-bit integer.
    I64,
}

impl ColumnKind {
    /// The type as written in the docs' column table.
    pub fn as_str(self) -> &'static str {
        match self {
            ColumnKind::Str => "string",
            ColumnKind::F64 => "float64",
            ColumnKind::I64 => "int64",
        }
    }
}

/// One output column: its name, unit, type and meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ColumnSpec {
    /// The column's name.
    pub name: &'static str,
    /// Its unit (`-` for a dimensionless number, empty for a name or a count).
    pub unit: &'static str,
    /// How it is stored.
    pub kind: ColumnKind,
    /// What it holds, in one line.
    pub meaning: &'static str,
}

/// A field written as a float column (a field of another type in a `F64` row fails to compile).
trait F64Cell {
    fn cell(&self) -> f64;
}
impl F64Cell for f64 {
    fn cell(&self) -> f64 {
        *self
    }
}
/// A field written as an integer column.
trait I64Cell {
    fn cell(&self) -> i64;
}
impl I64Cell for u64 {
    fn cell(&self) -> i64 {
        *self as i64
    }
}
/// A field written as a name column.
trait StrCell {
    fn cell(&self) -> String;
}
macro_rules! str_cell {
    ($($t:ty),*) => { $( impl StrCell for $t { fn cell(&self) -> String { self.to_string() } } )* };
}
str_cell!(Wheel, Axle, Variant, Class, Method, String);

/// Declares a row type, its typed column ids, its column table and its columns writer from one
/// table, so that a field, its column, its unit and its meaning cannot drift apart. Fields after
/// `extra` are carried by the row but are not its columns.
macro_rules! define_record {
    (
        $(#[$sattr:meta])* struct $row:ident;
        $(#[$eattr:meta])* enum $column:ident;
        $(#[$cattr:meta])* const $table:ident;
        $(#[$fattr:meta])* fn $writer:ident;
        extra { $( $(#[$xattr:meta])* $xfield:ident : $xty:ty, )* }
        $( $id:ident $field:ident : $ty:ty, $kind:ident, $unit:literal, $meaning:literal; )*
    ) => {
        $(#[$sattr])*
        #[derive(Debug, Clone, PartialEq, Serialize)]
        pub struct $row {
            $( #[doc = $meaning] pub $field: $ty, )*
            $( $(#[$xattr])* pub $xfield: $xty, )*
        }

        $(#[$eattr])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $column { $( #[doc = $meaning] $id, )* }

        $(#[$cattr])*
        pub const $table: &[ColumnSpec] = &[ $( ColumnSpec {
            name: stringify!($field), unit: $unit, kind: ColumnKind::$kind, meaning: $meaning,
        }, )* ];

        $(#[$fattr])*
        fn $writer(rows: &[$row]) -> Vec<Column> {
            vec![ $( define_record!(@col $kind, rows, $field, $unit), )* ]
        }

        impl $column {
            /// The column's row of its table.
            pub const fn spec(self) -> &'static ColumnSpec {
                &$table[self as usize]
            }

            /// The column's name in the files.
            pub const fn name(self) -> &'static str {
                self.spec().name
            }

            /// The column's unit.
            pub const fn unit(self) -> &'static str {
                self.spec().unit
            }
        }
    };
    (@col F64, $rows:expr, $field:ident, $unit:literal) => {
        Column::f64(stringify!($field), $unit, $rows.iter().map(|r| F64Cell::cell(&r.$field)).collect())
    };
    (@col I64, $rows:expr, $field:ident, $unit:literal) => {
        Column::i64(stringify!($field), $unit, $rows.iter().map(|r| I64Cell::cell(&r.$field)).collect())
    };
    (@col Str, $rows:expr, $field:ident, $unit:literal) => {
        Column::str(stringify!($field), $rows.iter().map(|r| StrCell::cell(&r.$field)).collect())
    };
}

define_record! {
    /// One row. Wheel, variant, class and method are the enums themselves; they become their
    /// names only when written (Parquet, CSV, JSON).
    struct WheelRecord;
    /// A column of [`WheelRecord`], typed: the analysis names columns by these.
    enum RecordColumn;
    /// Every record column, in field (and file) order.
    const RECORD_COLUMNS;
    /// The rows' own columns, without the wear stage's.
    fn core_columns;
    extra {
        /// The wear stage's figures ([`WEAR_COLUMNS`]), when the evaluation ran it.
        #[serde(flatten)]
        wear: Option<WearRecord>,
    }
    Wheel wheel: Wheel, Str, "", "The wheel: follower (free rolling) or driving.";
    Variant variant: Variant, Str, "", "The friction variant (MODEL.md#variants).";
    SpeedKmh speed_kmh: f64, F64, "km/h", "Vehicle speed V.";
    ToeDeg toe_deg: f64, F64, "deg", "Toe-in angle alpha.";
    LoadN load_n: f64, F64, "N", "Vertical load F_Z.";
    PressureKpa pressure_kpa: f64, F64, "kPa", "Inflation pressure P.";
    DeflectionM deflection_m: f64, F64, "m", "Maximum deflection delta (step 1).";
    ContactLengthM contact_length_m: f64, F64, "m", "Contact length a (step 2).";
    ContactWidthM contact_width_m: f64, F64, "m", "Contact width b (step 2).";
    KS k_s: f64, F64, "N/m", "Tread lateral stiffness K_s = sigma0 (step 3).";
    TreadMassKg tread_mass_kg: f64, F64, "kg", "Tread mass m (step 3).";
    SlipRatio slip_ratio: f64, F64, "-", "Slip ratio S (step 4; 0 for the follower).";
    Q q: f64, F64, "-", "Sliding share q of the contact length (step 4).";
    FM f_m: f64, F64, "N", "Maximum static friction level F_m (step 5).";
    FS f_s: f64, F64, "N", "Sliding friction level F_s (step 5).";
    Z0M z0_m: f64, F64, "m", "Bristle deflection z0 at the equilibrium (step 7).";
    Y0M y0_m: f64, F64, "m", "Tread displacement y0 at the equilibrium (step 7).";
    EigReMax eig_re_max: f64, F64, "1/s", "Largest real part of the Jacobian's eigenvalues (step 8).";
    EigFreqHz eig_freq_hz: f64, F64, "Hz", "Linear frequency of that eigenvalue (step 8).";
    Class class: Class, Str, "", "The verdict (step 9): stable, limit_cycle, bistable, no_traction, failed, standstill.";
    AmpYM amp_y_m: f64, F64, "m", "Half peak-to-peak of y over the cycle; 0 without a cycle, NaN when failed.";
    AmpVMps amp_v_mps: f64, F64, "m/s", "Half peak-to-peak of v over the cycle; 0 without a cycle, NaN when failed.";
    FreqHz freq_hz: f64, F64, "Hz", "The cycle's frequency 1/T.";
    PolygonOrder polygon_order: f64, F64, "-", "Wear facets n = f / f_rot of the vibration (MODEL.md#step-9-attractor); the wear's own order is polygon_order_wear.";
    Axle axle: Axle, Str, "", "The wheel's axle, front or rear, under the run's drivetrain (MODEL.md#the-car-axles-and-drivetrain); toe_deg, load_n and pressure_kpa are this axle's.";
    ToeMm toe_mm: f64, F64, "mm", "The toe-in toe_deg in mm at the rim's edge across rim_diameter_mm: D_rim tan(alpha).";
    ToeTotalDeg toe_total_deg: f64, F64, "deg", "The toe-in as the axle's total toe, both wheels: 2 alpha.";
    EnergyPerCycleJ energy_per_cycle_j: f64, F64, "J", "Energy friction feeds into the tread per cycle.";
    FloquetMax floquet_max: f64, F64, "-", "Modulus of the largest non-trivial Floquet multiplier (NaN if none).";
    RhsEvals rhs_evals: u64, I64, "", "Right-hand-side evaluations spent on the verdict.";
    Method method: Method, Str, "", "How the verdict was reached: linear, shooting, envelope or reference.";
    Reason reason: String, Str, "", "Why the class is failed, no_traction or standstill; empty otherwise.";
}

define_record! {
    /// The wear stage's figures for one wheel (MODEL.md#wear-columns): the per-sample
    /// estimator's, NaN where undefined (never 0 for unknown), with the reason.
    struct WearRecord;
    /// A column of [`WearRecord`], typed.
    enum WearColumn;
    /// The wear stage's columns, written after [`RECORD_COLUMNS`] when the stage ran.
    const WEAR_COLUMNS;
    /// The wear rows' columns.
    fn wear_columns;
    extra {}
    WearEvenMmPer1000km wear_even_mm_per_1000km: f64, F64, "mm/1000km", "Even wear rate w' at the point (MODEL.md#step-10-wear-law).";
    PolygonOrderWear polygon_order_wear: f64, F64, "-", "The wear's polygon order over the tread's life: the order visible first, else the one that got deepest, NaN where no order rises above its seed (every order levels); NaN where undefined. The vibration's is polygon_order.";
    DetuningRev detuning_rev: f64, F64, "-", "Its detuning nu - n from the tread frequency, in orders per revolution.";
    GrowthRatePer1000km growth_rate_per_1000km: f64, F64, "1/1000km", "Its closed-loop growth rate beta (> 0: the polygon grows; < 0: it levels out).";
    DistanceToVisibleKm distance_to_visible_km: f64, F64, "km", "Cruising distance at the point, with the speed spread, until the polygon is visible_depth_mm deep; inf when every order levels out.";
    TreadLifeKm tread_life_km: f64, F64, "km", "Cruising distance at the point until the position's whole even wear leaves tread_depth_worn_out_mm: (tread_depth_new_mm - tread_depth_worn_out_mm) / (w' + (1 - phi_s) w'_pos).";
    WearOutcome wear_outcome: String, Str, "", "The wear answer in words: visible (distance_to_visible_km within tread_life_km), not_within_life (later, or never), unknown (no figures; wear_reason says why).";
    WearPeakShareOfVisible wear_peak_share_of_visible: f64, F64, "-", "The deepest order's largest depth over the tread's life before the tire is worn out, as a share of visible_depth_mm (1 where a polygon is visible): how near a wheel without one came (saturated, where the unsaturated walk has a polygon; else that walk's, an upper bound).";
    WearLockedShare wear_locked_share: f64, F64, "-", "Share of the speed spread inside the dominant order's lock-in band (0 for a stable wheel).";
    WearShareStraight wear_share_straight: f64, F64, "-", "phi_s, the parameter wear_share_straight: the share of the reference wear that straight running couples to (field-fitted).";
    WearRhsEvals wear_rhs_evals: u64, I64, "", "Right-hand-side evaluations the wear stage spent on the wheel (0 for a stable one).";
    WearReason wear_reason: String, Str, "", "Why the wear figures are NaN; empty otherwise.";
    PolygonOrderDominant polygon_order_dominant: f64, F64, "-", "Deprecated: polygon_order_wear under its old name, kept for one version (the `deprecated` metadata lists it).";
    WearCalibrationShare wear_calibration_share: f64, F64, "-", "Deprecated: wear_share_straight under its old name, kept for one version (the `deprecated` metadata lists it).";
}

pub use crate::wear::physics::fitted::WearOutcome;

/// Output columns renamed, as (old, new): the rows carry both for one version, the files'
/// `deprecated` metadata lists the pairs, and `analyze` reads a file with only the old name
/// under the new one, saying so.
pub const RENAMED_COLUMNS: &[(&str, &str)] = &[
    ("polygon_order_dominant", "polygon_order_wear"),
    ("wear_calibration_share", "wear_share_straight"),
    // `polywear wear`'s wear_summary.
    ("dominant_order", "polygon_order_wear"),
    ("estimate_dominant_order", "estimate_polygon_order_wear"),
    // `polywear cycle`'s cycle_summary.
    ("wear_dominant_order", "polygon_order_wear"),
];

/// The column of a drawn parameter that is a length in m with no unit in its name (`tread_height`
/// → `tread_height_m`), so that no length in the rows is read in mm by mistake; None for any
/// other parameter.
pub fn unit_named_column(id: crate::params::ParamId) -> Option<String> {
    let s = id.spec();
    (s.unit == "m" && !s.name.ends_with("_m")).then(|| format!("{}_m", s.name))
}

/// The (old, new) pairs of [`RENAMED_COLUMNS`] and [`unit_named_column`] among `names`: what a
/// file's `deprecated` metadata lists.
pub fn deprecated_columns<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<(String, String)> {
    let names: Vec<&str> = names.into_iter().collect();
    let lengths = crate::params::ParamId::ALL
        .iter()
        .filter_map(|&id| unit_named_column(id).map(|new| (id.name().to_string(), new)));
    RENAMED_COLUMNS
        .iter()
        .map(|(o, n)| (o.to_string(), n.to_string()))
        .chain(lengths)
        .filter(|(old, new)| names.contains(&old.as_str()) && names.contains(&new.as_str()))
        .collect()
}

impl WearRecord {
    /// The row of an estimate at parameters `p` that spent `rhs_evals` evaluations.
    pub fn of(e: &WearAnswer, p: &Params, rhs_evals: u64) -> Self {
        let dominant = e
            .orders
            .iter()
            .find(|o| o.order as f64 == e.polygon_order_dominant);
        let tread_life_km = crate::wear::estimator::tread_life_km(p, e.tread_wear_mm_per_1000km);
        let outcome = WearOutcome::of(e.distance_to_visible_km, tread_life_km);
        WearRecord {
            wear_even_mm_per_1000km: e.wear_even_mm_per_1000km,
            polygon_order_wear: e.polygon_order_dominant,
            detuning_rev: e.detuning_rev,
            growth_rate_per_1000km: e.growth_rate_per_1000km,
            distance_to_visible_km: e.distance_to_visible_km,
            tread_life_km,
            wear_outcome: outcome.as_str().to_string(),
            wear_peak_share_of_visible: e.peak_share_of_visible,
            wear_locked_share: dominant.map_or(f64::NAN, |o| o.locked_share),
            wear_share_straight: e.wear_calibration_share,
            wear_rhs_evals: rhs_evals,
            wear_reason: e.reason.clone(),
            polygon_order_dominant: e.polygon_order_dominant,
            wear_calibration_share: e.wear_calibration_share,
        }
    }

    /// The row of a wheel the stage did not reach (a row of a run without the stage mixed into
    /// one with it): every figure NaN.
    fn missing() -> Self {
        WearRecord::of(
            &WearAnswer::undefined(f64::NAN, "the wear stage did not run".into()),
            &Params::default(),
            0,
        )
    }
}

/// The rows as typed columns with units: the record columns in field order, then the wear
/// stage's when any row carries them.
pub fn record_columns(rows: &[WheelRecord]) -> Vec<Column> {
    let mut cols = core_columns(rows);
    if rows.iter().any(|r| r.wear.is_some()) {
        let wear: Vec<WearRecord> = rows
            .iter()
            .map(|r| r.wear.clone().unwrap_or_else(WearRecord::missing))
            .collect();
        cols.extend(wear_columns(&wear));
    }
    cols
}

/// The column with each row's distance to a visible polygon \[km\] (+inf: never; NaN:
/// undefined), which the wear stage writes.
pub const DISTANCE_COLUMN: &str = "distance_to_visible_km";

/// The sample's index in a batch run, the first column of explore's chunks.
pub const SAMPLE_ID: ColumnSpec = ColumnSpec {
    name: "sample_id",
    unit: "",
    kind: ColumnKind::I64,
    meaning:
        "The sample's index in the run, from 0; every wheel and variant of a sample shares it.",
};

/// The row of a study's `[operating_points]` file a sample drew (explore's chunks, when the
/// study has one).
pub const OPERATING_POINT_ROW: ColumnSpec = ColumnSpec {
    name: "operating_point_row",
    unit: "",
    kind: ColumnKind::I64,
    meaning: "The operating-point file's row the sample drew, counted from 1 after the header.",
};

impl WheelRecord {
    /// Assembles the row; static fields are NaN where the model does not define them.
    pub fn new(
        p: &Params,
        wheel: Wheel,
        variant: Variant,
        model: &Result<WheelModel, ModelFailure>,
        verdict: &WheelVerdict,
    ) -> Self {
        let nan = f64::NAN;
        let (patch, tread) = match model {
            Ok(m) => (Some(m.patch), Some(m.tread)),
            Err(ModelFailure::NoTraction { patch, tread, .. }) => (Some(*patch), Some(*tread)),
            Err(ModelFailure::Invalid(_)) => (None, None),
        };
        let (slip, q, f_m, f_s, z0, y0) = match model {
            Ok(m) => {
                let eq = m.ode.equilibrium();
                (
                    m.slip_ratio,
                    m.friction.q,
                    m.friction.f_m,
                    m.friction.f_s,
                    eq[0],
                    eq[1],
                )
            }
            Err(_) => (nan, nan, nan, nan, nan, nan),
        };
        // A failed point has no cycle: its cycle quantities are NaN (null in JSON), never a 0.0
        // that a mean would silently take in.
        let failed = verdict.class == Class::Failed;
        let cycle = |x: f64| if failed { nan } else { x };
        WheelRecord {
            wheel,
            axle: p.drivetrain.axle_of(wheel),
            variant,
            speed_kmh: p.speed_kmh,
            toe_deg: p.toe_deg,
            load_n: p.load_n,
            pressure_kpa: p.pressure_kpa,
            deflection_m: patch.map_or(nan, |c| c.deflection_m),
            contact_length_m: patch.map_or(nan, |c| c.length_m),
            contact_width_m: patch.map_or(nan, |c| c.width_m),
            k_s: tread.map_or(nan, |t| t.stiffness_n_per_m),
            tread_mass_kg: tread.map_or(nan, |t| t.mass_kg),
            slip_ratio: slip,
            q,
            f_m,
            f_s,
            z0_m: z0,
            y0_m: y0,
            eig_re_max: verdict.eig_re_max,
            eig_freq_hz: verdict.eig_freq_hz,
            class: verdict.class,
            amp_y_m: cycle(verdict.amp_y_m),
            amp_v_mps: cycle(verdict.amp_v_mps),
            freq_hz: cycle(verdict.freq_hz),
            polygon_order: cycle(verdict.polygon_order),
            toe_mm: crate::params::toe::toe_mm(p.toe_deg, p.rim_diameter_mm),
            toe_total_deg: crate::params::toe::toe_total_deg(p.toe_deg),
            energy_per_cycle_j: cycle(verdict.energy_per_cycle_j),
            floquet_max: cycle(verdict.floquet_max),
            rhs_evals: verdict.rhs_evals,
            method: verdict.method,
            reason: verdict.reason.clone(),
            wear: None,
        }
    }
}

/// The columns of an explore chunk as a Markdown table (docs/book/src/reference/output-files.md#output-files carries it, and a
/// test keeps the two equal): the sample columns, then every record column.
pub fn columns_markdown() -> String {
    let mut out = String::from("| column | unit | type | meaning |\n|---|---|---|---|\n");
    for c in [SAMPLE_ID, OPERATING_POINT_ROW]
        .iter()
        .chain(RECORD_COLUMNS)
        .chain(WEAR_COLUMNS)
    {
        let unit = if c.unit.is_empty() { "" } else { c.unit };
        out.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            c.name,
            unit,
            c.kind.as_str(),
            c.meaning
        ));
    }
    out
}
