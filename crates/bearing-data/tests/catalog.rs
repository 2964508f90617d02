//! The embedded catalog (no disk access) and data-directory resolution.

use std::collections::HashSet;

use bearing_data::{
    BearingMake, Channels, DataError, DataLocation, FaultLabel, OuterPosition, Query, SensorEnd,
    catalog, entry,
};

#[test]
fn catalog_counts_and_unique_numbers() {
    let all: Vec<_> = catalog().collect();
    // 74 files in the shared copy (README "Contents") + 3 normal + 39 48 kHz files it lacks.
    assert_eq!(all.iter().filter(|e| e.in_shared_copy).count(), 74);
    assert_eq!(all.iter().filter(|e| !e.in_shared_copy).count(), 42);
    let numbers: HashSet<u32> = all.iter().map(|e| e.number).collect();
    assert_eq!(numbers.len(), all.len());
    // Gaps in CWRU's numbering.
    assert!(entry(157).is_none() && entry(216).is_none());
    // 12 absent records carry a SHA-256 pinned from the official server.
    assert_eq!(
        all.iter()
            .filter(|e| !e.in_shared_copy && e.sha256.is_some())
            .count(),
        12
    );
    assert!(all.iter().all(|e| e.sha256.is_none_or(|s| s.len() == 64)));
    // Each class at 48 kHz has all four loads once the absent files are counted.
    let q48 = Query::new()
        .fs_hz(48_000)
        .fault(FaultLabel::OuterRace)
        .diameter_in(0.021);
    assert_eq!(q48.run().len(), 12);
}

#[test]
fn quirks_are_in_the_catalog() {
    assert_eq!(entry(174).unwrap().variable, 173);
    assert_eq!(entry(3001).unwrap().variable, 56);
    assert_eq!(entry(3004).unwrap().variable, 59);
    assert_eq!(entry(3005).unwrap().variable, 48);
    assert_eq!(entry(3008).unwrap().variable, 51);
    assert_eq!(entry(99).unwrap().variable, 99);
    let e = entry(3002).unwrap();
    assert_eq!(e.channels, Channels::DE);
    assert_eq!(e.stored_rpm, None);
    assert_eq!(e.bearing(), BearingMake::Ntn6205Equivalent);
    assert_eq!(entry(97).unwrap().channels, Channels::DE_FE);
    assert_eq!(entry(97).unwrap().fs_hz, 48_000);
    assert_eq!(entry(105).unwrap().channels, Channels::DE_FE_BA);
    assert_eq!(entry(108).unwrap().stored_rpm, Some(1721));
    assert_eq!(entry(217).unwrap().load_hp, 3);
    assert_eq!(
        entry(158).unwrap().outer_position,
        Some(OuterPosition::Opposite12)
    );
    assert_eq!(entry(158).unwrap().class_name(), "OR007@12");
    assert_eq!(entry(100).unwrap().nominal_rpm, 1730);
}

#[test]
fn query_from_the_issue() {
    // "all 12 kHz drive-end 0.014 in records at 2 hp"
    let hits: Vec<u32> = Query::new()
        .fs_hz(12_000)
        .fault_end(SensorEnd::DriveEnd)
        .diameter_in(0.014)
        .load_hp(2)
        .run()
        .iter()
        .map(|e| e.number)
        .collect();
    assert_eq!(hits, vec![171, 187, 199]);
    // Normal records have no fault end.
    assert!(
        Query::new()
            .fault(FaultLabel::Normal)
            .fault_end(SensorEnd::DriveEnd)
            .run()
            .is_empty()
    );
    assert_eq!(Query::new().fault(FaultLabel::Normal).run().len(), 4);
    assert_eq!(Query::new().fs_hz(12_000).run().len(), 60);
    assert!(Query::new().diameter_in(f64::NAN).run().is_empty());
    assert_eq!(entry(171).unwrap().fault_diameter_in(), Some(0.014));
}

#[test]
fn data_location_resolution() {
    let root = std::env::temp_dir()
        .join("bearing-data-no-such-workspace")
        .join("ws");
    let loc = DataLocation::resolve(None, &root).unwrap();
    assert!(matches!(loc, DataLocation::Absent { .. }));
    assert_eq!(loc.require(false).unwrap(), None);
    // CI=true: absent data is an error, not a skip.
    assert!(matches!(
        loc.require(true),
        Err(DataError::DataAbsent { .. })
    ));
    assert!(loc.required().is_err());
    let bad = root.join("nope");
    assert!(matches!(
        DataLocation::resolve(Some(&bad), &root),
        Err(DataError::DataDirNotFound { .. })
    ));
    let here = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let found = DataLocation::resolve(Some(here), &root).unwrap();
    assert_eq!(found.path(), Some(here));
    assert_eq!(found.require(true).unwrap(), Some(here));
}

/// Code written against the label's former name, `FaultLocation`, still compiles (with a
/// deprecation warning) and means the same type.
#[test]
fn former_label_name_still_compiles() {
    #[allow(deprecated)]
    let old: bearing_data::FaultLocation = bearing_data::FaultLocation::InnerRace;
    assert_eq!(old, FaultLabel::InnerRace);
    assert_eq!(old.as_str(), "inner");
    assert_eq!(FaultLabel::parse("outer"), Some(FaultLabel::OuterRace));
}

/// Code written against the bearing make's former name, `Bearing`, still compiles (with a
/// deprecation warning) and means the same type.
#[test]
fn former_bearing_make_name_still_compiles() {
    #[allow(deprecated)]
    let old: bearing_data::Bearing = bearing_data::Bearing::Skf6205;
    assert_eq!(old, BearingMake::Skf6205);
}
