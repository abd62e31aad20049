//! The shapes an option takes on the command line, each a module of the same functions so
//! the declaration's macro can call `forms::$form::set_word(...)` for any field: the value
//! itself (`value`), an optional value (`maybe`), a repeated option (`repeat`), a
//! comma-separated list (`list`), a switch on (`flag`) or off (`noflag`), and `--ortho`'s
//! switch-or-value (`optional`).
use super::value::{shown, OptionValue};
use serde_json::Value;

/// How the command line spells an option.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Form {
    /// `--name VALUE`.
    Value,
    /// `--name VALUE`, repeatable; each adds one.
    Repeat,
    /// `--name A,B,C`, repeatable; each item adds one.
    List,
    /// `--name` alone turns it on.
    Flag,
    /// `--name` alone turns it off (`--no-shadows`).
    NoFlag,
    /// `--name` alone, or `--name VALUE`.
    Optional,
}

/// What the reference and the CLI's help say of an option's value: what it looks like, its
/// choices with their docs, its default as a word.
pub(crate) type Meta = (
    &'static str,
    Vec<(&'static str, &'static str)>,
    Option<String>,
);

fn flag_words(flag: &str, value: Option<String>) -> Vec<String> {
    std::iter::once(format!("--{flag}")).chain(value).collect()
}

pub(crate) mod value {
    use super::*;
    pub(crate) const FORM: Form = Form::Value;
    pub(crate) fn set_word<T: OptionValue>(slot: &mut T, s: &str) -> Result<(), String> {
        *slot = T::parse_word(s)?;
        Ok(())
    }
    pub(crate) fn set_json<T: OptionValue>(slot: &mut T, v: &Value) -> Result<(), String> {
        *slot = T::from_json(v)?;
        Ok(())
    }
    pub(crate) fn words<T: OptionValue>(v: &T, d: &T, flag: &str) -> Vec<String> {
        if v == d {
            Vec::new()
        } else {
            all_words(v, flag)
        }
    }
    pub(crate) fn all_words<T: OptionValue>(v: &T, flag: &str) -> Vec<String> {
        flag_words(flag, Some(v.to_word()))
    }
    pub(crate) fn meta<T: OptionValue>(d: &T) -> Meta {
        (T::EXPECTED, T::choices(), Some(d.to_word()))
    }
}

pub(crate) mod maybe {
    use super::*;
    pub(crate) const FORM: Form = Form::Value;
    pub(crate) fn set_word<T: OptionValue>(slot: &mut Option<T>, s: &str) -> Result<(), String> {
        *slot = Some(T::parse_word(s)?);
        Ok(())
    }
    pub(crate) fn set_json<T: OptionValue>(slot: &mut Option<T>, v: &Value) -> Result<(), String> {
        *slot = match v {
            Value::Null => None,
            v => Some(T::from_json(v)?),
        };
        Ok(())
    }
    pub(crate) fn words<T: OptionValue>(v: &Option<T>, d: &Option<T>, flag: &str) -> Vec<String> {
        if v == d {
            Vec::new()
        } else {
            all_words(v, flag)
        }
    }
    pub(crate) fn all_words<T: OptionValue>(v: &Option<T>, flag: &str) -> Vec<String> {
        v.iter()
            .flat_map(|x| flag_words(flag, Some(x.to_word())))
            .collect()
    }
    pub(crate) fn meta<T: OptionValue>(d: &Option<T>) -> Meta {
        (T::EXPECTED, T::choices(), d.as_ref().map(T::to_word))
    }
}

pub(crate) mod repeat {
    use super::*;
    pub(crate) const FORM: Form = Form::Repeat;
    pub(crate) fn set_word<T: OptionValue>(slot: &mut Vec<T>, s: &str) -> Result<(), String> {
        slot.push(T::parse_word(s)?);
        Ok(())
    }
    /// A list replaces the option's values; one value is a list of one.
    pub(crate) fn set_json<T: OptionValue>(slot: &mut Vec<T>, v: &Value) -> Result<(), String> {
        *slot = match v {
            Value::Null => Vec::new(),
            Value::Array(items) if !items.is_empty() && !items.iter().all(Value::is_number) => {
                items.iter().map(T::from_json).collect::<Result<_, _>>()?
            }
            Value::Array(items) if items.is_empty() => Vec::new(),
            one => vec![T::from_json(one)?],
        };
        Ok(())
    }
    pub(crate) fn words<T: OptionValue>(v: &[T], d: &[T], flag: &str) -> Vec<String> {
        if v == d {
            return Vec::new();
        }
        all_words(v, flag)
    }
    pub(crate) fn all_words<T: OptionValue>(v: &[T], flag: &str) -> Vec<String> {
        v.iter()
            .flat_map(|x| flag_words(flag, Some(x.to_word())))
            .collect()
    }
    pub(crate) fn meta<T: OptionValue>(_: &[T]) -> Meta {
        (T::EXPECTED, T::choices(), None)
    }
}

pub(crate) mod list {
    use super::*;
    pub(crate) const FORM: Form = Form::List;
    pub(crate) fn set_word<T: OptionValue>(slot: &mut Vec<T>, s: &str) -> Result<(), String> {
        for item in s.split(',') {
            slot.push(T::parse_word(item)?);
        }
        Ok(())
    }
    pub(crate) fn set_json<T: OptionValue>(slot: &mut Vec<T>, v: &Value) -> Result<(), String> {
        match v {
            Value::Array(items) => {
                *slot = items.iter().map(T::from_json).collect::<Result<_, _>>()?
            }
            Value::String(s) => {
                slot.clear();
                set_word(slot, s)?
            }
            Value::Null => slot.clear(),
            other => return Err(format!("expected a list of names, got {}", shown(other))),
        }
        Ok(())
    }
    pub(crate) fn words<T: OptionValue>(v: &[T], d: &[T], flag: &str) -> Vec<String> {
        if v == d {
            return Vec::new();
        }
        all_words(v, flag)
    }
    pub(crate) fn all_words<T: OptionValue>(v: &[T], flag: &str) -> Vec<String> {
        if v.is_empty() {
            return Vec::new();
        }
        let items: Vec<String> = v.iter().map(T::to_word).collect();
        flag_words(flag, Some(items.join(",")))
    }
    pub(crate) fn meta<T: OptionValue>(_: &[T]) -> Meta {
        (T::EXPECTED, T::choices(), None)
    }
}

fn json_bool(v: &Value) -> Result<bool, String> {
    match v {
        Value::Bool(b) => Ok(*b),
        Value::Null => Ok(false),
        Value::String(s) => bool::parse_word(s),
        other => Err(format!("expected true or false, got {}", shown(other))),
    }
}

pub(crate) mod flag {
    use super::*;
    pub(crate) const FORM: Form = Form::Flag;
    pub(crate) fn set_word(slot: &mut bool, _: &str) -> Result<(), String> {
        *slot = true;
        Ok(())
    }
    pub(crate) fn set_json(slot: &mut bool, v: &Value) -> Result<(), String> {
        *slot = json_bool(v)?;
        Ok(())
    }
    pub(crate) fn words(v: &bool, _: &bool, flag: &str) -> Vec<String> {
        all_words(v, flag)
    }
    /// A switch has no word for its off state: none.
    pub(crate) fn all_words(v: &bool, flag: &str) -> Vec<String> {
        if *v {
            flag_words(flag, None)
        } else {
            Vec::new()
        }
    }
    pub(crate) fn meta(_: &bool) -> Meta {
        ("", Vec::new(), None)
    }
}

/// A setting that is on unless `--no-...` is given; the keyword `no_shadows=True` turns it
/// off as the flag does.
pub(crate) mod noflag {
    use super::*;
    pub(crate) const FORM: Form = Form::NoFlag;
    pub(crate) fn set_word(slot: &mut bool, _: &str) -> Result<(), String> {
        *slot = false;
        Ok(())
    }
    /// [`flag`]'s, of the switch's opposite.
    pub(crate) fn set_json(slot: &mut bool, v: &Value) -> Result<(), String> {
        flag::set_json(slot, v)?;
        *slot = !*slot;
        Ok(())
    }
    pub(crate) fn words(v: &bool, d: &bool, name: &str) -> Vec<String> {
        flag::words(&!*v, &!*d, name)
    }
    pub(crate) fn all_words(v: &bool, name: &str) -> Vec<String> {
        flag::all_words(&!*v, name)
    }
    pub(crate) use super::flag::meta;
}

/// `--ortho` (fit the model) or `--ortho H`.
pub(crate) mod optional {
    use super::*;
    use crate::options::Ortho;
    pub(crate) const FORM: Form = Form::Optional;
    pub(crate) fn set_word(slot: &mut Option<Ortho>, s: &str) -> Result<(), String> {
        *slot = Some(if s.is_empty() {
            Ortho::Fit
        } else {
            Ortho::Height(f32::parse_word(s)?)
        });
        Ok(())
    }
    pub(crate) fn set_json(slot: &mut Option<Ortho>, v: &Value) -> Result<(), String> {
        *slot = match v {
            Value::Null | Value::Bool(false) => None,
            Value::Bool(true) => Some(Ortho::Fit),
            Value::String(s) if s == "fit" => Some(Ortho::Fit),
            Value::String(s) => Some(Ortho::Height(f32::parse_word(s)?)),
            Value::Number(_) => Some(Ortho::Height(f32::from_json(v)?)),
            other => {
                return Err(format!(
                    "expected true (fit the model) or a height, got {}",
                    shown(other)
                ))
            }
        };
        Ok(())
    }
    pub(crate) fn words(v: &Option<Ortho>, _: &Option<Ortho>, flag: &str) -> Vec<String> {
        all_words(v, flag)
    }
    pub(crate) fn all_words(v: &Option<Ortho>, flag: &str) -> Vec<String> {
        match v {
            None => Vec::new(),
            Some(Ortho::Fit) => flag_words(flag, None),
            Some(Ortho::Height(h)) => flag_words(flag, Some(h.to_string())),
        }
    }
    pub(crate) fn meta(_: &Option<Ortho>) -> Meta {
        ("a height", Vec::new(), None)
    }
}
