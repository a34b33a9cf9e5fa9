//! The protocol's one JSON reader and writer, used by the JSON channel, the HMI's JSON lines
//! and JSON arguments, and the clients. Not used inside the real-time cycle.
//!
//! Reading ([`parse`]): like `serde_json::from_str` into a [`Value`], except that a key repeated
//! in any object of the tree is refused with an error naming the key (serde_json alone would
//! keep the last value silently, so `{"command":"nope","command":"status"}` would run
//! `status`).
//!
//! Writing ([`to_ascii`], [`to_ascii_pretty`]): the protocol is ASCII, so every non-ASCII
//! character of a string is written as a `\uXXXX` escape (a UTF-16 surrogate pair above
//! U+FFFF); the JSON value is unchanged.
//!
//! ```
//! use mcm_shared::protocol::json::{ParseError, parse, to_ascii};
//! let v = parse(r#"{"a":"\u00e9\ud83d\ude00"}"#).unwrap();
//! assert_eq!(to_ascii(&v), r#"{"a":"\u00e9\ud83d\ude00"}"#);
//! let e = parse(r#"{"b":{"k":1,"k":2}}"#).unwrap_err();
//! assert_eq!(e, ParseError::DuplicateKey { key: "k".into() });
//! ```

use serde::de::{self, DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};
use serde_json::ser::{CompactFormatter, Formatter, PrettyFormatter};
use serde_json::{Map, Value};
use std::cell::RefCell;
use std::fmt;
use std::io;

/// The JSON type name of a value, for messages.
pub fn json_kind(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "boolean",
        Value::Number(_) => "number",
        Value::String(_) => "string",
        Value::Array(_) => "array",
        Value::Object(_) => "object",
    }
}

/// A value as a message shows it: its JSON text, cut after 60 characters.
pub fn shown(v: &Value) -> String {
    let s = v.to_string();
    // Cut at a character boundary: the value may hold any Unicode text.
    match s.char_indices().nth(60) {
        Some((cut, _)) => format!("{}...", &s[..cut]),
        None => s,
    }
}

/// Longest part of a key quoted in an error (in characters).
const KEY_EXCERPT_CHARS: usize = 40;

/// Why a JSON text was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ParseError {
    /// Not valid JSON; the text is serde_json's message with line and column.
    #[error("{0}")]
    Syntax(String),
    /// A key appears twice in one object.
    #[error("duplicate key \"{key}\" in one JSON object; each key may appear only once")]
    DuplicateKey { key: String },
}

/// Parse one JSON text; a repeated key in any object is an error.
pub fn parse(text: &str) -> Result<Value, ParseError> {
    let duplicate = RefCell::new(None);
    let mut de = serde_json::Deserializer::from_str(text);
    let result = UniqueValue(&duplicate)
        .deserialize(&mut de)
        .and_then(|v| de.end().map(|()| v));
    match (result, duplicate.into_inner()) {
        (Ok(v), _) => Ok(v),
        (Err(_), Some(key)) => Err(ParseError::DuplicateKey { key }),
        (Err(e), None) => Err(ParseError::Syntax(e.to_string())),
    }
}

/// Builds a [`Value`] and records the first repeated key (then fails).
#[derive(Clone, Copy)]
struct UniqueValue<'a>(&'a RefCell<Option<String>>);

impl<'de> DeserializeSeed<'de> for UniqueValue<'_> {
    type Value = Value;
    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<Value, D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for UniqueValue<'_> {
    type Value = Value;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, v: bool) -> Result<Value, E> {
        Ok(Value::Bool(v))
    }
    fn visit_i64<E>(self, v: i64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_u64<E>(self, v: u64) -> Result<Value, E> {
        Ok(Value::from(v))
    }
    fn visit_f64<E>(self, v: f64) -> Result<Value, E> {
        // JSON numbers are finite; from_f64 only refuses NaN and infinities.
        Ok(serde_json::Number::from_f64(v).map_or(Value::Null, Value::Number))
    }
    fn visit_str<E>(self, v: &str) -> Result<Value, E> {
        Ok(Value::String(v.to_string()))
    }
    fn visit_string<E>(self, v: String) -> Result<Value, E> {
        Ok(Value::String(v))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut out = Vec::new();
        while let Some(v) = seq.next_element_seed(self)? {
            out.push(v);
        }
        Ok(Value::Array(out))
    }
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut out = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            if out.contains_key(&key) {
                let shown: String = key.chars().take(KEY_EXCERPT_CHARS).collect();
                *self.0.borrow_mut() = Some(shown);
                return Err(de::Error::custom("duplicate key"));
            }
            let v = map.next_value_seed(self)?;
            out.insert(key, v);
        }
        Ok(Value::Object(out))
    }
}

/// Writes strings with every non-ASCII character as `\uXXXX`.
struct Ascii<F>(F);

impl<F: Formatter> Formatter for Ascii<F> {
    fn write_string_fragment<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        fragment: &str,
    ) -> io::Result<()> {
        let mut rest = fragment;
        while let Some(pos) = rest.find(|c: char| !c.is_ascii()) {
            w.write_all(&rest.as_bytes()[..pos])?;
            let c = rest[pos..].chars().next().expect("found at pos");
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                write!(w, "\\u{u:04x}")?;
            }
            rest = &rest[pos + c.len_utf8()..];
        }
        w.write_all(rest.as_bytes())
    }

    // Delegate the layout (indentation) to the wrapped formatter.
    fn begin_array<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_array(w)
    }
    fn end_array<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_array(w)
    }
    fn begin_array_value<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        self.0.begin_array_value(w, first)
    }
    fn end_array_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_array_value(w)
    }
    fn begin_object<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_object(w)
    }
    fn end_object<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object(w)
    }
    fn begin_object_key<W: ?Sized + io::Write>(
        &mut self,
        w: &mut W,
        first: bool,
    ) -> io::Result<()> {
        self.0.begin_object_key(w, first)
    }
    fn end_object_key<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object_key(w)
    }
    fn begin_object_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.begin_object_value(w)
    }
    fn end_object_value<W: ?Sized + io::Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.0.end_object_value(w)
    }
}

fn write<F: Formatter>(v: &Value, f: F) -> String {
    let mut out = Vec::new();
    let mut ser = serde_json::Serializer::with_formatter(&mut out, Ascii(f));
    serde::Serialize::serialize(v, &mut ser).expect("a JSON value serialises into memory");
    String::from_utf8(out).expect("only ASCII is written")
}

/// Compact JSON, pure ASCII.
pub fn to_ascii(v: &Value) -> String {
    write(v, CompactFormatter)
}

/// Indented JSON (for people), pure ASCII.
pub fn to_ascii_pretty(v: &Value) -> String {
    write(v, PrettyFormatter::new())
}

#[cfg(test)]
mod tests;
