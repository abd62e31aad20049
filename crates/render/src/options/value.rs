//! How one option's value is read and written: as a command-line word (`"0.2,0.2,0.2"`,
//! `"640x480"`, `"dir:0,-1,0"`) and as a JSON value (a Python keyword's, or a batch file's).
//! Each value type says what it expects, so an error reads `yaw: expected a number, got
//! 'north'` whatever surface the value came through.
use serde::de::DeserializeOwned;
use serde::Serialize;
use serde_json::Value;
use std::path::PathBuf;

/// A type an option can hold.
pub trait OptionValue: Sized + Clone + PartialEq + Serialize + DeserializeOwned {
    /// What a value looks like, for messages and the reference (`a number`, `R,G,B`).
    const EXPECTED: &'static str;
    /// The command-line word's meaning.
    fn parse_word(s: &str) -> Result<Self, String>;
    /// The word that parses back to this value.
    fn to_word(&self) -> String;
    /// A JSON value: a string is read as the command-line word; anything else through serde.
    fn from_json(v: &Value) -> Result<Self, String> {
        match v {
            Value::String(s) => Self::parse_word(s),
            other => serde_json::from_value(other.clone())
                .map_err(|_| format!("expected {}, got {}", Self::EXPECTED, shown(other))),
        }
    }
    /// The names a choice can take (empty for other types): the CLI's possible values.
    fn choices() -> Vec<(&'static str, &'static str)> {
        Vec::new()
    }
}

/// A JSON value as a message shows it: strings in single quotes, like Python's repr.
pub(crate) fn shown(v: &Value) -> String {
    match v {
        Value::String(s) => format!("'{s}'"),
        other => other.to_string(),
    }
}

fn number<T: std::str::FromStr>(s: &str) -> Result<T, String> {
    s.trim()
        .parse()
        .map_err(|_| format!("expected a number, got '{s}'"))
}

impl OptionValue for f32 {
    const EXPECTED: &'static str = "a number";
    fn parse_word(s: &str) -> Result<Self, String> {
        number(s)
    }
    fn to_word(&self) -> String {
        self.to_string()
    }
}

macro_rules! whole_number {
    ($($t:ty),*) => {$(
        impl OptionValue for $t {
            const EXPECTED: &'static str = "a whole number";
            fn parse_word(s: &str) -> Result<Self, String> {
                s.trim().parse().map_err(|_| format!("expected a whole number, got '{s}'"))
            }
            fn to_word(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
whole_number!(u8, u32);

impl OptionValue for String {
    const EXPECTED: &'static str = "text";
    fn parse_word(s: &str) -> Result<Self, String> {
        Ok(s.to_string())
    }
    /// A whole number is its digits: `camera=1` is `--camera 1` (an index).
    fn from_json(v: &Value) -> Result<Self, String> {
        match v {
            Value::String(s) => Ok(s.clone()),
            Value::Number(n) if n.is_u64() => Ok(n.to_string()),
            other => Err(format!("expected {}, got {}", Self::EXPECTED, shown(other))),
        }
    }
    fn to_word(&self) -> String {
        self.clone()
    }
}

impl OptionValue for PathBuf {
    const EXPECTED: &'static str = "a path";
    fn parse_word(s: &str) -> Result<Self, String> {
        Ok(PathBuf::from(s))
    }
    fn to_word(&self) -> String {
        self.to_string_lossy().into_owned()
    }
}

impl OptionValue for bool {
    const EXPECTED: &'static str = "true or false";
    fn parse_word(s: &str) -> Result<Self, String> {
        match s {
            "true" | "1" | "yes" | "on" => Ok(true),
            "false" | "0" | "no" | "off" => Ok(false),
            _ => Err(format!("expected true or false, got '{s}'")),
        }
    }
    fn to_word(&self) -> String {
        self.to_string()
    }
}

/// Three comma-separated finite numbers, read in f64 as they always were (a colour's f32
/// is the f64's nearest, as before the options were typed: pictures do not move).
pub(crate) fn parse_triple(s: &str) -> Result<[f64; 3], String> {
    crate::light::parse_vec3(s).map(|v| v.to_array())
}

fn from_list<T: Copy + DeserializeOwned>(v: &Value, expected: &str) -> Result<[T; 3], String> {
    serde_json::from_value::<[T; 3]>(v.clone())
        .map_err(|_| format!("expected {expected}, got {}", shown(v)))
}

/// A colour R,G,B (display or linear values as the option says; not clamped here).
impl OptionValue for [f32; 3] {
    const EXPECTED: &'static str = "R,G,B";
    fn parse_word(s: &str) -> Result<Self, String> {
        parse_triple(s).map(|v| v.map(|c| c as f32))
    }
    fn to_word(&self) -> String {
        format!("{},{},{}", self[0], self[1], self[2])
    }
    fn from_json(v: &Value) -> Result<Self, String> {
        match v {
            Value::String(s) => Self::parse_word(s),
            // Through f64, as a word would be.
            other => from_list::<f64>(other, Self::EXPECTED).map(|a| a.map(|c| c as f32)),
        }
    }
}

/// A point X,Y,Z in the file's coordinates (f64: a model far from the origin keeps it).
impl OptionValue for [f64; 3] {
    const EXPECTED: &'static str = "X,Y,Z";
    fn parse_word(s: &str) -> Result<Self, String> {
        parse_triple(s)
    }
    fn to_word(&self) -> String {
        format!("{},{},{}", self[0], self[1], self[2])
    }
    fn from_json(v: &Value) -> Result<Self, String> {
        match v {
            Value::String(s) => Self::parse_word(s),
            other => {
                let a = from_list::<f64>(other, Self::EXPECTED)?;
                if a.iter().all(|x| x.is_finite()) {
                    Ok(a)
                } else {
                    Err("values must be finite".into())
                }
            }
        }
    }
}

/// A picture size WxH.
impl OptionValue for (u32, u32) {
    const EXPECTED: &'static str = "WxH";
    fn parse_word(s: &str) -> Result<Self, String> {
        super::parse::parse_size(s)
    }
    fn to_word(&self) -> String {
        format!("{}x{}", self.0, self.1)
    }
    fn from_json(v: &Value) -> Result<Self, String> {
        match v {
            Value::String(s) => Self::parse_word(s),
            other => serde_json::from_value(other.clone())
                .map_err(|_| format!("expected WxH or [width, height], got {}", shown(other))),
        }
    }
}

/// A byte count: a number, or with K, M, G (powers of 1024).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct Bytes(pub u64);

impl OptionValue for Bytes {
    const EXPECTED: &'static str = "bytes (1G, 512M, 1048576)";
    fn parse_word(s: &str) -> Result<Self, String> {
        super::parse::parse_bytes(s).map(Bytes)
    }
    fn to_word(&self) -> String {
        for (unit, shift) in [("G", 30), ("M", 20), ("K", 10)] {
            if self.0 >= 1 << shift && self.0.is_multiple_of(1 << shift) {
                return format!("{}{unit}", self.0 >> shift);
            }
        }
        self.0.to_string()
    }
}

/// Enums whose names are their words: declares the enum with `FromStr`, `Display`, serde
/// as the word, and [`OptionValue`] (its choices and their docs are the CLI's possible
/// values and the reference's list).
#[macro_export]
macro_rules! choice {
    (
        $(#[doc = $doc:literal])*
        $(#[derive($($extra:ident),*)])?
        pub enum $name:ident {
            $( $(#[doc = $vdoc:literal])* $variant:ident = $word:literal, )*
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq $($(, $extra)*)?)]
        pub enum $name {
            $( $(#[doc = $vdoc])* $variant, )*
        }

        impl $name {
            /// Every choice with its word and doc, in declaration order.
            pub const ALL: &'static [($name, &'static str, &'static str)] = &[
                $( ($name::$variant, $word, concat!($($vdoc),*)), )*
            ];
            /// The word of this choice.
            pub fn word(self) -> &'static str {
                match self { $( $name::$variant => $word, )* }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.word())
            }
        }

        impl std::str::FromStr for $name {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                $name::ALL
                    .iter()
                    .find(|(_, w, _)| *w == s)
                    .map(|(v, _, _)| *v)
                    .ok_or_else(|| {
                        let words: Vec<&str> = $name::ALL.iter().map(|(_, w, _)| *w).collect();
                        format!("expected one of {}, got '{s}'", words.join(", "))
                    })
            }
        }

        impl serde::Serialize for $name {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.word())
            }
        }

        impl<'de> serde::Deserialize<'de> for $name {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let s = <String as serde::Deserialize>::deserialize(d)?;
                s.parse().map_err(serde::de::Error::custom)
            }
        }

        impl $crate::options::OptionValue for $name {
            const EXPECTED: &'static str = concat!("one of" $(, " ", $word)*);
            fn parse_word(s: &str) -> Result<Self, String> {
                s.parse()
            }
            fn to_word(&self) -> String {
                self.word().to_string()
            }
            fn choices() -> Vec<(&'static str, &'static str)> {
                $name::ALL.iter().map(|(_, w, d)| (*w, d.trim())).collect()
            }
        }
    };
}

/// Types that are words on the command line and strings in JSON (`FromStr` + `Display`).
#[macro_export]
macro_rules! word_value {
    ($t:ty, $expected:literal) => {
        impl serde::Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.collect_str(self)
            }
        }
        impl<'de> serde::Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let s = <String as serde::Deserialize>::deserialize(d)?;
                s.parse().map_err(serde::de::Error::custom)
            }
        }
        impl $crate::options::OptionValue for $t {
            const EXPECTED: &'static str = $expected;
            fn parse_word(s: &str) -> Result<Self, String> {
                s.parse()
            }
            fn to_word(&self) -> String {
                self.to_string()
            }
        }
    };
}

// The scene crate's up axis: a word (`+Y`, `-Z`, ...) in options as in its own Display and
// FromStr (its Serialize and Deserialize are the scene crate's).
impl OptionValue for crate::scene::UpAxis {
    const EXPECTED: &'static str = "an axis: +Y, -Y, +X, -X, +Z or -Z";
    fn parse_word(s: &str) -> Result<Self, String> {
        s.parse()
    }
    fn to_word(&self) -> String {
        self.to_string()
    }
}
