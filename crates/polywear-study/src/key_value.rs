//! A serde struct as Parquet key–value metadata and back. Parquet footers hold text only, and
//! pandas/pyarrow show each key as written, so a text field is written as its text and every
//! other field (numbers, lists, objects) as compact JSON; a field that is `None` is left out.
//! Reading back asks the target type what it expects: a text field takes the value as it is, any
//! other field parses it as JSON. One struct thus describes a footer, in both directions. A key
//! the struct does not name (`ARROW:schema`, which pyarrow and polars add when they rewrite a
//! file, or `pandas`) is skipped unread; an error names the key whose value is wrong.

use serde::de::{self, IntoDeserializer, Visitor};
use serde::ser::{self, Impossible, Serialize};

/// Why a struct cannot be written as key–value metadata, or read from it.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct KeyValueError(String);

impl ser::Error for KeyValueError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        KeyValueError(msg.to_string())
    }
}

impl de::Error for KeyValueError {
    fn custom<T: std::fmt::Display>(msg: T) -> Self {
        KeyValueError(msg.to_string())
    }
}

/// The fields of `value` (a struct) as (key, text) pairs in declaration order.
pub(crate) fn to_key_values<T: Serialize>(
    value: &T,
) -> Result<Vec<(String, String)>, KeyValueError> {
    value.serialize(StructSerializer)
}

/// A struct read from (key, text) pairs; keys the struct does not name are ignored, and an error
/// names the key (`` `seed`: invalid type ... ``).
pub(crate) fn from_key_values<T: de::DeserializeOwned>(
    pairs: &[(String, String)],
) -> Result<T, KeyValueError> {
    T::deserialize(de::value::MapAccessDeserializer::new(Pairs {
        pairs: pairs.iter(),
        current: None,
    }))
}

/// The pairs as a map, remembering the key whose value is read, for its errors.
struct Pairs<'a> {
    pairs: std::slice::Iter<'a, (String, String)>,
    current: Option<&'a (String, String)>,
}

impl<'de, 'a> de::MapAccess<'de> for Pairs<'a> {
    type Error = KeyValueError;

    fn next_key_seed<K: de::DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, KeyValueError> {
        let Some(pair) = self.pairs.next() else {
            return Ok(None);
        };
        self.current = Some(pair);
        seed.deserialize(pair.0.as_str().into_deserializer())
            .map(Some)
    }

    fn next_value_seed<V: de::DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> Result<V::Value, KeyValueError> {
        let (key, value) = self.current.take().expect("a value follows its key");
        let named = format!("`{key}`");
        seed.deserialize(FieldText(value)).map_err(|e| {
            // A field's own deserializer may already name its key.
            if e.0.starts_with(&named) {
                e
            } else {
                KeyValueError(format!("{named}: {e}"))
            }
        })
    }
}

/// The text of one field: raw for a string, compact JSON for anything else; None for a null.
fn field_text<T: Serialize + ?Sized>(value: &T) -> Result<Option<String>, KeyValueError> {
    let json = serde_json::to_value(value).map_err(|e| KeyValueError(e.to_string()))?;
    Ok(match json {
        serde_json::Value::Null => None,
        serde_json::Value::String(s) => Some(s),
        // Written from the value itself, not from `json`: a struct keeps its field order.
        _ => Some(serde_json::to_string(value).map_err(|e| KeyValueError(e.to_string()))?),
    })
}

struct StructSerializer;

/// Collects the fields of a struct.
struct Fields(Vec<(String, String)>);

impl ser::SerializeStruct for Fields {
    type Ok = Vec<(String, String)>;
    type Error = KeyValueError;
    fn serialize_field<T: Serialize + ?Sized>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), KeyValueError> {
        if let Some(text) = field_text(value)? {
            self.0.push((key.to_string(), text));
        }
        Ok(())
    }
    fn end(self) -> Result<Self::Ok, KeyValueError> {
        Ok(self.0)
    }
}

fn only_structs<T>() -> Result<T, KeyValueError> {
    Err(KeyValueError(
        "only a struct is written as key-value metadata".into(),
    ))
}

type Never = Impossible<Vec<(String, String)>, KeyValueError>;

macro_rules! refuse {
    ($($name:ident($($arg:ty),*)),* $(,)?) => {$(
        fn $name(self, $(_: $arg),*) -> Result<Self::Ok, KeyValueError> {
            only_structs()
        }
    )*};
}

impl ser::Serializer for StructSerializer {
    type Ok = Vec<(String, String)>;
    type Error = KeyValueError;
    type SerializeSeq = Never;
    type SerializeTuple = Never;
    type SerializeTupleStruct = Never;
    type SerializeTupleVariant = Never;
    type SerializeMap = Never;
    type SerializeStruct = Fields;
    type SerializeStructVariant = Never;

    refuse!(
        serialize_bool(bool),
        serialize_i8(i8),
        serialize_i16(i16),
        serialize_i32(i32),
        serialize_i64(i64),
        serialize_u8(u8),
        serialize_u16(u16),
        serialize_u32(u32),
        serialize_u64(u64),
        serialize_f32(f32),
        serialize_f64(f64),
        serialize_char(char),
        serialize_str(&str),
        serialize_bytes(&[u8]),
        serialize_none(),
        serialize_unit(),
        serialize_unit_struct(&'static str),
        serialize_unit_variant(&'static str, u32, &'static str),
    );

    fn serialize_some<T: Serialize + ?Sized>(self, _: &T) -> Result<Self::Ok, KeyValueError> {
        only_structs()
    }
    fn serialize_newtype_struct<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: &T,
    ) -> Result<Self::Ok, KeyValueError> {
        only_structs()
    }
    fn serialize_newtype_variant<T: Serialize + ?Sized>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<Self::Ok, KeyValueError> {
        only_structs()
    }
    fn serialize_seq(self, _: Option<usize>) -> Result<Never, KeyValueError> {
        only_structs()
    }
    fn serialize_tuple(self, _: usize) -> Result<Never, KeyValueError> {
        only_structs()
    }
    fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Never, KeyValueError> {
        only_structs()
    }
    fn serialize_tuple_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Never, KeyValueError> {
        only_structs()
    }
    fn serialize_map(self, _: Option<usize>) -> Result<Never, KeyValueError> {
        only_structs()
    }
    fn serialize_struct(self, _: &'static str, len: usize) -> Result<Fields, KeyValueError> {
        Ok(Fields(Vec::with_capacity(len)))
    }
    fn serialize_struct_variant(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: usize,
    ) -> Result<Never, KeyValueError> {
        only_structs()
    }
}

/// One field's text, read as the target type asks: as it is for a string, as JSON otherwise.
#[derive(Clone, Copy)]
struct FieldText<'a>(&'a str);

impl<'a> FieldText<'a> {
    fn json(self) -> Result<serde_json::Value, KeyValueError> {
        serde_json::from_str(self.0).map_err(|e| {
            KeyValueError(format!(
                "not JSON ({e}): {}",
                polywear_core::wording::snippet(self.0)
            ))
        })
    }
}

impl<'de, 'a> IntoDeserializer<'de, KeyValueError> for FieldText<'a> {
    type Deserializer = Self;
    fn into_deserializer(self) -> Self {
        self
    }
}

macro_rules! as_json {
    ($($name:ident),* $(,)?) => {$(
        fn $name<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
            self.json()?
                .$name(visitor)
                .map_err(|e| KeyValueError(e.to_string()))
        }
    )*};
}

impl<'de, 'a> de::Deserializer<'de> for FieldText<'a> {
    type Error = KeyValueError;

    as_json!(
        deserialize_any,
        deserialize_bool,
        deserialize_i8,
        deserialize_i16,
        deserialize_i32,
        deserialize_i64,
        deserialize_u8,
        deserialize_u16,
        deserialize_u32,
        deserialize_u64,
        deserialize_f32,
        deserialize_f64,
        deserialize_seq,
        deserialize_map,
        deserialize_unit,
    );

    /// A key the struct does not name is skipped without reading its value (it need not be
    /// JSON: `ARROW:schema` is base64).
    fn deserialize_ignored_any<V: Visitor<'de>>(
        self,
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        visitor.visit_unit()
    }

    fn deserialize_str<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
        visitor.visit_str(self.0)
    }
    fn deserialize_string<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
        visitor.visit_str(self.0)
    }
    fn deserialize_char<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
        visitor.visit_str(self.0)
    }
    fn deserialize_identifier<V: Visitor<'de>>(
        self,
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        visitor.visit_str(self.0)
    }
    fn deserialize_bytes<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
        visitor.visit_bytes(self.0.as_bytes())
    }
    fn deserialize_byte_buf<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
        visitor.visit_bytes(self.0.as_bytes())
    }
    fn deserialize_option<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, KeyValueError> {
        visitor.visit_some(self)
    }
    fn deserialize_unit_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        self.deserialize_unit(visitor)
    }
    fn deserialize_newtype_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        visitor.visit_newtype_struct(self)
    }
    fn deserialize_tuple<V: Visitor<'de>>(
        self,
        _: usize,
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        self.deserialize_seq(visitor)
    }
    fn deserialize_tuple_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        _: usize,
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        self.deserialize_seq(visitor)
    }
    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        _: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        self.deserialize_map(visitor)
    }
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        _: &'static str,
        _: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, KeyValueError> {
        visitor.visit_enum(self.0.into_deserializer())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Footer {
        name: String,
        seed: u64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        note: Option<String>,
        list: Vec<String>,
        hash: String,
        nothing: Option<u64>,
    }

    #[test]
    fn a_struct_goes_out_as_text_and_comes_back_the_same() {
        let f = Footer {
            name: "2014".into(),
            seed: 42,
            note: None,
            list: vec!["a".into(), "b".into()],
            hash: "12345".into(),
            nothing: None,
        };
        let kv = to_key_values(&f).unwrap();
        let text: Vec<(&str, &str)> = kv.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        assert_eq!(
            text,
            [
                ("name", "2014"),
                ("seed", "42"),
                ("list", r#"["a","b"]"#),
                ("hash", "12345")
            ]
        );
        let mut with_extra = kv.clone();
        with_extra.push(("units".into(), "{}".into()));
        // What pyarrow adds when it rewrites a file: not JSON, and never read.
        with_extra.push(("ARROW:schema".into(), "/////7gAAAAQAAAA".into()));
        assert_eq!(from_key_values::<Footer>(&with_extra).unwrap(), f);
        // A damaged value is named by its key, and quoted only in part.
        let mut damaged = kv.clone();
        damaged[1].1 = format!("x{}", "9".repeat(500));
        let e = from_key_values::<Footer>(&damaged).unwrap_err().to_string();
        assert!(e.starts_with("`seed`: not JSON"), "{e}");
        assert!(e.len() < 200, "{e}");
    }
}
