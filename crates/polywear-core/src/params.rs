//! Model parameters: the one place where names, units, defaults, provenance and accepted ranges
//! live (MODEL.md#constants). Every other module reads a [`Params`] value; the CLI, study files
//! and output metadata all use the names defined here.

use std::fmt;

use crate::wording::plain;

pub mod axle;
mod plausible;
pub mod table;
pub mod toe;
pub use plausible::{Plausible, UnitMistake};
use plausible::{
    CROWN_WIDTH, DENSITY, LOAD, PRESSURE, RIM_DIAMETER, SHEAR_MODULUS, TIRE_RADIUS, TOE,
    TREAD_HEIGHT,
};

/// Where a default value comes from (MODEL.md#sources-and-the-lost-digits).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Provenance {
    /// Legible in the paper, or only one reading fits the lost-digit rule.
    Paper,
    /// Several readings fit the lost-digit rule; the physically plausible one was chosen.
    Decoded,
    /// Illegible or absent in the paper; chosen so that the model reproduces the paper's results.
    Reconstructed,
    /// Fitted by `polywear calibrate` to both wheels' Table 3 results under the `sliding_share`
    /// variant (`studies/paper_targets.toml`): a reconstructed constant fitted continuously, or a
    /// decoded one whose lost-digit reading the fit chose, so every legible digit is kept.
    Fitted,
    /// Taken from published data outside the paper (tread-life figures, service limits;
    /// MODEL.md#wear-constants).
    Published,
    /// A modelling judgement with no measurement behind it, said so
    /// (MODEL.md#wear-constants).
    Judgement,
    /// Fitted so that the wear stage reproduces field observations of polygonal wear
    /// (MODEL.md#calibration-to-the-field).
    FieldFitted,
}

impl Provenance {
    /// The provenance as `polywear params` prints it.
    pub fn as_str(self) -> &'static str {
        match self {
            Provenance::Paper => "paper",
            Provenance::Decoded => "decoded",
            Provenance::Reconstructed => "reconstructed",
            Provenance::Fitted => "fitted to both wheels' Table 3",
            Provenance::Published => "published data",
            Provenance::Judgement => "judgement",
            Provenance::FieldFitted => "fitted to field observations",
        }
    }
}

/// Which group a parameter belongs to; the operating point is what studies explore.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Group {
    /// Speed, toe-in, load, pressure: the axes studies explore.
    OperatingPoint,
    /// Geometry and rubber of the tire.
    TireStructure,
    /// Friction coefficients, the LuGre law and damping.
    Friction,
    /// Drag and rolling resistance (driving wheel only).
    Vehicle,
    /// The wear stage (MODEL.md#step-10-wear-law to #step-12-feedback): wear rate, its
    /// calibration share, stiffnesses of the feedback, seed, thresholds, speed spread.
    Wear,
    /// An axle's own toe-in, load or pressure, absent (NaN) unless given: the axle then takes
    /// the shared operating-point value (MODEL.md#the-car-axles-and-drivetrain).
    Axle,
}

/// Static description of one parameter.
#[derive(Debug, Clone, Copy)]
pub struct ParamSpec {
    /// Name used on the command line (`--set name=value`), in study files and in output columns.
    pub name: &'static str,
    /// Symbol in MODEL.md#parameter-table and the paper.
    pub symbol: &'static str,
    /// Unit of the value.
    pub unit: &'static str,
    /// The shipped default.
    pub default: f64,
    /// Where the default comes from.
    pub provenance: Provenance,
    /// Which group the parameter belongs to.
    pub group: Group,
    /// Smallest accepted value; excluded when `min_exclusive`.
    pub min: f64,
    /// Whether `min` itself is refused.
    pub min_exclusive: bool,
    /// Largest accepted value (included).
    pub max: f64,
    /// Counts (wheels) must be whole numbers.
    pub integer: bool,
    /// The values plausible for a road tire, where a range makes sense (a value outside it is
    /// refused as a likely unit mix-up unless accepted: [`ParamSpec::check_plausible`]).
    pub plausible: Option<Plausible>,
    /// What the parameter is, in a sentence.
    pub description: &'static str,
}

impl ParamSpec {
    /// The accepted range written for people, e.g. `(0, 400]`.
    pub fn range_text(&self) -> String {
        let open = if self.min_exclusive { '(' } else { '[' };
        let kind = if self.integer { " (whole number)" } else { "" };
        format!("{open}{}, {}]{kind}", self.min, self.max)
    }

    /// Checks one value against this parameter's accepted range.
    pub fn check(&self, value: f64) -> Result<(), ParamError> {
        let below = if self.min_exclusive {
            value <= self.min
        } else {
            value < self.min
        };
        if value.is_nan() && self.default.is_nan() {
            // An axle's own value, absent: the axle takes the shared one.
            return Ok(());
        }
        let bad = !value.is_finite()
            || below
            || value > self.max
            || (self.integer && value.fract() != 0.0);
        if bad {
            return Err(ParamError::OutOfRange {
                name: self.name,
                value,
                range: self.range_text(),
                unit: self.unit,
            });
        }
        Ok(())
    }
}

/// A parameter problem found before any work starts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// No parameter has this name.
    #[error("unknown parameter `{name}`;{hint} accepted: {names}", hint = unknown_hint(name), names = ParamId::names().join(", "))]
    Unknown {
        /// The name given.
        name: String,
    },
    /// A value outside its parameter's accepted range (with the likely unit mix-up, where a
    /// conversion lands in the plausible range: `; 8 mm = 0.008 m?`).
    #[error("parameter `{name}` = {} is outside its accepted range {range} {unit}{}", plain(*value, 12), mistake_hint(name, *value))]
    OutOfRange {
        /// The parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The accepted range, as people read it.
        range: String,
        /// The parameter's unit.
        unit: &'static str,
    },
    /// A value in its accepted range but outside its plausible one (MODEL.md#parameter-table):
    /// most likely a unit mix-up, which the message names (`; 2.4 bar = 240 kPa?`).
    #[error("parameter `{name}` = {} {unit} is implausible for a road tire (plausible {} {unit}){} (if it is meant, --accept-implausible runs it anyway)", plain(*value, 12), plausible_text(name), mistake_hint(name, *value))]
    Implausible {
        /// The parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The parameter's unit.
        unit: &'static str,
    },
    /// Values that do not fit together (e.g. μ_s above μ_m).
    #[error("{message}")]
    Inconsistent {
        /// What does not fit, with the names and values.
        message: String,
    },
}

/// The likely unit mix-up of parameter `name`'s `value` (`; 2.4 bar = 240 kPa?`), or "".
fn mistake_hint(name: &str, value: f64) -> String {
    spec(name).map_or(String::new(), |s| s.mistake_hint(value))
}

/// Parameter `name`'s plausible range, as people read it.
fn plausible_text(name: &str) -> String {
    spec(name).map_or(String::new(), ParamSpec::plausible_text)
}

/// " did you mean `speed_kmh`?" for a misspelt name, or nothing.
fn unknown_hint(name: &str) -> String {
    suggest_name(name)
        .map(|s| format!(" did you mean `{s}`?"))
        .unwrap_or_default()
}

/// Declares the [`Params`] struct, its defaults, the [`ParamId`] enum and the [`SPECS`] table
/// from one list, so that a field, its name, its identifier and its range can never drift apart.
macro_rules! define_params {
    ($( $id:ident $field:ident : $symbol:literal, $unit:literal, $default:expr, $prov:ident, $group:ident,
        $min:expr, $minx:literal, $max:expr, $int:literal, $plaus:expr, $desc:literal; )*) => {
        /// All model inputs in the units of their names (km/h, deg, N, kPa; SI otherwise), and
        /// the drivetrain, the one input that is a category, not a number.
        #[derive(Debug, Clone, Copy)]
        pub struct Params {
            $( #[doc = $desc] pub $field: f64, )*
            /// Which axle is driven (MODEL.md#the-car-axles-and-drivetrain).
            pub drivetrain: axle::Drivetrain,
        }

        impl Default for Params {
            fn default() -> Self { Params { $( $field: $default, )* drivetrain: axle::Drivetrain::Fwd } }
        }

        /// One model parameter, typed: indexes [`Params`] (`p[ParamId::SpeedKmh]`) and names its
        /// [`ParamSpec`]. Names become identifiers only by parsing (`"speed_kmh".parse()`), at
        /// the edges where people type them (study files, `--set`, column headers).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum ParamId { $( #[doc = $desc] $id, )* }

        impl ParamId {
            /// Every parameter, in the canonical column order (the order of [`SPECS`]).
            pub const ALL: &'static [ParamId] = &[ $( ParamId::$id, )* ];
        }

        /// Every parameter, in the canonical column order.
        pub const SPECS: &[ParamSpec] = &[ $( ParamSpec {
            name: stringify!($field), symbol: $symbol, unit: $unit, default: $default,
            provenance: Provenance::$prov, group: Group::$group, min: $min,
            min_exclusive: $minx, max: $max, integer: $int, plausible: $plaus, description: $desc,
        }, )* ];

        impl std::ops::Index<ParamId> for Params {
            type Output = f64;
            fn index(&self, id: ParamId) -> &f64 {
                match id { $( ParamId::$id => &self.$field, )* }
            }
        }

        impl std::ops::IndexMut<ParamId> for Params {
            fn index_mut(&mut self, id: ParamId) -> &mut f64 {
                match id { $( ParamId::$id => &mut self.$field, )* }
            }
        }
    };
}

define_params! {
    SpeedKmh speed_kmh: "V", "km/h", 100.0, Decoded, OperatingPoint, 0.0, true, 400.0, false,
        None, "Vehicle speed.";
    ToeDeg toe_deg: "alpha", "deg", 0.3, Decoded, OperatingPoint, 0.0, true, 10.0, false,
        Some(TOE), "Toe-in (slip) angle between wheel plane and vehicle velocity.";
    LoadN load_n: "F_Z", "N", 4000.0, Decoded, OperatingPoint, 0.0, true, 50000.0, false,
        Some(LOAD), "Vertical load on the tire.";
    PressureKpa pressure_kpa: "P", "kPa", 240.0, Decoded, OperatingPoint, 0.0, true, 2000.0, false,
        Some(PRESSURE), "Tire inflation pressure.";
    RB r_b: "r_B", "m", 0.317, Paper, TireStructure, 0.0, true, 2.0, false,
        Some(TIRE_RADIUS), "Tire radius.";
    RW r_w: "r_w", "m", 0.155, Paper, TireStructure, 0.0, true, 10.0, false,
        None, "Tread lateral curvature radius.";
    B0 b0: "b0", "m", 0.166, Paper, TireStructure, 0.0, true, 1.0, false,
        Some(CROWN_WIDTH), "Crown width.";
    Xi xi: "xi", "-", 0.67, Decoded, TireStructure, 0.0, true, 10.0, false,
        None, "Structure constant of the contact length.";
    Psi psi: "psi", "1/m", 115.0, Decoded, TireStructure, 0.0, true, 1.0e4, false,
        None, "Structure constant of the contact width.";
    TreadHeight tread_height: "h", "m", 0.015, Decoded, TireStructure, 0.0, true, 0.2, false,
        Some(TREAD_HEIGHT), "Tread height.";
    Rho rho: "rho", "kg/m^3", 1250.0, Decoded, TireStructure, 0.0, true, 2.0e4, false,
        Some(DENSITY), "Tread mass density.";
    GMod g_mod: "G", "Pa", 0.8557e6, Fitted, TireStructure, 0.0, true, 1.0e10, false,
        Some(SHEAR_MODULUS), "Shear modulus of the tread rubber (reconstructed; R0 0.8645e6).";
    CBrush c_brush: "C", "N/m^3", 3.537e7, Fitted, TireStructure, 0.0, true, 1.0e13, false,
        None, "Tangential elastic constant of rubber (brush stiffness per area; reconstructed; R0 3.6e7).";
    Alpha2 alpha2: "alpha2", "m^2/N", 8.68e-9, Fitted, TireStructure, 0.0, false, 1.0e-3, false,
        None, "Carcass deflection constant (digits all lost in the paper; R0 4.0e-8).";
    RimDiameterMm rim_diameter_mm: "D_rim", "mm", toe::RIM_DIAMETER_15_IN_MM, Published, TireStructure, 0.0, true, 2000.0, false,
        Some(RIM_DIAMETER), "Rim diameter, across which a toe-in given as toe_mm is measured (toe_deg = atan(toe_mm / D_rim)); 381 mm = the 15-inch rim of the 195/65 R15 tire of r_b. No other use in the model.";
    MuM mu_m: "mu_m", "-", 0.76, Decoded, Friction, 0.0, true, 5.0, false,
        None, "Maximum static friction coefficient.";
    MuS mu_s: "mu_s", "-", 0.63, Decoded, Friction, 0.0, true, 5.0, false,
        None, "Sliding friction coefficient (at most mu_m).";
    VS v_s: "V_s", "m/s", 0.106, Fitted, Friction, 0.0, true, 100.0, false,
        None, "Stribeck speed (lost-digit reading \"0.1?6\" chosen by the fit; R0 0.126).";
    Phi phi: "phi", "-", 0.9, Fitted, Friction, 0.0, true, 10.0, false,
        None, "Stribeck index, normally 0.5..2 (lost-digit reading \"0.9?\" chosen by the fit; R0 0.94).";
    Sigma1 sigma1: "sigma1", "N s/m", 10.0, Decoded, Friction, 0.0, false, 1.0e6, false,
        None, "LuGre bristle damping.";
    CS c_s: "C_s", "N s/m", 14.0, Fitted, Friction, 0.0, false, 1.0e6, false,
        None, "Tread lateral damping (lost-digit reading \"1?\" chosen by the fit; R0 18).";
    CD c_d: "C_D", "-", 0.315, Paper, Vehicle, 0.0, false, 5.0, false,
        None, "Air-resistance coefficient (driving wheel only).";
    Area area: "A", "m^2", 2.2, Decoded, Vehicle, 0.0, false, 50.0, false,
        None, "Windward (frontal) area (driving wheel only).";
    F0 f0: "f0", "-", 0.0076, Reconstructed, Vehicle, 0.0, false, 1.0, false,
        None, "Rolling resistance, constant term (textbook radial-tire formula).";
    F1 f1: "f1", "h/km", 0.000056, Reconstructed, Vehicle, 0.0, false, 0.1, false,
        None, "Rolling resistance, speed term: f = f0 + f1 * V[km/h].";
    NWheels n_wheels: "n_w", "-", 4.0, Reconstructed, Vehicle, 1.0, false, 64.0, true,
        None, "Wheels sharing the rolling resistance.";
    NDriven n_driven: "n_d", "-", 2.0, Reconstructed, Vehicle, 1.0, false, 64.0, true,
        None, "Driven wheels sharing the drive force.";
    WearRateRef wear_rate_ref_mm_per_1000km: "w'_0", "mm/1000 km", 0.12, Published, Wear, 0.0, true, 10.0, false,
        None, "Even-wear rate of a tire at the reference point (tread-life figures, range 0.08..0.21).";
    WearRateDrivenFactor wear_rate_driven_factor: "k_d", "-", 1.76306, FieldFitted, Wear, 0.0, true, 10.0, false,
        None, "Even-wear rate of a driven-axle tyre over a free-rolling one's, under wear_power = with_slip (front-wheel-drive cars: front tyres wear 1.5 to 2 times as fast, tyre-rotation guidance; near 1 for a rear-driven axle); the calibration's nominal within that range (data/calibration_band.toml).";
    WearShareStraight wear_share_straight: "phi_s", "-", 0.25309, FieldFitted, Wear, 0.0, true, 1.0, false,
        None, "Share of the even wear that straight running with toe causes, the share the vibration couples to (1 = worst case); the calibration's nominal (data/calibration_band.toml; 0.18-0.35 accepted).";
    FoundationFactor foundation_stiffness_factor: "E_c/G", "-", 3.0, Judgement, Wear, 0.0, false, 1000.0, false,
        None, "Tread foundation stiffness k_t = factor * G / h (3 = incompressible rubber; 0 switches the local pressure feedback off).";
    RadialStiffnessFactor radial_stiffness_factor: "k_r/k_r0", "-", 1.0, Judgement, Wear, 0.0, false, 100.0, false,
        None, "Radial stiffness as a factor on the model's own tangent stiffness dF_Z/d delta of step 1 (324.8 kN/m at the default point; 0 switches the load feedback off).";
    SeedRunoutUm seed_runout_um: "R^0", "um", 2.0, Judgement, Wear, 0.0, false, 1000.0, false,
        None, "Radius run-out of a new tire in every order, the seed a polygon grows from.";
    VisibleDepthMm visible_depth_mm: "d_visible", "mm", 0.5, Judgement, Wear, 0.0, true, 100.0, false,
        None, "Peak-to-valley depth at which a polygon counts as visible (heard).";
    LimitDepthMm limit_depth_mm: "d_limit", "mm", 1.5, Published, Wear, 0.0, true, 100.0, false,
        None, "Peak-to-valley depth of the service limit on radial run-out (at least visible_depth_mm).";
    SpeedSpreadKmh speed_spread_kmh: "sigma_V", "km/h", 6.83021, FieldFitted, Wear, 0.0, false, 100.0, false,
        None, "Standard deviation of the cruising speed around the operating point's speed (a normal spread); the calibration's nominal (data/calibration_band.toml; searched 2-10 km/h).";
    TreadDepthNewMm tread_depth_new_mm: "d_new", "mm", 8.0, Published, Wear, 0.0, true, 200.0, false,
        None, "Usable groove depth of the new tire's tread (the rubber the long-term loop may wear away; new passenger tires: 7-8 mm in DEKRA's 2022 tests, 10/32-11/32 in = 7.9-8.7 mm in US practice; at most tread_height).";
    TreadDepthWornOutMm tread_depth_worn_out_mm: "d_out", "mm", 1.6, Published, Wear, 0.0, false, 200.0, false,
        None, "Groove depth at which the tire is worn out and the loop ends (the legal minimum: 1.6 mm in the EU, Council Directive 89/459/EEC; 2/32 in = 1.6 mm in US inspection rules; below tread_depth_new_mm).";
    CarcassShare carcass_share: "c", "-", 0.539057, FieldFitted, Wear, 0.0, false, 1.0, false,
        None, "Share of the new tire's contact lateral compliance 1/K_s that is carcass and belt, not tread: the worn tire's 1/K_s = c/K_s0 + (1 - c)/K_t(h), K_t of Eq. 16 at the worn height (no figure found, bounded 0.3..0.7 by judgement; the calibration's nominal within it; 0 = the tread alone, f nearly as 1/h).";
    BeltMassShare belt_mass_share: "mu_b", "-", 0.316235, FieldFitted, Wear, 0.0, false, 1.0, false,
        None, "Share of the tread mode's mass that does not wear, the belt and carcass moving with the tread: the worn tire's m = m0 (mu_b + (1 - mu_b) h/h0) (no measurement found, bounded 0..0.7 by judgement in MODEL.md#the-ageing-tread; the calibration's nominal within it; 0 = the tread rubber alone, m = rho a b h). The new tire is the paper's at any share.";
    ToeFrontDeg toe_front_deg: "alpha_f", "deg", f64::NAN, Judgement, Axle, 0.0, true, 10.0, false,
        Some(TOE), "Toe-in of the front axle's wheels; absent = toe_deg (MODEL.md#the-car-axles-and-drivetrain).";
    ToeRearDeg toe_rear_deg: "alpha_r", "deg", f64::NAN, Judgement, Axle, 0.0, true, 10.0, false,
        Some(TOE), "Toe-in of the rear axle's wheels; absent = toe_deg.";
    LoadFrontN load_front_n: "F_Z,f", "N", f64::NAN, Judgement, Axle, 0.0, true, 50000.0, false,
        Some(LOAD), "Vertical load on a front tire; absent = load_n.";
    LoadRearN load_rear_n: "F_Z,r", "N", f64::NAN, Judgement, Axle, 0.0, true, 50000.0, false,
        Some(LOAD), "Vertical load on a rear tire; absent = load_n.";
    PressureFrontKpa pressure_front_kpa: "P_f", "kPa", f64::NAN, Judgement, Axle, 0.0, true, 2000.0, false,
        Some(PRESSURE), "Inflation pressure of the front tires; absent = pressure_kpa.";
    PressureRearKpa pressure_rear_kpa: "P_r", "kPa", f64::NAN, Judgement, Axle, 0.0, true, 2000.0, false,
        Some(PRESSURE), "Inflation pressure of the rear tires; absent = pressure_kpa.";
}

/// Equal when every value is (an absent axle value, NaN, equals an absent one) and the
/// drivetrain is: a resumed run compares its parameters with the recorded ones.
impl PartialEq for Params {
    fn eq(&self, other: &Params) -> bool {
        self.drivetrain == other.drivetrain
            && ParamId::ALL.iter().all(|&id| !self.differs(other, id))
    }
}

impl Params {
    /// Whether parameter `id` differs between the two sets (an absent axle value, NaN, equals
    /// an absent one).
    pub fn differs(&self, other: &Params, id: ParamId) -> bool {
        let (a, b) = (self[id], other[id]);
        a != b && !(a.is_nan() && b.is_nan())
    }
}

/// Every parameter by name, an absent axle value left out, then the drivetrain: the
/// `params` object of a run's manifest ([`Params::set`] reads the numbers back).
impl serde::Serialize for Params {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        for &id in ParamId::ALL {
            if !(self[id].is_nan() && id.is_per_axle()) {
                m.serialize_entry(id.name(), &self[id])?;
            }
        }
        m.serialize_entry("drivetrain", &self.drivetrain)?;
        m.end()
    }
}

/// The reference constants R0 (MODEL.md#r0-and-the-shipped-defaults) where the shipped defaults
/// differ from them. The reference data in `tests/data/` was computed with R0; tests pass
/// [`Params::r0`] so that defaults can move.
/// `studies/params_r0.toml` holds the same values for `--params`.
pub(crate) const R0_OVERRIDES: &[(ParamId, f64)] = &[
    (ParamId::GMod, 0.8645e6),
    (ParamId::CBrush, 3.6e7),
    (ParamId::Alpha2, 4.0e-8),
    (ParamId::VS, 0.126),
    (ParamId::Phi, 0.94),
    (ParamId::CS, 18.0),
];

/// The operating point, the axes studies explore and every record carries (speed, toe-in, load,
/// pressure; MODEL.md#operating-point-and-wheels): the parameters of [`Group::OperatingPoint`],
/// in column order.
pub const OPERATING_AXES: [ParamId; 4] = [
    ParamId::SpeedKmh,
    ParamId::ToeDeg,
    ParamId::LoadN,
    ParamId::PressureKpa,
];

impl ParamId {
    /// The parameters tied together by [`Params::validate`]'s cross-parameter rules (μ_s ≤ μ_m,
    /// n_d ≤ n_w, d_visible ≤ d_limit, d_new ≤ h, d_out < d_new): drawing one of them can make a
    /// sample inconsistent.
    pub const CROSS_RULES: [ParamId; 9] = [
        ParamId::MuS,
        ParamId::MuM,
        ParamId::NDriven,
        ParamId::NWheels,
        ParamId::VisibleDepthMm,
        ParamId::LimitDepthMm,
        ParamId::TreadDepthNewMm,
        ParamId::TreadHeight,
        ParamId::TreadDepthWornOutMm,
    ];

    /// The parameter's row of the table: name, unit, default, accepted range.
    pub fn spec(self) -> &'static ParamSpec {
        &SPECS[self as usize]
    }

    /// The name used on the command line, in study files and in output columns.
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// Every parameter's name, in column order.
    pub fn names() -> Vec<&'static str> {
        SPECS.iter().map(|s| s.name).collect()
    }

    /// Whether the parameter is one of the [`OPERATING_AXES`].
    pub fn is_operating_axis(self) -> bool {
        self.spec().group == Group::OperatingPoint
    }

    /// The parameter named in words for titles, axes and sentences (see [`label`]).
    pub fn label(self) -> String {
        label(self.name())
    }
}

impl fmt::Display for ParamId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for ParamId {
    type Err = ParamError;

    /// Parses a parameter's exact name; an unknown one is refused with the accepted names and the
    /// closest one.
    fn from_str(name: &str) -> Result<ParamId, ParamError> {
        SPECS
            .iter()
            .position(|s| s.name == name)
            .map(|i| ParamId::ALL[i])
            .ok_or_else(|| ParamError::Unknown {
                name: name.to_string(),
            })
    }
}

impl serde::Serialize for ParamId {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for ParamId {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<ParamId, D::Error> {
        let name = <std::borrow::Cow<'de, str>>::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

/// The parameter name closest to a misspelt `typed` one ("sped_kmh" → "speed_kmh", "speed" →
/// "speed_kmh"), for "did you mean" in every place a name is typed: study keys, `--set`,
/// `--param`, `--pair` and the columns of input files.
pub fn suggest_name(typed: &str) -> Option<&'static str> {
    crate::wording::closest(typed, SPECS.iter().map(|s| s.name))
}

/// A parameter named in words for titles, axes and sentences: "Speed", "Toe-in", "Load",
/// "Pressure" for the operating point; otherwise the first clause of its description and its
/// symbol ("Shear modulus of the tread rubber G"); an unknown name as it is.
pub fn label(name: &str) -> String {
    let Ok(id) = name.parse::<ParamId>() else {
        return name.to_string();
    };
    let short = match id {
        ParamId::SpeedKmh => "Speed",
        ParamId::ToeDeg => "Toe-in",
        ParamId::LoadN => "Load",
        ParamId::PressureKpa => "Pressure",
        _ => {
            let s = id.spec();
            let clause = s.description.split([':', '.']).next().unwrap_or(name);
            let clause = clause.split(" (").next().unwrap_or(name).trim();
            return format!("{clause} {}", s.symbol);
        }
    };
    short.to_string()
}

/// An axis label with its unit from the parameter table, "Speed [km/h]"; `unit` is used for a
/// name that is not a parameter (a record column); no brackets for a dimensionless one.
pub fn axis_label(name: &str, unit: &str) -> String {
    let unit = spec(name).map_or(unit, |s| s.unit);
    if unit.is_empty() || unit == "-" {
        label(name)
    } else {
        format!("{} [{unit}]", label(name))
    }
}

/// Looks a parameter up by name: the parsing boundary for names people type (prefer
/// [`ParamId::spec`] once the name is parsed).
pub fn spec(name: &str) -> Option<&'static ParamSpec> {
    name.parse::<ParamId>().ok().map(ParamId::spec)
}

impl Params {
    /// The reference constants R0 (MODEL.md#r0-and-the-shipped-defaults): the defaults with
    /// `R0_OVERRIDES` applied.
    pub fn r0() -> Params {
        let mut p = Params::default();
        for (id, value) in R0_OVERRIDES {
            p[*id] = *value;
        }
        p
    }

    /// Value of a parameter by its name: the parsing boundary for names read from text (output
    /// metadata, `--set`); typed code indexes with a [`ParamId`].
    pub fn get(&self, name: &str) -> Option<f64> {
        name.parse::<ParamId>().ok().map(|id| self[id])
    }

    /// Mutable access by name, for names read from text; typed code indexes with a [`ParamId`].
    pub fn get_mut(&mut self, name: &str) -> Option<&mut f64> {
        name.parse::<ParamId>().ok().map(|id| &mut self[id])
    }

    /// Sets a parameter by name, checking its range: the parsing boundary for `--set name=value`
    /// and named values in files (an unknown name is refused with the accepted names).
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), ParamError> {
        self.try_set(name.parse()?, value)
    }

    /// Sets a parameter, checking its accepted range.
    pub fn try_set(&mut self, id: ParamId, value: f64) -> Result<(), ParamError> {
        id.spec().check(value)?;
        self[id] = value;
        Ok(())
    }

    /// Checks every value and the rules that tie several together. Called before any work.
    pub fn validate(&self) -> Result<(), ParamError> {
        for &id in ParamId::ALL {
            id.spec().check(self[id])?;
        }
        if self.mu_s > self.mu_m {
            return Err(ParamError::Inconsistent {
                message: format!(
                    "parameter `mu_s` = {} must not exceed `mu_m` = {} (sliding friction is at most the static maximum)",
                    plain(self.mu_s, 12),
                    plain(self.mu_m, 12)
                ),
            });
        }
        if self.n_driven > self.n_wheels {
            return Err(ParamError::Inconsistent {
                message: format!(
                    "parameter `n_driven` = {} must not exceed `n_wheels` = {}",
                    plain(self.n_driven, 12),
                    plain(self.n_wheels, 12)
                ),
            });
        }
        if self.visible_depth_mm > self.limit_depth_mm {
            return Err(ParamError::Inconsistent {
                message: format!(
                    "parameter `visible_depth_mm` = {} must not exceed `limit_depth_mm` = {} (a polygon is visible before it reaches the service limit)",
                    plain(self.visible_depth_mm, 12),
                    plain(self.limit_depth_mm, 12)
                ),
            });
        }
        let tread_mm = self.tread_height * 1e3;
        if self.tread_depth_new_mm > tread_mm {
            return Err(ParamError::Inconsistent {
                message: format!(
                    "parameter `tread_depth_new_mm` = {} mm is outside its accepted range (0, {}] mm: it must not exceed `tread_height` = {} m (the usable groove depth is part of the tread)",
                    plain(self.tread_depth_new_mm, 12),
                    plain(tread_mm, 12),
                    plain(self.tread_height, 12)
                ),
            });
        }
        if self.tread_depth_worn_out_mm >= self.tread_depth_new_mm {
            return Err(ParamError::Inconsistent {
                message: format!(
                    "parameter `tread_depth_worn_out_mm` = {} mm is outside its accepted range [0, {}) mm: it must be below `tread_depth_new_mm` = {} mm (a tire is worn out before its usable tread is gone)",
                    plain(self.tread_depth_worn_out_mm, 12),
                    plain(self.tread_depth_new_mm, 12),
                    plain(self.tread_depth_new_mm, 12)
                ),
            });
        }
        Ok(())
    }

    /// The depth the tread may lose before the tire is worn out \[m\]:
    /// `tread_depth_new_mm` − `tread_depth_worn_out_mm` (MODEL.md#the-long-term-loop).
    pub fn usable_wear_m(&self) -> f64 {
        (self.tread_depth_new_mm - self.tread_depth_worn_out_mm) * 1e-3
    }

    /// Checks every value against its plausible range (MODEL.md#parameter-table): the first
    /// implausible one is refused with the unit mix-up that most likely produced it.
    pub fn check_plausible(&self) -> Result<(), ParamError> {
        for &id in ParamId::ALL {
            id.spec().check_plausible(self[id])?;
        }
        Ok(())
    }

    /// Vehicle speed in m/s (MODEL.md#operating-point-and-wheels: SI units inside).
    pub fn speed_mps(&self) -> f64 {
        self.speed_kmh / 3.6
    }

    /// Toe-in angle in radians.
    pub fn toe_rad(&self) -> f64 {
        self.toe_deg.to_radians()
    }

    /// Tire pressure in Pa.
    pub fn pressure_pa(&self) -> f64 {
        self.pressure_kpa * 1.0e3
    }

    /// `(name, value)` for every parameter, in canonical order (for metadata and records).
    pub fn pairs(&self) -> Vec<(&'static str, f64)> {
        ParamId::ALL
            .iter()
            .map(|&id| (id.name(), self[id]))
            .collect()
    }
}

#[cfg(test)]
mod tests;
