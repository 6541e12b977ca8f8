//! Plausible ranges: the values a parameter takes on a road tire in service, narrower than the
//! accepted ranges (which bound what the model can evaluate). A value outside its plausible
//! range is most often a unit mix-up (a pressure in bar, a load in kg, a tread height in mm), so
//! it is refused before any work with the conversion that lands in the plausible range, unless
//! the user says it is meant (`--accept-implausible`). The ranges sit in the parameter table of
//! [`super`] (MODEL.md#parameter-table), one per parameter where one makes sense.

use super::{ParamError, ParamSpec};
use crate::wording::plain;

/// A unit a value is often given in by mistake, and how it converts to the parameter's unit.
#[derive(Debug, Clone, Copy)]
pub struct UnitMistake {
    /// The unit the value may have been written in, e.g. `bar`.
    pub unit: &'static str,
    /// The parameter's unit per unit of `unit` (bar to kPa: 100).
    pub factor: f64,
    /// How the conversion is said: `=`, or `carry` for a mass read as a weight.
    pub verb: &'static str,
    /// The conversion where it is not a factor (a toe-in in mm at the rim is an angle through
    /// the arc tangent): the parameter's value of `x` given in `unit`.
    pub convert: Option<fn(f64) -> f64>,
    /// The input that takes the value in `unit` as it is (`toe_mm`), where one does.
    pub input: Option<&'static str>,
}

impl UnitMistake {
    /// `x`, read as given in [`UnitMistake::unit`], in the parameter's unit.
    pub fn apply(&self, x: f64) -> f64 {
        self.convert.map_or(x * self.factor, |f| f(x))
    }
}

/// The range of values plausible for a road tire, and the unit mix-ups that most likely
/// produced a value outside it, tried in order.
#[derive(Debug, Clone, Copy)]
pub struct Plausible {
    /// Smallest plausible value (included, unless it is the accepted range's excluded minimum).
    pub min: f64,
    /// Largest plausible value (included).
    pub max: f64,
    /// The mix-ups, most likely first.
    pub mistakes: &'static [UnitMistake],
}

const fn mistake(unit: &'static str, factor: f64) -> UnitMistake {
    UnitMistake {
        unit,
        factor,
        verb: "=",
        convert: None,
        input: None,
    }
}

/// Standard gravity \[m/s²\], for a load given in kg.
const STANDARD_GRAVITY: f64 = 9.80665;

/// A pressure in bar, psi, MPa or mbar instead of kPa.
pub(super) const PRESSURE: Plausible = Plausible {
    min: 50.0,
    max: 1000.0,
    mistakes: &[
        mistake("bar", 100.0),
        mistake("psi", 6.894_757),
        mistake("MPa", 1000.0),
        mistake("mbar", 0.1),
    ],
};

/// A wheel load in kg or kN instead of N; any load up to the accepted maximum is plausible for
/// some vehicle.
pub(super) const LOAD: Plausible = Plausible {
    min: 500.0,
    max: 50_000.0,
    mistakes: &[
        UnitMistake {
            unit: "kg",
            factor: STANDARD_GRAVITY,
            verb: "carry",
            convert: None,
            input: None,
        },
        mistake("kN", 1000.0),
    ],
};

/// A per-wheel toe-in angle: a service value is 0.05° to 0.3°, a misaligned wheel's 0.5°, and
/// the paper's sweeps end at 1° (MODEL.md#parameter-table). Above that the value is most likely
/// a toe in mm at the rim, a total toe (both wheels) or arc minutes (alignment sheets give toe
/// as 0°10'); every reading that lands in range is named.
pub(super) const TOE: Plausible = Plausible {
    min: 0.0,
    max: 1.0,
    mistakes: &[
        UnitMistake {
            unit: "mm at a 15-inch (381 mm) rim",
            factor: 1.0 / super::toe::RIM_DIAMETER_15_IN_MM,
            verb: "=",
            convert: Some(super::toe::toe_deg_at_15_inch_rim),
            input: Some("toe_mm, --toe-mm"),
        },
        UnitMistake {
            unit: "deg total toe (both wheels)",
            factor: 0.5,
            verb: "=",
            convert: None,
            input: Some("toe_total_deg, --toe-total"),
        },
        mistake("arc minutes", 1.0 / 60.0),
    ],
};

/// A rim diameter in inches or m instead of mm.
pub(super) const RIM_DIAMETER: Plausible = Plausible {
    min: 250.0,
    max: 700.0,
    mistakes: &[mistake("in", 25.4), mistake("m", 1000.0)],
};

/// A tread height in mm or cm instead of m.
pub(super) const TREAD_HEIGHT: Plausible = Plausible {
    min: 0.001,
    max: 0.03,
    mistakes: &[mistake("mm", 1e-3), mistake("cm", 1e-2)],
};

/// A tire radius in mm, cm or inches instead of m.
pub(super) const TIRE_RADIUS: Plausible = Plausible {
    min: 0.15,
    max: 0.8,
    mistakes: &[
        mistake("mm", 1e-3),
        mistake("cm", 1e-2),
        mistake("in", 0.0254),
    ],
};

/// A crown width in mm, cm or inches instead of m.
pub(super) const CROWN_WIDTH: Plausible = Plausible {
    min: 0.08,
    max: 0.5,
    mistakes: &[
        mistake("mm", 1e-3),
        mistake("cm", 1e-2),
        mistake("in", 0.0254),
    ],
};

/// A rubber density in g/cm³ instead of kg/m³.
pub(super) const DENSITY: Plausible = Plausible {
    min: 800.0,
    max: 2500.0,
    mistakes: &[mistake("g/cm^3", 1000.0)],
};

/// A rubber shear modulus in MPa or kPa instead of Pa.
pub(super) const SHEAR_MODULUS: Plausible = Plausible {
    min: 1.0e5,
    max: 1.0e7,
    mistakes: &[mistake("MPa", 1.0e6), mistake("kPa", 1.0e3)],
};

impl Plausible {
    /// Whether `x` lies in the range.
    pub fn contains(&self, x: f64) -> bool {
        x >= self.min && x <= self.max
    }

    /// Every mix-up that turns `x` into a plausible value, most likely first, said for people:
    /// `2.4 bar = 240 kPa`, with the input that takes it as given where one does.
    pub fn likely_mistakes(&self, x: f64, unit: &str) -> Vec<String> {
        self.mistakes
            .iter()
            .filter(|m| self.contains(m.apply(x)) && m.apply(x) != x)
            .map(|m| {
                let input = m.input.map(|i| format!(" ({i})")).unwrap_or_default();
                format!(
                    "{} {} {} {} {unit}{input}",
                    plain(x, 6),
                    m.unit,
                    m.verb,
                    plain(m.apply(x), 4)
                )
            })
            .collect()
    }
}

impl ParamSpec {
    /// The plausible range written for people, e.g. `[50, 1000]`, with the accepted range's
    /// bracket where the two share an excluded end (`(0, 2]`); "" where none is set.
    pub fn plausible_text(&self) -> String {
        let Some(q) = &self.plausible else {
            return String::new();
        };
        let open = if self.min_exclusive && q.min == self.min {
            '('
        } else {
            '['
        };
        format!("{open}{}, {}]", plain(q.min, 6), plain(q.max, 6))
    }

    /// "; 2.4 bar = 240 kPa?"-style hint for any value outside the plausible range (each
    /// reading that lands in range, "; A? B?"), or "".
    pub(super) fn mistake_hint(&self, value: f64) -> String {
        let readings = self
            .plausible
            .as_ref()
            .filter(|q| value.is_finite() && !q.contains(value))
            .map(|q| q.likely_mistakes(value, self.unit))
            .unwrap_or_default();
        if readings.is_empty() {
            return String::new();
        }
        format!("; {}?", readings.join("? "))
    }

    /// Checks a value that is in its accepted range against the plausible range: a value
    /// outside it is refused with the likely unit mix-up.
    pub fn check_plausible(&self, value: f64) -> Result<(), ParamError> {
        match &self.plausible {
            Some(q) if value.is_finite() && !q.contains(value) => Err(ParamError::Implausible {
                name: self.name,
                value,
                unit: self.unit,
            }),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::params::{ParamError, ParamId, Params, SPECS};

    #[test]
    fn the_likely_mistake_is_the_conversion_that_lands_in_range() {
        let p = ParamId::PressureKpa.spec();
        let e = p.check_plausible(2.4).unwrap_err().to_string();
        assert!(e.contains("2.4 bar = 240 kPa?"), "{e}");
        assert!(e.contains("plausible [50, 1000] kPa"), "{e}");
        let e = p.check_plausible(35.0).unwrap_err().to_string();
        assert!(e.contains("35 psi = 241.3 kPa?"), "{e}");
        let e = p.check_plausible(0.24).unwrap_err().to_string();
        assert!(e.contains("0.24 MPa = 240 kPa?"), "{e}");
        let e = ParamId::LoadN.spec().check_plausible(400.0).unwrap_err();
        assert!(e.to_string().contains("400 kg carry 3923 N?"), "{e}");
        let e = ParamId::LoadN.spec().check_plausible(4.0).unwrap_err();
        assert!(e.to_string().contains("4 kN = 4000 N?"), "{e}");
        let e = ParamId::ToeDeg.spec().check_plausible(6.0).unwrap_err();
        assert!(e.to_string().contains("6 arc minutes = 0.1 deg?"), "{e}");
        assert!(e.to_string().contains("plausible (0, 1] deg"), "{e}");
        // A toe typed in mm at the rim or as total toe: both readings named, with their inputs.
        let e = ParamId::ToeDeg.spec().check_plausible(2.0).unwrap_err();
        assert!(e.to_string().contains("; 2 mm at a 15-inch (381 mm) rim = 0.3008 deg (toe_mm, --toe-mm)? 2 deg total toe (both wheels) = 1 deg (toe_total_deg, --toe-total)?"), "{e}");
        let e = ParamId::RimDiameterMm
            .spec()
            .check_plausible(15.0)
            .unwrap_err();
        assert!(e.to_string().contains("15 in = 381 mm?"), "{e}");
        let e = ParamId::Rho.spec().check_plausible(1.25).unwrap_err();
        assert!(e.to_string().contains("1.25 g/cm^3 = 1250 kg/m^3?"), "{e}");
        let e = ParamId::RB.spec().check_plausible(12.5).unwrap_err();
        assert!(e.to_string().contains("12.5 in = 0.3175 m?"), "{e}");
        // No conversion fits: the range alone.
        let e = ParamId::PressureKpa
            .spec()
            .check_plausible(1500.0)
            .unwrap_err();
        assert!(e.to_string().contains("1500 mbar = 150 kPa?"), "{e}");
        let e = ParamId::RB.spec().check_plausible(1.5).unwrap_err();
        assert!(matches!(e, ParamError::Implausible { .. }));
        assert!(
            e.to_string()
                .ends_with("[0.15, 0.8] m) (if it is meant, --accept-implausible runs it anyway)"),
            "{e}"
        );
        // Plausible values, and parameters without a plausible range, pass.
        assert!(p.check_plausible(240.0).is_ok() && p.check_plausible(50.0).is_ok());
        assert!(ParamId::SpeedKmh.spec().check_plausible(399.0).is_ok());
    }

    #[test]
    fn a_value_out_of_its_accepted_range_says_the_likely_mistake_too() {
        let e = ParamId::TreadHeight
            .spec()
            .check(8.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("accepted range (0, 0.2] m; 8 mm = 0.008 m?"),
            "{e}"
        );
        let e = ParamId::ToeDeg.spec().check(0.0).unwrap_err().to_string();
        assert!(e.ends_with("(0, 10] deg"), "{e}");
    }

    #[test]
    fn plausible_ranges_hold_the_defaults_and_lie_in_the_accepted_ranges() {
        let d = Params::default();
        for s in SPECS {
            let Some(q) = &s.plausible else { continue };
            assert!(
                q.min >= s.min && q.max <= s.max && q.min < q.max,
                "{}",
                s.name
            );
            assert!(s.check_plausible(s.default).is_ok(), "{}", s.name);
            // Every mix-up named converts to a different value.
            assert!(q.mistakes.iter().all(|m| m.apply(3.0) != 3.0), "{}", s.name);
        }
        assert!(d.check_plausible().is_ok());
        assert!(Params::r0().check_plausible().is_ok());
    }
}
