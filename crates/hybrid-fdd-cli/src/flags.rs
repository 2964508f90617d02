//! What several commands' flags share: [`SignalFlags`] (how a recording is read: `diagnose`,
//! `train-classifier`, `close-loop`, `calibrate`), and the parsers of `--fault`
//! ([`FaultClassParser`], [`FaultLocationParser`]), which give the workspace's own fault types
//! (`bearing_model::FaultClass`, `bearing_model::FaultLocation`) with every spelling their
//! parsers accept, while `--help` lists the values and anything else is clap's error listing
//! them. The `--model` flags are `clap::ValueEnum`s beside their commands.

use std::ffi::OsStr;

use bearing_model::{FaultClass, FaultLocation, ModelError};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::error::ErrorKind;

/// How a recording is read: the channel, and the sampling rate of a recording that stores none.
/// One reader serves `diagnose`, `train-classifier`, `close-loop` and `calibrate`
/// ([`crate::diagnose::load`]), so the flags mean the same in each.
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct SignalFlags {
    /// Channel: of a CWRU `.mat` file DE, FE or BA; of another MAT-file a variable path
    /// (`bearing.gs`), a struct element's `Name` (`vibration_1`) or a last path component, by
    /// default its only vector of at least 1024 samples; of a text file a column name or number
    /// (1 = first; by default `accel`, the only column, or the second of `time,signal`).
    #[arg(long, default_value = "DE")]
    pub channel: String,
    /// Sampling rate, Hz, of recordings that store none (a text file without a time column, a
    /// MAT-file without a scalar rate beside its signal: `fs`, `sr`, `sample_rate`,
    /// `sampling_rate`, `SampleFrequency`, `SamplingFrequency`, `SampleRate`, `freq_sampling`, …,
    /// case and `_` ignored).
    /// A CWRU `.mat` file's rate, a stored rate and a time column's always win: for a single file, a `--fs` more than 0.1 % (`.mat`) or 1 % (time column)
    /// away from it is an error; in a directory batch (and `train-classifier`'s labelled list)
    /// `--fs` applies only to the files that store no rate.
    #[arg(long)]
    pub fs: Option<f64>,
}

impl Default for SignalFlags {
    /// The flags' defaults: channel `DE`, no rate.
    fn default() -> Self {
        Self {
            channel: "DE".to_string(),
            fs: None,
        }
    }
}

/// The fault class `text` (the argument `value` of `arg`) names, by bearing-model's own parser;
/// `Err(None)` when it names none, `Err(Some(e))` for a location named twice (the parser's own
/// reason, worded as clap words a value a parser refused).
fn fault_class(
    cmd: &clap::Command,
    arg: Option<&clap::Arg>,
    value: &OsStr,
    text: &str,
) -> Result<FaultClass, Option<clap::Error>> {
    match text.parse::<FaultClass>() {
        Ok(c) => Ok(c),
        Err(ModelError::RepeatedFaultLocation { .. }) => {
            let parse = |s: &str| s.parse::<FaultClass>();
            Err(Some(parse.parse_ref(cmd, arg, value).err().unwrap_or_else(
                || clap::Error::new(ErrorKind::ValueValidation).with_cmd(cmd),
            )))
        }
        Err(_) => Err(None),
    }
}

/// The fault location `text` names (any case, surrounding blanks ignored).
fn fault_location(text: &str) -> Option<FaultLocation> {
    let t = text.trim();
    FaultLocation::ALL
        .into_iter()
        .find(|l| l.name().eq_ignore_ascii_case(t))
}

/// Parse `value` of `arg` with `parse` (given the text; `Err(None)` when it names no value):
/// a value that is no UTF-8 text or names none is clap's error listing `names` ([`invalid`]).
fn parse_fault<T>(
    cmd: &clap::Command,
    arg: Option<&clap::Arg>,
    value: &OsStr,
    names: &[&'static str],
    parse: impl Fn(&clap::Command, Option<&clap::Arg>, &OsStr, &str) -> Result<T, Option<clap::Error>>,
) -> Result<T, clap::Error> {
    let text = value
        .to_str()
        .ok_or_else(|| invalid(cmd, arg, value, names))?;
    parse(cmd, arg, value, text).map_err(|e| e.unwrap_or_else(|| invalid(cmd, arg, value, names)))
}

/// `TypedValueParser` for the unit struct `$parser`, giving a `$value` (a type with `ALL` and
/// `name`) by `$parse` ([`parse_fault`]), `--help` listing every name.
macro_rules! fault_value_parser {
    ($parser:ty, $value:ty, $parse:expr) => {
        impl TypedValueParser for $parser {
            type Value = $value;

            fn parse_ref(
                &self,
                cmd: &clap::Command,
                arg: Option<&clap::Arg>,
                value: &OsStr,
            ) -> Result<$value, clap::Error> {
                parse_fault(cmd, arg, value, &<$value>::ALL.map(<$value>::name), $parse)
            }

            fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
                Some(Box::new(
                    <$value>::ALL
                        .into_iter()
                        .map(|v| PossibleValue::new(v.name())),
                ))
            }
        }
    };
}

/// `--fault` as a fault class: bearing-model's own parser ([`FaultClass`]'s `FromStr`), so
/// every spelling it accepts is taken (`none|normal|healthy`; any `+`, `-` or `,`-joined set of
/// `inner|ir`, `outer|or`, `ball|b`, in any order and case). `--help` lists the eight classes;
/// any other value is clap's error listing them (with the nearest as a tip); a location named
/// twice is the parser's one-line error.
#[derive(Clone, Copy, Debug, Default)]
pub struct FaultClassParser;

fault_value_parser!(FaultClassParser, FaultClass, fault_class);

/// `--fault` as one fault location: `inner`, `outer` or `ball` (any case, surrounding blanks
/// ignored), as bearing-model's [`FaultLocation::name`] spells them; anything else is clap's
/// error listing them.
#[derive(Clone, Copy, Debug, Default)]
pub struct FaultLocationParser;

fault_value_parser!(FaultLocationParser, FaultLocation, |_, _, _, t| {
    fault_location(t).ok_or(None)
});

/// clap's own error for a value outside `names` (`invalid value 'x' for '--flag <FLAG>'`, the
/// possible values, the nearest as a tip), as its value-enum parser gives it.
fn invalid(
    cmd: &clap::Command,
    arg: Option<&clap::Arg>,
    value: &OsStr,
    names: &[&'static str],
) -> clap::Error {
    PossibleValuesParser::new(names.iter().copied())
        .parse_ref(cmd, arg, value)
        .err()
        .unwrap_or_else(|| clap::Error::new(ErrorKind::InvalidValue).with_cmd(cmd))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn class(v: &str) -> Result<FaultClass, clap::Error> {
        let arg = clap::Arg::new("fault")
            .long("fault")
            .value_parser(FaultClassParser);
        clap::Command::new("t")
            .arg(arg)
            .try_get_matches_from(["t", "--fault", v])
            .map(|m| *m.get_one::<FaultClass>("fault").expect("given"))
    }

    #[test]
    fn every_spelling_the_model_accepts_is_taken() {
        for (v, want) in [
            ("none", FaultClass::None),
            ("normal", FaultClass::None),
            ("Healthy", FaultClass::None),
            ("IR", FaultClass::Inner),
            ("or+ir", FaultClass::InnerOuter),
            ("ball-outer", FaultClass::OuterBall),
            ("b,ir,OUTER", FaultClass::InnerOuterBall),
        ] {
            assert_eq!(class(v).unwrap(), want, "{v}");
        }
        for c in FaultClass::ALL {
            assert_eq!(class(c.name()).unwrap(), c);
        }
    }

    #[test]
    fn an_unknown_value_lists_the_classes_and_a_repeated_location_says_so() {
        let e = class("cage").unwrap_err();
        assert_eq!(e.kind(), ErrorKind::InvalidValue);
        let text = e.to_string();
        assert!(
            text.contains("inner+outer+ball") && text.contains("cage"),
            "{text}"
        );
        let e = class("inner+inner").unwrap_err();
        assert_eq!(e.kind(), ErrorKind::ValueValidation);
        assert!(e.to_string().contains("twice"), "{e}");
    }
}
