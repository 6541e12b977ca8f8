//! What `optimize` minimises: a weighted sum of risks (of a visible polygon within a distance,
//! of vibration) for the follower, the driving wheel, both or the worse of the two, as a mean
//! over the study's samples of a per-sample score; its 95% interval; and the paired difference
//! of two settings on the same samples.
//!
//! A sample's outcomes are packed in one byte ([`Outcomes`]), two bits per wheel and risk:
//! 0 no, 1 yes, 2 unknown (failed, no traction, or an undefined distance).

use std::str::FromStr;

use crate::stats::{newcombe_paired, wilson, Z95};
use polywear_core::model::Wheel;
use polywear_core::params::axle::{Axle, Drivetrain};
use polywear_core::wording::did_you_mean;

/// One risk of a wheel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Term {
    /// A visible polygon within the objective's distance.
    Wear,
    /// Vibration (limit cycle or bistable).
    Vibration,
}

/// The risks' names, as `--objective` and `--constraint` take them.
pub(crate) const TERMS: [&str; 2] = ["wear", "vibration"];

impl Term {
    /// The term's name.
    pub fn name(self) -> &'static str {
        match self {
            Term::Wear => "wear",
            Term::Vibration => "vibration",
        }
    }
}

/// Why `--objective` or `--wheel` is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObjectiveError {
    /// A risk no objective knows.
    #[error(
        "unknown objective `{name}`;{} accepted: wear, vibration, or a weighted sum such as 0.7*wear+0.3*vibration",
        did_you_mean(name, TERMS)
    )]
    UnknownTerm {
        /// The name given.
        name: String,
    },
    /// A wheel choice no objective knows.
    #[error(
        "unknown wheel `{name}`;{} accepted: {}",
        did_you_mean(name, WHEEL_CHOICES),
        WHEEL_CHOICES.join(", ")
    )]
    UnknownWheel {
        /// The name given.
        name: String,
    },
    /// A term's weight that is not a number.
    #[error("`{term}`: the weight `{weight}` is not a number")]
    WeightNotANumber {
        /// The term as typed (`x*wear`).
        term: String,
        /// The weight as typed.
        weight: String,
    },
    /// A term's weight that is not a positive number.
    #[error("`{term}`: the weight must be a positive number")]
    WeightNotPositive {
        /// The term as typed.
        term: String,
    },
    /// A risk named twice.
    #[error("`{}` appears twice", .0.name())]
    TermTwice(Term),
    /// Weights adding up to more than `MAX_WEIGHT_SUM`.
    #[error(
        "`{objective}`: the weights add up to more than 1e100; accepted: weights adding up to at most 1e100 (only their ratios matter: 1*wear+1*vibration has the same optimum as 1e308*wear+1e308*vibration)"
    )]
    WeightsTooLarge {
        /// The objective as typed.
        objective: String,
    },
}

impl FromStr for Term {
    type Err = ObjectiveError;
    fn from_str(s: &str) -> Result<Term, ObjectiveError> {
        match s.trim() {
            "wear" => Ok(Term::Wear),
            "vibration" => Ok(Term::Vibration),
            other => Err(ObjectiveError::UnknownTerm {
                name: other.to_string(),
            }),
        }
    }
}

/// Which wheel a risk is counted on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WheelChoice {
    /// The follower.
    Follower,
    /// The driving wheel.
    Driving,
    /// The mean of the two wheels (the share of a car's wheels).
    Both,
    /// The worse wheel of each sample (either wheel).
    Worst,
    /// The wheel on the front axle under the study's drivetrain
    /// (MODEL.md#the-car-axles-and-drivetrain): the problem reads it as that wheel
    /// ([`WheelChoice::on`]).
    Front,
    /// The wheel on the rear axle under the study's drivetrain.
    Rear,
}

/// The wheel choices' names, as `--wheel` takes them.
pub(crate) const WHEEL_CHOICES: [&str; 6] =
    ["follower", "driving", "both", "worst", "front", "rear"];

impl WheelChoice {
    /// The choice's name.
    pub fn name(self) -> &'static str {
        WHEEL_CHOICES[self as usize]
    }

    /// The choice under `drivetrain`: the front or rear wheel as the follower or the driving
    /// one it is; the other choices as they are.
    pub fn on(self, drivetrain: Drivetrain) -> WheelChoice {
        let of = |axle| match drivetrain.wheel_on(axle) {
            Wheel::Follower => WheelChoice::Follower,
            Wheel::Driving => WheelChoice::Driving,
        };
        match self {
            WheelChoice::Front => of(Axle::Front),
            WheelChoice::Rear => of(Axle::Rear),
            other => other,
        }
    }
}

impl FromStr for WheelChoice {
    type Err = ObjectiveError;
    fn from_str(s: &str) -> Result<WheelChoice, ObjectiveError> {
        match s.trim() {
            "follower" => Ok(WheelChoice::Follower),
            "driving" => Ok(WheelChoice::Driving),
            "both" => Ok(WheelChoice::Both),
            "worst" => Ok(WheelChoice::Worst),
            "front" => Ok(WheelChoice::Front),
            "rear" => Ok(WheelChoice::Rear),
            other => Err(ObjectiveError::UnknownWheel {
                name: other.to_string(),
            }),
        }
    }
}

/// A sample's outcomes at one setting: two bits per (risk, wheel).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Outcomes(pub u8);

/// An outcome code: no.
pub const NO: u8 = 0;
/// An outcome code: yes (the codes are read by shifting; the tests name it).
#[cfg(test)]
pub(crate) const YES: u8 = 1;
/// An outcome code: unknown.
pub(crate) const UNKNOWN: u8 = 2;

impl Outcomes {
    fn shift(term: Term, wheel: Wheel) -> u8 {
        let t = match term {
            Term::Vibration => 0,
            Term::Wear => 4,
        };
        t + if wheel == Wheel::Driving { 2 } else { 0 }
    }

    /// The outcome with `term` of `wheel` set to `code`.
    pub fn with(self, term: Term, wheel: Wheel, code: u8) -> Outcomes {
        let s = Self::shift(term, wheel);
        Outcomes((self.0 & !(3 << s)) | ((code & 3) << s))
    }

    /// The code of `term` on `wheel`.
    pub fn get(self, term: Term, wheel: Wheel) -> u8 {
        (self.0 >> Self::shift(term, wheel)) & 3
    }

    /// The indicator of `term` on `choice` (a fraction for `both`); None where unknown.
    pub fn indicator(self, term: Term, choice: WheelChoice) -> Option<f64> {
        let f = self.get(term, Wheel::Follower);
        let d = self.get(term, Wheel::Driving);
        let known = |c: u8| (c != UNKNOWN).then_some(f64::from(c));
        match choice {
            WheelChoice::Follower => known(f),
            WheelChoice::Driving => known(d),
            WheelChoice::Both => Some(0.5 * (known(f)? + known(d)?)),
            WheelChoice::Worst => Some(known(f)?.max(known(d)?)),
            // A problem holds the follower or driving wheel these stand for (`Problem::new`).
            WheelChoice::Front | WheelChoice::Rear => {
                unreachable!("an axle's wheel is read as its role when the problem is built")
            }
        }
    }
}

/// A weighted sum of risks on a wheel choice.
#[derive(Debug, Clone, PartialEq)]
pub struct Objective {
    /// (weight, risk), weights positive.
    pub terms: Vec<(f64, Term)>,
    /// Which wheel.
    pub wheel: WheelChoice,
}

/// An objective's value over samples, with its 95% interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// The mean score.
    pub value: f64,
    /// The interval's lower end.
    pub low: f64,
    /// Its upper end.
    pub high: f64,
    /// Samples with a known score.
    pub n: u64,
}

/// Parses `wear`, `vibration`, `0.7*wear+0.3*vibration` (weights positive; a risk at most once).
pub fn parse_terms(s: &str) -> Result<Vec<(f64, Term)>, ObjectiveError> {
    let mut terms: Vec<(f64, Term)> = Vec::new();
    for part in s.split('+') {
        let part = part.trim();
        let (w, name) = match part.split_once('*') {
            Some((w, name)) => {
                let w: f64 = w
                    .trim()
                    .parse()
                    .map_err(|_| ObjectiveError::WeightNotANumber {
                        term: part.to_string(),
                        weight: w.trim().to_string(),
                    })?;
                (w, name)
            }
            None => (1.0, part),
        };
        if !(w.is_finite() && w > 0.0) {
            return Err(ObjectiveError::WeightNotPositive {
                term: part.to_string(),
            });
        }
        let term: Term = name.parse()?;
        if terms.iter().any(|t| t.1 == term) {
            return Err(ObjectiveError::TermTwice(term));
        }
        terms.push((w, term));
    }
    // A sample's score sums the weights and the interval squares it: a total above this would
    // overflow, and only the weights' ratios move the optimum.
    let total: f64 = terms.iter().map(|t| t.0).sum();
    if total > MAX_WEIGHT_SUM {
        return Err(ObjectiveError::WeightsTooLarge {
            objective: s.to_string(),
        });
    }
    Ok(terms)
}

/// The largest sum of an objective's weights: its square, the scale of the interval's
/// variance, stays far from overflow.
pub(crate) const MAX_WEIGHT_SUM: f64 = 1e100;

impl Objective {
    /// Whether the objective needs the wear stage's distance.
    pub fn uses_wear(&self) -> bool {
        self.terms.iter().any(|t| t.1 == Term::Wear)
    }

    /// The objective in words: `0.7 × wear + 0.3 × vibration, worst wheel`.
    pub fn text(&self) -> String {
        let terms: Vec<String> = self
            .terms
            .iter()
            .map(|(w, t)| {
                if *w == 1.0 {
                    t.name().to_string()
                } else {
                    format!("{}*{}", polywear_core::wording::plain(*w, 6), t.name())
                }
            })
            .collect();
        format!("{} ({} wheel)", terms.join("+"), self.wheel.name())
    }

    /// A sample's score; None where an outcome it needs is unknown.
    pub fn score(&self, o: Outcomes) -> Option<f64> {
        self.terms
            .iter()
            .map(|(w, t)| o.indicator(*t, self.wheel).map(|x| w * x))
            .sum()
    }

    /// Whether every score is 0 or the one weight `w`: a proportion scaled by `w` (one risk on
    /// the follower, the driving wheel or the worse of the two).
    fn binary_weight(&self) -> Option<f64> {
        match (&self.terms[..], self.wheel) {
            ([(w, _)], WheelChoice::Follower | WheelChoice::Driving | WheelChoice::Worst) => {
                Some(*w)
            }
            _ => None,
        }
    }

    /// The mean score over the samples with a known score and its 95% interval: Wilson's for
    /// a proportion, else the normal interval of the mean.
    pub fn estimate(&self, outcomes: &[Outcomes]) -> Estimate {
        let scores: Vec<f64> = outcomes.iter().filter_map(|o| self.score(*o)).collect();
        let n = scores.len() as u64;
        if n == 0 {
            return Estimate {
                value: f64::NAN,
                low: f64::NAN,
                high: f64::NAN,
                n,
            };
        }
        let mean = scores.iter().sum::<f64>() / n as f64;
        let (low, high) = match self.binary_weight() {
            Some(w) => {
                let k = scores.iter().filter(|s| **s > 0.0).count() as u64;
                let (a, b) = wilson(k, n);
                (w * a, w * b)
            }
            None => normal_interval(&scores, mean),
        };
        Estimate {
            value: mean,
            low,
            high,
            n,
        }
    }

    /// Setting `a` minus setting `b` on the same samples (those with a known score under both),
    /// with its 95% interval: Newcombe's paired interval for a proportion, else the normal
    /// interval of the mean difference.
    pub fn paired_difference(&self, a: &[Outcomes], b: &[Outcomes]) -> (f64, f64, f64) {
        let pairs: Vec<(f64, f64)> = a
            .iter()
            .zip(b)
            .filter_map(|(x, y)| Some((self.score(*x)?, self.score(*y)?)))
            .collect();
        if pairs.is_empty() {
            return (f64::NAN, f64::NAN, f64::NAN);
        }
        let diffs: Vec<f64> = pairs.iter().map(|(x, y)| x - y).collect();
        let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
        if let Some(w) = self.binary_weight() {
            let mut t = [0u64; 4];
            for (x, y) in &pairs {
                t[usize::from(*x == 0.0) * 2 + usize::from(*y == 0.0)] += 1;
            }
            // t: [both, only a, only b, neither].
            let (lo, hi) = newcombe_paired(t[0], t[1], t[2], t[3]);
            return (mean, w * lo, w * hi);
        }
        let (lo, hi) = normal_interval(&diffs, mean);
        (mean, lo, hi)
    }
}

/// mean ± z₀.₉₇₅ · sd / √n.
fn normal_interval(x: &[f64], mean: f64) -> (f64, f64) {
    let n = x.len() as f64;
    if n < 2.0 {
        return (mean, mean);
    }
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let half = Z95 * (var / n).sqrt();
    (mean - half, mean + half)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_front_or_rear_wheel_is_the_drivetrains_follower_or_driving_one() {
        assert_eq!("rear".parse::<WheelChoice>().unwrap(), WheelChoice::Rear);
        assert_eq!(WheelChoice::Rear.on(Drivetrain::Fwd), WheelChoice::Follower);
        assert_eq!(WheelChoice::Front.on(Drivetrain::Fwd), WheelChoice::Driving);
        assert_eq!(WheelChoice::Rear.on(Drivetrain::Rwd), WheelChoice::Driving);
        assert_eq!(WheelChoice::Worst.on(Drivetrain::Rwd), WheelChoice::Worst);
    }

    fn o(fv: u8, dv: u8, fw: u8, dw: u8) -> Outcomes {
        Outcomes::default()
            .with(Term::Vibration, Wheel::Follower, fv)
            .with(Term::Vibration, Wheel::Driving, dv)
            .with(Term::Wear, Wheel::Follower, fw)
            .with(Term::Wear, Wheel::Driving, dw)
    }

    #[test]
    fn outcomes_pack_and_score_by_wheel_choice() {
        let x = o(YES, NO, UNKNOWN, YES);
        assert_eq!(x.get(Term::Vibration, Wheel::Follower), YES);
        assert_eq!(x.get(Term::Wear, Wheel::Follower), UNKNOWN);
        let obj = |t, wheel| Objective {
            terms: vec![(1.0, t)],
            wheel,
        };
        assert_eq!(
            obj(Term::Vibration, WheelChoice::Follower).score(x),
            Some(1.0)
        );
        assert_eq!(
            obj(Term::Vibration, WheelChoice::Driving).score(x),
            Some(0.0)
        );
        assert_eq!(obj(Term::Vibration, WheelChoice::Both).score(x), Some(0.5));
        assert_eq!(obj(Term::Vibration, WheelChoice::Worst).score(x), Some(1.0));
        assert_eq!(obj(Term::Wear, WheelChoice::Worst).score(x), None);
        assert_eq!(obj(Term::Wear, WheelChoice::Driving).score(x), Some(1.0));
        let sum = Objective {
            terms: parse_terms("0.7*vibration + 0.3*wear").unwrap(),
            wheel: WheelChoice::Driving,
        };
        assert!((sum.score(x).unwrap() - 0.3).abs() < 1e-15);
    }

    #[test]
    fn objectives_parse_or_say_what_is_accepted() {
        assert_eq!(parse_terms("wear").unwrap(), vec![(1.0, Term::Wear)]);
        let e = parse_terms("wer").unwrap_err().to_string();
        assert!(
            e.contains("did you mean `wear`") && e.contains("weighted sum"),
            "{e}"
        );
        assert!(parse_terms("-1*wear").is_err());
        let e = parse_terms("1e308*wear+1e308*vibration")
            .unwrap_err()
            .to_string();
        assert!(e.contains("at most 1e100"), "{e}");
        assert!(parse_terms("1e99*wear+1e99*vibration").is_ok());
        assert!(parse_terms("wear+wear").is_err());
        assert!(parse_terms("x*wear").is_err());
        assert!("worse"
            .parse::<WheelChoice>()
            .unwrap_err()
            .to_string()
            .contains("worst"));
    }

    #[test]
    fn a_proportion_gets_wilsons_interval_and_the_paired_difference_newcombes() {
        let obj = Objective {
            terms: vec![(1.0, Term::Vibration)],
            wheel: WheelChoice::Follower,
        };
        let a: Vec<Outcomes> = (0..100).map(|i| o(u8::from(i < 30), 0, 0, 0)).collect();
        let b: Vec<Outcomes> = (0..100).map(|i| o(u8::from(i < 20), 0, 0, 0)).collect();
        let e = obj.estimate(&a);
        assert_eq!((e.value, e.n), (0.3, 100));
        assert_eq!((e.low, e.high), wilson(30, 100));
        let (d, lo, hi) = obj.paired_difference(&a, &b);
        assert!((d - 0.1).abs() < 1e-15);
        assert_eq!((lo, hi), newcombe_paired(20, 10, 0, 70));
        assert_eq!(
            obj.paired_difference(&a, &a),
            (
                0.0,
                newcombe_paired(30, 0, 0, 70).0,
                newcombe_paired(30, 0, 0, 70).1
            )
        );
    }
}
