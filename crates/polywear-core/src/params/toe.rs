//! Toe-in as alignment sheets give it: the model's `toe_deg` is the angle of one wheel
//! (MODEL.md#operating-point-and-wheels), while a workshop reads toe in mm at the rim or as the
//! total toe of an axle (both wheels). These inputs are converted to the per-wheel angle once,
//! where they are read, and every row carries the toe in all three forms
//! ([`toe_mm`], [`toe_total_deg`]).

use std::fmt;

use crate::wording::plain;

/// The nominal diameter of a 15-inch rim \[mm\] (15 × 25.4; ETRTO), the rim of the 195/65 R15
/// tire whose radius `r_b` = 0.317 m the paper gives (190.5 mm + 0.65 × 195 mm).
pub(crate) const RIM_DIAMETER_15_IN_MM: f64 = 381.0;

/// A toe-in given in mm at the rim's edge across its diameter `rim_diameter_mm`: the angle
/// \[deg\] whose tangent is the one over the other.
pub(crate) fn toe_deg_from_mm(toe_mm: f64, rim_diameter_mm: f64) -> f64 {
    (toe_mm / rim_diameter_mm).atan().to_degrees()
}

/// [`toe_deg_from_mm`] at the 15-inch rim: the reading a plausibility hint names.
pub(super) fn toe_deg_at_15_inch_rim(toe_mm: f64) -> f64 {
    toe_deg_from_mm(toe_mm, RIM_DIAMETER_15_IN_MM)
}

/// The per-wheel angle `toe_deg` as mm at the rim's edge across `rim_diameter_mm`.
pub fn toe_mm(toe_deg: f64, rim_diameter_mm: f64) -> f64 {
    rim_diameter_mm * toe_deg.to_radians().tan()
}

/// The per-wheel angle `toe_deg` as the axle's total toe \[deg\] (both wheels toed in alike).
pub fn toe_total_deg(toe_deg: f64) -> f64 {
    2.0 * toe_deg
}

/// A way to give the toe-in other than the per-wheel angle `toe_deg`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ToeInput {
    /// `toe_mm`: mm at the rim's edge across the rim diameter `rim_diameter_mm`.
    Mm,
    /// `toe_total_deg`: the axle's total toe, twice the per-wheel angle.
    TotalDeg,
}

impl ToeInput {
    /// Both, in the order their names are listed.
    pub const ALL: [ToeInput; 2] = [ToeInput::Mm, ToeInput::TotalDeg];

    /// The name in study files and `--set` (`toe_mm`), also the row's column.
    pub fn name(self) -> &'static str {
        match self {
            ToeInput::Mm => "toe_mm",
            ToeInput::TotalDeg => "toe_total_deg",
        }
    }

    /// The command-line flag of the commands with `--toe`.
    pub fn flag(self) -> &'static str {
        match self {
            ToeInput::Mm => "--toe-mm",
            ToeInput::TotalDeg => "--toe-total",
        }
    }

    /// The value's unit.
    pub fn unit(self) -> &'static str {
        match self {
            ToeInput::Mm => "mm",
            ToeInput::TotalDeg => "deg",
        }
    }

    /// The input named `name`, if it is one.
    pub fn parse(name: &str) -> Option<ToeInput> {
        ToeInput::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The per-wheel angle \[deg\] of `x` given this way at a rim of `rim_diameter_mm`.
    pub fn to_deg(self, x: f64, rim_diameter_mm: f64) -> f64 {
        match self {
            ToeInput::Mm => toe_deg_from_mm(x, rim_diameter_mm),
            ToeInput::TotalDeg => x / 2.0,
        }
    }

    /// The conversion in words, for messages and notes: "toe_mm = 2 mm at the 381 mm rim
    /// (rim_diameter_mm) = 0.3008 deg per wheel".
    pub fn words(self, x: f64, rim_diameter_mm: f64) -> String {
        let deg = plain(self.to_deg(x, rim_diameter_mm), 4);
        match self {
            ToeInput::Mm => format!(
                "{} mm at the {} mm rim (rim_diameter_mm) = {deg} deg per wheel",
                plain(x, 12),
                plain(rim_diameter_mm, 6)
            ),
            ToeInput::TotalDeg => format!(
                "{} deg total toe (both wheels) = {deg} deg per wheel",
                plain(x, 12)
            ),
        }
    }
}

impl fmt::Display for ToeInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_three_forms_of_one_toe_agree() {
        // 1 mm at the 381 mm rim is atan(1/381) = 0.1503823°, and back.
        let deg = toe_deg_from_mm(1.0, 381.0);
        assert!((deg - (1.0f64 / 381.0).atan().to_degrees()).abs() < 1e-15);
        assert!((deg - 0.150_382_278).abs() < 1e-9, "{deg}");
        assert!((toe_mm(deg, 381.0) - 1.0).abs() < 1e-12);
        assert_eq!(ToeInput::TotalDeg.to_deg(0.5, 381.0), 0.25);
        assert_eq!(toe_total_deg(0.25), 0.5);
        assert_eq!(ToeInput::parse("toe_mm"), Some(ToeInput::Mm));
        assert_eq!(ToeInput::parse("toe_deg"), None);
        assert_eq!(
            ToeInput::Mm.words(2.0, 381.0),
            "2 mm at the 381 mm rim (rim_diameter_mm) = 0.3008 deg per wheel"
        );
    }
}
