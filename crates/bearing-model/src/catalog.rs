//! A built-in catalogue of common rolling bearings, so a bearing can be given by its designation
//! (`6205`, `UC204`, `ZA-2115`) instead of its geometry.
//!
//! Each row ([`CatalogEntry`]) holds the designation, the name reports use, aliases, the type,
//! the number of rolling elements `n`, the element diameter `d`, the pitch diameter `D` and the
//! contact angle, in the units its source gives them, and a `source` saying where the geometry
//! comes from. Rows whose geometry is an approximation say "typical, not manufacturer-specific":
//! bearings of one designation from different makers (and different generations of one maker)
//! differ in ball count and ball size, so their defect orders can differ by a few per cent.
//!
//! The derived orders are [`BearingGeometry::orders`]: contact-angle-adjusted kinematics
//! (`r = d/D·cos α`, `BPFO + BPFI = n`), with the ball-defect rate twice the ball spin (the value
//! CWRU's table calls "BSF"; [`FaultOrders`]).
//!
//! Lookup ([`lookup`]) ignores case, spaces, `-`, `_`, `/` and `.`, a maker's name in front
//! (`SKF 6205`, `LDK UER204`, `Rexnord ZA-2115`), a housed unit's housing letters (`UCP204`,
//! `UCFL204` → `UC204`) and seal, shield, clearance and cage suffixes behind the designation
//! (`6205-2RS`, `6205 2RS JEM`, `6206ZZ/C3`). An unknown designation is
//! [`ModelError::UnknownBearing`], whose message lists the nearest rows ([`nearest`]).

use crate::error::{ModelError, Result};
use crate::geometry::{Bearing, BearingGeometry, FaultOrders};
use crate::spec::BearingSpec;

/// A length as a source states it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Length {
    /// Millimetres.
    Mm(f64),
    /// Inches (25.4 mm).
    In(f64),
}

impl Length {
    /// The length in metres.
    pub fn metres(self) -> f64 {
        match self {
            Length::Mm(x) => x * 1e-3,
            Length::In(x) => x * 0.0254,
        }
    }

    /// The length in millimetres.
    pub fn mm(self) -> f64 {
        self.metres() * 1e3
    }
}

/// The kind of rolling bearing a catalogue row is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BearingKind {
    /// Single-row deep-groove ball bearing (60xx, 62xx, 63xx).
    DeepGrooveBall,
    /// Insert ball bearing of a housed unit (UC2xx, ER, UER): a deep-groove ball bearing with a
    /// wide inner ring and a spherical outer ring.
    InsertBall,
    /// Double-row roller bearing (`n` counts the rollers of one row).
    DoubleRowRoller,
    /// A rolling bearing whose element type its source does not state.
    Unstated,
}

impl BearingKind {
    /// The kind in words, for tables.
    pub fn label(self) -> &'static str {
        match self {
            BearingKind::DeepGrooveBall => "deep-groove ball",
            BearingKind::InsertBall => "insert ball",
            BearingKind::DoubleRowRoller => "double-row roller",
            BearingKind::Unstated => "rolling (type not stated)",
        }
    }
}

impl std::fmt::Display for BearingKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.label())
    }
}

/// One row of the catalogue.
#[derive(Debug, Clone, PartialEq)]
pub struct CatalogEntry {
    /// The designation the catalogue lists it under (unique; `6205`, `UC204`, `ZA-2115`).
    pub designation: &'static str,
    /// The name reports use ([`BearingSpec::name`], [`BearingGeometry::name`]): the full
    /// designation (`SKF 6205-2RS JEM`, `LDK UER204`), or the designation itself.
    pub name: &'static str,
    /// Other names it is found by (besides the designation and the name).
    pub aliases: &'static [&'static str],
    /// Bearing type.
    pub kind: BearingKind,
    /// Number of rolling elements (of one row, for a double-row bearing).
    pub n_elements: usize,
    /// Rolling-element diameter `d`.
    pub element_diameter: Length,
    /// Pitch diameter `D`.
    pub pitch_diameter: Length,
    /// Contact angle, degrees.
    pub contact_angle_deg: f64,
    /// Where the geometry comes from.
    pub source: &'static str,
    /// The built-in model bearing it is, if any ([`Bearing`]: the CWRU 6205 and 6203, whose
    /// geometry is [`Bearing::geometry`] exactly).
    pub builtin: Option<Bearing>,
}

impl CatalogEntry {
    /// The geometry (for a built-in bearing, [`Bearing::geometry`] itself).
    pub fn geometry(&self) -> BearingGeometry {
        match self.builtin {
            Some(b) => b.geometry(),
            None => BearingGeometry {
                name: self.name,
                n_balls: self.n_elements,
                ball_diameter_m: self.element_diameter.metres(),
                pitch_diameter_m: self.pitch_diameter.metres(),
                contact_angle_rad: self.contact_angle_deg.to_radians(),
            },
        }
    }

    /// The fault orders ([`BearingGeometry::orders`]; `ball_defect` is twice the ball spin).
    pub fn orders(&self) -> FaultOrders {
        self.geometry().orders()
    }

    /// The bearing spec of this row, echoing `given` (the text the user typed, trimmed): named
    /// by [`CatalogEntry::name`], with its geometry. A built-in bearing's spec is
    /// [`BearingSpec::builtin`]'s.
    pub fn spec(&self, given: &str) -> BearingSpec {
        let given = given.trim().to_string();
        match self.builtin {
            Some(b) => BearingSpec {
                given,
                ..BearingSpec::builtin(b)
            },
            None => {
                let g = self.geometry();
                BearingSpec {
                    name: self.name.to_string(),
                    given,
                    geometry: Some(g),
                    orders: g.orders(),
                }
            }
        }
    }

    /// Whether its geometry is an approximation of the designation ("typical, not
    /// manufacturer-specific"), not a data set's or a maker's stated geometry.
    pub fn is_typical(&self) -> bool {
        self.source.starts_with(TYPICAL)
    }

    /// The normalised keys it is found by: designation, name and aliases.
    fn keys(&self) -> impl Iterator<Item = String> + '_ {
        [self.designation, self.name]
            .into_iter()
            .chain(self.aliases.iter().copied())
            .map(normalise)
    }
}

/// How the source of a row whose geometry is an approximation begins ([`CatalogEntry::is_typical`]).
pub const TYPICAL: &str = "typical, not manufacturer-specific";

/// The catalogue, in the order [`entries`] lists it.
static CATALOG: [CatalogEntry; 18] = [
    CatalogEntry {
        designation: "6004",
        name: "6004",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 9,
        element_diameter: Length::In(0.25),
        pitch_diameter: Length::Mm(31.0),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 9 balls of 1/4 in on the ISO 15 mean diameter (20 + 42)/2 = 31 mm",
        builtin: None,
    },
    CatalogEntry {
        designation: "6005",
        name: "6005",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 10,
        element_diameter: Length::In(0.25),
        pitch_diameter: Length::Mm(36.0),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 10 balls of 1/4 in on the ISO 15 mean diameter (25 + 47)/2 = 36 mm",
        builtin: None,
    },
    CatalogEntry {
        designation: "6006",
        name: "6006",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 11,
        element_diameter: Length::In(0.28125),
        pitch_diameter: Length::Mm(42.5),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 11 balls of 9/32 in on the ISO 15 mean diameter (30 + 55)/2 = 42.5 mm",
        builtin: None,
    },
    CatalogEntry {
        designation: "6203",
        name: "SKF 6203-2RS JEM",
        aliases: &["FE", "fan-end"],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 8,
        element_diameter: Length::In(0.2656),
        pitch_diameter: Length::In(1.122),
        contact_angle_deg: 0.0,
        source: "CWRU Bearing Data Center, fan-end bearing (SKF 6203-2RS JEM): 8 balls, d = 0.2656 in, D = 1.122 in; Paderborn's 6203s (Lessmeier et al. 2016) are given as d = 6.75 mm, D = 28.55 mm (orders within 0.1 %)",
        builtin: Some(Bearing::Skf6203),
    },
    CatalogEntry {
        designation: "6204",
        name: "6204",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 8,
        element_diameter: Length::In(0.3125),
        pitch_diameter: Length::Mm(33.5),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 8 balls of 5/16 in on the ISO 15 mean diameter (20 + 47)/2 = 33.5 mm; a size of the HUST data set (Thuan & Hong 2023), geometry not taken from it",
        builtin: None,
    },
    CatalogEntry {
        designation: "6205",
        name: "SKF 6205-2RS JEM",
        aliases: &["DE", "drive-end"],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 9,
        element_diameter: Length::In(0.3126),
        pitch_diameter: Length::In(1.537),
        contact_angle_deg: 0.0,
        source: "CWRU Bearing Data Center, drive-end bearing (SKF 6205-2RS JEM): 9 balls, d = 0.3126 in, D = 1.537 in; other makers' 6205s (HUST's, Thuan & Hong 2023) may differ",
        builtin: Some(Bearing::Skf6205),
    },
    CatalogEntry {
        designation: "6206",
        name: "6206",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 9,
        element_diameter: Length::In(0.375),
        pitch_diameter: Length::Mm(46.0),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 9 balls of 3/8 in on the ISO 15 mean diameter (30 + 62)/2 = 46 mm; a size of the HUST data set (Thuan & Hong 2023), geometry not taken from it",
        builtin: None,
    },
    CatalogEntry {
        designation: "6207",
        name: "6207",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 9,
        element_diameter: Length::In(0.4375),
        pitch_diameter: Length::Mm(53.5),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 9 balls of 7/16 in on the ISO 15 mean diameter (35 + 72)/2 = 53.5 mm; a size of the HUST data set (Thuan & Hong 2023), geometry not taken from it",
        builtin: None,
    },
    CatalogEntry {
        designation: "6208",
        name: "6208",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 9,
        element_diameter: Length::In(0.5),
        pitch_diameter: Length::Mm(60.0),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 9 balls of 1/2 in on the ISO 15 mean diameter (40 + 80)/2 = 60 mm; a size of the HUST data set (Thuan & Hong 2023), geometry not taken from it",
        builtin: None,
    },
    CatalogEntry {
        designation: "6305",
        name: "6305",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 8,
        element_diameter: Length::In(0.40625),
        pitch_diameter: Length::Mm(43.5),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 8 balls of 13/32 in on the ISO 15 mean diameter (25 + 62)/2 = 43.5 mm",
        builtin: None,
    },
    CatalogEntry {
        designation: "6308",
        name: "6308",
        aliases: &[],
        kind: BearingKind::DeepGrooveBall,
        n_elements: 8,
        element_diameter: Length::In(0.59375),
        pitch_diameter: Length::Mm(65.0),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: 8 balls of 19/32 in on the ISO 15 mean diameter (40 + 90)/2 = 65 mm",
        builtin: None,
    },
    CatalogEntry {
        designation: "UC204",
        name: "UC204",
        aliases: &["UCPH 20"],
        kind: BearingKind::InsertBall,
        n_elements: 8,
        element_diameter: Length::In(0.3125),
        pitch_diameter: Length::Mm(33.5),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: a 47 mm OD (204-class) insert, 8 balls of 5/16 in on D = 33.5 mm, as the UESTC data's README in this project assumes for its ASAHI UCPH 20; LDK's UER204 of the same class is given D = 34.55 mm (XJTU-SY; BPFO 1 % higher)",
        builtin: None,
    },
    CatalogEntry {
        designation: "UC205",
        name: "UC205",
        aliases: &[],
        kind: BearingKind::InsertBall,
        n_elements: 9,
        element_diameter: Length::In(0.3125),
        pitch_diameter: Length::In(1.516),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: a 52 mm OD (205-class) insert, taken with the geometry of Rexnord's ER-16K of that class (9 balls of 5/16 in, D = 1.516 in; Huang & Baddour 2018)",
        builtin: None,
    },
    CatalogEntry {
        designation: "UC206",
        name: "UC206",
        aliases: &[],
        kind: BearingKind::InsertBall,
        n_elements: 9,
        element_diameter: Length::In(0.375),
        pitch_diameter: Length::Mm(46.0),
        contact_angle_deg: 0.0,
        source: "typical, not manufacturer-specific: a 62 mm OD (206-class) insert taken with 6206-class internals, 9 balls of 3/8 in on D = (30 + 62)/2 = 46 mm",
        builtin: None,
    },
    CatalogEntry {
        designation: "MFPT-NICE",
        name: "MFPT NICE",
        aliases: &["NICE", "MFPT"],
        kind: BearingKind::Unstated,
        n_elements: 8,
        element_diameter: Length::In(0.235),
        pitch_diameter: Length::In(1.245),
        contact_angle_deg: 0.0,
        source: "MFPT Society bearing fault data (MathWorks' RollingElementBearingFaultDiagnosis-Data; this project's data/mfpt README): NICE bearing, 8 elements, d = 0.235 in, D = 1.245 in, 0 deg; its BPFO 81.12 and BPFI 118.88 Hz at 25 Hz agree, its BSF 63.91 Hz is the ball spin and its FTF 14.84 Hz is not the cage order (0.406)",
        builtin: None,
    },
    CatalogEntry {
        designation: "ZA-2115",
        name: "Rexnord ZA-2115",
        aliases: &["IMS"],
        kind: BearingKind::DoubleRowRoller,
        n_elements: 16,
        element_diameter: Length::In(0.331),
        pitch_diameter: Length::In(2.815),
        contact_angle_deg: 15.17,
        source: "IMS run-to-failure data (NASA PCoE; Qiu, Lee, Lin & Yu, J. Sound Vib. 289, 2006): 16 rollers per row, d = 0.331 in, D = 2.815 in, contact angle 15.17 deg; its README gives BPFO 236.4 Hz and BPFI 296.9 Hz at 2000 rpm",
        builtin: None,
    },
    CatalogEntry {
        designation: "UER204",
        name: "LDK UER204",
        aliases: &["XJTU-SY"],
        kind: BearingKind::InsertBall,
        n_elements: 8,
        element_diameter: Length::Mm(7.92),
        pitch_diameter: Length::Mm(34.55),
        contact_angle_deg: 0.0,
        source: "XJTU-SY run-to-failure data (Wang, Lei, Li & Li, IEEE Trans. Reliab. 2020): 8 balls, d = 7.92 mm, D = 34.55 mm, 0 deg; at 35 Hz it gives BPFO 107.91, BPFI 172.09, FTF 13.49 Hz and BSF 72.33 Hz (the ball spin)",
        builtin: None,
    },
    CatalogEntry {
        designation: "ER-16K",
        name: "Rexnord ER-16K",
        aliases: &[],
        kind: BearingKind::InsertBall,
        n_elements: 9,
        element_diameter: Length::In(0.3125),
        pitch_diameter: Length::In(1.516),
        contact_angle_deg: 0.0,
        source: "University of Ottawa variable-speed data (Huang & Baddour, Data in Brief 21, 2018): 9 balls, d = 0.3125 in, D = 1.516 in, 0 deg; it gives BPFI 5.43 and BPFO 3.57 x fr",
        builtin: None,
    },
];

/// Every row of the catalogue: deep-groove 60xx/62xx/63xx, UC2xx inserts, then the bearings of
/// public data sets (MFPT, IMS, XJTU-SY, Ottawa).
pub fn entries() -> &'static [CatalogEntry] {
    &CATALOG
}

/// Makers' names read in front of a designation (`SKF 6205`, `LDK UER204`).
const MAKERS: [&str; 20] = [
    "SKF",
    "FAG",
    "NSK",
    "NTN",
    "KOYO",
    "TIMKEN",
    "NACHI",
    "ASAHI",
    "FYH",
    "LDK",
    "REXNORD",
    "LINKBELT",
    "DODGE",
    "SEALMASTER",
    "ZWZ",
    "HRB",
    "INA",
    "MRC",
    "SNR",
    "NMB",
];

/// Housing letters of a housed unit between `UC` and the size (`UCP204`, `UCFL204`), longest
/// first.
const HOUSINGS: [&str; 8] = ["PH", "FL", "FC", "FB", "PA", "P", "F", "T"];

/// Seal, shield, clearance, precision and cage suffixes read behind a designation (`-2RS`,
/// `ZZ`, `/C3`, `JEM`), longest first where one is a prefix of another.
const DECORATIONS: [&str; 37] = [
    "2RS1", "2RSH", "2RSL", "2RSR", "2RS", "RS1", "RSH", "RS", "2RZ", "RZ", "2Z", "ZZ", "Z", "DDU",
    "LLU", "LLB", "LLH", "VV", "DU", "UU", "JEM", "EM", "J", "ETN9", "TN9", "C2", "C3", "C4", "C5",
    "CN", "P0", "P6", "P5", "NR", "N", "E", "G",
];

/// `text` upper-cased with everything but ASCII letters and digits removed (`6205-2RS JEM` →
/// `62052RSJEM`).
pub fn normalise(text: &str) -> String {
    text.chars()
        .filter(char::is_ascii_alphanumeric)
        .map(|c| c.to_ascii_uppercase())
        .collect()
}

/// Whether `rest` is a sequence of [`DECORATIONS`] (the empty sequence included).
fn is_decoration(rest: &str) -> bool {
    rest.is_empty()
        || DECORATIONS
            .iter()
            .any(|t| rest.strip_prefix(t).is_some_and(is_decoration))
}

/// The forms of a normalised text that are matched against the keys: itself, without makers'
/// names in front, and a housed unit's name as its insert's (`UCP204` → `UC204`).
fn candidates(key: &str) -> Vec<String> {
    let mut out = vec![key.to_string()];
    let mut k = key;
    while let Some(rest) = MAKERS.iter().find_map(|m| k.strip_prefix(m)) {
        k = rest;
        out.push(k.to_string());
    }
    for c in out.clone() {
        if let Some(tail) = c.strip_prefix("UC") {
            for h in HOUSINGS {
                if let Some(size) = tail.strip_prefix(h)
                    && size.starts_with(|ch: char| ch.is_ascii_digit())
                {
                    out.push(format!("UC{size}"));
                    break;
                }
            }
        }
    }
    out
}

/// The row `text` names (see the module documentation for what is ignored).
///
/// # Errors
/// [`ModelError::UnknownBearing`] naming `text` (trimmed) when no row fits; its message lists
/// the nearest rows ([`nearest`]).
pub fn lookup(text: &str) -> Result<&'static CatalogEntry> {
    let key = normalise(text);
    let mut best: Option<(&'static CatalogEntry, usize)> = None;
    if !key.is_empty() {
        for cand in candidates(&key) {
            for e in entries() {
                for k in e.keys() {
                    let fits = cand
                        .strip_prefix(k.as_str())
                        .is_some_and(|rest| !k.is_empty() && is_decoration(rest));
                    if fits && best.is_none_or(|(_, len)| k.len() > len) {
                        best = Some((e, k.len()));
                    }
                }
            }
        }
    }
    best.map(|(e, _)| e)
        .ok_or_else(|| ModelError::UnknownBearing(text.trim().to_string()))
}

/// At most `k` rows nearest to `text`: by edit distance (within 2, or a third of the text's
/// length) or by a shared start of at least 3 characters, nearest first.
pub fn nearest(text: &str, k: usize) -> Vec<&'static CatalogEntry> {
    let key = normalise(text);
    if key.is_empty() {
        return Vec::new();
    }
    let cands = candidates(&key);
    let mut scored: Vec<(usize, usize, usize, &'static CatalogEntry)> = Vec::new();
    for (i, e) in entries().iter().enumerate() {
        let mut best: Option<(usize, usize)> = None;
        for c in &cands {
            for key in e.keys() {
                let d = edit_distance(c, &key);
                let p = c
                    .bytes()
                    .zip(key.bytes())
                    .take_while(|(a, b)| a == b)
                    .count();
                let limit = 2.max(c.len() / 3);
                // nearer first; of two as near, the longer shared start
                let better = best.is_none_or(|(bd, bp)| d < bd || (d == bd && p > bp));
                if (d <= limit || p >= 3) && better {
                    best = Some((d, p));
                }
            }
        }
        if let Some((d, p)) = best {
            scored.push((d, p, i, e));
        }
    }
    scored.sort_by_key(|&(d, p, i, _)| (d, std::cmp::Reverse(p), i));
    scored.into_iter().take(k).map(|(.., e)| e).collect()
}

/// The part of [`ModelError::UnknownBearing`]'s message after the text: the nearest rows and
/// the other forms a bearing can be given in.
pub(crate) fn unknown_hint(text: &str) -> String {
    let near: Vec<&str> = nearest(text, 5).iter().map(|e| e.designation).collect();
    let tail = "give n=…,d=…,D=…[,angle=…] or bpfo=…,bpfi=…,ftf=…,bsf=… instead";
    if near.is_empty() {
        format!("not in the catalogue (`hybrid-fdd bearings` lists it); {tail}")
    } else {
        format!(
            "near {} (all: `hybrid-fdd bearings`); {tail}",
            near.join(", ")
        )
    }
}

/// Levenshtein distance between two ASCII strings.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b) = (a.as_bytes(), b.as_bytes());
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, &x) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, &y) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(x != y))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edit_distance_counts_single_edits() {
        assert_eq!(edit_distance("UC2O4", "UC204"), 1);
        assert_eq!(edit_distance("6306", "6305"), 1);
        assert_eq!(edit_distance("", "6205"), 4);
        assert_eq!(edit_distance("ZA2115", "ZA2115"), 0);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn decorations_are_whole_tokens() {
        assert!(is_decoration(""));
        assert!(is_decoration("2RSJEM"));
        assert!(is_decoration("2RSHC3"));
        assert!(is_decoration("ZZC3"));
        assert!(!is_decoration("2"));
        assert!(!is_decoration("X"));
    }
}
