//! A record's [`FaultLabel`] in `bearing-model`'s fault vocabulary (feature `bearing-model`):
//! its [`FaultClass`] and its [`FaultLocation`] (`None` for a normal record), and back.
//!
//! ```
//! use bearing_data::FaultLabel;
//! use bearing_model::{FaultClass, FaultLocation};
//! assert_eq!(FaultClass::from(FaultLabel::OuterRace), FaultClass::Outer);
//! assert_eq!(Option::<FaultLocation>::from(FaultLabel::Normal), None);
//! assert_eq!(FaultLabel::from(FaultLocation::Ball), FaultLabel::Ball);
//! ```

use bearing_model::{FaultClass, FaultLocation};

use crate::FaultLabel;

impl From<FaultLabel> for Option<FaultLocation> {
    /// Where the record's fault is; `None` for a normal record.
    fn from(label: FaultLabel) -> Self {
        match label {
            FaultLabel::Normal => None,
            FaultLabel::InnerRace => Some(FaultLocation::Inner),
            FaultLabel::Ball => Some(FaultLocation::Ball),
            FaultLabel::OuterRace => Some(FaultLocation::Outer),
        }
    }
}

impl From<FaultLabel> for FaultClass {
    /// The record's class among the eight (`None` for a normal record, else a single location).
    fn from(label: FaultLabel) -> Self {
        Option::<FaultLocation>::from(label).map_or(FaultClass::None, FaultLocation::class)
    }
}

impl From<FaultLocation> for FaultLabel {
    /// The label of a record with a fault at `location`.
    fn from(location: FaultLocation) -> Self {
        match location {
            FaultLocation::Inner => FaultLabel::InnerRace,
            FaultLocation::Outer => FaultLabel::OuterRace,
            FaultLocation::Ball => FaultLabel::Ball,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_round_trip_and_spell_as_the_model() {
        for label in [
            FaultLabel::Normal,
            FaultLabel::InnerRace,
            FaultLabel::Ball,
            FaultLabel::OuterRace,
        ] {
            let location = Option::<FaultLocation>::from(label);
            assert_eq!(location.map(FaultLabel::from).unwrap_or(label), label);
            // the manifest's spelling is the model's (`none` for a normal record's class)
            let class = FaultClass::from(label);
            match location {
                Some(l) => assert_eq!((l.name(), class.name()), (label.as_str(), label.as_str())),
                None => assert_eq!(class.name(), "none"),
            }
        }
    }
}
