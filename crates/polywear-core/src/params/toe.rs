//! Toe-in as alignment sheets give it: the model's `toe_deg` is the angle of one wheel
//! (MODEL.md#operating-point-and-wheels), while a workshop reads toe in mm at the rim or as the
//! total toe of an axle (both wheels). These inputs are converted to the per-wheel angle once,
//! where they are read, and every row carries the toe in all three forms
//! ([`toe_mm`], [`toe_total_deg`]).

use std::fmt;

use super::axle::Axle;
use super::ParamId;
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

/// How a toe-in is written other than as the per-wheel angle: in mm at the rim, or as total toe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ToeForm {
    /// mm at the rim's edge across the rim diameter `rim_diameter_mm`.
    Mm,
    /// The axle's total toe, twice the per-wheel angle.
    TotalDeg,
}

/// A way to give a toe-in other than the per-wheel angle: its form, and the axle whose toe-in it
/// is (`toe_rear_mm`; none for the shared `toe_mm`; MODEL.md#the-car-axles-and-drivetrain).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ToeInput {
    /// In mm or as total toe.
    pub form: ToeForm,
    /// The axle, or none for both axles' shared toe-in.
    pub axle: Option<Axle>,
}

impl ToeInput {
    /// `toe_mm`: the shared toe-in in mm at the rim.
    pub const MM: ToeInput = ToeInput {
        form: ToeForm::Mm,
        axle: None,
    };
    /// `toe_total_deg`: the shared toe-in as total toe.
    pub const TOTAL_DEG: ToeInput = ToeInput {
        form: ToeForm::TotalDeg,
        axle: None,
    };

    /// Every input, the shared ones first, in the order their names are listed.
    pub const ALL: [ToeInput; 6] = [
        ToeInput::MM,
        ToeInput::TOTAL_DEG,
        ToeInput::of(ToeForm::Mm, Axle::Front),
        ToeInput::of(ToeForm::TotalDeg, Axle::Front),
        ToeInput::of(ToeForm::Mm, Axle::Rear),
        ToeInput::of(ToeForm::TotalDeg, Axle::Rear),
    ];

    const fn of(form: ToeForm, axle: Axle) -> ToeInput {
        ToeInput {
            form,
            axle: Some(axle),
        }
    }

    /// The name in study files and `--set` (`toe_mm`, `toe_rear_total_deg`); the shared ones
    /// are also the row's columns.
    pub fn name(self) -> &'static str {
        match (self.form, self.axle) {
            (ToeForm::Mm, None) => "toe_mm",
            (ToeForm::TotalDeg, None) => "toe_total_deg",
            (ToeForm::Mm, Some(Axle::Front)) => "toe_front_mm",
            (ToeForm::TotalDeg, Some(Axle::Front)) => "toe_front_total_deg",
            (ToeForm::Mm, Some(Axle::Rear)) => "toe_rear_mm",
            (ToeForm::TotalDeg, Some(Axle::Rear)) => "toe_rear_total_deg",
        }
    }

    /// The parameter the input gives: `toe_deg`, or the axle's `toe_front_deg`/`toe_rear_deg`.
    pub fn target(self) -> ParamId {
        match self.axle {
            None => ParamId::ToeDeg,
            Some(Axle::Front) => ParamId::ToeFrontDeg,
            Some(Axle::Rear) => ParamId::ToeRearDeg,
        }
    }

    /// The command-line flag of the commands with `--toe` (the shared toe-in's; an axle's is
    /// given with `--set`).
    pub fn flag(self) -> &'static str {
        match self.form {
            ToeForm::Mm => "--toe-mm",
            ToeForm::TotalDeg => "--toe-total",
        }
    }

    /// The value's unit.
    pub fn unit(self) -> &'static str {
        match self.form {
            ToeForm::Mm => "mm",
            ToeForm::TotalDeg => "deg",
        }
    }

    /// The input named `name`, if it is one.
    pub fn parse(name: &str) -> Option<ToeInput> {
        ToeInput::ALL.into_iter().find(|t| t.name() == name)
    }

    /// The per-wheel angle \[deg\] of `x` given this way at a rim of `rim_diameter_mm`.
    pub fn to_deg(self, x: f64, rim_diameter_mm: f64) -> f64 {
        match self.form {
            ToeForm::Mm => toe_deg_from_mm(x, rim_diameter_mm),
            ToeForm::TotalDeg => x / 2.0,
        }
    }

    /// The conversion in words, for messages and notes: "toe_mm = 2 mm at the 381 mm rim
    /// (rim_diameter_mm) = 0.3008 deg per wheel".
    pub fn words(self, x: f64, rim_diameter_mm: f64) -> String {
        let deg = plain(self.to_deg(x, rim_diameter_mm), 4);
        match self.form {
            ToeForm::Mm => format!(
                "{} mm at the {} mm rim (rim_diameter_mm) = {deg} deg per wheel",
                plain(x, 12),
                plain(rim_diameter_mm, 6)
            ),
            ToeForm::TotalDeg => format!(
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
        assert_eq!(ToeInput::TOTAL_DEG.to_deg(0.5, 381.0), 0.25);
        assert_eq!(toe_total_deg(0.25), 0.5);
        assert_eq!(ToeInput::parse("toe_mm"), Some(ToeInput::MM));
        assert_eq!(ToeInput::parse("toe_deg"), None);
        let rear = ToeInput::parse("toe_rear_total_deg").unwrap();
        assert_eq!(rear.target(), ParamId::ToeRearDeg);
        assert_eq!(rear.to_deg(0.6, 381.0), 0.3);
        assert_eq!(
            ToeInput::parse("toe_front_mm").unwrap().target(),
            ParamId::ToeFrontDeg
        );
        assert_eq!(
            ToeInput::MM.words(2.0, 381.0),
            "2 mm at the 381 mm rim (rim_diameter_mm) = 0.3008 deg per wheel"
        );
    }
}
