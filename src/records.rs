//! One output row per wheel and operating point: the inputs, the static model (steps 1–7), the
//! linear stability (step 8) and the verdict (step 9). The first 24 fields carry exactly the
//! column names of `tests/data/points.csv`; the rest extend it.

use serde::Serialize;

use crate::classify::{Class, Method, WheelVerdict};
use crate::model::{ModelFailure, Variant, Wheel, WheelModel};
use crate::params::Params;

/// One row. Wheel, variant, class and method are the enums themselves; they become their names
/// only when written (Parquet, CSV, JSON).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WheelRecord {
    /// The wheel.
    pub wheel: Wheel,
    /// The friction variant.
    pub variant: Variant,
    /// Vehicle speed V [km/h].
    pub speed_kmh: f64,
    /// Toe-in angle α \[deg\].
    pub toe_deg: f64,
    /// Vertical load F_Z \[N\].
    pub load_n: f64,
    /// Inflation pressure P \[kPa\].
    pub pressure_kpa: f64,
    /// Maximum deflection δ \[m\] (step 1).
    pub deflection_m: f64,
    /// Contact length a \[m\] (step 2).
    pub contact_length_m: f64,
    /// Contact width b \[m\] (step 2).
    pub contact_width_m: f64,
    /// Tread lateral stiffness K_s = σ0 [N/m].
    pub k_s: f64,
    /// Tread mass m \[kg\] (step 3).
    pub tread_mass_kg: f64,
    /// Slip ratio S (step 4; 0 for the follower).
    pub slip_ratio: f64,
    /// Sliding share of the contact length.
    pub q: f64,
    /// Maximum static friction level F_m \[N\] (step 5).
    pub f_m: f64,
    /// Sliding friction level F_s \[N\] (step 5).
    pub f_s: f64,
    /// Bristle deflection z0 at the equilibrium \[m\] (step 7).
    pub z0_m: f64,
    /// Tread displacement y0 at the equilibrium \[m\] (step 7).
    pub y0_m: f64,
    /// Largest real part of the Jacobian's eigenvalues [1/s] (step 8).
    pub eig_re_max: f64,
    /// Linear frequency of that eigenvalue \[Hz\] (step 8).
    pub eig_freq_hz: f64,
    /// The verdict (step 9).
    pub class: Class,
    /// Half peak-to-peak of y over the cycle \[m\]; 0 without a cycle, NaN when failed.
    pub amp_y_m: f64,
    /// Half peak-to-peak of v over the cycle [m/s]; 0 without a cycle, NaN when failed.
    pub amp_v_mps: f64,
    /// The cycle's frequency 1/T \[Hz\].
    pub freq_hz: f64,
    /// Wear facets n = f / f_rot.
    pub polygon_order: f64,
    /// Energy friction feeds into the tread per cycle \[J\].
    pub energy_per_cycle_j: f64,
    /// Modulus of the largest non-trivial Floquet multiplier (NaN if none).
    pub floquet_max: f64,
    /// Right-hand-side evaluations spent on the verdict.
    pub rhs_evals: u64,
    /// How the verdict was reached.
    pub method: Method,
    /// Why the class is `failed` or `no_traction`; empty otherwise.
    pub reason: String,
}

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
            energy_per_cycle_j: cycle(verdict.energy_per_cycle_j),
            floquet_max: cycle(verdict.floquet_max),
            rhs_evals: verdict.rhs_evals,
            method: verdict.method,
            reason: verdict.reason.clone(),
        }
    }
}

/// Builds typed columns from a slice of rows: one list says each field's name, unit and type.
macro_rules! columns_of {
    ($rows:expr; $( $kind:ident $field:ident $unit:literal ),* $(,)?) => {
        vec![ $( columns_of!(@col $kind, $rows, $field, $unit), )* ]
    };
    (@col f64, $rows:expr, $field:ident, $unit:literal) => {
        Column::f64(stringify!($field), $unit, $rows.iter().map(|r| r.$field).collect())
    };
    (@col i64, $rows:expr, $field:ident, $unit:literal) => {
        Column::i64(stringify!($field), $unit, $rows.iter().map(|r| r.$field as i64).collect())
    };
    (@col str, $rows:expr, $field:ident, $unit:literal) => {
        Column::str(stringify!($field), $rows.iter().map(|r| r.$field.to_string()).collect())
    };
}

use crate::parquet_out::Column;

/// The rows as typed columns with units, in field order.
pub fn record_columns(rows: &[WheelRecord]) -> Vec<Column> {
    columns_of![rows;
        str wheel "", str variant "",
        f64 speed_kmh "km/h", f64 toe_deg "deg", f64 load_n "N", f64 pressure_kpa "kPa",
        f64 deflection_m "m", f64 contact_length_m "m", f64 contact_width_m "m",
        f64 k_s "N/m", f64 tread_mass_kg "kg", f64 slip_ratio "-", f64 q "-",
        f64 f_m "N", f64 f_s "N", f64 z0_m "m", f64 y0_m "m",
        f64 eig_re_max "1/s", f64 eig_freq_hz "Hz", str class "",
        f64 amp_y_m "m", f64 amp_v_mps "m/s", f64 freq_hz "Hz", f64 polygon_order "-",
        f64 energy_per_cycle_j "J", f64 floquet_max "-", i64 rhs_evals "",
        str method "", str reason "",
    ]
}
