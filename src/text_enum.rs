//! Enums written as names in files and on screen (wheel, variant, class, method, design): one
//! place that turns them into text and back, so that nothing else compares their names.

/// `serde::Serialize` as the enum's `as_str()` name (e.g. `"limit_cycle"` in `simulate --json`).
macro_rules! serialize_as_str {
    ($($t:ty),* $(,)?) => {$(
        impl serde::Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.as_str())
            }
        }
    )*};
}

/// `Display` as `as_str()` (honouring width and alignment), and `FromStr` accepting exactly the names of `ALL`, refusing any
/// other with the accepted names listed; `$what` names the kind in that message.
macro_rules! display_and_parse {
    ($t:ty, $what:literal) => {
        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.pad(self.as_str())
            }
        }

        impl std::str::FromStr for $t {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                <$t>::ALL
                    .iter()
                    .copied()
                    .find(|x| x.as_str() == s)
                    .ok_or_else(|| {
                        let names: Vec<&str> = <$t>::ALL.iter().map(|x| x.as_str()).collect();
                        format!(
                            concat!("unknown ", $what, " `{}`; accepted: {}"),
                            s,
                            names.join(", ")
                        )
                    })
            }
        }
    };
}

/// `serde::Deserialize` from the enum's name through its `FromStr`, whose refusal (with the
/// accepted names) becomes the error of the key that holds it.
macro_rules! deserialize_by_name {
    ($($t:ty),* $(,)?) => {$(
        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let name = <std::borrow::Cow<'de, str>>::deserialize(d)?;
                name.parse().map_err(serde::de::Error::custom)
            }
        }
    )*};
}

deserialize_by_name!(crate::model::Variant);

#[cfg(test)]
mod tests {
    use crate::classify::{Class, Method};
    use crate::model::{Variant, Wheel};

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for c in Class::ALL {
            assert_eq!(c.as_str().parse::<Class>(), Ok(c));
            assert_eq!(format!("{c:>12}"), format!("{:>12}", c.as_str()));
        }
        for m in Method::ALL {
            assert_eq!(m.to_string().parse::<Method>(), Ok(m));
        }
        for v in Variant::ALL {
            assert_eq!(v.to_string().parse::<Variant>(), Ok(v));
        }
        for w in Wheel::BOTH {
            assert_eq!(format!("{w:>9}"), format!("{:>9}", w.as_str()));
        }
        let e = "oscillating".parse::<Class>().unwrap_err();
        assert!(
            e.contains("`oscillating`") && e.contains("limit_cycle"),
            "{e}"
        );
        let json = serde_json::to_string(&(Class::LimitCycle, Wheel::Driving)).unwrap();
        assert_eq!(json, r#"["limit_cycle","driving"]"#);
    }
}
