//! The bearing catalogue: every row physical, its orders against published values, lookups with
//! the decorations users type, and the error for a designation it does not hold.

use bearing_model::catalog::{self, entries, lookup, nearest, normalise};
use bearing_model::{Bearing, BearingGeometry, BearingSpec, ModelError};

/// Relative difference.
fn rel(got: f64, want: f64) -> f64 {
    ((got - want) / want).abs()
}

#[test]
fn every_row_validates_and_gives_physical_orders() {
    assert!(entries().len() >= 18);
    for e in entries() {
        let g = e.geometry();
        g.validate()
            .unwrap_or_else(|err| panic!("{}: {err}", e.designation));
        assert_eq!(g.name, e.name, "{}", e.designation);
        let o = e.orders();
        let n = e.n_elements as f64;
        // contact-angle-adjusted kinematics: r = d/D·cos α, BPFO = n/2 (1 − r), BPFI = n/2 (1 + r)
        assert!((o.bpfo + o.bpfi - n).abs() < 1e-12, "{}", e.designation);
        assert!((o.bpfo - n * o.ftf).abs() < 1e-12, "{}", e.designation);
        assert!(
            0.0 < o.ftf && o.ftf < 0.5,
            "{}: ftf {}",
            e.designation,
            o.ftf
        );
        assert!(o.bpfo < o.bpfi, "{}", e.designation);
        assert_eq!(o.ball_defect, 2.0 * o.ball_spin, "{}", e.designation);
        // the balls fill 40–65 % of the pitch circle: a typo in d, D or n shows here
        let fill = n * g.ball_diameter_m / (std::f64::consts::PI * g.pitch_diameter_m);
        assert!(
            (0.4..0.65).contains(&fill),
            "{}: fill {fill}",
            e.designation
        );
        assert!(!e.source.is_empty() && !e.source.contains('\n'));
        // the designation finds its own row, named by the catalogue, with its geometry
        let s = BearingSpec::parse(e.designation).unwrap();
        assert_eq!(s.name, e.name);
        assert_eq!(s.given, e.designation);
        assert_eq!(s.geometry, Some(g));
        assert_eq!(s.orders, o);
        assert!(s.warnings().is_empty());
    }
}

#[test]
fn no_designation_or_alias_is_listed_twice() {
    let mut seen: Vec<(String, &str)> = Vec::new();
    for e in entries() {
        let keys = [e.designation, e.name]
            .into_iter()
            .chain(e.aliases.iter().copied());
        for k in keys {
            let n = normalise(k);
            assert!(!n.is_empty(), "{}: empty key", e.designation);
            if let Some((_, other)) = seen.iter().find(|(s, o)| *s == n && *o != e.designation) {
                panic!("{k} names both {other} and {}", e.designation);
            }
            seen.push((n, e.designation));
            // and every key finds its own row (no other row's key plus a suffix takes it)
            assert_eq!(lookup(k).unwrap().designation, e.designation, "{k}");
        }
    }
}

#[test]
fn the_cwru_rows_are_the_built_in_bearings_unchanged() {
    // regression fixtures elsewhere in the repository depend on these exact numbers
    for (text, b, full) in [
        ("6205", Bearing::Skf6205, "SKF 6205-2RS JEM"),
        ("6203", Bearing::Skf6203, "SKF 6203-2RS JEM"),
    ] {
        let e = lookup(text).unwrap();
        assert_eq!(e.builtin, Some(b));
        assert_eq!(e.name, full);
        let g = b.geometry();
        assert_eq!(e.geometry(), g);
        // the row's own numbers are the built-in geometry to the bit
        assert_eq!(e.element_diameter.metres(), g.ball_diameter_m);
        assert_eq!(e.pitch_diameter.metres(), g.pitch_diameter_m);
        assert_eq!(e.contact_angle_deg.to_radians(), g.contact_angle_rad);
        assert_eq!(e.n_elements, g.n_balls);
        // the spec is what `6205` / `6203` gave before the catalogue
        let s = BearingSpec::parse(text).unwrap();
        let before = BearingSpec {
            given: text.to_string(),
            ..BearingSpec::builtin(b)
        };
        assert_eq!(s, before);
        assert_eq!(s.name, full);
        assert_eq!(s.echo(), format!("{text} ({full})"));
    }
    assert_eq!(
        lookup("6205").unwrap().geometry(),
        BearingGeometry::skf_6205()
    );
    assert_eq!(
        lookup("6203").unwrap().geometry(),
        BearingGeometry::skf_6203()
    );
    // the names `Bearing` always took still give the built-in bearings
    for (text, b) in [
        ("6205", Bearing::Skf6205),
        ("skf6205", Bearing::Skf6205),
        ("DE", Bearing::Skf6205),
        ("drive-end", Bearing::Skf6205),
        ("6203", Bearing::Skf6203),
        ("SKF6203", Bearing::Skf6203),
        ("fe", Bearing::Skf6203),
        ("Fan-End", Bearing::Skf6203),
        ("SKF 6205-2RS JEM", Bearing::Skf6205),
        ("6205-2RS", Bearing::Skf6205),
    ] {
        assert_eq!(text.parse::<Bearing>(), Ok(b), "{text}");
    }
    // a catalogue bearing that is not built in is said to be so
    assert_eq!(
        "uc204".parse::<Bearing>(),
        Err(ModelError::NotBuiltIn {
            given: "uc204".into(),
            name: "UC204"
        })
    );
}

#[test]
fn cwru_6205_orders_match_the_cwru_table() {
    // CWRU Bearing Data Center, drive-end bearing table (× shaft speed); its "BSF" is the
    // ball-defect rate, twice the ball spin. Tolerance 1e-4: the table's rounding.
    let o = lookup("6205").unwrap().orders();
    for (got, want) in [
        (o.bpfi, 5.4152),
        (o.bpfo, 3.5848),
        (o.ftf, 0.39828),
        (o.ball_defect, 4.7135),
    ] {
        assert!(rel(got, want) < 1e-4, "{got} vs {want}");
    }
}

#[test]
fn mfpt_nice_orders_match_the_mfpt_files() {
    // MFPT data files (data/mfpt/README.md): BPFO 81.12 Hz, BPFI 118.88 Hz at a 25 Hz shaft,
    // stored to 0.01 Hz: within half of that.
    let o = lookup("nice").unwrap().orders().at(25.0);
    assert!((o.bpfo - 81.12).abs() <= 0.005, "{}", o.bpfo);
    assert!((o.bpfi - 118.88).abs() <= 0.005, "{}", o.bpfi);
    // their BSF 63.91 Hz is the ball spin (ours 63.86 Hz, 0.07 % off), not the ball-defect rate
    assert!(rel(o.ball_spin, 63.91) < 2e-3, "{}", o.ball_spin);
}

#[test]
fn ims_za_2115_orders_match_the_ims_readme() {
    // IMS bearing data README (NASA PCoE; Qiu et al. 2006): BPFO 236.4 Hz, BPFI 296.9 Hz at
    // 2000 rpm, to 0.1 Hz: within half of that.
    let o = lookup("ZA-2115").unwrap().orders().at(2000.0 / 60.0);
    assert!((o.bpfo - 236.4).abs() <= 0.05, "{}", o.bpfo);
    assert!((o.bpfi - 296.9).abs() <= 0.05, "{}", o.bpfi);
}

#[test]
fn xjtu_sy_uer204_orders_match_the_xjtu_sy_paper() {
    // Wang, Lei, Li & Li (IEEE Trans. Reliab. 2020), XJTU-SY characteristic frequencies at
    // 2100 rpm (35 Hz), to 0.01 Hz: within half of that. Their BSF is the ball spin.
    let o = lookup("LDK UER204").unwrap().orders().at(35.0);
    for (got, want) in [
        (o.bpfo, 107.91),
        (o.bpfi, 172.09),
        (o.ftf, 13.49),
        (o.ball_spin, 72.33),
    ] {
        assert!((got - want).abs() <= 0.005, "{got} vs {want}");
    }
}

#[test]
fn ottawa_er_16k_orders_match_the_data_paper() {
    // Huang & Baddour (Data in Brief 21, 2018): BPFI 5.43 × fr, BPFO 3.57 × fr, to 0.01
    // (half a unit of the last digit: 0.005).
    let o = lookup("ER16K").unwrap().orders();
    assert!((o.bpfi - 5.43).abs() <= 0.005, "{}", o.bpfi);
    assert!((o.bpfo - 3.57).abs() <= 0.005, "{}", o.bpfo);
}

#[test]
fn designations_are_found_through_their_decorations() {
    for (text, want) in [
        ("UC204", "UC204"),
        ("uc204", "UC204"),
        ("UC 204", "UC204"),
        ("  Uc-204 ", "UC204"),
        ("UCP204", "UC204"),
        ("UCFL 204", "UC204"),
        ("ASAHI UCPH 20", "UC204"),
        ("UCPH204", "UC204"),
        ("6205-2RS", "6205"),
        ("SKF 6205", "6205"),
        ("6205 2RS JEM", "6205"),
        ("skf 6205-2rs1/c3", "6205"),
        ("6206ZZ", "6206"),
        ("6208-2Z C3", "6208"),
        ("FAG 6203", "6203"),
        ("NSK 6308 DDU", "6308"),
        ("ZA-2115", "ZA-2115"),
        ("za2115", "ZA-2115"),
        ("Rexnord ZA-2115", "ZA-2115"),
        ("ER16K", "ER-16K"),
        ("ER-16K", "ER-16K"),
        ("rexnord er-16k", "ER-16K"),
        ("UER204", "UER204"),
        ("LDK UER204", "UER204"),
        ("MFPT", "MFPT-NICE"),
        ("nice", "MFPT-NICE"),
    ] {
        let e = lookup(text).unwrap_or_else(|err| panic!("{text}: {err}"));
        assert_eq!(e.designation, want, "{text}");
        let s = BearingSpec::parse(text).unwrap();
        assert_eq!(s.name, e.name, "{text}");
        assert_eq!(s.given, text.trim(), "{text}");
        assert!(s.geometry.is_some());
    }
    // echoed as typed, with the catalogue's name after it when that differs
    assert_eq!(BearingSpec::parse("uc204").unwrap().echo(), "uc204 (UC204)");
    assert_eq!(BearingSpec::parse("UC204").unwrap().echo(), "UC204");
    assert_eq!(
        BearingSpec::parse("za2115").unwrap().echo(),
        "za2115 (Rexnord ZA-2115)"
    );
    // a decoration is a whole suffix, not any trailing text
    for text in ["62051", "6205X", "UC2045", "6205-2", "UC20"] {
        assert!(
            matches!(lookup(text), Err(ModelError::UnknownBearing(_))),
            "{text}"
        );
    }
}

#[test]
fn an_unknown_designation_names_the_nearest_rows() {
    let e = BearingSpec::parse("UC2O4").unwrap_err();
    assert_eq!(e, ModelError::UnknownBearing("UC2O4".into()));
    let msg = e.to_string();
    assert!(
        msg.starts_with("unknown bearing \"UC2O4\": near UC204, UC205, UC206"),
        "{msg}"
    );
    assert!(msg.contains("n=…,d=…,D=…[,angle=…]"), "{msg}");
    assert!(msg.contains("hybrid-fdd bearings"), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
    // a one-digit slip in a 63xx: its neighbours first, at most five
    let near: Vec<&str> = nearest("6306", 5).iter().map(|e| e.designation).collect();
    assert!(near.len() <= 5 && near.len() >= 2, "{near:?}");
    assert_eq!(&near[..2], ["6305", "6308"], "{near:?}");
    // a shared start is enough for a longer name
    let near: Vec<&str> = nearest("ZA-2200", 5)
        .iter()
        .map(|e| e.designation)
        .collect();
    assert_eq!(near.first(), Some(&"ZA-2115"), "{near:?}");
    // a maker's name does not count against the distance
    let msg = BearingSpec::parse("SKF 6306").unwrap_err().to_string();
    assert!(
        msg.starts_with("unknown bearing \"SKF 6306\": near 6305, 6308"),
        "{msg}"
    );
    // nothing near: the message says where the list is
    let msg = BearingSpec::parse("qqqqqqqq").unwrap_err().to_string();
    assert!(msg.contains("not in the catalogue"), "{msg}");
    assert!(nearest("", 5).is_empty());
    // `unknown` is not special here: it is simply not a designation
    assert!(matches!(
        BearingSpec::parse("unknown"),
        Err(ModelError::UnknownBearing(_))
    ));
}

#[test]
fn approximations_say_so_and_data_set_rows_cite_their_data() {
    let typical: Vec<&str> = entries()
        .iter()
        .filter(|e| e.is_typical())
        .map(|e| e.designation)
        .collect();
    assert_eq!(
        typical,
        [
            "6004", "6005", "6006", "6204", "6206", "6207", "6208", "6305", "6308", "UC204",
            "UC205", "UC206"
        ]
    );
    for (d, cites) in [
        ("6205", "CWRU"),
        ("6203", "CWRU"),
        ("MFPT-NICE", "MFPT"),
        ("ZA-2115", "IMS"),
        ("UER204", "XJTU-SY"),
        ("ER-16K", "Ottawa"),
    ] {
        assert!(lookup(d).unwrap().source.contains(cites), "{d}");
    }
}

#[test]
fn lengths_convert_from_the_units_sources_give() {
    assert_eq!(catalog::Length::In(1.0).metres(), 0.0254);
    assert!((catalog::Length::Mm(34.55).mm() - 34.55).abs() < 1e-12);
    assert!((catalog::Length::In(0.3125).mm() - 7.9375).abs() < 1e-12);
}
