//! The unit of a recording's samples, as the input layer knows it: the workspace's one unit type
//! (the command's loaders build it; `diagnose` and `close-loop`/`calibrate` reports state it; a
//! machine model keeps its [`SampleUnit::code`]).

use serde::{Deserialize, Serialize};

use crate::error::{DataError, Result};

/// What CWRU's `.mat` samples are: the data README states no unit; they are commonly read as g.
pub const CWRU_STATEMENT: &str =
    "file units (CWRU accelerometer data; the data README states no unit, commonly read as g)";

/// The unit of a recording's samples: a short code that machine models record and compare, and
/// the statement reports print.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct SampleUnit {
    /// One of [`SampleUnit::CODES`]: `g`, `m/s^2` or `unknown` (a machine model's `units`).
    pub code: String,
    /// The unit as far as it is known, for reports: `g`, `m/s²`,
    /// `file units (CWRU …, commonly read as g)`, `CSV units (not stated in the file)`, `unknown`.
    pub statement: String,
}

impl SampleUnit {
    /// The accepted codes (`--units`, a machine model's `units`).
    pub const CODES: [&'static str; 3] = ["g", "m/s^2", "unknown"];

    /// The unit of a code, stated as the code says (`m/s^2` is stated `m/s²`).
    ///
    /// # Errors
    /// [`DataError::UnknownUnit`] for a code not in [`SampleUnit::CODES`].
    pub fn from_code(code: &str) -> Result<Self> {
        let statement = match code {
            "g" => "g",
            "m/s^2" => "m/s²",
            "unknown" => "unknown",
            _ => {
                return Err(DataError::UnknownUnit {
                    code: code.to_string(),
                });
            }
        };
        Ok(Self {
            code: code.to_string(),
            statement: statement.to_string(),
        })
    }

    /// A unit of code `code` with its own statement (what the input layer knows about it).
    ///
    /// # Errors
    /// [`DataError::UnknownUnit`] for a code not in [`SampleUnit::CODES`].
    pub fn stated(code: &str, statement: &str) -> Result<Self> {
        Ok(Self {
            statement: statement.to_string(),
            ..Self::from_code(code)?
        })
    }

    /// Not stated anywhere.
    pub fn unknown() -> Self {
        Self {
            code: "unknown".into(),
            statement: "unknown".into(),
        }
    }

    /// A CWRU record's samples: code `g`, stated as [`CWRU_STATEMENT`].
    pub fn cwru() -> Self {
        Self {
            code: "g".into(),
            statement: CWRU_STATEMENT.into(),
        }
    }

    /// Whether the code is `unknown`.
    pub fn is_unknown(&self) -> bool {
        self.code == "unknown"
    }

    /// The statement without its parenthesis, to follow a number: `g`, `m/s²`, `file units`,
    /// `CSV units`; `unknown units` for a bare `unknown`.
    pub fn label(&self) -> &str {
        let head = self
            .statement
            .split_once(" (")
            .map_or(self.statement.as_str(), |(head, _)| head)
            .trim();
        if head == "unknown" {
            "unknown units"
        } else {
            head
        }
    }
}

impl Default for SampleUnit {
    /// [`SampleUnit::unknown`] (what a report written before units were stated holds).
    fn default() -> Self {
        Self::unknown()
    }
}

impl std::fmt::Display for SampleUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.statement)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_statements_and_labels() {
        for code in SampleUnit::CODES {
            assert_eq!(SampleUnit::from_code(code).unwrap().code, code);
        }
        assert_eq!(SampleUnit::from_code("m/s^2").unwrap().label(), "m/s²");
        assert_eq!(SampleUnit::cwru().code, "g");
        assert_eq!(SampleUnit::cwru().label(), "file units");
        assert!(SampleUnit::default().is_unknown());
        assert_eq!(SampleUnit::unknown().label(), "unknown units");
        let e = SampleUnit::from_code("mm/s").unwrap_err();
        assert!(matches!(e, DataError::UnknownUnit { .. }));
        assert!(!e.to_string().contains('\n'));
        assert!(SampleUnit::stated("V", "volts").is_err());
    }
}
