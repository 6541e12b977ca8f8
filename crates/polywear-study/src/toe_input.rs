//! A toe-in typed in mm at the rim or as total toe (`--toe-mm`, `--toe-total`, `--set toe_mm=2`,
//! `--set toe_total_deg=0.5`), turned into the per-wheel angle `toe_deg` the model takes
//! (MODEL.md#operating-point-and-wheels) before anything else reads it, so that every later
//! check (range, plausibility, the one-place rule) sees one parameter and quotes the words the
//! user typed.

use std::path::Path;

use polywear_core::params::toe::ToeInput;
use polywear_core::params::ParamId;
use polywear_core::wording::plain;

use crate::param_sources::{check_plausible_toe, param_file, Refusal};

/// The rim diameter \[mm\] a toe in mm is read at: `--set rim_diameter_mm` if typed, else the
/// `--params` file's, else the default (a 15-inch rim).
pub fn rim_diameter_mm(
    params_file: Option<&Path>,
    set: &[(String, f64)],
    accept_implausible: bool,
) -> Result<f64, Refusal> {
    let name = ParamId::RimDiameterMm.name();
    if let Some((_, d)) = set.iter().find(|(n, _)| n == name) {
        ParamId::RimDiameterMm
            .spec()
            .check(*d)
            .map_err(|source| Refusal::Param {
                by: format!("--set {name}"),
                source,
            })?;
        return Ok(*d);
    }
    Ok(param_file(params_file, accept_implausible)?
        .0
        .rim_diameter_mm)
}

/// The toe-in given as `input` = `x`, as the per-wheel angle, and the words that say how it was
/// typed and converted (`--toe-mm 2 (2 mm at the 381 mm rim (rim_diameter_mm) = 0.3008 deg per
/// wheel)`), quoted by every later message about it.
/// An angle outside the plausible per-wheel range is refused, in the words typed, unless
/// `accept_implausible`.
pub fn typed_toe(
    typed_as: &str,
    input: ToeInput,
    x: f64,
    rim_mm: f64,
    accept_implausible: bool,
) -> Result<(f64, String), Refusal> {
    let by = format!("{typed_as} ({})", input.words(x, rim_mm));
    let deg = input.to_deg(x, rim_mm);
    if !accept_implausible && ParamId::ToeDeg.spec().check(deg).is_ok() {
        check_plausible_toe(deg, &by)?;
    }
    Ok((deg, by))
}

/// `--set` pairs: (name, value).
pub(crate) type SetPairs = Vec<(String, f64)>;

/// `--set` pairs with every toe input (`toe_mm`, `toe_total_deg`) replaced by `toe_deg` at its
/// converted value, and a note for each ("note: --set toe_mm=2 is toe_deg = 0.3008 (...)").
/// An implausible toe is refused as [`typed_toe`] refuses it.
pub fn set_as_angles(
    set: &[(String, f64)],
    rim_mm: f64,
    accept_implausible: bool,
) -> Result<(SetPairs, Vec<String>), Refusal> {
    let mut notes = Vec::new();
    let mut pairs = Vec::new();
    for (name, x) in set {
        let Some(input) = ToeInput::parse(name) else {
            pairs.push((name.clone(), *x));
            continue;
        };
        let typed_as = format!("--set {name}={}", plain(*x, 12));
        let (deg, by) = typed_toe(&typed_as, input, *x, rim_mm, accept_implausible)?;
        let toe = input.target();
        notes.push(format!("note: {by} is {toe} = {}", plain(deg, 12)));
        pairs.push((toe.name().to_string(), deg));
    }
    Ok((pairs, notes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_toe_in_mm_or_total_becomes_the_per_wheel_angle() {
        let set = vec![("toe_mm".to_string(), 2.0), ("load_n".to_string(), 4000.0)];
        let (pairs, notes) = set_as_angles(&set, 381.0, false).unwrap();
        assert_eq!(pairs[0].0, "toe_deg");
        assert!((pairs[0].1 - (2.0f64 / 381.0).atan().to_degrees()).abs() < 1e-15);
        assert_eq!(pairs[1], ("load_n".to_string(), 4000.0));
        assert_eq!(
            notes[0],
            "note: --set toe_mm=2 (2 mm at the 381 mm rim (rim_diameter_mm) = 0.3008 deg per wheel) is toe_deg = 0.300762484243"
        );
        let (deg, by) =
            typed_toe("--toe-total 0.5", ToeInput::TOTAL_DEG, 0.5, 381.0, false).unwrap();
        assert_eq!(deg, 0.25);
        assert_eq!(
            by,
            "--toe-total 0.5 (0.5 deg total toe (both wheels) = 0.25 deg per wheel)"
        );
        let rim = rim_diameter_mm(None, &[("rim_diameter_mm".into(), 406.4)], false).unwrap();
        assert_eq!(rim, 406.4);
        assert_eq!(rim_diameter_mm(None, &[], false).unwrap(), 381.0);
        // 30 mm at the rim is 4.5 deg per wheel: refused in the words typed, unless accepted.
        let e = typed_toe("--toe-mm 30", ToeInput::MM, 30.0, 381.0, false).unwrap_err();
        assert_eq!(e.to_string(), "--toe-mm 30 (30 mm at the 381 mm rim (rim_diameter_mm) = 4.502 deg per wheel): implausible for a road tire (plausible toe_deg (0, 1] deg per wheel) (if it is meant, --accept-implausible runs it anyway)");
        assert!(typed_toe("--toe-mm 30", ToeInput::MM, 30.0, 381.0, true).is_ok());
    }
}
