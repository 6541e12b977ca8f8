//! Enums written as names in files and on screen (wheel, variant, class, method, design, wear
//! zone), each declared through `named_enum!`. Their names come from one derive (strum:
//! `EnumString`, `Display`, `IntoStaticStr`, `VariantNames` with `serialize_all = "snake_case"`),
//! so the name written, the name parsed and the list of accepted names cannot drift apart; this
//! module adds what the derive does not give: the refusal of an unknown name with the closest
//! and the accepted ones, and serde by name.

/// A name that names no case of an enum written as text; its message suggests the closest
/// accepted name, if one is close.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown {kind} `{name}`;{hint} accepted: {}", accepted.join(", "), hint = crate::wording::did_you_mean(name, accepted.iter().copied()))]
pub struct UnknownName {
    /// What the enum names ("class", "variant").
    pub kind: &'static str,
    /// The name given.
    pub name: String,
    /// The accepted names, in the order of the declaration.
    pub accepted: &'static [&'static str],
}

/// An enum written as text: its kind, for messages (the names come from the derive).
pub trait TextEnum: strum::VariantNames {
    /// What the enum names, for messages ("class").
    const KIND: &'static str;
}

/// The refusal of `name` as a `T` (the `parse_err_fn` of the derive).
pub fn unknown<T: TextEnum>(name: &str) -> UnknownName {
    UnknownName {
        kind: T::KIND,
        name: name.to_string(),
        accepted: T::VARIANTS,
    }
}

/// `TextEnum`, `as_str` (the derived name as `&'static str`), `serde::Serialize` as that name
/// and `serde::Deserialize` from it (an unknown name is refused with the accepted ones).
#[macro_export]
macro_rules! text_enum {
    ($($t:ty => $kind:literal),* $(,)?) => {$(
        impl $crate::text_enum::TextEnum for $t {
            const KIND: &'static str = $kind;
        }

        impl $t {
            /// The name written in output files and accepted by parsers.
            pub fn as_str(self) -> &'static str {
                self.into()
            }
        }

        impl serde::Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.as_str())
            }
        }

        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let name = <std::borrow::Cow<'de, str>>::deserialize(d)?;
                name.parse().map_err(|_| {
                    serde::de::Error::unknown_variant(
                        &name,
                        <$t as strum::VariantNames>::VARIANTS,
                    )
                })
            }
        }
    )*};
}

/// Declares an enum written as names: the one derive that gives its names (snake_case, parsed
/// with a typed refusal), and [`TextEnum`], `as_str` and serde by name. `$kind` names the enum
/// in messages ("class").
#[macro_export]
macro_rules! named_enum {
    ($(#[$meta:meta])* $vis:vis enum $name:ident: $kind:literal { $($body:tt)* }) => {
        $(#[$meta])*
        #[derive(
            Debug,
            Clone,
            Copy,
            PartialEq,
            Eq,
            Hash,
            PartialOrd,
            Ord,
            strum::EnumString,
            strum::Display,
            strum::IntoStaticStr,
            strum::VariantNames,
        )]
        #[strum(
            serialize_all = "snake_case",
            parse_err_fn = $crate::text_enum::unknown::<Self>,
            parse_err_ty = $crate::text_enum::UnknownName
        )]
        $vis enum $name { $($body)* }

        $crate::text_enum!($name => $kind);
    };
}

#[cfg(test)]
mod tests {
    use crate::classify::{Class, Method};
    use crate::model::{Variant, Wheel};
    use crate::sampling::design::Design;
    use crate::wear::WearZone;

    /// The names written into Parquet files: they must never change.
    #[test]
    fn names_are_the_ones_in_files() {
        let names = |v: &[&str]| v.join(",");
        assert_eq!(names(&Wheel::BOTH.map(Wheel::as_str)), "follower,driving");
        assert_eq!(
            names(&Variant::ALL.map(Variant::as_str)),
            "paper,combined,sliding_share"
        );
        assert_eq!(
            names(&Class::ALL.map(Class::as_str)),
            "stable,limit_cycle,bistable,no_traction,failed,standstill"
        );
        assert_eq!(
            names(&Method::ALL.map(Method::as_str)),
            "linear,shooting,envelope,reference"
        );
        assert_eq!(
            names(&Design::ALL.map(Design::as_str)),
            "random,lhs,sobol,grid,saltelli"
        );
        assert_eq!("latin_hypercube".parse(), Ok(Design::LatinHypercube));
        assert_eq!(
            names(&WearZone::ALL.map(WearZone::as_str)),
            "trailing,whole_patch,whole_patch_uniform"
        );
    }

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
            assert_eq!(w.as_str().parse::<Wheel>(), Ok(w));
        }
        for d in Design::ALL {
            assert_eq!(d.as_str().parse::<Design>(), Ok(d));
        }
        // The ALL lists hold every case, in the order of the declaration.
        assert_eq!(
            <Class as strum::VariantNames>::VARIANTS,
            Class::ALL.map(Class::as_str)
        );
        assert_eq!(
            <Variant as strum::VariantNames>::VARIANTS,
            Variant::ALL.map(Variant::as_str)
        );
        assert_eq!(
            <Method as strum::VariantNames>::VARIANTS,
            Method::ALL.map(Method::as_str)
        );
        assert_eq!(
            <Wheel as strum::VariantNames>::VARIANTS,
            Wheel::BOTH.map(Wheel::as_str)
        );
        assert_eq!(
            <Design as strum::VariantNames>::VARIANTS,
            Design::ALL.map(Design::as_str)
        );
        assert_eq!(
            <WearZone as strum::VariantNames>::VARIANTS,
            WearZone::ALL.map(WearZone::as_str)
        );
        let e = "wholepatch".parse::<WearZone>().unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown wear zone `wholepatch`; did you mean `whole_patch`? accepted: trailing, whole_patch, whole_patch_uniform"
        );
        let e = "oscillating".parse::<Class>().unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown class `oscillating`; accepted: stable, limit_cycle, bistable, no_traction, failed, standstill"
        );
        assert!("Stable".parse::<Class>().is_err(), "names are exact");
        let e = "limit_cylce".parse::<Class>().unwrap_err().to_string();
        assert!(
            e.starts_with(
                "unknown class `limit_cylce`; did you mean `limit_cycle`? accepted: stable"
            ),
            "{e}"
        );
        let json = serde_json::to_string(&(Class::LimitCycle, Wheel::Driving)).unwrap();
        assert_eq!(json, r#"["limit_cycle","driving"]"#);
    }
}
