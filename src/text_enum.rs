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
