//! Diagnosis of a bearing whose geometry nobody knows (`--bearing unknown`): the fault's order
//! is found from the squared envelope spectrum's non-integer combs, its kind named from their
//! relations, and the report says it guessed.
//!
//! 1. The speed, residual and bands are those of [`diagnose`](crate::diagnose), planned for fault
//!    orders up to [`MAX_ORDER`].
//! 2. **Combs**: for every fundamental order `o` from [`MIN_ORDER`] to [`MAX_ORDER`] on a grid of
//!    half the slip window, except within [`view::COMB_TOLERANCE`]·2 of an integer (a comb at
//!    integer orders is the shaft's), an outer-race-like template (harmonics 1..3 over
//!    `o·fr·[`[`SLIP`]`]`) is read in every band by the line test of [`crate::detect`] (each line
//!    against the band's clear windows off the template's lattice, Fisher's method). The search
//!    over `B` bands and `N` independent orders is paid for by Bonferroni:
//!    `p = min(1, B·N·min p_b)`. The comb found is the most significant one whose harmonics
//!    modulate the envelope deeply enough ([`MIN_MODULATION_DEPTH`]), reported when
//!    `p ≤ α`. (The catalogue path's test for a slower source's comb,
//!    `detect::slower_comb_explains`, is not asked here: without the geometry the bearing's own
//!    cage modulation cannot be told from another source — asked, it cost 11 of 128 detected
//!    faulty machines for 5 of 38 healthy alarms, `docs/journal/diagnosis.md`.)
//!
//!    When no shaft comb gave the speed (the declared one is then uncertain by ± u, 10 %), the
//!    comb is still one in Hz: its lines are read at the comb tolerance, no shaft order is
//!    masked or skipped (none was seen), the orders searched widen to
//!    `[MIN_ORDER·(1 − u), MAX_ORDER·(1 + u)]`, and the order found is reported ± u
//!    ([`BearingGuess::order_uncertainty`]); the `± fr` sidebands are then searched over
//!    `fr·(1 ± u)` and the cage orders over their range widened by u (Bonferroni over the
//!    steps), and no partner comb is sought (`BPFO + BPFI = n·fr` needs the rate).
//! 3. **Its kind**, from what else the spectrum holds around it (each a line test of two
//!    sideband windows in the comb's band, significant at [`SIDEBAND_LEVEL`]):
//!    - `± fr` sidebands: the defect turns with the shaft through the load zone — **inner race**;
//!    - else `± ν·fr` sidebands for a cage order ν in `[0.30, 0.48]` (`FTF = ½(1 − r)` for
//!      `r = d/D·cos α` up to 0.4): the defect turns with the cage — **ball** (ν searched,
//!      Bonferroni over its independent steps);
//!    - else a defect fixed in the load zone — **outer race**.
//!
//!    A second significant comb `o₂` with `o + o₂` within 2 % of an integer `n` (5–24) and
//!    `max/min` in `[(1 + 0.1)/(1 − 0.1), (1 + 0.45)/(1 − 0.45)]`, and not a harmonic or
//!    sub-harmonic of it (ratio within 1 % of an integer), is the other race's
//!    (`BPFO + BPFI = n`, `BPFI/BPFO = (1 + r)/(1 − r)`): both races are named, the higher order
//!    inner. The report lists the geometries each reading of the order allows (`n` balls and
//!    `r` for BPFO or BPFI; `r` for the ball-defect rate `(1 − r²)/r`).

use serde::{Deserialize, Serialize};

use residual_features::SpectralEngine;

use crate::detect::linetest::{BandReading, LineTest};
use crate::detect::template::{Sidebands, Template, Term, Window};
use crate::detect::view::{self, BandView};
use crate::detect::{MIN_MODULATION_DEPTH, Masks, Significance};
use crate::driver::{FirstLook, Look, analyse, diagnose_tracked, first_look};
use crate::report::band_choice;
use crate::{
    Baseline, DiagnoseOptions, Diagnosis, EnvelopeSpectrum, HARMONICS, Hypothesis,
    HypothesisEvidence, OperatingPointUsed, Result, Scores, SearchedLine, Thresholds, check_fs,
};
use bearing_model::FaultOrders;

/// Lowest fault order searched (× fr).
pub const MIN_ORDER: f64 = 1.5;
/// Highest fault order searched (× fr): a bearing of up to about 20 rolling elements.
pub const MAX_ORDER: f64 = 10.0;
/// Slip window of a comb's fundamental, as ratios of the order searched.
pub const SLIP: (f64, f64) = (0.977, 1.0063);
/// A pair of sidebands names the fault's kind when its line test gives at most this.
pub const SIDEBAND_LEVEL: f64 = 0.01;
/// Cage orders searched for a ball fault's sidebands.
pub const CAGE_ORDERS: (f64, f64) = (0.30, 0.48);

/// What was guessed about a bearing nobody gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BearingGuess {
    /// Order (× fr) of the comb found: its fundamental's line over the shaft rate.
    pub fault_order: f64,
    /// Its fundamental, Hz.
    pub fault_hz: f64,
    /// Probability under "healthy" of a comb this strong somewhere in the search (Bonferroni
    /// over the bands and the independent orders).
    pub p_healthy: f64,
    /// Modulation depth of its harmonics.
    pub modulation_depth: f64,
    /// Orders searched (× fr).
    pub orders_searched: [f64; 2],
    /// Independent orders in the search.
    pub independent_orders: usize,
    /// The fault named (`None`: no comb significant).
    pub named: Option<Hypothesis>,
    /// Why that kind.
    pub basis: String,
    /// Line test of the `± fr` sidebands around the fundamental.
    pub shaft_sidebands_p: f64,
    /// The cage order whose `± ν·fr` sidebands read best, and their line test (Bonferroni over
    /// the cage orders searched).
    pub cage_sidebands: Option<[f64; 2]>,
    /// A second comb with `o + o₂ ≈ n` (the other race), order and probability.
    pub second_comb: Option<[f64; 2]>,
    /// The geometries each reading of the order allows.
    pub interpretations: Vec<String>,
    /// Relative uncertainty of `fault_order`: 0 when a shaft comb gave the speed, else the
    /// declared speed's (the comb was found in Hz).
    #[serde(default)]
    pub order_uncertainty: f64,
    /// "guessed": the report's plain statement.
    pub note: String,
}

/// The comb search's reading of one order.
struct CombReading {
    order: f64,
    band: usize,
    reading: BandReading,
    depth: f64,
    p: f64,
}

/// Diagnose a recording on a bearing whose geometry is unknown (see the module documentation).
///
/// # Errors
/// As [`crate::diagnose_with_options`].
pub fn diagnose_unknown_bearing(
    signal: &crate::Signal<'_>,
    baseline: Option<&Baseline>,
    options: &DiagnoseOptions,
) -> Result<Diagnosis> {
    crate::driver::with_engine(|engine| unknown_in(engine, signal, baseline, options, Look::Track))
}

fn unknown_in(
    engine: &mut SpectralEngine,
    signal: &crate::Signal<'_>,
    baseline: Option<&Baseline>,
    options: &DiagnoseOptions,
    look: Look,
) -> Result<Diagnosis> {
    let fs_hz = signal.fs_hz();
    check_fs(fs_hz)?;
    let options = options.check()?;
    let spectrum_comb = match first_look(engine, signal, baseline, &options, look)? {
        FirstLook::Steady(c) => c,
        // a tracked record the search refuses is read at one speed instead
        FirstLook::Varying(t, m, c) => {
            match diagnose_tracked(*t, m, &options, |s, o, l| unknown_in(engine, s, None, o, l)) {
                Ok(d) => return Ok(d),
                Err(_) => c,
            }
        }
    };
    // bands wide enough for three harmonics of the highest order searched
    let plan_orders = FaultOrders {
        ftf: CAGE_ORDERS.1,
        bpfo: MAX_ORDER,
        bpfi: MAX_ORDER,
        ball_spin: 0.5 * MAX_ORDER,
        ball_defect: MAX_ORDER,
    };
    let a = analyse(
        engine,
        signal,
        &plan_orders,
        0.0,
        baseline,
        &options,
        spectrum_comb,
    )?;
    let fr = a.fr;
    // no comb gave the speed: the fault's fundamental is still a comb in Hz (its harmonics
    // k·f within the slip window whatever the shaft's rate), so the lines are read at the comb
    // tolerance, no shaft order is masked (none was seen), and the orders searched widen by the
    // speed's uncertainty (an order is then known to ± that uncertainty, the report says so).
    // Reading the windows at the speed's ± 10 % instead masked every line above the 5th order
    // and found 22 of 302 simulated faulty machines (false_alarm_unknown.md, 2026-12-06)
    let u = a.finding.relative_uncertainty;
    let unconfirmed = u > view::COMB_TOLERANCE;
    let tolerance = if unconfirmed {
        view::COMB_TOLERANCE
    } else {
        view::COMB_TOLERANCE.max(u)
    };
    let (lo_order, hi_order) = if unconfirmed {
        (MIN_ORDER * (1.0 - u), MAX_ORDER * (1.0 + u))
    } else {
        (MIN_ORDER, MAX_ORDER)
    };
    let views: Vec<BandView> = a
        .spectra
        .iter()
        .enumerate()
        .map(|(i, sp)| {
            let mut v = BandView::new(
                sp,
                a.base_spectra.get(i).and_then(Option::as_ref),
                fr,
                tolerance,
                &[],
            );
            if !unconfirmed {
                v.mask_shaft_orders(fr);
            }
            v
        })
        .collect();
    let step = 0.5 * (SLIP.1 - SLIP.0);
    let mut orders = Vec::new();
    let mut o = lo_order;
    while o <= hi_order {
        if unconfirmed || (o - o.round()).abs() > 2.0 * view::COMB_TOLERANCE * o {
            orders.push(o);
        }
        o *= 1.0 + step;
    }
    let independent = ((hi_order / lo_order).ln() / (1.0 + 2.0 * step).ln()).ceil() as usize;
    let looks = (views.len() * independent) as f64;
    let readings: Vec<CombReading> = orders
        .iter()
        .map(|&o| read_comb(&views, comb_template(o, fr), looks))
        .collect();
    let alpha = options.false_alarm;
    let strong = |c: &CombReading| c.p <= alpha && c.depth >= MIN_MODULATION_DEPTH;
    let best = readings
        .iter()
        .filter(|c| strong(c))
        .min_by(|a, b| a.p.total_cmp(&b.p).then(b.depth.total_cmp(&a.depth)))
        .or_else(|| readings.iter().min_by(|a, b| a.p.total_cmp(&b.p)));
    let guess = best.map(|c| {
        name_comb(
            c,
            &readings,
            &views,
            Speed {
                fr,
                uncertainty: if unconfirmed { u } else { 0.0 },
            },
            strong(c),
            [lo_order, hi_order],
            independent,
        )
    });
    Ok(report(a, fs_hz, best, guess, &views, alpha))
}

/// An outer-race-like template of order `o` (no sidebands).
fn comb_template(o: f64, fr: f64) -> Template {
    Template {
        hypothesis: Hypothesis::Outer,
        fault_hz: o * fr,
        ratio: SLIP,
        harmonics: HARMONICS,
        sidebands: Sidebands::None,
        fr,
        ftf_hz: 0.0,
        speed_slack: 0.0,
    }
}

/// The comb at `t` read in every band; the best band's reading, `p` after `looks` looks.
fn read_comb(views: &[BandView], t: Template, looks: f64) -> CombReading {
    let lattice = t.lattice(views.iter().map(|v| v.top_hz).fold(0.0, f64::max));
    let mut best: Option<CombReading> = None;
    for (b, v) in views.iter().enumerate() {
        let r = LineTest::new(v, &lattice, t.fr).read(&t);
        let depth = crate::detect::harmonics_depth(v, &r);
        let better = best.as_ref().is_none_or(|c| {
            (depth >= MIN_MODULATION_DEPTH, -r.p) > (c.depth >= MIN_MODULATION_DEPTH, -c.reading.p)
        });
        if better {
            best = Some(CombReading {
                order: t.fault_hz / t.fr,
                band: b,
                p: (r.p * looks).min(1.0),
                depth,
                reading: r,
            });
        }
    }
    best.unwrap_or(CombReading {
        order: t.fault_hz / t.fr,
        band: 0,
        reading: BandReading {
            terms: Vec::new(),
            fisher: 0.0,
            p: 1.0,
            statistic_db: 0.0,
        },
        depth: 0.0,
        p: 1.0,
    })
}

/// Two sideband windows `f₁ ± s` (s in Hz, ± its slip) read in `v`.
fn sideband_test(v: &BandView, f1: f64, s: f64, lattice: &[(f64, f64)], fr: f64) -> f64 {
    let w = |sign: f64| {
        let c = f1 + sign * s;
        Window {
            term: Term::Sideband(if sign < 0.0 { -1 } else { 1 }),
            expected_hz: c,
            lo_hz: c - 0.01 * s.abs() - 0.5 * v.df,
            hi_hz: c + 0.01 * s.abs() + 0.5 * v.df,
        }
    };
    LineTest::new(v, lattice, fr)
        .read_windows(&[w(-1.0), w(1.0)])
        .p
}

/// Whether the comb at order `d` is a harmonic or a sub-harmonic of the comb at order `c`
/// (their ratio within 1 % of an integer from 2 to 9). Such a comb reads `c`'s own lines and is
/// significant whenever `c` is, so it is no second race: an impact train's harmonics reach far
/// beyond the three a template reads, and its comb at 2·o "partnered" it as `o + 2o ≈ n`
/// rolling elements (a healthy machine with another shaft's impacts at 2.309 fr, read as both
/// races of a 7-ball bearing). A real pair is at BPFI/BPFO = (1 + r)/(1 − r), 2 only for
/// r = d/D·cos α within 0.331–0.336.
fn shares_lines(d: f64, c: f64) -> bool {
    let ratio = d.max(c) / d.min(c);
    let k = ratio.round();
    (2.0..=9.0).contains(&k) && (ratio / k - 1.0).abs() <= 0.01
}

/// The shaft rate the comb's order is read at, and its relative uncertainty (0 when a comb gave
/// the speed).
#[derive(Clone, Copy)]
struct Speed {
    fr: f64,
    uncertainty: f64,
}

/// The `± fr` sidebands' line test around `f1`: at `fr`, or, with the speed unconfirmed, the
/// best of the spacings `fr·(1 ± uncertainty)` in steps of 1 %, Bonferroni over the
/// independent ones.
fn shaft_sidebands(v: &BandView, f1: f64, speed: Speed, lattice: &[(f64, f64)]) -> f64 {
    let fr = speed.fr;
    if speed.uncertainty <= 0.0 {
        return sideband_test(v, f1, fr, lattice, fr);
    }
    let (mut s, hi) = (
        fr * (1.0 - speed.uncertainty),
        fr * (1.0 + speed.uncertainty),
    );
    let (mut best, mut steps) = (1.0f64, 0usize);
    while s <= hi {
        best = best.min(sideband_test(v, f1, s, lattice, fr));
        s *= 1.01;
        steps += 1;
    }
    (best * (steps as f64 / 2.0).max(1.0)).min(1.0)
}

/// Name the comb `c` from its sidebands and a partner comb.
fn name_comb(
    c: &CombReading,
    all: &[CombReading],
    views: &[BandView],
    speed: Speed,
    significant: bool,
    searched: [f64; 2],
    independent: usize,
) -> BearingGuess {
    let fr = speed.fr;
    let v = &views[c.band];
    let f1 = c
        .reading
        .terms
        .iter()
        .find(|t| t.window.term == Term::Harmonic(1))
        .map_or(c.order * fr, |t| t.bin as f64 * v.df);
    let order = f1 / fr;
    let lattice = comb_template(c.order, fr).lattice(v.top_hz);
    let shaft_p = shaft_sidebands(v, f1, speed, &lattice);
    // cage sidebands: ν over its range (widened by the speed's uncertainty) in steps of 1 % of
    // ν, Bonferroni over the independent ones
    let mut cage: Option<[f64; 2]> = None;
    let mut nu = CAGE_ORDERS.0 * (1.0 - speed.uncertainty);
    let mut steps = 0usize;
    while nu <= CAGE_ORDERS.1 * (1.0 + speed.uncertainty) {
        let p = sideband_test(v, f1, nu * fr, &lattice, fr);
        if cage.is_none_or(|[_, q]| p < q) {
            cage = Some([nu, p]);
        }
        nu *= 1.01;
        steps += 1;
    }
    let cage = cage.map(|[nu, p]| [nu, (p * (steps as f64 / 2.0).max(1.0)).min(1.0)]);
    // a partner comb: the other race
    // (BPFO + BPFI = n·fr needs the shaft's rate: with the speed unconfirmed, no partner)
    let partner = if speed.uncertainty > 0.0 {
        None
    } else {
        all.iter()
            .filter(|d| d.p <= SIDEBAND_LEVEL && d.depth >= MIN_MODULATION_DEPTH)
            .filter(|d| !shares_lines(d.order, c.order))
            .filter(|d| {
                let n = (d.order + c.order).round();
                let ratio = d.order.max(c.order) / d.order.min(c.order);
                (5.0..=24.0).contains(&n)
                    && ((d.order + c.order) / n - 1.0).abs() <= 0.02
                    && (1.1 / 0.9..=1.45 / 0.55).contains(&ratio)
            })
            .min_by(|a, b| a.p.total_cmp(&b.p))
            .map(|d| [d.order, d.p])
    };
    let (named, basis) = if !significant {
        (
            None,
            "no comb is significant at the stated level with a defect's modulation depth".into(),
        )
    } else if let Some([o2, _]) = partner {
        let inner = if o2 > order { "the higher" } else { "this" };
        (
            Some(Hypothesis::Inner),
            format!(
                "a second comb at {o2:.3} × fr with {order:.3} + {o2:.3} ≈ {:.0} rolling elements: both races; {inner} one is the inner race's (named inner, the outer race's comb listed)",
                (order + o2).round()
            ),
        )
    } else if shaft_p <= SIDEBAND_LEVEL {
        (
            Some(Hypothesis::Inner),
            format!("± fr sidebands around it (p {shaft_p:.1e}): the defect turns with the shaft"),
        )
    } else if let Some([nu, p]) = cage.filter(|[_, p]| *p <= SIDEBAND_LEVEL) {
        (
            Some(Hypothesis::Ball),
            format!(
                "± {nu:.3} × fr sidebands around it (p {p:.1e}), a cage rate: the defect turns with the cage"
            ),
        )
    } else {
        (
            Some(Hypothesis::Outer),
            "no shaft or cage sidebands around it: a defect fixed in the load zone".into(),
        )
    };
    BearingGuess {
        fault_order: order,
        fault_hz: f1,
        p_healthy: c.p,
        modulation_depth: c.depth,
        orders_searched: searched,
        independent_orders: independent,
        named,
        basis,
        shaft_sidebands_p: shaft_p,
        cage_sidebands: cage,
        second_comb: partner,
        interpretations: interpretations(order),
        order_uncertainty: speed.uncertainty,
        note: if speed.uncertainty > 0.0 {
            format!(
                "guessed: the bearing was not given and no shaft comb gave the speed; the comb was found in Hz and its order is known to ± {:.0} % (the declared speed's uncertainty); its kind from its sidebands",
                100.0 * speed.uncertainty
            )
        } else {
            "guessed: the bearing was not given; the fault's order was found from the envelope spectrum's non-integer combs and its kind from their sidebands and relations".into()
        },
    }
}

/// The geometries an order allows: as BPFO or BPFI, each ball count `n` with `r = d/D·cos α` in
/// `[0.1, 0.45]`; as the ball-defect rate `(1 − r²)/r`, its `r`.
fn interpretations(o: f64) -> Vec<String> {
    let mut out = Vec::new();
    let fit = |r: f64| (0.1..=0.45).contains(&r);
    let as_bpfo: Vec<String> = (5..=24)
        .filter_map(|n| {
            let r = 1.0 - 2.0 * o / f64::from(n);
            fit(r).then(|| format!("n={n}, r={r:.3}"))
        })
        .collect();
    if !as_bpfo.is_empty() {
        out.push(format!("as BPFO: {}", as_bpfo.join("; ")));
    }
    let as_bpfi: Vec<String> = (5..=24)
        .filter_map(|n| {
            let r = 2.0 * o / f64::from(n) - 1.0;
            fit(r).then(|| format!("n={n}, r={r:.3}"))
        })
        .collect();
    if !as_bpfi.is_empty() {
        out.push(format!("as BPFI: {}", as_bpfi.join("; ")));
    }
    // (1 − r²)/r = o → r² + o r − 1 = 0
    let r = 0.5 * (-o + (o * o + 4.0).sqrt());
    if fit(r) {
        out.push(format!("as the ball-defect rate: r={r:.3}"));
    }
    out
}

/// The comb's lines in its band, as the guessed fault's harmonics.
fn comb_lines(c: &CombReading, views: &[BandView]) -> Vec<SearchedLine> {
    c.reading
        .terms
        .iter()
        .map(|t| {
            let v = &views[c.band];
            let k = t.bin;
            SearchedLine {
                label: format!(
                    "comb×{}",
                    match t.window.term {
                        Term::Harmonic(k) => k,
                        Term::Sideband(_) => 0,
                    }
                ),
                expected_hz: t.window.expected_hz,
                search_hz: [t.window.lo_hz, t.window.hi_hz],
                found_hz: k as f64 * v.df,
                prominence_db: v.raw.get(k).copied().unwrap_or(0.0),
                baseline_prominence_db: None,
                evidence_db: t.value,
                present: t.value >= crate::LINE_THRESHOLD_DB,
                explained_by: None,
                consistent: true,
                shaft_order: None,
                passed_over: None,
            }
        })
        .collect()
}

/// The comb's reading as the detector's significance of the guessed fault, its fundamental
/// `fundamental_hz` in the band `band_hz`.
fn comb_significance(c: &CombReading, band_hz: [f64; 2], fundamental_hz: f64) -> Significance {
    Significance {
        band_index: c.band,
        band_hz,
        statistic_db: c.reading.statistic_db,
        fisher: c.reading.fisher,
        lines_read: c.reading.terms.len(),
        fundamental_hz,
        speed_slack: 0.0,
        speed_ratio: 1.0,
        p_band: c.reading.p,
        modulation_depth: c.depth,
        p_healthy: c.p,
        null_size: 0,
        significant: true,
        explained_by: None,
        p_given_stronger: None,
        masks: Masks::default(),
        shaft_comb_hz: None,
        slower_comb_hz: None,
    }
}

/// Each hypothesis' evidence: the named fault's is the comb found (`best`), read in band `bi`;
/// the others' are empty.
fn guessed_evidence(
    spectra: &[EnvelopeSpectrum],
    bi: usize,
    best: Option<&CombReading>,
    guess: Option<&BearingGuess>,
    views: &[BandView],
) -> Vec<HypothesisEvidence> {
    let named = guess.and_then(|g| g.named);
    let sp = &spectra[bi];
    Hypothesis::ALL
        .iter()
        .map(|&h| {
            let own = (Some(h) == named).then_some(best).flatten();
            let harmonics: Vec<SearchedLine> = own.map_or(Vec::new(), |c| comb_lines(c, views));
            let sig = own.map(|c| {
                comb_significance(
                    c,
                    spectra[c.band].band_hz,
                    guess.map_or(0.0, |g| g.fault_hz),
                )
            });
            HypothesisEvidence {
                hypothesis: h,
                fault_hz: guess.filter(|_| own.is_some()).map_or(0.0, |g| g.fault_hz),
                band_hz: sp.band_hz,
                band_spectral_kurtosis: sp.spectral_kurtosis,
                harmonics_present: harmonics.iter().filter(|l| l.present).count(),
                sidebands_present: 0,
                harmonics,
                sidebands: Vec::new(),
                score_db: own.map_or(0.0, |c| c.reading.statistic_db),
                detected: own.is_some(),
                significance: sig,
            }
        })
        .collect()
}

/// The fault orders the guess implies: the named fault's order (and, for a ball fault, the
/// cage sidebands' order as the FTF), every other order 0.
fn guessed_orders(guess: Option<&BearingGuess>) -> FaultOrders {
    let named = guess.and_then(|g| g.named);
    let order = guess
        .filter(|g| g.named.is_some())
        .map_or(0.0, |g| g.fault_order);
    FaultOrders {
        ftf: guess
            .and_then(|g| g.cage_sidebands)
            .filter(|_| named == Some(Hypothesis::Ball))
            .map_or(0.0, |[nu, _]| nu),
        bpfo: if named == Some(Hypothesis::Outer) {
            order
        } else {
            0.0
        },
        bpfi: if named == Some(Hypothesis::Inner) {
            order
        } else {
            0.0
        },
        ball_spin: if named == Some(Hypothesis::Ball) {
            0.5 * order
        } else {
            0.0
        },
        ball_defect: if named == Some(Hypothesis::Ball) {
            order
        } else {
            0.0
        },
    }
}

/// The diagnosis of an unknown bearing: the guessed fault's lines as its evidence.
fn report(
    a: crate::driver::Analysis,
    fs_hz: f64,
    best: Option<&CombReading>,
    guess: Option<BearingGuess>,
    views: &[BandView],
    alpha: f64,
) -> Diagnosis {
    let fr = a.fr;
    let named = guess.as_ref().and_then(|g| g.named);
    let bi = best.map_or(0, |c| c.band);
    let sp = &a.spectra[bi];
    let evidence = guessed_evidence(&a.spectra, bi, best, guess.as_ref(), views);
    let orders = guessed_orders(guess.as_ref());
    let score = |h: Hypothesis| {
        evidence
            .iter()
            .find(|e| e.hypothesis == h)
            .map_or(0.0, |e| e.score_db)
    };
    let mut finding = a.finding;
    finding.read_at = Some(crate::detect::SpeedStage::Measured);
    let rpm_used = finding.rpm_used;
    let sk_best = (0..a.spectra.len())
        .max_by(|&x, &y| {
            a.spectra[x]
                .spectral_kurtosis
                .total_cmp(&a.spectra[y].spectral_kurtosis)
        })
        .unwrap_or(0);
    Diagnosis {
        verdict: named.map_or("normal".to_string(), |h| h.name().to_string()),
        detected: named.into_iter().collect(),
        scores: Scores {
            inner: score(Hypothesis::Inner),
            outer: score(Hypothesis::Outer),
            ball: score(Hypothesis::Ball),
        },
        reference: a.reference,
        operating_point: OperatingPointUsed {
            fs_hz,
            rpm: finding.declared_rpm.unwrap_or(rpm_used),
            shaft_hz: fr,
            rpm_used,
            measured_speed: a.spectrum_comb,
            envelope_speed: a.envelope_comb,
            bearing: "unknown".into(),
            bearing_spec: "unknown".into(),
            orders,
            frequencies_hz: orders.at(fr),
            speed: Some(finding),
            rate_uncertainty: 0.0,
        },
        whitening: a.whitener,
        band: band_choice(
            sp,
            "the band where the comb found reads strongest against the band's clear windows".into(),
        ),
        kurtogram_band: band_choice(&a.spectra[sk_best], "maximum spectral kurtosis".into()),
        evidence,
        shaft_harmonics: Vec::new(),
        statistics: a.statistics,
        thresholds: Thresholds::with_false_alarm(alpha),
        envelope: sp.clone(),
        secondary: Vec::new(),
        candidates: Vec::new(),
        p_healthy: guess.as_ref().map_or(1.0, |g| g.p_healthy),
        false_alarm: alpha,
        bearing_guess: guess,
        order_tracking: None,
    }
}

#[cfg(test)]
mod tests {
    use super::shares_lines;

    /// A comb's harmonics and sub-harmonics are not another race's; a BPFO/BPFI pair of a
    /// real bearing is (6205: 3.585 and 5.415 fr; UC204: 3.053 and 4.947).
    #[test]
    fn a_comb_s_own_harmonics_are_no_second_race() {
        for ratio in [2.0, 3.0, 0.5, 1.0 / 3.0, 2.015] {
            assert!(shares_lines(2.309 * ratio, 2.309), "ratio {ratio}");
        }
        assert!(shares_lines(4.597, 2.302));
        assert!(!shares_lines(5.415, 3.585));
        assert!(!shares_lines(4.947, 3.053));
    }
}
