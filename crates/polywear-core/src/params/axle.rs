//! The car around the pair of wheels (MODEL.md#the-car-axles-and-drivetrain): which axle is
//! driven, and the values an axle may have of its own. The paper evaluates a follower and a
//! driving wheel at one toe-in, load and pressure; a car has a front and a rear axle, each with
//! its own toe-in (alignment sheets give them apart), load and, sometimes, pressure. A wheel's
//! model reads the values of its axle ([`Params::at_wheel`]); an axle without a value of its own
//! takes the shared one, so that a study without per-axle keys is the paper's pair.

use super::{ParamError, ParamId, Params};

named_enum! {
    /// A wheel's role (re-exported as `model::Wheel`). Driving wheels transmit the drive force through a slip ratio; followers roll freely (S = 0).
    pub enum Wheel: "wheel" {
        /// Rolls freely: slip ratio S = 0.
        Follower,
        /// Transmits the drive force through a slip ratio S > 0.
        Driving,
    }
}

impl Wheel {
    /// Both wheels, follower first.
    pub const BOTH: [Wheel; 2] = [Wheel::Follower, Wheel::Driving];
}

named_enum! {
    /// Where a wheel sits on the car.
    pub enum Axle: "axle" {
        /// The front axle.
        Front,
        /// The rear axle.
        Rear,
    }
}

named_enum! {
    /// Which axle the engine drives (MODEL.md#the-car-axles-and-drivetrain). The driven axle's
    /// wheels share the drive force through a slip ratio (`n_driven` of them) and wear at the
    /// driven position's rate k_d; the other axle's wheels roll freely.
    #[derive(Default)]
    pub enum Drivetrain: "drivetrain" {
        /// Front-wheel drive: the driving wheel is a front wheel, the follower a rear one (the
        /// compact cars of the field reports; the default).
        #[default]
        Fwd,
        /// Rear-wheel drive: the driving wheel is a rear wheel, the follower a front one.
        Rwd,
    }
}

impl Axle {
    /// A wheel on this axle in words with its role, as every summary names it:
    /// "rear (follower)".
    pub fn with_role(self, wheel: Wheel) -> String {
        format!("{self} ({wheel})")
    }
}

impl Drivetrain {
    /// The axle that `wheel` sits on under this drivetrain.
    pub fn axle_of(self, wheel: Wheel) -> Axle {
        match (self, wheel) {
            (Drivetrain::Fwd, Wheel::Driving) | (Drivetrain::Rwd, Wheel::Follower) => Axle::Front,
            (Drivetrain::Fwd, Wheel::Follower) | (Drivetrain::Rwd, Wheel::Driving) => Axle::Rear,
        }
    }

    /// The wheel that sits on `axle` under this drivetrain.
    pub fn wheel_on(self, axle: Axle) -> Wheel {
        Wheel::BOTH
            .into_iter()
            .find(|&w| self.axle_of(w) == axle)
            .expect("each axle holds one of the pair")
    }

    /// The wheel in words with its axle: "rear (follower)", "front (driving)".
    pub fn words(self, wheel: Wheel) -> String {
        self.axle_of(wheel).with_role(wheel)
    }
}

/// A quantity an axle may have of its own: the shared parameter and each axle's.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AxleQuantity {
    /// The shared parameter, both axles' value when neither has its own.
    pub shared: ParamId,
    /// The front axle's parameter.
    pub front: ParamId,
    /// The rear axle's parameter.
    pub rear: ParamId,
}

impl AxleQuantity {
    /// The axle's parameter.
    pub fn of(self, axle: Axle) -> ParamId {
        match axle {
            Axle::Front => self.front,
            Axle::Rear => self.rear,
        }
    }
}

/// Toe-in, load and pressure: the quantities an axle may have of its own.
pub const AXLE_QUANTITIES: [AxleQuantity; 3] = [
    AxleQuantity {
        shared: ParamId::ToeDeg,
        front: ParamId::ToeFrontDeg,
        rear: ParamId::ToeRearDeg,
    },
    AxleQuantity {
        shared: ParamId::LoadN,
        front: ParamId::LoadFrontN,
        rear: ParamId::LoadRearN,
    },
    AxleQuantity {
        shared: ParamId::PressureKpa,
        front: ParamId::PressureFrontKpa,
        rear: ParamId::PressureRearKpa,
    },
];

impl ParamId {
    /// The quantity this parameter gives for one axle or both, if it is one of
    /// [`AXLE_QUANTITIES`].
    pub fn axle_quantity(self) -> Option<AxleQuantity> {
        AXLE_QUANTITIES
            .into_iter()
            .find(|q| [q.shared, q.front, q.rear].contains(&self))
    }

    /// Whether this is an axle's own value (`toe_rear_deg`), absent (NaN) unless given.
    pub fn is_per_axle(self) -> bool {
        self.axle_quantity().is_some_and(|q| q.shared != self)
    }
}

/// Refuses a shared key given beside a per-axle key of the same quantity (`toe_deg` and
/// `toe_rear_deg`): a parameter is set in one place, and which one wins would be a guess.
/// `given` are the parameters one input names; `place` says where, for the message
/// (`"the study's [params]"`).
pub fn check_one_place(given: &[ParamId], place: &str) -> Result<(), ParamError> {
    for q in AXLE_QUANTITIES {
        if !given.contains(&q.shared) {
            continue;
        }
        if let Some(own) = [q.front, q.rear].into_iter().find(|id| given.contains(id)) {
            return Err(ParamError::Inconsistent {
                message: format!(
                    "{place} gives both `{}` (both axles) and `{own}` (one axle); give the axles' values alone, or the shared one alone",
                    q.shared
                ),
            });
        }
    }
    Ok(())
}

impl Params {
    /// The value of `quantity` on `axle`: the axle's own, or the shared one where it has none.
    pub fn on_axle(&self, quantity: AxleQuantity, axle: Axle) -> f64 {
        self.value_or_shared(quantity.of(axle))
    }

    /// The value of `id`, an axle's absent own value read as the shared one it stands for (a
    /// scenario's change of `toe_rear_deg` in a study that gives only `toe_deg` starts there).
    pub fn value_or_shared(&self, id: ParamId) -> f64 {
        match id.axle_quantity() {
            Some(q) if self[id].is_nan() && q.shared != id => self[q.shared],
            _ => self[id],
        }
    }

    /// The parameters as `wheel` sees them (MODEL.md#the-car-axles-and-drivetrain): each
    /// axle's value of toe-in, load and pressure written out (an absent one from the shared
    /// key), and the shared keys set to the values of the wheel's axle. Idempotent: resolving
    /// twice gives the same. Without per-axle values it changes nothing the model reads.
    pub fn at_wheel(&self, wheel: Wheel) -> Params {
        let axle = self.drivetrain.axle_of(wheel);
        let mut p = *self;
        for q in AXLE_QUANTITIES {
            let front = self.on_axle(q, Axle::Front);
            let rear = self.on_axle(q, Axle::Rear);
            p[q.front] = front;
            p[q.rear] = rear;
            p[q.shared] = match axle {
                Axle::Front => front,
                Axle::Rear => rear,
            };
        }
        p
    }

    /// The mean wheel load over both axles \[N\], which the rolling resistance of all
    /// `n_wheels` wheels reads (the shared load when no axle has its own).
    pub fn mean_load_n(&self) -> f64 {
        let q = AXLE_QUANTITIES[1];
        0.5 * (self.on_axle(q, Axle::Front) + self.on_axle(q, Axle::Rear))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_per_axle_values_a_wheel_sees_the_shared_ones() {
        let p = Params::default();
        for w in Wheel::BOTH {
            let at = p.at_wheel(w);
            assert_eq!(at.toe_deg.to_bits(), p.toe_deg.to_bits());
            assert_eq!(at.load_n.to_bits(), p.load_n.to_bits());
            assert_eq!(at.toe_front_deg, p.toe_deg);
            assert_eq!(at.at_wheel(w), at, "idempotent");
        }
        assert_eq!(p.mean_load_n().to_bits(), p.load_n.to_bits());
    }

    #[test]
    fn each_wheel_reads_its_own_axle() {
        let mut p = Params {
            toe_front_deg: 0.1,
            toe_rear_deg: 0.4,
            load_rear_n: 3000.0,
            ..Params::default()
        };
        assert_eq!(p.at_wheel(Wheel::Follower).toe_deg, 0.4);
        assert_eq!(p.at_wheel(Wheel::Follower).load_n, 3000.0);
        assert_eq!(p.at_wheel(Wheel::Driving).toe_deg, 0.1);
        assert_eq!(p.at_wheel(Wheel::Driving).load_n, 4000.0);
        assert_eq!(p.mean_load_n(), 3500.0);
        p.drivetrain = Drivetrain::Rwd;
        assert_eq!(p.at_wheel(Wheel::Driving).toe_deg, 0.4);
        assert_eq!(p.at_wheel(Wheel::Follower).toe_deg, 0.1);
        assert_eq!(Drivetrain::Rwd.words(Wheel::Follower), "front (follower)");
        assert_eq!(Drivetrain::Fwd.words(Wheel::Follower), "rear (follower)");
        assert_eq!(Drivetrain::Fwd.wheel_on(Axle::Front), Wheel::Driving);
    }

    #[test]
    fn a_shared_key_beside_an_axles_key_is_refused() {
        use ParamId::*;
        assert!(check_one_place(&[ToeFrontDeg, ToeRearDeg, LoadN], "x").is_ok());
        let e = check_one_place(&[ToeDeg, SpeedKmh, ToeRearDeg], "the study's [params]")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`toe_deg`") && e.contains("`toe_rear_deg`"),
            "{e}"
        );
        assert!(e.starts_with("the study's [params] gives both"), "{e}");
    }
}
