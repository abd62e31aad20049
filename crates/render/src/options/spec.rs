//! The one declaration of every option ([`declare_options!`]) and what is made from it: the
//! typed groups with serde, [`Options`](super::Options), and a table of [`OptionSpec`]s (name,
//! group, doc, form, value type, default, setters) from which the command line's arguments,
//! the keyword arguments, the words of a reproducing command line and the reference docs
//! are all derived, so an option is named, checked and documented once.
use super::forms::Form;
use serde_json::Value;

/// One option, as every surface sees it.
pub struct OptionSpec {
    /// The long command-line name (`shadow-bias`); the Python keyword is the same with `_`.
    pub name: &'static str,
    /// Where it lives in [`Options`](super::Options) and in its JSON form (`shadow.bias`).
    pub path: &'static str,
    pub doc: &'static str,
    pub form: Form,
    /// What a value looks like (`a number`, `R,G,B`); empty for switches.
    pub(crate) expected: &'static str,
    /// A choice's words and their docs.
    pub choices: Vec<(&'static str, &'static str)>,
    /// The default as a command-line word (None: unset by default, or a switch).
    pub default: Option<String>,
    pub(crate) set_word: fn(&mut super::Options, &str) -> Result<(), String>,
    pub(super) set_json: fn(&mut super::Options, &Value) -> Result<(), String>,
    /// The words that give this option's value (none where it is the default's).
    pub(super) words: fn(&super::Options, &super::Options) -> Vec<String>,
    /// The words that give this option's value, the default's too (an unset value or a
    /// switch in its usual state has none).
    pub(super) all_words: fn(&super::Options) -> Vec<String>,
    /// This option's own checks (ranges); checks across options are in `validate`.
    pub(super) check: fn(&super::Options) -> Result<(), String>,
}

impl OptionSpec {
    /// The Python keyword.
    pub(crate) fn keyword(&self) -> String {
        self.name.replace('-', "_")
    }

    /// The doc's first sentence line, for short help.
    pub fn summary(&self) -> &'static str {
        self.doc.lines().next().unwrap_or_default()
    }

    /// Sets this option from a command-line word (the value; empty for a switch).
    pub fn set(&self, o: &mut super::Options, word: &str) -> Result<(), String> {
        (self.set_word)(o, word)
    }

    /// The command-line words of this option's value in `o`, written even where it is the
    /// default (`["--tonemap", "khronos-neutral"]`), so a text can state what a picture was
    /// drawn with; none for an unset value or a switch in its usual state.
    pub fn value_words(&self, o: &super::Options) -> Vec<String> {
        (self.all_words)(o)
    }

    /// The option group it belongs to (`shadow` for `shadow.bias`).
    pub fn group(&self) -> &'static str {
        self.path.split('.').next().unwrap_or_default()
    }
}

/// An option that cannot be used: which one (its name as the surface spells it is added by
/// the surface) and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{name}: {message}")]
pub struct OptionError {
    /// The option's name (`yaw`, `shadow-bias`) or, for a JSON key, its path.
    pub(crate) name: String,
    pub(crate) message: String,
}

impl OptionError {
    pub fn new(name: impl Into<String>, message: impl Into<String>) -> OptionError {
        OptionError {
            name: name.into(),
            message: message.into(),
        }
    }

    /// As the command line says it: `--yaw: expected a number, got 'north'`.
    pub fn on_command_line(&self) -> String {
        if self.name.is_empty() || self.name == "model" {
            self.message.clone()
        } else {
            format!("--{}: {}", self.name, self.message)
        }
    }

    /// As a keyword argument says it: `shadow_bias: ...`.
    pub fn as_keyword(&self) -> String {
        if self.name.is_empty() {
            self.message.clone()
        } else {
            format!("{}: {}", self.name.replace('-', "_"), self.message)
        }
    }
}

impl From<OptionError> for crate::Error {
    fn from(e: OptionError) -> crate::Error {
        crate::Error::Usage(e.on_command_line())
    }
}

/// Declares the option groups (structs with serde, defaults), [`Options`](super::Options)
/// and the spec table. Each field: doc comments, `name: Type = default, "cli-name" form`,
/// optionally `, check = f` where `f(&Type) -> Result<(), String>`.
macro_rules! declare_options {
    (
        $(
            $(#[doc = $gdoc:literal])*
            $group:ident : $Group:ident {
                $(
                    $(#[doc = $doc:literal])*
                    $field:ident : $ty:ty = $default:expr, $flag:literal $form:ident
                        $(, check = $check:expr)?;
                )*
            }
        )*
    ) => {
        $(
            $(#[doc = $gdoc])*
            #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
            #[serde(default, deny_unknown_fields)]
            pub struct $Group {
                $( $(#[doc = $doc])* pub $field: $ty, )*
            }

            impl Default for $Group {
                fn default() -> Self {
                    $Group { $( $field: $default, )* }
                }
            }
        )*

        /// Everything one picture depends on, as typed values in groups (f3d's options tree
        /// is the model). Every surface makes one: the command line (`glview ...`), a batch
        /// line, Python keywords, the JSON in a PNG's text.
        ///
        /// ```
        /// let mut o = glview_render::Options::default();
        /// o.camera.yaw = 45.0;
        /// o.picture.size = (64, 48);
        /// o.validate().unwrap();
        /// let json = serde_json::to_string(&o).unwrap();
        /// assert_eq!(serde_json::from_str::<glview_render::Options>(&json).unwrap(), o);
        /// ```
        #[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(default, deny_unknown_fields)]
        pub struct Options {
            $( $(#[doc = $gdoc])* pub $group: $Group, )*
        }

        fn build_specs() -> Vec<OptionSpec> {
            use $crate::options::forms;
            use $crate::options::OptionSpec;
            let d = Options::default();
            let mut specs = Vec::new();
            $($(
                let (expected, choices, default) = forms::$form::meta(&d.$group.$field);
                specs.push(OptionSpec {
                    name: $flag,
                    path: concat!(stringify!($group), ".", stringify!($field)),
                    doc: concat!($($doc, "\n"),*),
                    form: forms::$form::FORM,
                    expected,
                    choices,
                    default,
                    set_word: |o, s| forms::$form::set_word(&mut o.$group.$field, s),
                    set_json: |o, v| forms::$form::set_json(&mut o.$group.$field, v),
                    words: |o, d| forms::$form::words(&o.$group.$field, &d.$group.$field, $flag),
                    all_words: |o| forms::$form::all_words(&o.$group.$field, $flag),
                    check: |_o| {
                        $( return ($check)(&_o.$group.$field); )?
                        #[allow(unreachable_code)]
                        Ok(())
                    },
                });
            )*)*
            specs
        }
    };
}
pub(super) use declare_options;
