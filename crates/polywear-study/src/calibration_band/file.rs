//! A file of calibrated sets as people and `explore` read it: checked before any work (every
//! refusal names the file, and the set, key and line where that applies), and written back as
//! TOML that reads to the same band.

use std::collections::BTreeSet;

use polywear_core::params::ParamId;
use polywear_core::wear::FittedConstants;
use polywear_core::wording::data_number;

use super::{
    evaluate, BandError, BandProblem, CalibrationBand, NotALine, RangeProblem, SetProblem, MAX_SETS,
};

/// The most characters of a band file's `method` and `generated_by`: what the report quotes
/// (a sentence, a command), never a document.
pub const MAX_TEXT_CHARS: usize = 400;

impl CalibrationBand {
    /// Reads a file of sets. Refused: text that is not TOML of that shape (a set that misses a
    /// constant or names one twice among it), no set, more than `MAX_SETS`, a repeated,
    /// malformed or reserved id, not exactly one nominal set, a prior range that misses a
    /// calibrated constant or names one twice, and a constant outside its parameter's accepted
    /// range (`polywear params`) or its prior range.
    pub fn parse(text: &str, file: &str) -> Result<Self, BandError> {
        let refuse = |what: BandProblem| BandError {
            file: file.to_string(),
            what: Box::new(what),
        };
        if text.trim().is_empty() {
            return Err(refuse(BandProblem::Empty));
        }
        let band: CalibrationBand =
            toml::from_str(text).map_err(|e| refuse(toml_refusal(text, &e)))?;
        for (key, value) in [
            ("method", &band.method),
            ("generated_by", &band.generated_by),
            ("fit.shipped", &band.fit.shipped),
            ("fit.region", &band.fit.region),
        ] {
            if let Some(why) = not_a_plain_line(value) {
                return Err(refuse(BandProblem::NotALine { key, why }));
            }
        }
        band.check_ranges().map_err(refuse)?;
        band.check_sets().map_err(refuse)?;
        Ok(band)
    }

    /// Each calibrated constant has one prior range, within its parameter's accepted range.
    fn check_ranges(&self) -> Result<(), BandProblem> {
        let mut seen = BTreeSet::new();
        for (i, r) in self.ranges.iter().enumerate() {
            let refuse = |why| BandProblem::Range {
                number: i + 1,
                param: r.param.clone(),
                why,
            };
            let Some(&id) = FittedConstants::PARAMS.iter().find(|p| p.name() == r.param) else {
                return Err(refuse(RangeProblem::UnknownConstant));
            };
            if !seen.insert(id) {
                return Err(refuse(RangeProblem::Repeated(id)));
            }
            let spec = id.spec();
            let inside = |x: f64| spec.check(x).is_ok();
            if !(r.min <= r.max && inside(r.min) && inside(r.max)) {
                return Err(refuse(RangeProblem::NotWithin {
                    id,
                    min: r.min,
                    max: r.max,
                }));
            }
            if let Some(why) = not_a_plain_line(&r.provenance) {
                return Err(refuse(RangeProblem::Provenance(why)));
            }
        }
        if let Some(&missing) = FittedConstants::PARAMS.iter().find(|p| !seen.contains(p)) {
            return Err(BandProblem::MissingRange(missing));
        }
        Ok(())
    }

    /// The sets: at least one, at most [`MAX_SETS`], ids well-formed and unique and not the
    /// run's own, every constant within its parameter's accepted range and its prior range,
    /// exactly one nominal.
    fn check_sets(&self) -> Result<(), BandProblem> {
        if self.sets.is_empty() {
            return Err(BandProblem::NoSets);
        }
        if self.sets.len() > MAX_SETS {
            return Err(BandProblem::TooManySets(self.sets.len()));
        }
        let mut ids = BTreeSet::new();
        for (i, s) in self.sets.iter().enumerate() {
            let refuse = |why| BandProblem::Set {
                number: i + 1,
                id: s.id.clone(),
                why,
            };
            if s.id.is_empty()
                || !s
                    .id
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
            {
                return Err(refuse(SetProblem::BadId));
            }
            if s.id == evaluate::RUN_SET {
                return Err(refuse(SetProblem::ReservedId));
            }
            if !ids.insert(s.id.clone()) {
                return Err(refuse(SetProblem::RepeatedId));
            }
            for (id, v) in FittedConstants::PARAMS.iter().zip(s.constants().values()) {
                self.check_constant(*id, v).map_err(refuse)?;
            }
        }
        let nominal = self.sets.iter().filter(|s| s.nominal).count();
        if nominal != 1 {
            return Err(BandProblem::Nominals(nominal));
        }
        Ok(())
    }

    /// `v` of `id` within its parameter's accepted range and the file's prior range.
    fn check_constant(&self, id: ParamId, v: f64) -> Result<(), SetProblem> {
        if id.spec().check(v).is_err() {
            return Err(SetProblem::OutsideAccepted { id, value: v });
        }
        match self.prior_range(id) {
            Some(r) if v < r.min || v > r.max => Err(SetProblem::OutsidePrior {
                id,
                value: v,
                min: r.min,
                max: r.max,
            }),
            _ => Ok(()),
        }
    }

    /// The file's text (TOML), with a header saying what it is.
    pub fn to_toml(&self) -> String {
        let text = |s: &str| serde_json::Value::String(s.to_string()).to_string();
        let f = &self.fit;
        let mut body = format!(
            "method = {}\ngenerated_by = {}\n\n[fit]\ndesign = {}\npoints = {}\nfleet_samples = {}\nsides_share_min = {}\naccepted = {}\nshipped = {}\nregion = {}\n",
            text(&self.method),
            text(&self.generated_by),
            text(&f.design),
            f.points,
            f.fleet_samples,
            toml_number(f.sides_share_min),
            f.accepted,
            text(&f.shipped),
            text(&f.region),
        );
        for r in &self.ranges {
            body.push_str(&format!(
                "\n[[range]]\nparam = {}\nmin = {}\nmax = {}\nprovenance = {}\n",
                text(&r.param),
                toml_number(r.min),
                toml_number(r.max),
                text(&r.provenance)
            ));
        }
        for s in &self.sets {
            body.push_str(&format!(
                "\n[[set]]\nid = {}\nnominal = {}\n",
                text(&s.id),
                s.nominal
            ));
            for (id, v) in FittedConstants::PARAMS.iter().zip(s.constants().values()) {
                body.push_str(&format!("{} = {}\n", id.name(), toml_number(v)));
            }
            for (key, v) in [
                ("highway_median_km", s.highway_median_km),
                ("fleet_median_km", s.fleet_median_km),
                ("sides_share", s.sides_share),
            ] {
                if let Some(v) = v {
                    body.push_str(&format!("{key} = {}\n", toml_number(v)));
                }
            }
        }
        format!(
            "# The wear stage's calibrated sets: the constants no measurement fixes (phi_s, sigma_V,\n\
             # k_d, the carcass and belt shares) at the points of the design that meet every fitting\n\
             # target of data/field_facts.toml within its range (MODEL.md#the-calibration-band).\n\
             # explore re-evaluates its wear answer under each set on a subsample of the same samples\n\
             # and reports the range beside the sampling interval. Regenerate with `generated_by`.\n\n{body}"
        )
    }
}

/// Why `text` is not one plain line for the report and the summary (a line break, a control
/// character, or more than [`MAX_TEXT_CHARS`]), or None.
fn not_a_plain_line(text: &str) -> Option<NotALine> {
    let n = text.chars().count();
    if n > MAX_TEXT_CHARS {
        return Some(NotALine::TooLong(n));
    }
    if text.trim().is_empty() {
        return Some(NotALine::Empty);
    }
    text.chars().find(|c| c.is_control()).map(NotALine::Control)
}

/// A TOML error of a band file: where (line, and the `[[set]]` it falls in) and what.
fn toml_refusal(text: &str, e: &toml::de::Error) -> BandProblem {
    let message = e.message().trim_end().to_string();
    let Some(span) = e.span() else {
        return BandProblem::Toml {
            line: None,
            set: None,
            message,
        };
    };
    let start = span.start.min(text.len());
    let line = text[..start].matches('\n').count() + 1;
    // Up to the end of that line: a missing key is spanned from its `[[set]]` header.
    let line_end = text[start..].find('\n').map_or(text.len(), |i| start + i);
    let sets_before = text[..line_end]
        .lines()
        .filter(|l| l.trim_start().starts_with("[[set]]"))
        .count();
    BandProblem::Toml {
        line: Some(line),
        set: (sets_before > 0).then_some(sets_before),
        message,
    }
}

/// A number as TOML writes it: `inf`, `-inf` and `nan` spelled as TOML spells them, and a
/// whole number with a decimal point so that it reads back as a float.
fn toml_number(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else if x == x.trunc() && x.abs() < 1e15 {
        format!("{x:.1}")
    } else {
        data_number(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use polywear_core::params::Params;

    #[test]
    fn the_shipped_band_reads_and_holds_the_shipped_defaults_as_its_nominal() {
        let band = CalibrationBand::shipped();
        assert!(band.nominal_is(&Params::default()), "{:?}", band.nominal());
        assert!(band.sets.len() >= 2);
        let again = CalibrationBand::parse(&band.to_toml(), "again").unwrap();
        assert_eq!(again, band);
    }

    /// A small file: its head, the five prior ranges, and one set with `extra` lines.
    fn file(extra: &str) -> String {
        let ranges: String = [
            ("wear_share_straight", 0.02, 0.5),
            ("speed_spread_kmh", 2.0, 10.0),
            ("wear_rate_driven_factor", 1.5, 2.0),
            ("carcass_share", 0.3, 0.7),
            ("belt_mass_share", 0.0, 0.7),
        ]
        .iter()
        .map(|(p, lo, hi)| {
            format!("[[range]]\nparam = \"{p}\"\nmin = {lo}\nmax = {hi}\nprovenance = \"judged\"\n")
        })
        .collect();
        format!(
            "method = \"m\"\ngenerated_by = \"g\"\n[fit]\ndesign = \"sobol\"\npoints = 8\nfleet_samples = 10\nsides_share_min = 0.8\naccepted = 1\nshipped = \"all\"\nregion = \"r\"\n{ranges}[[set]]\nid = \"a\"\nnominal = true\nwear_share_straight = 0.12\nspeed_spread_kmh = 5\nwear_rate_driven_factor = 1.75\ncarcass_share = 0.5\nbelt_mass_share = 0.4\n{extra}"
        )
    }

    #[test]
    fn a_damaged_empty_or_out_of_range_file_is_refused_naming_file_key_and_range() {
        let err = |t: &str| CalibrationBand::parse(t, "c.toml").unwrap_err().to_string();
        assert!(err("").contains("c.toml: empty file"), "{}", err(""));
        assert!(err("method = [").starts_with("c.toml: line 1: "));
        assert!(CalibrationBand::parse(&file(""), "c.toml").is_ok());
        let e = err(&file("").replace("0.12", "1.5"));
        assert!(
            e.contains("set 1 (`a`): `wear_share_straight` = 1.5: accepted (0, 1]"),
            "{e}"
        );
        let e = err(&file("").replace("speed_spread_kmh = 5", "speed_spread_kmh = -1"));
        assert!(e.contains("`speed_spread_kmh` = -1: accepted"), "{e}");
        let e = err(&file("").replace("belt_mass_share = 0.4", "belt_mass_share = 0.9"));
        assert!(
            e.contains("set 1 (`a`): `belt_mass_share` = 0.9 is outside the file's range [0, 0.7]"),
            "{e}"
        );
        let e = err(&file("").replace("nominal = true", "nominal = false"));
        assert!(e.contains("0 sets say `nominal = true`"), "{e}");
        let e = err(&file("bogus = 1\n"));
        assert!(e.contains("bogus"), "{e}");
        let two = format!(
            "{}{}",
            file(""),
            file("")[file("").rfind("[[set]]").unwrap()..].replace("nominal = true\n", "")
        );
        assert!(err(&two).contains("`id` repeats"), "{}", err(&two));
    }

    /// A set that misses a constant or names one twice, and ranges that miss one, name one
    /// twice or leave its parameter's range, are refused naming the key.
    #[test]
    fn a_set_or_range_that_misses_or_repeats_a_constant_is_refused() {
        let err = |t: &str| CalibrationBand::parse(t, "c.toml").unwrap_err().to_string();
        let e = err(&file("").replace("carcass_share = 0.5\n", ""));
        assert!(
            e.contains("(set 1)") && e.contains("missing field `carcass_share`"),
            "{e}"
        );
        let e = err(&file("carcass_share = 0.6\n"));
        assert!(e.contains("(set 1)") && e.contains("carcass_share"), "{e}");
        let no_mu = file("").replace(
            "[[range]]\nparam = \"belt_mass_share\"\nmin = 0\nmax = 0.7\nprovenance = \"judged\"\n",
            "",
        );
        let e = err(&no_mu);
        assert!(e.contains("no `[[range]]` for `belt_mass_share`"), "{e}");
        let twice = file("").replace("param = \"belt_mass_share\"", "param = \"carcass_share\"");
        assert!(
            err(&twice).contains("names `carcass_share` a second time"),
            "{}",
            err(&twice)
        );
        let wide = file("").replace("min = 0.3\nmax = 0.7", "min = 0.3\nmax = 1.7");
        assert!(
            err(&wide)
                .contains("[0.3, 1.7] is not a range within `carcass_share`'s accepted [0, 1]"),
            "{}",
            err(&wide)
        );
    }
}
