//! A fault-line detector with a stated false-alarm probability (step 3 of
//! [`diagnose`](crate::diagnose)).
//!
//! Each band's squared envelope spectrum is read as the prominence of its local maxima over the
//! local median, dB, less what a healthy baseline already holds there, with shaft orders, half
//! orders and mains multiples masked where the band shows their comb (`view::BandView`).
//!
//! For each hypothesis (BPFO, BPFI, the ball-defect rate) its **template** — harmonics `1..=K`
//! over their slip windows and the distinguishing sidebands of harmonic 1 (inner `± fr`, ball
//! `± FTF`) — is read in every band ([`linetest`]): each line's probability under "healthy" is
//! the share of the band's same-width windows off the fault's own lattice whose strongest line
//! is as prominent, and the lines' probabilities are combined by Fisher's method into the band's
//! `p_b`. The search over `B` bands (and, with a speed no comb confirmed, over `R` independent
//! speed ratios) is paid for by Bonferroni: `p_healthy = min(1, B · R · min_b p_b)`, the probability
//! that a healthy machine shows evidence at least this strong for this fault. The bands overlap
//! heavily, so this errs on the safe side.
//!
//! A fault is reported when `p_healthy ≤ α/3` (Bonferroni over the three hypotheses: a healthy
//! recording is called faulty with probability at most α, [`DEFAULT_FALSE_ALARM`]) **and** its
//! harmonics modulate the band's envelope deeply enough to be a defect's impacts rather than a
//! healthy bearing's smooth ball-pass modulation ([`MIN_MODULATION_DEPTH`]).
//!
//! **Several significant hypotheses** are taken in order of significance: each is tested again
//! with the line families of those already confirmed masked (a ball fault's cage harmonics hold
//! BPFO; an outer-race fault's `k·BPFO ± j·fr` can fall on BSF), and kept when it stays
//! significant (a second fault). A hypothesis dropped that way is tested the other way round:
//! when the stronger one also loses its significance with the weaker one's family masked, the
//! two explain the same lines: they are told apart by their probabilities
//! ([`UNCERTAIN_DECADES`]) and their harmonics' depths ([`UNCERTAIN_DEPTH_RATIO`]) when one of
//! these decides and the other does not say the opposite; otherwise the verdict is
//! `uncertain`, naming both. Hypotheses are taken in order of depth (the probabilities of
//! strong faults all reach their floors).

pub mod linetest;
pub mod template;
pub mod view;

use serde::{Deserialize, Serialize};

use crate::{EnvelopeSpectrum, HARMONICS, Hypothesis};
use bearing_model::FaultOrders;
#[cfg(test)]
use linetest::read_band;
use linetest::{BandReading, LineTest};
use template::{Template, Term};
use view::BandView;
pub use view::Masks;

/// Default false-alarm probability per recording (α): a healthy recording is called faulty at
/// most this often, whatever its spectrum holds besides bearing fault lines.
pub const DEFAULT_FALSE_ALARM: f64 = 0.01;
/// Smallest modulation depth of a fault's harmonics ([`Significance::modulation_depth`]) for it
/// to be reported. Statistical significance alone says a line family is there, not that it is a
/// fault: a healthy bearing's rolling elements modulate the path to the sensor at BPFO (varying
/// compliance, a ball passing under the load) smoothly and weakly, and a long record averages
/// the envelope spectrum down until such a family is significant (the shared rig's healthy
/// recordings read depths of 0.19–0.29 at BPFO, `p` down to 1e-11; CWRU 97 0.11 at BPFI). A
/// localized defect strikes: a train of short impacts carrying a share q of the band's power
/// has depths near 2q at each of its first harmonics, so 0.5 over three harmonics is a defect
/// whose impacts carry roughly a sixth of the band's power or more. Chosen on the healthy
/// recordings and this reasoning, before any faulty recording was read with it.
pub const MIN_MODULATION_DEPTH: f64 = 0.5;
/// Two hypotheses that explain each other's lines are told apart by their harmonics' modulation
/// depth when one's is at least this many times the other's.
pub const UNCERTAIN_DEPTH_RATIO: f64 = 1.5;
/// … or by their probabilities under healthy when these differ by at least this many decades.
pub const UNCERTAIN_DECADES: f64 = 2.0;

/// The detector's reading of one hypothesis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Significance {
    /// The band (index into the recording's bands) where the hypothesis reads strongest.
    pub band_index: usize,
    /// That band, Hz.
    pub band_hz: [f64; 2],
    /// `Σ harmonics + ½ Σ sidebands` of its lines' evidence in that band, dB.
    pub statistic_db: f64,
    /// Fisher's statistic of its lines' probabilities there (`−2 Σ ln p_k`).
    pub fisher: f64,
    /// Lines read there (harmonics and sidebands whose windows are not wholly masked).
    pub lines_read: usize,
    /// The strongest line in the window of harmonic 1 there, Hz.
    pub fundamental_hz: f64,
    /// Relative speed uncertainty the lines' windows were widened by (0 when a comb gave the
    /// speed to the lines' own tolerance).
    #[serde(default)]
    pub speed_slack: f64,
    /// The ratio to the speed used at which the lines read best (1 unless the speed was
    /// searched by the templates: a declared speed no comb confirmed).
    #[serde(default = "one")]
    pub speed_ratio: f64,
    /// `P(evidence ≥ this)` in that band alone, under "healthy".
    pub p_band: f64,
    /// The fault's share of the squared envelope's modulation there: `√(Σ_k m_k²)` over its
    /// harmonics, `m_k` the modulation depth at harmonic k (a squared envelope
    /// `μ(1 + m cos 2πft)` has depth m; a train of short impacts well above the background has
    /// depths near 1 at its first harmonics).
    pub modulation_depth: f64,
    /// The probability under "healthy" of evidence at least this strong for this fault after
    /// the search over bands (and speeds): what the decision compares with `α/3`.
    pub p_healthy: f64,
    /// Non-overlapping clear windows behind the smallest line reference there.
    pub null_size: usize,
    /// `p_healthy ≤ α/3`, a modulation depth of at least [`MIN_MODULATION_DEPTH`], and not
    /// explained by a stronger fault's lines.
    pub significant: bool,
    /// Significant on its own, but its lines belong to this stronger fault's family.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub explained_by: Option<Hypothesis>,
    /// `p_healthy` with the line families of the stronger confirmed faults masked (present when
    /// it was tested that way).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub p_given_stronger: Option<f64>,
    /// What that band masked.
    pub masks: Masks,
    /// The shaft rate, Hz, whose comb explains every line carrying this hypothesis's evidence
    /// when the speed was not confirmed by a comb (`detect::shaft_explains`): the lines are the
    /// shaft's, and the hypothesis is not significant (its `p_healthy` is 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaft_comb_hz: Option<f64>,
    /// The rate, Hz, of a comb slower than the fault whose orders hold every line carrying this
    /// hypothesis's evidence and which stands between them, off the fault's own lattice
    /// (`detect::slower_comb_explains`): another periodic source's, and the hypothesis is not
    /// significant (its `p_healthy` is 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slower_comb_hz: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// Which reading of an uncertain speed a detection comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpeedStage {
    /// The speed was measured (a comb): one reading at α.
    Measured,
    /// The declared speed taken as right, at α/2.
    Declared,
    /// The templates searched over the speed range, at α/2.
    Searched,
}

/// The detector's outcome.
#[derive(Debug, Clone)]
pub(crate) struct Detection {
    /// Per hypothesis, in [`Hypothesis::ALL`] order.
    pub per_hypothesis: Vec<Significance>,
    /// Per hypothesis, its reading in its best band (for the lines of the report).
    pub readings: Vec<BandReading>,
    /// Confirmed faults, in `Hypothesis::ALL` order.
    pub confirmed: Vec<Hypothesis>,
    /// Two hypotheses that explain the same lines (verdict `uncertain`), strongest first.
    pub uncertain: Vec<Hypothesis>,
    /// The prepared band views (for the lines of the report).
    pub views: Vec<BandView>,
    /// The templates at the speed each was read at.
    pub templates: Vec<Template>,
    /// Which reading of the speed it comes from.
    pub stage: SpeedStage,
}

/// Two hypotheses that explain each other's lines: `Some(true)` when `a` is the fault,
/// `Some(false)` when `b` is, `None` when they cannot be told apart. Each criterion — the
/// probability under healthy (decisive at [`UNCERTAIN_DECADES`] decades) and the harmonics'
/// modulation depth (decisive at [`UNCERTAIN_DEPTH_RATIO`]) — names a winner when decisive;
/// one decisive criterion and the other not against it decide, anything else is `None`.
fn tell_apart(a: &Significance, b: &Significance) -> Option<bool> {
    let decades = b.p_healthy.max(1e-300).log10() - a.p_healthy.max(1e-300).log10();
    let by_p = (decades.abs() >= UNCERTAIN_DECADES).then_some(decades > 0.0);
    let ratio =
        a.modulation_depth.max(f64::MIN_POSITIVE) / b.modulation_depth.max(f64::MIN_POSITIVE);
    let by_depth = (ratio >= UNCERTAIN_DEPTH_RATIO || 1.0 / ratio >= UNCERTAIN_DEPTH_RATIO)
        .then_some(ratio > 1.0);
    match (by_p, by_depth) {
        (Some(x), None) | (None, Some(x)) => Some(x),
        (Some(x), Some(y)) if x == y => Some(x),
        _ => None,
    }
}

/// One hypothesis read in every band (at every speed ratio searched).
#[derive(Debug, Clone)]
struct Scan {
    /// Best band, speed ratio and reading, and the modulation depth of its harmonics there.
    band: usize,
    rho: f64,
    reading: BandReading,
    depth: f64,
    p_healthy: f64,
    /// What the band read masked (at a searched speed, its shaft comb's orders too).
    masks: Masks,
}

/// The modulation depth of a reading's harmonics in `v`: `√(Σ_k m_k²)`.
pub(crate) fn harmonics_depth(v: &BandView, r: &BandReading) -> f64 {
    r.terms
        .iter()
        .filter(|t| matches!(t.window.term, Term::Harmonic(_)))
        .map(|t| v.depth(t.bin as f64 * v.df).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// A speed ratio searched, and the views read at it.
struct Ratio {
    /// The ratio to the declared speed.
    rho: f64,
    /// The views with the shaft's orders masked at the speed the ratio stands for, when the
    /// bands show a shaft comb there ([`shaft_masked_at`]); `None`: the views as given.
    masked: Option<Vec<BandView>>,
}

/// The ratio 1 alone (the speed known): the views as given.
const AT_SPEED: [Ratio; 1] = [Ratio {
    rho: 1.0,
    masked: None,
}];

/// The speed ratios `rhos` of a search, each with its views: a searched speed is a hypothesis
/// about the shaft too, so the comb the bands show at it is the shaft's, masked as at a
/// measured speed ([`shaft_masked_at`], at the templates' shaft rate `fr`; a single ratio is
/// no search and masks nothing). Built once per ratio for every hypothesis's scan.
fn searched_ratios(views: &[BandView], all: &[Template], fr: f64, rhos: &[f64]) -> Vec<Ratio> {
    let step = if rhos.len() > 1 {
        rhos[1] - rhos[0]
    } else {
        0.0
    };
    rhos.iter()
        .map(|&rho| Ratio {
            rho,
            masked: (step > 0.0)
                .then(|| shaft_masked_at(views, all, fr, rho, step))
                .flatten(),
        })
        .collect()
}

/// Read template `t` in every view at each speed ratio of `ratios` (1 when the speed is known),
/// each ratio's lines against references off its own lattice, in the ratio's views (its shaft
/// comb masked, see [`searched_ratios`]); the search paid for by Bonferroni over the bands and
/// the `independent` ratios. The reading kept is the most significant among those whose
/// harmonics modulate the envelope deeply enough to be a defect's ([`MIN_MODULATION_DEPTH`]),
/// else the most significant: a band where a weak smooth modulation stands out of a quiet
/// spectrum must not hide the band where the impacts ring.
fn scan(
    t: &Template,
    all: &[Template],
    views: &[BandView],
    ratios: &[Ratio],
    independent: usize,
) -> Scan {
    let mut best: Option<Scan> = None;
    let key = |s: &Scan| {
        (
            s.depth >= MIN_MODULATION_DEPTH,
            -s.reading.p,
            s.reading.statistic_db,
        )
    };
    for ratio in ratios {
        let rho = ratio.rho;
        let tr = t.at_speed(rho);
        // the references are read off every hypothesis's lattice: a fault's own lines, and
        // those of a fault of another kind, are not what a healthy band holds
        let top = views.iter().map(|v| v.top_hz).fold(0.0, f64::max);
        let lattice: Vec<(f64, f64)> = all
            .iter()
            .flat_map(|o| o.at_speed(rho).lattice(top))
            .collect();
        let views = ratio.masked.as_deref().unwrap_or(views);
        for (b, v) in views.iter().enumerate() {
            let r = LineTest::new(v, &lattice, tr.fr).read(&tr);
            let cand = Scan {
                band: b,
                rho,
                depth: harmonics_depth(v, &r),
                reading: r,
                p_healthy: 1.0,
                masks: v.masks,
            };
            let better = best.as_ref().is_none_or(|s| {
                let (a, c) = (key(&cand), key(s));
                (a.0, a.1, a.2).partial_cmp(&(c.0, c.1, c.2)) == Some(std::cmp::Ordering::Greater)
            });
            if better {
                best = Some(cand);
            }
        }
    }
    let looks = (views.len() * independent.max(1)) as f64;
    match best {
        Some(mut s) => {
            s.p_healthy = (s.reading.p * looks).min(1.0);
            s
        }
        None => Scan {
            band: 0,
            rho: 1.0,
            depth: 0.0,
            reading: BandReading {
                terms: Vec::new(),
                fisher: 0.0,
                p: 1.0,
                statistic_db: 0.0,
            },
            p_healthy: 1.0,
            masks: Masks::default(),
        },
    }
}

/// Whether `t` is an inner race whose family's near-comb (`BPFI/n`, `n` the integer nearest
/// the BPFI order) lies within half a bin `df` (relative to its shaft rate) plus the rates'
/// uncertainty `u` of the shaft's comb: its harmonics on a comb's orders are then its own
/// family's as much as a shaft's — an inner race modulated by the load zone fills the envelope
/// with shaft orders itself — so [`shaft_explains`] is not asked (a 6203's BPFI 4.947 fr, a
/// 6308's 4.928, a UC204's 4.95 ± 3 % against bins of fr/8 … fr/32).
fn inner_near_comb(t: &Template, df: f64, u: f64) -> bool {
    if t.hypothesis != Hypothesis::Inner || t.fr <= 0.0 {
        return false;
    }
    let q = t.fault_hz / t.fr;
    let n = q.round().max(1.0);
    (q / n - 1.0).abs() <= 0.5 * df / t.fr + u
}

/// Orders of a shaft comb off a hypothesis's lines that [`shaft_explains`] looks at (the first
/// ones not among the lines).
const SHAFT_CHECK_ORDERS: usize = 6;
/// … of which at least this many must stand as lines: a shaft comb (once-per-rev impacts, a
/// rub) holds nearly every order; a fault family's near-comb meets a few of them by chance at
/// the envelope spectrum's resolution (a bin of fr/8 … fr/32).
const SHAFT_MIN_ORDERS: usize = 4;

/// The shaft rate in `range` (Hz) whose comb explains every line carrying evidence in `r` (read
/// in `v`), if one does: each such line within `max(½ bin, COMB_TOLERANCE)` of an order of it
/// (the rate fitted to them, the strongest line's order `n` taken in turn), and at least
/// [`SHAFT_MIN_ORDERS`] of its first [`SHAFT_CHECK_ORDERS`] orders off those lines standing
/// [`LINE_THRESHOLD_DB`] over their median, as close, in some band of `views`. A fault explains
/// lines at non-integer orders; a comb at integer orders is the shaft's (once-per-rev impacts,
/// a rub, looseness). With a speed no comb confirmed a template slides until its lines sit on
/// the shaft's orders (BPFI 4.93 fr on the 5th, 10th and 15th; a ball's BSF×2 ± FTF on the
/// 8th, 9th and 17th), and the declared speed's masks, a few per cent off, do not cover them.
/// A fault's own lines are told from a shaft comb by the orders between: an inner race's
/// family `k·BPFI ± m·fr` forms a near-comb at `BPFI/5 ≈ 0.986–0.989 fr` whose orders lie
/// 1.1–1.4 % (first), 2.2–2.9 % (second) … from the shaft's lines and the family's: at the
/// envelope spectrum's resolution (half a bin is 1.6 % of fr at fr/32 bins) a few of them meet
/// a line, not four of six.
pub(crate) fn shaft_explains(
    views: &[BandView],
    v: &BandView,
    r: &linetest::BandReading,
    range: [f64; 2],
) -> Option<f64> {
    let lines = evidence_lines(v, r);
    let &(f_max, _) = lines.iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
    let tol = |f: f64| comb_tol(v, f);
    (1..)
        .map(|n| f_max / n as f64)
        .take_while(|&f| f >= range[0])
        .filter(|&f| f <= range[1])
        .find_map(|f0| {
            let (fs, ks) = comb_fit(&lines, f0, tol)?;
            comb_shown(views, v, fs, &ks).then_some(fs)
        })
}

/// Whether at least [`SHAFT_MIN_ORDERS`] of the first [`SHAFT_CHECK_ORDERS`] orders of a comb
/// at `fs` Hz other than `ks` (the orders a hypothesis's lines took) stand as lines, within
/// [`comb_tol`] of `v`, in some band of `views`, read before any mask: a comb masked at a
/// declared speed a bin off, or whose orders on mains multiples read as a mains comb, is still
/// a comb (a ZA-2115 at 600 rpm declared 2 % slow: its masks covered four of the six orders
/// asked).
fn comb_shown(views: &[BandView], v: &BandView, fs: f64, ks: &[f64]) -> bool {
    let tol = |f: f64| comb_tol(v, f);
    (1..)
        .map(|j| j as f64)
        .filter(|j| !ks.contains(j))
        .take(SHAFT_CHECK_ORDERS)
        .filter(|&j| {
            views
                .iter()
                .any(|w| w.holds_line_unmasked(j * fs, tol(j * fs)))
        })
        .count()
        >= SHAFT_MIN_ORDERS
}

/// Whether the recording's own spectrum's shaft comb, at `fc` Hz (an independent reading: the
/// raw signal's comb, complete, its rate `resolution` relative), explains every line carrying
/// evidence in `r` (read in `v`): each within [`comb_tol`] (widened by the rate's placement at
/// its order) of an order of `fc` itself — no rate fitted to the lines — and the comb shown at
/// the orders between ([`comb_shown`]). Asked of an inner race whose near-comb may meet the
/// shaft's ([`inner_near_comb`]), which [`shaft_explains`] cannot judge (it fits a rate to the
/// lines, and a near-comb `BPFI/5` fits one): with the geometry known to a few per cent the
/// near-comb may lie anywhere within them of the shaft's orders, and lines standing at the
/// exact orders of a comb the spectrum shows are that comb's — a fault there could not be told
/// from it; a fault's family off them by more than the tolerance is not touched.
fn spectrum_comb_explains(
    views: &[BandView],
    v: &BandView,
    r: &BandReading,
    fc: f64,
    resolution: f64,
) -> bool {
    let lines = evidence_lines(v, r);
    if lines.is_empty() || fc <= 0.0 {
        return false;
    }
    let ks: Vec<f64> = lines.iter().map(|&(f, _)| (f / fc).round()).collect();
    let on_orders = lines.iter().zip(&ks).all(|(&(f, _), &k)| {
        k >= 1.0 && (f - k * fc).abs() <= comb_tol(v, f) + k * resolution * fc
    });
    on_orders && comb_shown(views, v, fc, &ks)
}

/// The strongest line in the window of harmonic 1 of reading `r` (read in `v`), Hz.
fn fundamental_hz(v: &BandView, r: &BandReading) -> Option<f64> {
    r.terms
        .iter()
        .find(|x| x.window.term == Term::Harmonic(1))
        .map(|x| x.bin as f64 * v.df)
}

/// The lines of reading `r` (in `v`) that carry evidence — at least [`crate::LINE_THRESHOLD_DB`]
/// — as (Hz, dB).
fn evidence_lines(v: &BandView, r: &BandReading) -> Vec<(f64, f64)> {
    r.terms
        .iter()
        .filter(|t| t.value >= crate::LINE_THRESHOLD_DB)
        .map(|t| (t.bin as f64 * v.df, t.value))
        .collect()
}

/// How close a line must lie to a comb's order in `v`: half a bin, or
/// [`view::COMB_TOLERANCE`] of the frequency where that is wider.
fn comb_tol(v: &BandView, f: f64) -> f64 {
    (0.5 * v.df).max(view::COMB_TOLERANCE * f)
}

/// Whether every line of `lines` (Hz, dB) lies on an order of a comb near `f0`: the rate fitted
/// to the lines' nearest orders (least squares through the origin) and those orders, when each
/// line lies within `tol` of its order of the fitted rate (and none below the first).
fn comb_fit(lines: &[(f64, f64)], f0: f64, tol: impl Fn(f64) -> f64) -> Option<(f64, Vec<f64>)> {
    let ks: Vec<f64> = lines.iter().map(|&(f, _)| (f / f0).round()).collect();
    if ks.iter().any(|&k| k < 1.0) {
        return None;
    }
    let (num, den) = lines
        .iter()
        .zip(&ks)
        .fold((0.0, 0.0), |(a, b), (&(f, _), &k)| (a + k * f, b + k * k));
    let fs = num / den;
    lines
        .iter()
        .zip(&ks)
        .all(|(&(f, _), &k)| (f - k * fs).abs() <= tol(f))
        .then_some((fs, ks))
}

/// Orders of a slower comb between a hypothesis's lines, off them and off the fault's own
/// lines, that [`slower_comb_explains`] looks at (the lowest ones).
const SLOWER_CHECK_ORDERS: usize = 10;
/// … at least this many of them (fewer: no test), and as many standing.
const SLOWER_MIN_ORDERS: usize = 3;
/// A slower comb's rate is at most this share of the fault's fundamental (the fault's lines are
/// every m-th of its orders, m ≥ 2) …
const SLOWER_MAX_SHARE: f64 = 0.6;
/// … and spans at least this many bins: its orders resolved from each other, with room between
/// them (beyond the two bins either side of each order) to read the band's line density.
const SLOWER_MIN_BINS: f64 = 6.0;
/// Divisors of the strongest line tried for the slower comb's rate.
const SLOWER_MAX_DIVISOR: usize = 32;
/// The slower comb's orders between the fault's lines stand as lines more often than the band's
/// lines fall on such positions by chance: at most this probability (binomial, Bonferroni over
/// the rates tried). A chance alignment would cost a real fault; this is the rate at which it may.
const SLOWER_LEVEL: f64 = 0.01;
/// Positions sampled for the band's line density (off the comb and the fault's own lines) …
const DENSITY_SAMPLES: usize = 400;
/// … of which at least this many must lie off both for the density to be read (else no test).
const DENSITY_MIN_SAMPLES: usize = 100;

/// Where the fault of template `t`, its fundamental at `f1` Hz, puts lines itself in `v`: every
/// harmonic `k·f₁` shifted by `j·fr` (|j| ≤ [`template::FAMILY_SHAFT_ORDERS`], as its family:
/// the load zone and a shaft's unbalance modulate the impacts at fr), for a race the orders of
/// `f₁/Z` (the rate its `Z` rolling elements pass a point of it: the cage modulating the
/// impacts), for a ball its spin lines at `(k − ½)·f₁`, `k·f₁ ± j·FTF` (|j| ≤ 8) and the cage's
/// orders (the ball passes the load zone with the cage), each within the comb tolerance plus
/// half a bin; and every shaft order. The harmonics are placed from the fundamental found (not over the slip windows the template
/// searches): an inner race's family `k·f₁ ± j·fr` makes a near-comb at `f₁/m` where that is
/// close to a shaft order, and its orders are then the fault's own lines.
fn own_lines<'a>(v: &'a BandView, t: &Template, f1: f64) -> impl Fn(f64) -> bool + 'a {
    let (df, fr, hyp) = (v.df, t.fr, t.hypothesis);
    // the cage sidebands slip with the ball line
    let ftf = t.ftf_hz * f1 / t.fault_hz.max(f64::MIN_POSITIVE);
    let shifts = template::FAMILY_SHAFT_ORDERS;
    let reach = f64::from(shifts + 1) * fr + f1;
    // a race's rolling elements pass a point of it at f₁/Z: the cage modulating its impacts
    // puts lines at that rate's orders
    let passing = t.rolling_elements().map(|z| f1 / z);
    move |f: f64| {
        let tol = comb_tol(v, f);
        let j = (f / fr).round();
        if j >= 1.0 && (f - j * fr).abs() <= tol.max(crate::SPEED_TOL * f) {
            return true;
        }
        let near = |c: f64| (f - c).abs() <= tol + 0.5 * df;
        if let Some(p) = passing {
            let i = (f / p).round();
            if i >= 1.0 && near(i * p) {
                return true;
            }
        }
        // the harmonics whose shifts reach f
        let k_lo = ((f - reach) / f1).floor().max(1.0) as i64;
        let k_hi = ((f + reach) / f1).ceil() as i64;
        for k in k_lo..=k_hi {
            let kf = k as f64 * f1;
            if (-shifts..=shifts).any(|j| near(kf + f64::from(j) * fr)) {
                return true;
            }
            if hyp == Hypothesis::Ball
                && (near(kf - 0.5 * f1)
                    || (-shifts..=shifts).any(|j| near(kf + f64::from(j) * ftf)))
            {
                return true;
            }
        }
        // a ball passes the load zone with the cage: the cage's orders (its rate slipping with
        // the ball line) are the ball's own modulation, as the shaft's are an inner race's
        if hyp == Hypothesis::Ball && ftf > 0.0 {
            let i = (f / ftf).round();
            return i >= 1.0 && near(i * ftf);
        }
        false
    }
}

/// Whether a comb at `fs` Hz is the machine's or the bearing's own rather than a slower
/// source's, for template `t` whose fundamental was found at `f1` in `v`: at (a multiple of) the
/// shaft's rate — masked where it shows, [`shaft_explains`] where the speed is unconfirmed (a
/// ball-defect rate near an order sits in it); for a race, `f1/m` with `m` dividing its rolling
/// elements `Z` (`BPFO = Z·FTF`, `BPFI = Z·(fr − FTF)`: a multiple of the rate they pass a point
/// of it, which the cage modulating the impacts fills — CWRU's faults do); for a ball, a multiple
/// of a cage rate within the cage's slip.
fn own_rate(v: &BandView, t: &Template, f1: f64, fs: f64) -> bool {
    let i = (fs / t.fr).round();
    let shaft = i >= 1.0 && (fs - i * t.fr).abs() <= v.df.max(crate::SPEED_TOL * fs);
    let (lo, hi) = template::cage_window();
    let c = t.ftf_hz;
    let i = (fs / c.max(f64::MIN_POSITIVE)).round();
    let cage = t.hypothesis == Hypothesis::Ball
        && c > 0.0
        && i >= 1.0
        && fs >= i * c * lo - 0.5 * v.df
        && fs <= i * c * hi + 0.5 * v.df;
    let m = (f1 / fs).round();
    let elements = t
        .rolling_elements()
        .is_some_and(|z| m >= 1.0 && z % m == 0.0);
    shaft || cage || elements
}

/// The rate, Hz, of a comb slower than the fault that explains every line carrying evidence for
/// template `t` in reading `r` (read in `v`), if one does: each such line on an order of it (as
/// [`shaft_explains`] fits a shaft rate, within [`comb_tol`]), the rate at most
/// [`SLOWER_MAX_SHARE`] of the fault's fundamental and [`SLOWER_MIN_BINS`] bins, and its orders
/// between those lines — the lowest [`SLOWER_CHECK_ORDERS`] below the highest line that are not
/// where the fault itself puts lines ([`own_lines`]) nor masked, at least
/// [`SLOWER_MIN_ORDERS`] — standing as lines (≥ 6 dB within a bin) at least half of them, and
/// more often than the band's lines fall on positions by chance: the density `q` of lines is
/// read at [`DENSITY_SAMPLES`] positions across the same span, off the comb's orders and the
/// fault's lines, and `P(Bin(n, q) ≥ shown)`, times the rates that fit, must be at most
/// [`SLOWER_LEVEL`]; of several such rates the most significant. A rate of the machine's or
/// the bearing's own ([`own_rate`]) is not tested. A periodic source slower than the fault —
/// another shaft's once-per-turn impacts, a belt joint, a coupling — puts a line at every order
/// of its rate; when one of its multiples falls near a fault's rate its comb holds that fault's
/// harmonics, and the lines between them are the slower source's, which no bearing fault of
/// that kind makes (`docs/equations/diagnosis.md`, *A slower source's comb*). Asked only where
/// no comb confirmed the speed (`detect_at` and the unknown-bearing search ask it then).
pub(crate) fn slower_comb_explains(v: &BandView, r: &BandReading, t: &Template) -> Option<f64> {
    let lines = evidence_lines(v, r);
    let &(f_max, _) = lines.iter().max_by(|a, b| a.1.total_cmp(&b.1))?;
    let f1 = fundamental_hz(v, r).unwrap_or(t.fault_hz);
    let tol = |f: f64| comb_tol(v, f);
    // a line within a bin: a line between two bins peaks in either, speed wander moves it
    let hold_tol = |f: f64| v.df.max(view::COMB_TOLERANCE * f);
    let holds = |f: f64| v.holds_line(f, hold_tol(f));
    let fits: Vec<(f64, Vec<f64>)> = (1..=SLOWER_MAX_DIVISOR)
        .rev()
        .map(|n| f_max / n as f64)
        .filter(|&f0| f0 <= SLOWER_MAX_SHARE * f1 && f0 >= SLOWER_MIN_BINS * v.df)
        .filter_map(|f0| comb_fit(&lines, f0, tol))
        .collect();
    let looks = fits.len() as f64;
    let tested = fits
        .into_iter()
        .filter(|(fs, _)| !own_rate(v, t, f1, *fs))
        .filter_map(|(fs, ks)| {
            // the fault's own lines from its fundamental on the comb (read to a fraction of a bin)
            let owned = own_lines(v, t, fs * (f1 / fs).round().max(1.0));
            // between the fault's lines: a comb fades with frequency as the fault's harmonics do
            let last = ks.iter().copied().fold(0.0, f64::max);
            let positions: Vec<f64> = (1..)
                .map(|j| j as f64)
                .take_while(|&j| j < last)
                .filter(|j| !ks.contains(j))
                .map(|j| j * fs)
                .take_while(|&f| f < v.top_hz)
                .filter(|&f| !owned(f) && !v.masked_at(f))
                .take(SLOWER_CHECK_ORDERS)
                .collect();
            let (&lo, &hi) = (positions.first()?, positions.last()?);
            if positions.len() < SLOWER_MIN_ORDERS {
                return None;
            }
            let shown = positions.iter().filter(|&&f| holds(f)).count();
            // a comb stands at most of its orders (a slower rate's every m-th order is the comb
            // itself: not a comb of that rate)
            if 2 * shown < positions.len() || shown < SLOWER_MIN_ORDERS {
                return None;
            }
            // the band's density of lines at positions off the comb and off the fault's lines
            let off_comb = |f: f64| {
                let j = (f / fs).round();
                (f - j * fs).abs() > 2.0 * hold_tol(f) && !owned(f) && !v.masked_at(f)
            };
            let (held, sampled) = (0..DENSITY_SAMPLES)
                .map(|i| lo + (hi - lo) * (i as f64 + 0.5) / DENSITY_SAMPLES as f64)
                .filter(|&f| off_comb(f))
                .fold((0usize, 0usize), |(h, n), f| {
                    (h + usize::from(holds(f)), n + 1)
                });
            if sampled < DENSITY_MIN_SAMPLES {
                return None;
            }
            let q = (held as f64 + 1.0) / (sampled as f64 + 2.0);
            let p = linetest::binomial_sf(positions.len(), shown, q) * looks;
            (p <= SLOWER_LEVEL).then_some((p, fs))
        });
    tested.min_by(|a, b| a.0.total_cmp(&b.0)).map(|(_, fs)| fs)
}

/// Sub-steps of a speed-ratio step at which [`shaft_masked_at`] looks for the shaft comb.
const COMB_SUBSTEPS: usize = 8;

/// The views with the shaft's orders masked at the speed a searched ratio stands for, when the
/// bands show a shaft comb there; `None` when none does. A ratio `rho` stands for the speeds
/// within half a step `step` of `rho·fr`; the comb is looked for across them (in
/// [`COMB_SUBSTEPS`], finer than [`view::COMB_TOLERANCE`] wherever the step is a few per cent),
/// its lines counted as [`BandView::new`] counts them at the speed used (the faults' harmonic
/// windows at that ratio excluded), and masked at the speed where the bands hold the most when
/// one band holds [`view::COMB_MIN_LINES`]. Without this, a template searched over a range a
/// declared speed is uncertain by settles where its lines fall on a shaft comb: on a machine
/// declared 5 % fast with once-per-rev impacts, BPFI 4.93 fr read at a ratio placing BPFI×1..3
/// on the shaft's 5th, 10th and 15th orders (`false_alarm.md`, *Declared-speed error*).
fn shaft_masked_at(
    views: &[BandView],
    all: &[Template],
    fr: f64,
    rho: f64,
    step: f64,
) -> Option<Vec<BandView>> {
    let kinematic: Vec<(f64, f64)> = all
        .iter()
        .flat_map(|t| t.at_speed(rho).harmonic_windows().collect::<Vec<_>>())
        .collect();
    let (lines, speed) = (0..=COMB_SUBSTEPS)
        .map(|i| {
            let r = rho + step * (i as f64 / COMB_SUBSTEPS as f64 - 0.5);
            let f = fr * r;
            let per_band: Vec<usize> = views
                .iter()
                .map(|v| v.shaft_comb_lines(f, &kinematic))
                .collect();
            let shown = per_band.iter().any(|&n| n >= view::COMB_MIN_LINES);
            (if shown { per_band.iter().sum() } else { 0 }, f)
        })
        .fold((0, 0.0), |b, c| if c.0 > b.0 { c } else { b });
    (lines > 0).then(|| {
        views
            .iter()
            .map(|v| v.with_shaft_orders_at(speed))
            .collect()
    })
}

/// The speed ratios searched for a relative speed uncertainty `u` (steps of half the narrowest
/// fundamental window), and how many of them are independent (windows side by side).
fn speed_ratios(templates: &[Template], u: f64) -> (Vec<f64>, usize) {
    if u <= 0.0 {
        return (vec![1.0], 1);
    }
    let w = templates
        .iter()
        .map(|t| t.ratio.1 - t.ratio.0)
        .fold(f64::INFINITY, f64::min)
        .max(1e-3);
    let steps = ((2.0 * u) / (0.5 * w)).ceil() as usize;
    let rhos = (0..=steps)
        .map(|i| 1.0 - u + 2.0 * u * i as f64 / steps as f64)
        .collect();
    (rhos, ((2.0 * u) / w).ceil().max(1.0) as usize)
}

/// The masked views: every view with the families of `by` (each template with the fundamental
/// it found) masked.
fn masked_views(views: &[BandView], by: &[(Template, f64)]) -> Vec<BandView> {
    views
        .iter()
        .map(|v| {
            let mut w = v.clone();
            for (t, f1) in by {
                for (f, half) in t.family(*f1, w.df) {
                    w.mask_around(f, w.df.max(1e-3 * f).max(half));
                }
            }
            w.refresh();
            w
        })
        .collect()
}

/// How far the fault lines' windows are widened beyond the slip and the lines' own speed
/// tolerance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Slack {
    /// Relative uncertainty of the speed beyond that tolerance (a coarse comb's placement; the
    /// whole search range when no comb confirmed a declared speed).
    pub speed: f64,
    /// Relative uncertainty of the bearing's fault rates (a typical geometry).
    pub rate: f64,
}

/// Run the detector on the bands' squared envelope spectra.
///
/// `slack.speed`: relative uncertainty of the shaft speed beyond the lines' own tolerance, by
/// which every line's window is widened (a coarse comb's placement, or the whole search range
/// when no comb was found); `unconfirmed`: the speed is a declared one no comb confirmed — the
/// detector then runs twice, each at `α/2`: at the declared speed as if it were right, and with
/// the windows widened by `speed_slack` (a fault comb consistent with some speed in the range;
/// each line's reference read with windows of the same width); where both find a fault, the
/// searched reading is reported when its strongest finding's `p_healthy` is at least
/// [`UNCERTAIN_DECADES`] smaller than the declared reading's, else the declared one.
/// `alpha`: the false-alarm probability per recording. `spectrum_comb`: the recording's own
/// spectrum's complete shaft comb (Hz, relative resolution), accepted or not, when it has one —
/// with the speed unconfirmed, an inner race's lines at its exact orders are its
/// ([`spectrum_comb_explains`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn detect(
    spectra: &[EnvelopeSpectrum],
    baseline: &[Option<EnvelopeSpectrum>],
    o: &FaultOrders,
    fr: f64,
    slack: Slack,
    unconfirmed: bool,
    spectrum_comb: Option<(f64, f64)>,
    alpha: f64,
) -> Detection {
    let comb_tolerance = view::COMB_TOLERANCE.max(if unconfirmed { 0.0 } else { slack.speed });
    // a comb of shaft orders or mains multiples is recognised by lines outside the faults'
    // own windows: a 6203's ball-defect rate at 900 rpm (59.8 Hz) is not a mains comb
    let kinematic: Vec<(f64, f64)> = Hypothesis::ALL
        .iter()
        .flat_map(|&h| {
            Template::new(h, o, fr, HARMONICS)
                .widened(slack.speed + slack.rate)
                .harmonic_windows()
                .collect::<Vec<_>>()
        })
        .collect();
    let mut views: Vec<BandView> = spectra
        .iter()
        .enumerate()
        .map(|(i, sp)| {
            BandView::new(
                sp,
                baseline.get(i).and_then(Option::as_ref),
                fr,
                comb_tolerance,
                &kinematic,
            )
        })
        .collect();
    if views.iter().any(|v| v.masks.shaft_orders) {
        for v in &mut views {
            v.mask_shaft_orders(fr);
        }
    }
    if !unconfirmed {
        return detect_at(
            spectra,
            views,
            o,
            fr,
            slack.speed + slack.rate,
            0.0,
            None,
            alpha,
        );
    }
    // the speeds the shaft may run at: a comb of any of them explains lines at its orders
    let shaft = Some(ShaftCheck {
        range: [fr * (1.0 - slack.speed), fr * (1.0 + slack.speed)],
        spectrum_comb,
    });
    let at_declared = detect_at(
        spectra,
        views.clone(),
        o,
        fr,
        slack.rate,
        0.0,
        shaft,
        0.5 * alpha,
    );
    let searched = detect_at(
        spectra,
        views,
        o,
        fr,
        slack.rate,
        slack.speed,
        shaft,
        0.5 * alpha,
    );
    // a fault is reported when either reading finds one (at α/2 each: α in all); where both
    // do, the declared reading names it unless the searched one's strongest finding is
    // decisively rarer on a healthy machine (by [`UNCERTAIN_DECADES`], as two hypotheses are
    // told apart; the searched probability carries its search): a declared speed 1 % off puts
    // another fault's sideband where this fault's fundamental stands, and the first reading
    // to find something is not thereby the better one
    match (strongest_p(&at_declared), strongest_p(&searched)) {
        (Some(d), Some(s))
            if d.max(1e-300).log10() - s.max(1e-300).log10() >= UNCERTAIN_DECADES =>
        {
            Detection {
                stage: SpeedStage::Searched,
                ..searched
            }
        }
        (Some(_), _) => Detection {
            stage: SpeedStage::Declared,
            ..at_declared
        },
        (None, _) => Detection {
            stage: SpeedStage::Searched,
            ..searched
        },
    }
}

/// The smallest `p_healthy` among a detection's reported hypotheses (confirmed or
/// `uncertain`), `None` when it reports none.
fn strongest_p(d: &Detection) -> Option<f64> {
    d.per_hypothesis
        .iter()
        .zip(&d.templates)
        .filter(|(_, t)| d.confirmed.contains(&t.hypothesis) || d.uncertain.contains(&t.hypothesis))
        .map(|(s, _)| s.p_healthy)
        .min_by(f64::total_cmp)
}

/// What may explain a hypothesis's lines when no comb confirmed the speed.
#[derive(Debug, Clone, Copy)]
struct ShaftCheck {
    /// The speeds (Hz) the shaft may run at: a comb of any of them explains lines at its
    /// orders ([`shaft_explains`]).
    range: [f64; 2],
    /// The recording's own spectrum's complete comb (Hz, relative resolution), when it has
    /// one ([`spectrum_comb_explains`]).
    spectrum_comb: Option<(f64, f64)>,
}

/// One reading: windows widened by `speed_slack` (a coarse comb's placement), or the speed
/// searched over `± search` by speed ratios (a declared speed no comb confirmed). `shaft`, when
/// no comb confirmed the speed: a hypothesis whose evidence a shaft comb explains is not
/// significant.
#[allow(clippy::too_many_arguments)]
fn detect_at(
    spectra: &[EnvelopeSpectrum],
    views: Vec<BandView>,
    o: &FaultOrders,
    fr: f64,
    speed_slack: f64,
    search: f64,
    shaft: Option<ShaftCheck>,
    alpha: f64,
) -> Detection {
    let base: Vec<Template> = Hypothesis::ALL
        .iter()
        .map(|&h| Template::new(h, o, fr, HARMONICS).widened(speed_slack))
        .collect();
    let (rhos, independent) = speed_ratios(&base, search);
    let level = alpha / Hypothesis::ALL.len() as f64;
    let strong =
        |s: &Significance| s.p_healthy <= level && s.modulation_depth >= MIN_MODULATION_DEPTH;
    // every template shares the shaft rate `fr`: the ratios' masked views are the same for all
    let ratios = searched_ratios(&views, &base, fr, &rhos);
    let scans: Vec<Scan> = base
        .iter()
        .map(|t| scan(t, &base, &views, &ratios, independent))
        .collect();
    drop(ratios);
    // each hypothesis at the speed it read best at
    let templates: Vec<Template> = base
        .iter()
        .zip(&scans)
        .map(|(t, s)| t.at_speed(s.rho))
        .collect();
    let mut per_hypothesis: Vec<Significance> = scans
        .iter()
        .map(|s| significance(s, &views[s.band], spectra[s.band].band_hz, speed_slack))
        .collect();
    if let Some(check) = shaft {
        for ((sig, s), t) in per_hypothesis.iter_mut().zip(&scans).zip(&templates) {
            if inner_near_comb(t, views[s.band].df, speed_slack) {
                if let Some((fc, resolution)) = check.spectrum_comb
                    && spectrum_comb_explains(&views, &views[s.band], &s.reading, fc, resolution)
                {
                    sig.shaft_comb_hz = Some(fc);
                    sig.p_healthy = 1.0;
                }
                continue;
            }
            if let Some(f) = shaft_explains(&views, &views[s.band], &s.reading, check.range) {
                sig.shaft_comb_hz = Some(f);
                sig.p_healthy = 1.0;
            }
        }
    }
    // a slower source's comb holding a fault's lines is that source's, not the fault's — asked
    // where no comb confirmed the speed (a template searched over it settles on any comb
    // within reach; at a measured speed the windows are the slip's, and a real fault's own
    // family — the cage and the load zone modulating its impacts — fills the orders between)
    for ((sig, s), t) in per_hypothesis.iter_mut().zip(&scans).zip(&templates) {
        if sig.p_healthy >= 1.0 || shaft.is_none() {
            continue;
        }
        if let Some(f) = slower_comb_explains(&views[s.band], &s.reading, t) {
            sig.slower_comb_hz = Some(f);
            sig.p_healthy = 1.0;
        }
    }
    // significant hypotheses, strongest first
    let order = strongest_first(&per_hypothesis, strong);
    let (confirmed, uncertain) = confirm(
        &order,
        &mut per_hypothesis,
        &templates,
        &views,
        independent,
        level,
    );
    for &i in &confirmed {
        per_hypothesis[i].significant = true;
    }
    let mut confirmed: Vec<Hypothesis> =
        confirmed.iter().map(|&i| templates[i].hypothesis).collect();
    confirmed.sort_by_key(|h| Hypothesis::ALL.iter().position(|x| x == h));
    Detection {
        per_hypothesis,
        readings: scans.into_iter().map(|s| s.reading).collect(),
        confirmed,
        uncertain,
        views,
        templates,
        stage: SpeedStage::Measured,
    }
}

/// A hypothesis's scan `s` as its significance (not yet judged: `significant` false, nothing
/// explaining it), its fundamental read in `v`, the view of its best band `band_hz`.
fn significance(s: &Scan, v: &BandView, band_hz: [f64; 2], speed_slack: f64) -> Significance {
    let fundamental_hz = fundamental_hz(v, &s.reading).unwrap_or(0.0);
    Significance {
        band_index: s.band,
        band_hz,
        statistic_db: s.reading.statistic_db,
        fisher: s.reading.fisher,
        lines_read: s.reading.terms.len(),
        fundamental_hz,
        speed_slack,
        speed_ratio: s.rho,
        p_band: s.reading.p,
        modulation_depth: s.depth,
        p_healthy: s.p_healthy,
        null_size: s
            .reading
            .terms
            .iter()
            .map(|r| r.null_size)
            .min()
            .unwrap_or(0),
        significant: false,
        explained_by: None,
        p_given_stronger: None,
        masks: s.masks,
        shaft_comb_hz: None,
        slower_comb_hz: None,
    }
}

/// The indices of the `strong` hypotheses, strongest first: by the depth of the envelope
/// modulation their lines carry (the probabilities of strong faults all reach their floors),
/// then by probability under healthy, then in [`Hypothesis::ALL`] order.
fn strongest_first(
    per_hypothesis: &[Significance],
    strong: impl Fn(&Significance) -> bool,
) -> Vec<usize> {
    let mut order: Vec<usize> = (0..per_hypothesis.len())
        .filter(|&i| strong(&per_hypothesis[i]))
        .collect();
    order.sort_by(|&a, &b| {
        per_hypothesis[b]
            .modulation_depth
            .total_cmp(&per_hypothesis[a].modulation_depth)
            .then(
                per_hypothesis[a]
                    .p_healthy
                    .total_cmp(&per_hypothesis[b].p_healthy),
            )
            .then(a.cmp(&b))
    });
    order
}

/// Confirm the significant hypotheses of `order` (strongest first): the strongest is confirmed;
/// each other one is confirmed when it stays significant (`≤ level`) with the confirmed ones'
/// families masked, else it is explained by the strongest (`per_hypothesis` records both).
/// Returns the confirmed indices and, when the strongest and another explain each other's lines
/// and cannot be told apart ([`tell_apart`]), the two as uncertain.
fn confirm(
    order: &[usize],
    per_hypothesis: &mut [Significance],
    templates: &[Template],
    views: &[BandView],
    independent: usize,
    level: f64,
) -> (Vec<usize>, Vec<Hypothesis>) {
    let rescan =
        |t: &Template, vs: &[BandView]| scan(t, templates, vs, &AT_SPEED, independent).p_healthy;
    let mut confirmed: Vec<usize> = Vec::new();
    let mut uncertain = Vec::new();
    for &i in order {
        if confirmed.is_empty() {
            confirmed.push(i);
            continue;
        }
        let by: Vec<(Template, f64)> = confirmed
            .iter()
            .map(|&j| (templates[j], per_hypothesis[j].fundamental_hz))
            .collect();
        let p = rescan(&templates[i], &masked_views(views, &by));
        per_hypothesis[i].p_given_stronger = Some(p);
        if p <= level {
            confirmed.push(i);
            continue;
        }
        let first = confirmed[0];
        per_hypothesis[i].explained_by = Some(templates[first].hypothesis);
        // the other way round, for the strongest only: when each explains the other's lines,
        // the two are told apart by their lines' probability and by their harmonics' depth —
        // one decisive and the other not against it names that one; otherwise `uncertain`
        if confirmed.len() == 1 && uncertain.is_empty() {
            let back = rescan(
                &templates[first],
                &masked_views(views, &[(templates[i], per_hypothesis[i].fundamental_hz)]),
            );
            if back > level {
                match tell_apart(&per_hypothesis[first], &per_hypothesis[i]) {
                    Some(true) => {}
                    Some(false) => {
                        per_hypothesis[i].explained_by = None;
                        per_hypothesis[first].explained_by = Some(templates[i].hypothesis);
                        per_hypothesis[first].p_given_stronger = Some(back);
                        confirmed[0] = i;
                    }
                    None => {
                        uncertain = vec![templates[first].hypothesis, templates[i].hypothesis];
                    }
                }
            }
        }
    }
    (confirmed, uncertain)
}

#[cfg(test)]
mod calibration {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// A white-noise squared envelope spectrum: each bin the mean of `k` exponentials.
    fn noise_spectrum(
        rng: &mut rand_chacha::ChaCha8Rng,
        n: usize,
        df: f64,
        k: usize,
    ) -> EnvelopeSpectrum {
        let power = (0..n)
            .map(|_| {
                (0..k)
                    .map(|_| -(1.0 - rng.random::<f64>()).ln())
                    .sum::<f64>()
                    / k as f64
            })
            .collect();
        EnvelopeSpectrum {
            band_hz: [2000.0, 2000.0 + n as f64 * df],
            resolution_hz: df,
            power,
            mean_square: 1.0,
            ..EnvelopeSpectrum::default()
        }
    }

    /// Four noise bands with lines at `lines` (Hz, × the noise's mean power).
    fn bands_with_powers(
        seed: u64,
        df: f64,
        nbins: usize,
        lines: &[(f64, f64)],
    ) -> Vec<EnvelopeSpectrum> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..4)
            .map(|_| {
                let mut s = noise_spectrum(&mut rng, nbins, df, 4);
                for &(f, amp) in lines {
                    if let Some(p) = s.power.get_mut((f / df).round() as usize) {
                        *p += amp;
                    }
                }
                s
            })
            .collect()
    }

    /// Four noise bands with lines of `amp` × the noise's mean power at every frequency of
    /// `lines` (Hz).
    fn bands_with_lines(
        seed: u64,
        df: f64,
        nbins: usize,
        lines: &[f64],
        amp: f64,
    ) -> Vec<EnvelopeSpectrum> {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        (0..4)
            .map(|_| {
                let mut s = noise_spectrum(&mut rng, nbins, df, 4);
                for &f in lines {
                    if let Some(p) = s.power.get_mut((f / df).round() as usize) {
                        *p += amp;
                    }
                }
                s
            })
            .collect()
    }

    /// A comb at exactly 10 Hz in bins of ⅔ Hz, the views built at a declared speed 2 % slow
    /// (9.8 Hz): the declared comb's mask (± a bin) covers the true comb's first three orders,
    /// and its 50 or 60 Hz orders read as a mains comb and are masked too. Asked whether the
    /// comb stands at the orders between lines on its 7th, 14th and 21st orders, the evidence
    /// after the masks holds two of the six; before them, all six.
    #[test]
    fn a_comb_masked_at_a_speed_a_bin_off_is_still_shown() {
        let df = 2.0 / 3.0;
        let nbins = (600.0 / df) as usize;
        let comb: Vec<f64> = (1..=50).map(|k| k as f64 * 10.0).collect();
        let views: Vec<BandView> = bands_with_lines(5, df, nbins, &comb, 60.0)
            .iter()
            .map(|s| BandView::new(s, None, 9.8, view::COMB_TOLERANCE, &[]))
            .collect();
        assert!(views.iter().all(|v| v.masks.shaft_orders));
        let tol = |f: f64| comb_tol(&views[0], f);
        let after_masks = [10.0, 20.0, 30.0, 40.0, 50.0, 60.0]
            .iter()
            .filter(|&&f| views.iter().any(|w| w.holds_line(f, tol(f))))
            .count();
        assert!(after_masks < SHAFT_MIN_ORDERS, "{after_masks}");
        assert!(comb_shown(&views, &views[0], 10.0, &[7.0, 14.0, 21.0]));
    }

    /// A shaft comb (once-per-rev impacts: every order of 10 Hz to 400 Hz) read at a declared
    /// speed 5 % fast, no comb confirming it: a template searching the range settles on the
    /// comb's orders, and the comb explains them, so no fault is called; an outer race at the
    /// same declared speed (BPFO×1..6 beside the shaft's 1× and 2×) is still called, its lines
    /// explained by no shaft comb.
    #[test]
    fn a_shaft_comb_at_an_unconfirmed_speed_is_no_fault() {
        let o = bearing_model::BearingSpec::parse("6308").unwrap().orders;
        let (fr_true, fr) = (10.0, 10.5);
        let df = 1.0 / 6.0;
        let nbins = (1000.0 / df) as usize;
        let slack = Slack {
            speed: 0.1,
            rate: 0.0,
        };
        let comb: Vec<f64> = (1..=40).map(|k| k as f64 * fr_true).collect();
        for seed in 1..=5 {
            let spectra = bands_with_lines(seed, df, nbins, &comb, 60.0);
            let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
            assert!(
                d.confirmed.is_empty() && d.uncertain.is_empty(),
                "seed {seed}: {:?} {:?}",
                d.confirmed,
                d.uncertain
            );
            let explained = d
                .per_hypothesis
                .iter()
                .filter_map(|s| s.shaft_comb_hz)
                .collect::<Vec<_>>();
            assert!(
                explained.iter().all(|f| (f - fr_true).abs() < 0.05),
                "{explained:?}"
            );
        }
        let outer: Vec<f64> = (1..=6)
            .map(|k| k as f64 * o.bpfo * fr_true)
            .chain([fr_true, 2.0 * fr_true])
            .collect();
        let spectra = bands_with_lines(1, df, nbins, &outer, 60.0);
        let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
        assert!(
            d.confirmed.contains(&Hypothesis::Outer),
            "{:?}",
            d.confirmed
        );
        let outer = Hypothesis::ALL
            .iter()
            .position(|h| *h == Hypothesis::Outer)
            .unwrap();
        assert_eq!(d.per_hypothesis[outer].shaft_comb_hz, None);
    }

    /// A catalogue's typical geometry (± 3 %) puts an inner race's near-comb (`BPFI/5`,
    /// 0.986 fr on a 6308) anywhere within 3 % of the shaft's orders, so the fitted-rate check
    /// ([`shaft_explains`]) is not asked of it. A once-per-rev comb at 10.05 Hz (every order to
    /// 400 Hz), the declared 10 Hz unconfirmed: read against no spectrum comb, the inner race's
    /// template settles on the comb's orders 4, 5, 6 and is called; the recording's own
    /// spectrum showing the comb at 10.05 Hz, the lines stand at its exact orders and nothing is
    /// called. A real inner race at the same speed (its family `k·BPFI ± fr` beside the shaft's
    /// 1× and 2×) is called with that spectrum comb as without it.
    #[test]
    fn lines_at_the_spectrum_comb_s_exact_orders_are_the_shaft_s() {
        let o = bearing_model::BearingSpec::parse("6308").unwrap().orders;
        let (fr_true, fr) = (10.05, 10.0);
        let df = 1.0 / 6.0;
        let nbins = (1000.0 / df) as usize;
        let slack = Slack {
            speed: 0.1,
            rate: 0.03,
        };
        let inner = Hypothesis::ALL
            .iter()
            .position(|h| *h == Hypothesis::Inner)
            .unwrap();
        let comb_hz = Some((fr_true, 8e-4));
        let comb: Vec<f64> = (1..=40).map(|k| k as f64 * fr_true).collect();
        let spectra = bands_with_lines(3, df, nbins, &comb, 60.0);
        let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
        assert!(
            d.confirmed.contains(&Hypothesis::Inner) || d.uncertain.contains(&Hypothesis::Inner),
            "without the spectrum's comb: {:?} {:?}",
            d.confirmed,
            d.uncertain
        );
        let d = detect(&spectra, &[], &o, fr, slack, true, comb_hz, 0.01);
        assert!(
            d.confirmed.is_empty() && d.uncertain.is_empty(),
            "{:?} {:?}",
            d.confirmed,
            d.uncertain
        );
        assert_eq!(d.per_hypothesis[inner].shaft_comb_hz, Some(fr_true));
        let bpfi = o.bpfi * fr_true;
        let family: Vec<f64> = (1..=4)
            .flat_map(|k| [-1.0, 0.0, 1.0].map(|m| k as f64 * bpfi + m * fr_true))
            .chain([fr_true, 2.0 * fr_true])
            .collect();
        let spectra = bands_with_lines(4, df, nbins, &family, 60.0);
        for spectrum_comb in [None, comb_hz] {
            let d = detect(&spectra, &[], &o, fr, slack, true, spectrum_comb, 0.01);
            assert!(
                d.confirmed.contains(&Hypothesis::Inner),
                "{spectrum_comb:?}: {:?} {:?}",
                d.confirmed,
                d.uncertain
            );
            assert_eq!(d.per_hypothesis[inner].shaft_comb_hz, None);
        }
    }

    /// MFPT's NICE bearing, an inner race at a shaft 1.1 % slower than the declared 25 Hz and
    /// no comb confirming either: at the declared speed the ball's `BSF − FTF` window (4.70 fr)
    /// holds the inner race's fundamental (4.755 × 0.989 fr) and the ball reads significant
    /// there (under the former rule, the declared reading whenever it found anything, 6 of
    /// these 12 seeds read `ball`); read over the range, the inner race's whole family stands
    /// at one speed, decades rarer on a healthy machine, and names the fault (or `uncertain`
    /// with it among the two). The declared speed right, its own reading names the fault.
    #[test]
    fn a_decisively_stronger_searched_reading_names_the_fault() {
        let o = bearing_model::BearingSpec::parse("NICE").unwrap().orders;
        let fr = 25.0;
        let df = 0.25;
        let nbins = (2000.0 / df) as usize;
        let slack = Slack {
            speed: 0.1,
            rate: 0.0,
        };
        let family = |fr_true: f64| -> Vec<(f64, f64)> {
            let bpfi = o.bpfi * fr_true;
            (1..=4)
                .flat_map(|k| {
                    [(-1.0, 20.0), (0.0, 60.0), (1.0, 20.0)]
                        .map(|(m, a)| (k as f64 * bpfi + m * fr_true, a))
                })
                .chain([(fr_true, 30.0)])
                .collect()
        };
        let mut inner_alone = 0;
        for seed in 1..=12 {
            let spectra = bands_with_powers(seed, df, nbins, &family(24.73));
            let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
            assert_eq!(d.stage, SpeedStage::Searched, "seed {seed}");
            assert!(
                d.confirmed == [Hypothesis::Inner] && d.uncertain.is_empty()
                    || d.uncertain.contains(&Hypothesis::Inner),
                "seed {seed}: {:?} {:?}",
                d.confirmed,
                d.uncertain
            );
            inner_alone += usize::from(d.uncertain.is_empty());
        }
        assert!(inner_alone >= 10, "{inner_alone}/12 inner alone");
        // the declared speed right: its reading names the fault
        for seed in 1..=3 {
            let spectra = bands_with_powers(seed, df, nbins, &family(fr));
            let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
            assert_eq!(d.stage, SpeedStage::Declared, "seed {seed}");
            assert_eq!(d.confirmed, [Hypothesis::Inner], "seed {seed}");
        }
    }

    /// Another shaft's once-per-turn impacts: a comb at a rate `f₀` not an order of the measured
    /// shaft, with `m·f₀` inside a fault's window (m = 3…7; its lines at every order of `f₀` to
    /// 1 kHz), at a declared speed no comb confirmed. Its lines between the fault's harmonics are
    /// the slower source's: that fault is not called, and its hypothesis names the comb's rate. The
    /// fault alone (its harmonics, an inner race's `± fr`, a ball's spin lines at odd multiples
    /// of half its rate and `± FTF`) is still called, explained by no slower comb.
    #[test]
    fn a_slower_comb_holding_a_fault_s_lines_is_no_fault() {
        let o = bearing_model::BearingSpec::parse("6308").unwrap().orders;
        let fr = 10.0;
        let df = 1.0 / 6.0;
        let nbins = (1000.0 / df) as usize;
        // a declared speed no comb confirmed (the other source's comb is no shaft comb)
        let slack = Slack {
            speed: 0.1,
            rate: 0.0,
        };
        let index = |h: Hypothesis| Hypothesis::ALL.iter().position(|x| *x == h).unwrap();
        for (i, (h, order, m)) in [
            // m not a divisor of the 8 balls: m | Z is a rate of the bearing's own
            (Hypothesis::Outer, o.bpfo, 5),
            (Hypothesis::Outer, o.bpfo, 7),
            (Hypothesis::Inner, o.bpfi, 3),
            (Hypothesis::Inner, o.bpfi, 7),
            (Hypothesis::Ball, o.ball_defect, 3),
        ]
        .into_iter()
        .enumerate()
        {
            // inside the fault's slip window (an inner race's rate rises with slip)
            let slip = if h == Hypothesis::Inner { 1.006 } else { 0.992 };
            let f0 = slip * order * fr / m as f64;
            // short impacts ringing a mode: the comb's lines fade with frequency
            let comb: Vec<(f64, f64)> = (1..)
                .map(|k| k as f64 * f0)
                .take_while(|&f| f < 1000.0)
                .map(|f| (f, 300.0 * (-f / 150.0).exp()))
                .collect();
            let spectra = bands_with_powers(10 + i as u64, df, nbins, &comb);
            let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
            // the comb's lines at the fault's harmonics are evidence enough on their own
            let sig = &d.per_hypothesis[index(h)];
            assert!(
                sig.p_band * 4.0 <= 0.01 / 3.0 && sig.modulation_depth >= MIN_MODULATION_DEPTH,
                "{h:?} m = {m}: {sig:?}"
            );
            // (another hypothesis may still read the comb where its m divides the balls)
            assert!(
                !d.confirmed.contains(&h) && !d.uncertain.contains(&h),
                "{h:?} m = {m}: {:?} {:?}",
                d.confirmed,
                d.uncertain
            );
            let named = d.per_hypothesis[index(h)].slower_comb_hz;
            assert!(
                named.is_some_and(|f| (f - f0).abs() < 0.01 * f0),
                "{h:?} m = {m}: {named:?} for {f0}"
            );
        }
        let fault = |h: Hypothesis| -> Vec<f64> {
            let f1 = fr
                * match h {
                    Hypothesis::Outer => o.bpfo,
                    Hypothesis::Inner => o.bpfi,
                    Hypothesis::Ball => o.ball_defect,
                };
            let ftf = o.ftf * fr * 0.992;
            let mut v: Vec<f64> = (1..=6).map(|k| k as f64 * f1).collect();
            match h {
                Hypothesis::Outer => {}
                Hypothesis::Inner => v.extend([f1 - fr, f1 + fr, 2.0 * f1 - fr, 2.0 * f1 + fr]),
                Hypothesis::Ball => {
                    v.extend((0..6).map(|k| (k as f64 + 0.5) * f1));
                    v.extend([f1 - ftf, f1 + ftf]);
                }
            }
            v
        };
        for (i, h) in Hypothesis::ALL.into_iter().enumerate() {
            let spectra = bands_with_lines(20 + i as u64, df, nbins, &fault(h), 60.0);
            let d = detect(&spectra, &[], &o, fr, slack, true, None, 0.01);
            assert_eq!(d.confirmed, vec![h], "{h:?}: {:?}", d.uncertain);
            assert_eq!(d.per_hypothesis[index(h)].slower_comb_hz, None, "{h:?}");
        }
    }

    /// Four white-noise bands (16 averages) as the detector views them, shaft at `fr`.
    fn noise_views(
        rng: &mut rand_chacha::ChaCha8Rng,
        nbins: usize,
        df: f64,
        fr: f64,
    ) -> Vec<BandView> {
        (0..4)
            .map(|_| noise_spectrum(rng, nbins, df, 16))
            .map(|s| BandView::new(&s, None, fr, view::COMB_TOLERANCE, &[]))
            .collect()
    }

    /// At most the nominal share of band readings `pb` and searches `ph` is significant at
    /// 10 %, 1 % and 0.33 % (with a sampling slack).
    fn assert_calibrated(pb: &[f64], ph: &[f64]) {
        let frac =
            |v: &[f64], l: f64| v.iter().filter(|p| **p <= l).count() as f64 / v.len() as f64;
        for l in [0.1, 0.01, 0.0033] {
            eprintln!("level {l}: band {} search {}", frac(pb, l), frac(ph, l));
        }
        for (l, slack) in [(0.1, 0.02), (0.01, 0.005), (0.0033, 0.003)] {
            assert!(frac(pb, l) <= l + slack, "band at {l}: {}", frac(pb, l));
            assert!(frac(ph, l) <= l + slack, "search at {l}: {}", frac(ph, l));
        }
    }

    /// On white-noise spectra (four bands, 16 averages, fr/32 bins) each band's line test and
    /// the band search are calibrated or conservative: at most the nominal share of hypotheses
    /// is called significant at 10 %, 1 % and 0.33 % (with the sampling error of 900
    /// hypotheses).
    #[test]
    fn line_test_is_calibrated_on_noise() {
        let o = bearing_model::BearingSpec::parse("6205").unwrap().orders;
        let fr = 29.95;
        let df = fr / 32.0;
        let nbins = (1000.0 / df) as usize;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let mut pb = Vec::new();
        let mut ph = Vec::new();
        for _ in 0..300 {
            let views = noise_views(&mut rng, nbins, df, fr);
            for &h in &Hypothesis::ALL {
                let t = Template::new(h, &o, fr, HARMONICS);
                for v in &views {
                    pb.push(read_band(v, &t).p);
                }
                let all: Vec<Template> = Hypothesis::ALL
                    .iter()
                    .map(|&g| Template::new(g, &o, fr, HARMONICS))
                    .collect();
                ph.push(scan(&t, &all, &views, &AT_SPEED, 1).p_healthy);
            }
        }
        assert_calibrated(&pb, &ph);
    }

    /// A 6205 at 29.95 Hz, bins of fr/16, and its three templates widened by 8 % (a
    /// catalogue's typical geometry and a speed no comb confirmed).
    fn wide_6205_templates() -> (f64, f64, Vec<Template>) {
        let o = bearing_model::BearingSpec::parse("6205").unwrap().orders;
        let fr = 29.95;
        let all = Hypothesis::ALL
            .iter()
            .map(|&g| Template::new(g, &o, fr, HARMONICS).widened(0.08))
            .collect();
        (fr, fr / 16.0, all)
    }

    /// Each template of `all` read in every view of `views` (at least three lines each, and
    /// `check`ed) and searched over them: the band readings' probabilities onto `pb`, the
    /// searches' onto `ph`.
    fn read_wide(
        all: &[Template],
        views: &[BandView],
        pb: &mut Vec<f64>,
        ph: &mut Vec<f64>,
        check: impl Fn(&Template, &BandView, &BandReading),
    ) {
        for t in all {
            for v in views {
                let r = read_band(v, t);
                assert!(
                    r.terms.len() >= 3,
                    "{:?}: {} lines",
                    t.hypothesis,
                    r.terms.len()
                );
                check(t, v, &r);
                pb.push(r.p);
            }
            ph.push(scan(t, all, views, &AT_SPEED, 1).p_healthy);
        }
    }

    /// Windows widened by 8 % (a catalogue's typical geometry and a speed no comb confirmed)
    /// overlap: a ball's `± FTF` windows reach into its fundamental's. A peak in the overlap
    /// read by both lines would count twice in Fisher's statistic, which asks independent
    /// lines; each bin is read by one line only (`LineTest::read_windows`). On white noise the
    /// band's line test and the search stay calibrated or conservative (1800 hypotheses searched),
    /// and
    /// the windows do overlap (else this test would not test it).
    #[test]
    fn overlapping_wide_windows_are_calibrated_on_noise() {
        let (fr, df, all) = wide_6205_templates();
        let nbins = (4000.0 / df) as usize;
        let ball = all[Hypothesis::ALL
            .iter()
            .position(|h| *h == Hypothesis::Ball)
            .unwrap()]
        .windows(0.5 * df);
        let overlap =
            |a: &template::Window, b: &template::Window| a.lo_hz < b.hi_hz && b.lo_hz < a.hi_hz;
        assert!(
            ball.iter()
                .any(|w| w.term == Term::Sideband(-1) && overlap(w, &ball[0]))
        );
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        let (mut pb, mut ph) = (Vec::new(), Vec::new());
        for _ in 0..600 {
            let views = noise_views(&mut rng, nbins, df, fr);
            read_wide(&all, &views, &mut pb, &mut ph, |_, _, _| {});
        }
        assert_calibrated(&pb, &ph);
    }

    /// A band whose shaft comb is masked at every order, read with windows widened by 8 %: the
    /// runs between masked orders (16 bins) are shorter than a third harmonic's window, and a
    /// reference of whole windows meeting no masked bin would hold none. Masked bins hold no
    /// evidence in a line's window nor in the reference's, so the reference's windows of as
    /// many unmasked bins span them: every line keeps a reference rich enough for a tail, and
    /// on white noise beside the comb the band's test and the search stay calibrated or
    /// conservative.
    #[test]
    fn a_masked_shaft_comb_leaves_wide_windows_their_reference() {
        let (fr, df, all) = wide_6205_templates();
        let nbins = (8000.0 / df) as usize;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let (mut pb, mut ph) = (Vec::new(), Vec::new());
        for _ in 0..400 {
            let views: Vec<BandView> = (0..4)
                .map(|_| {
                    let mut s = noise_spectrum(&mut rng, nbins, df, 16);
                    let mut f = fr;
                    while let Some(p) = s.power.get_mut((f / df).round() as usize) {
                        *p += 20.0;
                        f += fr;
                    }
                    BandView::new(&s, None, fr, view::COMB_TOLERANCE, &[])
                })
                .collect();
            read_wide(&all, &views, &mut pb, &mut ph, |t, v, r| {
                assert!(v.masks.shaft_orders);
                for term in &r.terms {
                    assert!(
                        term.null_size >= linetest::MIN_TAIL_WINDOWS,
                        "{:?}: {} reference windows",
                        t.hypothesis,
                        term.null_size
                    );
                }
            });
        }
        assert_calibrated(&pb, &ph);
    }
}
