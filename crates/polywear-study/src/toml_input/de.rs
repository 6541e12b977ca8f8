//! A serde deserializer over a parsed TOML value that names the full key of every problem:
//! derived schemas (`#[derive(Deserialize)]`, `deny_unknown_fields`) read the file, and each
//! error leaves with its dotted key path (`params.toe_deg.levels[2]`), built on the way out as
//! it passes each table and array. Numbers are read as numbers whether written as integers or
//! floats; the expected type is named in words ("a number", "a table").

use serde::de::{self, DeserializeSeed, IntoDeserializer, MapAccess, SeqAccess, Visitor};
use serde::forward_to_deserialize_any;

use super::TomlError;

/// Deserializes `T` from `value`; errors name the key relative to `value`.
pub fn from_value<'de, T: de::Deserialize<'de>>(value: &'de toml::Value) -> Result<T, TomlError> {
    T::deserialize(Keyed(value))
}

/// One value of the file, borrowed for the lifetime of the deserialization.
#[derive(Clone, Copy)]
struct Keyed<'de>(&'de toml::Value);

impl<'de> Keyed<'de> {
    fn wrong(self, expected: &str) -> TomlError {
        TomlError::WrongType {
            key: String::new(),
            expected: expected.to_string(),
            got: self.0.type_str().to_string(),
        }
    }
}

impl<'de> de::Deserializer<'de> for Keyed<'de> {
    type Error = TomlError;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        match self.0 {
            toml::Value::String(s) => visitor.visit_borrowed_str(s),
            toml::Value::Integer(i) => visitor.visit_i64(*i),
            toml::Value::Float(x) => visitor.visit_f64(*x),
            toml::Value::Boolean(b) => visitor.visit_bool(*b),
            toml::Value::Datetime(d) => visitor.visit_string(d.to_string()),
            toml::Value::Array(a) => visitor.visit_seq(Elements {
                items: a.iter().enumerate(),
            }),
            toml::Value::Table(t) => visitor.visit_map(Entries {
                entries: t.iter(),
                value: None,
            }),
        }
    }

    fn deserialize_f64<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        match self.0 {
            toml::Value::Integer(i) => visitor.visit_f64(*i as f64),
            toml::Value::Float(x) => visitor.visit_f64(*x),
            _ => Err(self.wrong("a number")),
        }
    }

    fn deserialize_f32<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        self.deserialize_f64(visitor)
    }

    fn deserialize_str<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        match self.0 {
            toml::Value::String(s) => visitor.visit_borrowed_str(s),
            _ => Err(self.wrong("a string")),
        }
    }

    fn deserialize_string<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        self.deserialize_str(visitor)
    }

    fn deserialize_seq<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        match self.0 {
            toml::Value::Array(_) => self.deserialize_any(visitor),
            _ => Err(self.wrong("an array")),
        }
    }

    fn deserialize_map<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        match self.0 {
            toml::Value::Table(_) => self.deserialize_any(visitor),
            _ => Err(self.wrong("a table")),
        }
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, TomlError> {
        self.deserialize_map(visitor)
    }

    /// A key that is present holds a value: `Some`.
    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, TomlError> {
        visitor.visit_some(self)
    }

    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _name: &'static str,
        visitor: V,
    ) -> Result<V::Value, TomlError> {
        visitor.visit_newtype_struct(self)
    }

    /// A unit variant written as its name.
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, TomlError> {
        match self.0 {
            toml::Value::String(s) => visitor.visit_enum(s.as_str().into_deserializer()),
            _ => Err(self.wrong("a string")),
        }
    }

    forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 char bytes byte_buf unit unit_struct
        tuple tuple_struct identifier ignored_any
    }
}

/// An array's elements; an error inside element i is named `[i]`.
struct Elements<'de> {
    items: std::iter::Enumerate<std::slice::Iter<'de, toml::Value>>,
}

impl<'de> SeqAccess<'de> for Elements<'de> {
    type Error = TomlError;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, TomlError> {
        match self.items.next() {
            Some((i, v)) => seed
                .deserialize(Keyed(v))
                .map(Some)
                .map_err(|e| e.within(&format!("[{i}]"))),
            None => Ok(None),
        }
    }

    fn size_hint(&self) -> Option<usize> {
        Some(self.items.len())
    }
}

/// A table's entries; an error in a key or its value is named by that key.
struct Entries<'de> {
    entries: toml::map::Iter<'de>,
    value: Option<(&'de str, &'de toml::Value)>,
}

impl<'de> MapAccess<'de> for Entries<'de> {
    type Error = TomlError;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, TomlError> {
        let Some((k, v)) = self.entries.next() else {
            return Ok(None);
        };
        self.value = Some((k.as_str(), v));
        let key = de::value::BorrowedStrDeserializer::<TomlError>::new(k.as_str());
        // An unknown field is refused while its key is read and already names it.
        seed.deserialize(key).map(Some).map_err(|e| match e {
            e @ TomlError::UnknownKey { .. } => e,
            e => e.within(k),
        })
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(&mut self, seed: V) -> Result<V::Value, TomlError> {
        let (k, v) = self.value.take().expect("a value follows its key");
        seed.deserialize(Keyed(v)).map_err(|e| e.within(k))
    }
}

/// The type of a value serde saw, in TOML's words.
fn toml_type(u: &de::Unexpected) -> String {
    match u {
        de::Unexpected::Str(_) | de::Unexpected::Char(_) => "string".into(),
        de::Unexpected::Signed(_) | de::Unexpected::Unsigned(_) => "integer".into(),
        de::Unexpected::Float(_) => "float".into(),
        de::Unexpected::Bool(_) => "boolean".into(),
        de::Unexpected::Seq => "array".into(),
        de::Unexpected::Map => "table".into(),
        other => other.to_string(),
    }
}

impl de::Error for TomlError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        TomlError::Unparsable {
            key: String::new(),
            problem: msg.to_string(),
        }
    }

    fn invalid_type(unexp: de::Unexpected, exp: &dyn de::Expected) -> Self {
        TomlError::WrongType {
            key: String::new(),
            expected: exp.to_string(),
            got: toml_type(&unexp),
        }
    }

    fn unknown_field(field: &str, expected: &'static [&'static str]) -> Self {
        TomlError::UnknownKey {
            key: field.to_string(),
            accepted: super::accepted_hint(
                field,
                expected,
                &format!("accepted: {}", expected.join(", ")),
            ),
        }
    }

    fn unknown_variant(variant: &str, expected: &'static [&'static str]) -> Self {
        TomlError::UnknownName {
            key: String::new(),
            name: variant.to_string(),
            accepted: expected.join(", "),
        }
    }

    fn missing_field(field: &'static str) -> Self {
        TomlError::Missing {
            key: String::new(),
            field: field.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::Deserialize;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Inner {
        levels: Vec<f64>,
        name: Option<String>,
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Outer {
        a: Inner,
        list: Option<Vec<Inner>>,
    }

    fn err(text: &str) -> String {
        let v = toml::Value::Table(super::super::parse(text).unwrap());
        from_value::<Outer>(&v).unwrap_err().to_string()
    }

    #[test]
    fn every_error_names_its_full_key() {
        assert_eq!(
            err("a = { levels = [1, \"x\"] }"),
            "`a.levels[1]` must be a number, got string"
        );
        assert_eq!(
            err("a = { levels = 3 }"),
            "`a.levels` must be an array, got integer"
        );
        assert_eq!(
            err("a = { levels = [], nam = \"q\" }"),
            "unknown key `a.nam`; did you mean `name`? accepted: levels, name"
        );
        assert_eq!(err("a = { name = \"q\" }"), "`a` needs `levels`");
        assert_eq!(
            err("a = { levels = [] }\nlist = [{ levels = [] }, { levels = [], name = 4 }]"),
            "`list[1].name` must be a string, got integer"
        );
        assert_eq!(err("a = 2"), "`a` must be a table, got integer");
        let v = toml::Value::Table(super::super::parse("a = { levels = [2, 3.5] }").unwrap());
        let o: Outer = from_value(&v).unwrap();
        assert_eq!(o.a.levels, vec![2.0, 3.5]);
        assert!(o.a.name.is_none() && o.list.is_none());
    }
}
