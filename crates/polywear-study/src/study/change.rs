//! A scenario's change of one parameter (`{ set = v }`, `{ shift = d }`, `{ scale = k }`,
//! `{ cap = c }`), and the change of the toe-in given as an alignment sheet gives it
//! (`toe_mm`, `toe_total_deg`), read as the change of the per-wheel angle `toe_deg` the model
//! takes (MODEL.md#operating-point-and-wheels), as `[params]` reads them.

use super::{DrawnParam, StudyError};
use polywear_core::params::toe::{ToeForm, ToeInput};
use polywear_core::params::{ParamId, Params};
use polywear_core::wording::plain;

/// One change to one parameter, as `{ set = v }`, `{ shift = d }`, `{ scale = k }` or
/// `{ cap = c }` writes it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Change {
    /// Every sample takes the value.
    Set(f64),
    /// Every sample's value moves by this amount (the fleet's spread kept).
    Shift(f64),
    /// Every sample's value is multiplied by this positive factor.
    Scale(f64),
    /// Every sample's value is held to at most this.
    Cap(f64),
}

/// The kinds of change, as the study file names them.
pub const CHANGE_KINDS: [&str; 4] = ["set", "shift", "scale", "cap"];

impl Change {
    /// The changed value of `x`.
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Change::Set(v) => v,
            Change::Shift(d) => x + d,
            Change::Scale(k) => x * k,
            Change::Cap(c) => x.min(c),
        }
    }

    /// The change's key in the study file.
    pub fn kind(self) -> &'static str {
        match self {
            Change::Set(_) => "set",
            Change::Shift(_) => "shift",
            Change::Scale(_) => "scale",
            Change::Cap(_) => "cap",
        }
    }

    /// The change's number.
    pub fn amount(self) -> f64 {
        match self {
            Change::Set(x) | Change::Shift(x) | Change::Scale(x) | Change::Cap(x) => x,
        }
    }

    /// The change as the study file writes it: `{ shift = -0.15 }`.
    pub fn text(self) -> String {
        format!("{{ {} = {} }}", self.kind(), plain(self.amount(), 12))
    }
}

/// The second toe-in key of a scenario's changes, if it gives one axle's toe-in (or the shared
/// one) twice.
pub(super) fn toe_keys_twice(changes: &[(ParamId, Change, String)]) -> Option<&str> {
    [ParamId::ToeDeg, ParamId::ToeFrontDeg, ParamId::ToeRearDeg]
        .into_iter()
        .find_map(|id| {
            let mut toe = changes.iter().filter(|c| c.0 == id);
            toe.next()?;
            toe.next().map(|c| c.2.as_str())
        })
}

/// A change of the toe-in given in mm at the rim or as total toe, as the change of the per-wheel
/// angle it is: a total toe halves (every kind); in mm, a value (set, cap) converts at the
/// study's fixed rim, since the arc tangent keeps order, but a shift or scale in mm is no shift
/// or scale of the angle, so it is refused with the angle's nearly equal change named.
pub(super) fn toe_change(
    input: ToeInput,
    typed: Change,
    key: &str,
    base: &Params,
    drawn: &[DrawnParam],
) -> Result<Change, StudyError> {
    let rim = base.rim_diameter_mm;
    let toe = input.target();
    if input.form == ToeForm::Mm && drawn.iter().any(|d| d.param == ParamId::RimDiameterMm) {
        return Err(StudyError::DrawnRule(format!(
            "`{key}` is read at the rim diameter, which the study draws; fix `params.rim_diameter_mm` or change `{toe}`"
        )));
    }
    let deg = |x: f64| input.to_deg(x, rim);
    Ok(match (input.form, typed) {
        (ToeForm::TotalDeg, Change::Scale(k)) => Change::Scale(k),
        (_, Change::Set(x)) => Change::Set(deg(x)),
        (_, Change::Cap(x)) => Change::Cap(deg(x)),
        (ToeForm::TotalDeg, Change::Shift(d)) => Change::Shift(d / 2.0),
        (ToeForm::Mm, c) => {
            let near = match c {
                Change::Shift(d) => format!("`{toe} = {{ shift = {} }}`", plain(deg(d), 4)),
                _ => format!("`{toe} = {{ scale = {} }}`", plain(c.amount(), 6)),
            };
            return Err(StudyError::DrawnRule(format!(
                "`{key}.{}`: a {} in mm at the rim is no {0} of the toe angle (the arc tangent); near the small angles of a toe-in it is {near} at the {} mm rim, or give the value as `set`",
                c.kind(),
                c.kind(),
                plain(rim, 6)
            )));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn toe_changes_read_as_the_angle_s_and_a_shift_in_mm_is_refused_with_its_near_angle() {
        let p = Params::default();
        let mm = |c| toe_change(ToeInput::MM, c, "scenarios.a.toe_mm", &p, &[]);
        let total = |c| toe_change(ToeInput::TOTAL_DEG, c, "scenarios.a.toe_total_deg", &p, &[]);
        let at_rim = (2.0f64 / 381.0).atan().to_degrees();
        assert_eq!(mm(Change::Set(2.0)).unwrap(), Change::Set(at_rim));
        assert_eq!(mm(Change::Cap(2.0)).unwrap(), Change::Cap(at_rim));
        assert_eq!(total(Change::Shift(-0.2)).unwrap(), Change::Shift(-0.1));
        assert_eq!(total(Change::Set(0.6)).unwrap(), Change::Set(0.3));
        assert_eq!(total(Change::Scale(0.5)).unwrap(), Change::Scale(0.5));
        let e = mm(Change::Shift(-1.0)).unwrap_err().to_string();
        assert!(
            e.contains("`scenarios.a.toe_mm.shift`")
                && e.contains("`toe_deg = { shift = -0.1504 }` at the 381 mm rim"),
            "{e}"
        );
        assert!(mm(Change::Scale(0.5)).is_err());
        let drawn_rim = [DrawnParam {
            param: ParamId::RimDiameterMm,
            dist: polywear_core::sampling::distribution::Distribution::Uniform {
                min: 330.0,
                max: 432.0,
                count: None,
            },
        }];
        let e = toe_change(ToeInput::MM, Change::Set(2.0), "k", &p, &drawn_rim)
            .unwrap_err()
            .to_string();
        assert!(e.contains("which the study draws"), "{e}");
    }
}
