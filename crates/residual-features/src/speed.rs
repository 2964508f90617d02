//! The shaft speed the recording itself shows: its shaft-harmonic comb.
//!
//! A speed read from a nameplate, a drive setting or a rounded log is often off by a few tenths of
//! a percent to a few percent, while the fault-line windows of a diagnosis (`diagnosis::evidence`)
//! allow only ± [`SPEED_TOL`] for the speed itself (widening them lets one fault's harmonics
//! match another's: on the CWRU records a ± 1 % tolerance turned outer-race records into ball
//! faults). Instead the speed is measured: the comb `k·fr`, `k = 1..=`[`COMB_ORDERS`], is
//! searched within ± [`SPEED_SEARCH`] of the declared speed in the recording's log amplitude
//! spectrum, each harmonic scored by the height of its peak (± 1 bin) over the mean log level
//! within ± 0.3 fr of it. The best ratio is accepted only when the comb stands out: its score
//! is at least [`COMB_MIN_PER_ORDER`] per harmonic (10 dB on average) and [`COMB_MIN_CONTRAST`]
//! times the median score within ± [`CONTRAST_HALF_WIDTH`] of the best
//! ratio. On the CWRU drive-end records the comb agrees with
//! the logged speed within 0.1 % (score 27–36 against medians of 6–12 for ten orders); white
//! noise scores ~5 with a contrast below 2. The comb must also be *complete*: its first order
//! ≥ 10 dB and ≥ 80 % of the orders ≥ 5 dB over their background (every CWRU record has all ten
//! orders, the first at 19–44 dB), and orders on a multiple of 50 or 60 Hz are not scored. A
//! black-box check found the best comb elsewhere without these rules: mains harmonics (50, 100,
//! 150 Hz … are the even orders of a comb at 25 Hz, 1.3 % from a 1480 rpm shaft) and a fault's
//! own line family (k·BPFI ± m·fr of a 6203 forms a near-comb at 0.989 fr) outscored a weak or
//! absent true comb and moved the speed by 1–2 %, breaking right verdicts. When the best comb is
//! not complete, the declared speed is kept. See `docs/equations/diagnosis.md`, "Speed".
//!
//! One shaft-speed estimator for the workspace: `diagnosis` measures the speed it searches the
//! fault lines at with it, and `close-loop` tells a speed change from a defect-rate offset with
//! it (moved here from `diagnosis` on 2026-11-26 when the loop needed it).

use serde::{Deserialize, Serialize};

use crate::{Result, SpectralEngine, Taper};

/// Tolerance on a declared speed a fault-line search allows (± 0.3 %): the comb must resolve the
/// speed to half of it to be read ([`estimate_speed`]). `diagnosis::SPEED_TOL` is this constant.
pub const SPEED_TOL: f64 = 0.003;

/// Relative half-width of the speed search around the declared speed: a nameplate speed of an
/// induction motor is off by its slip, up to 3–5 % (was ± 2 % until 2026-11-25).
pub const SPEED_SEARCH: f64 = 0.05;
/// Relative half-width of the neighbourhood of the best comb whose median score the contrast is
/// taken against ([`COMB_MIN_CONTRAST`]).
pub const CONTRAST_HALF_WIDTH: f64 = 0.02;
/// Shaft orders in the comb.
pub const COMB_ORDERS: usize = 10;
/// Smallest comb score per order (log₁₀ power units: 1.0 = 10 dB) to accept a measured speed.
pub const COMB_MIN_PER_ORDER: f64 = 1.0;
/// Smallest ratio of the best comb score to the median score within ± [`CONTRAST_HALF_WIDTH`]
/// of it.
pub const COMB_MIN_CONTRAST: f64 = 2.0;
/// The first order must stand this far over its background (log₁₀ power: 1.0 = 10 dB).
pub const COMB_MIN_FIRST_ORDER: f64 = 1.0;
/// An order counts as present at this height over its background (0.5 = 5 dB).
pub const COMB_MIN_ORDER_PRESENT: f64 = 0.5;
/// A search whose relative half-width exceeds this (a range wider than about 1.9 : 1) looks for
/// the comb's fundamental among several candidates ([`estimate_speed_in`]).
pub const WIDE_SEARCH: f64 = 0.3;
/// Candidate combs (the best-scoring local maxima) weighed in a wide search.
pub const WIDE_CANDIDATES: usize = 8;
/// Mains frequencies whose harmonics are not counted as shaft orders, Hz.
pub const MAINS_HZ: [f64; 2] = [50.0, 60.0];
/// An order within this many bins of a mains multiple is not scored: an order reads the
/// largest of three bins (± 1) and a Hann-windowed line's main lobe spans ± 2 bins, so a line on
/// the multiple reaches an order's reading up to 3 bins away. Until 2026-12-07 1.5, with combs
/// compared by their summed score: a shaft at 600 rpm (orders 5, 6 and 10 on 50, 60 and 100 Hz)
/// then scored best 0.5 % fast, where those orders stepped out of the exclusion and read the
/// lobes of its own lines (combs are now compared per scored order, [`COMB_MIN_PER_ORDER`]).
pub const MAINS_REACH_BINS: f64 = 3.5;
/// Fraction of the scored (non-mains) orders that must be present.
pub const COMB_MIN_COMPLETE: f64 = 0.8;
/// In a wide search a comb at `f/n` is as complete as `f`'s when the machine shows fractional
/// orders (looseness puts lines at 0.5, 1.5, 2.5 … × fr, a rub at thirds; the healthy corpus
/// draws half orders 5–15 dB under 1×): it is taken for the fundamental only when its first
/// order stands no more than this (log₁₀ of the peak over its background: 0.4 = 4 dB) under its
/// `n`-th, the stronger comb's first. A shaft's 1× carries the unbalance and is rarely far under
/// its 2× (the corpus' misalignment puts 2× at −10 … +3 dB re 1×); the margin lies between the
/// two. A machine whose 1× stands further under its 2× and whose spectrum holds half orders is
/// read at twice its speed (give the speed); one whose half orders stand within 4 dB of 1× at
/// half its speed. Reading a comb at half the speed puts the shaft's orders on every fault's
/// windows at half their frequency: on the healthy corpus searched over 300–3600 rpm it was
/// what every false alarm of that path came from (journal, 2026-12-07).
pub const FUNDAMENTAL_MARGIN: f64 = 0.4;
/// Relative tolerance of a candidate comb's rate as an integer multiple of another's.
const SUBHARMONIC_TOL: f64 = 0.01;

/// The shaft speed measured from the recording's shaft-harmonic comb.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedEstimate {
    /// Measured shaft speed, rpm.
    pub rpm: f64,
    /// Comb score at that speed (sum over orders of log₁₀ peak-over-background; orders on a
    /// mains multiple not scored, the sum over the others scaled to every order searched).
    pub comb_score: f64,
    /// Best score over the median score within ± [`CONTRAST_HALF_WIDTH`] of the best ratio.
    pub contrast: f64,
    /// Orders scored (those below the Nyquist frequency).
    pub orders: usize,
    /// Height of the first order over its background (log₁₀ power units; 0 on a mains line).
    #[serde(default)]
    pub first_order_score: f64,
    /// Orders standing ≥ [`COMB_MIN_ORDER_PRESENT`] over their background (mains lines
    /// excluded).
    #[serde(default)]
    pub orders_present: usize,
    /// Orders scored at the comb's speed: those off every mains multiple
    /// ([`MAINS_REACH_BINS`]); completeness counts the present ones among them
    /// ([`SpeedEstimate::is_complete`]).
    #[serde(default)]
    pub orders_scored: usize,
    /// Whether the comb stands out enough to be trusted (see the module docs).
    pub accepted: bool,
    /// The speed refined from the comb's own lines, rpm (`refine`: each present order's line
    /// placed by the zoom DFT, the speed the least-squares fit over the largest set of orders
    /// that tell one speed, [`REFINE_CONSISTENCY`]); `None` unless the comb is complete (first
    /// order and [`COMB_MIN_COMPLETE`] of the orders present; its contrast is not asked), the
    /// record resolves [`REFINE_RESOLUTION`],
    /// [`REFINE_MIN_ORDERS`] orders agree, and the refined first order lies within a bin of the
    /// strongest line within ± [`SPEED_SEARCH`] of the declared shaft rate (a search that settled
    /// 1 % off the shaft on a weak comb — CWRU's 48 kHz records decimated, 5 s halves — found a
    /// consistent set of other lines there). The comb search
    /// itself places the speed only to a bin at its top order (its score takes each order's
    /// peak within ± 1 bin): ± 8e-4 on a 5 s, 30 Hz record, too coarse to tell a 0.3 % offset of
    /// a fault's rate from a speed change (`close-loop`); the refined speed reads CWRU's shafts
    /// to about 1e-4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refined_rpm: Option<f64>,
    /// `[low, high]` Hz of the demodulation band when the comb was read in that band's squared
    /// envelope ([`estimate_envelope_speed`]) rather than in the recording's own spectrum.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub envelope_band_hz: Option<[f64; 2]>,
    /// Half a spectral bin at the comb's top order, relative to the speed: how finely the comb
    /// search alone places the speed (a refined speed is finer).
    #[serde(default)]
    pub resolution: f64,
}

impl SpeedEstimate {
    /// Whether the comb is complete, accepted or not: its first order at least
    /// [`COMB_MIN_FIRST_ORDER`] over its background and [`COMB_MIN_COMPLETE`] of its scored
    /// orders present (its contrast not asked: on a machine whose speed wanders, or a slow shaft
    /// in a short record, the contrast falls).
    pub fn is_complete(&self) -> bool {
        comb_complete(
            self.first_order_score,
            self.orders_present,
            self.orders_scored,
        )
    }
}

/// A comb whose first order scores `first_order`, `present` of its `scored` orders standing
/// out, is complete (see [`SpeedEstimate::is_complete`]).
fn comb_complete(first_order: f64, present: usize, scored: usize) -> bool {
    first_order >= COMB_MIN_FIRST_ORDER
        && scored > 0
        && present as f64 >= COMB_MIN_COMPLETE * scored as f64
}

/// Orders a refined speed ([`SpeedEstimate::refined_rpm`]) must rest on.
pub const REFINE_MIN_ORDERS: usize = 3;
/// The refinement needs a bin no wider than this fraction of the shaft rate: its first order is
/// then told from lines a percent away (a 2.5 s half of a CWRU 48 kHz record, 0.4 Hz bins at
/// 30 Hz, placed the shaft 1 % slow on four records).
pub const REFINE_RESOLUTION: f64 = 0.01;
/// Half-width of the window each order's line is placed in by the refinement, as a fraction of
/// its frequency around the comb search's speed (which is at most a bin off at its top order).
pub const REFINE_WINDOW: f64 = 0.002;
/// The refinement's orders tell one speed ρ when each lies within this fraction of k·fr (plus a
/// tenth of a resolution bin) of k·fr·ρ: CWRU's shaft lines agree within 1e-4 at orders 3–9; a
/// 1× line, read to a fraction of a 0.2 Hz bin, within 6e-4.
pub const REFINE_CONSISTENCY: f64 = 2e-4;

/// Fine grid steps (a twentieth of a bin) per coarse step of the refinement's search.
const COARSE: i64 = 5;

/// The speed ratio (to `fr0`) refined from the lines of orders `1..=orders` that `present`
/// admits at the comb search's ratio `r0` and that `stands_out` confirms where they are placed
/// (10 dB over their background, [`COMB_MIN_FIRST_ORDER`]): each line placed by the zoom DFT
/// ([`crate::spectral::LocalZoom`]) of the Hann-windowed `x` — the largest power on a grid of
/// a twentieth of a bin within ± [`REFINE_WINDOW`], then a parabola through it and its
/// neighbours; a largest power on the window's edge that still rises beyond it is the flank of
/// a line outside the window and places nothing — and the ratio the least-squares fit f_k = k·fr0·ρ (weights k²) over the largest
/// set of orders within [`REFINE_CONSISTENCY`] of one ρ (taken from each order in turn) that
/// holds the first order (the comb's defining line: without it, a search that settled 1 % off
/// the shaft on a weak comb found a consistent set of other lines — a fault's sidebands — on
/// nine CWRU records); `None` unless [`REFINE_MIN_ORDERS`] agree.
fn refine(
    x: &[f64],
    fs: f64,
    fr0: f64,
    r0: f64,
    orders: usize,
    present: &dyn Fn(usize, f64) -> bool,
    stands_out: &dyn Fn(usize, f64) -> bool,
) -> Option<f64> {
    use crate::spectral::LocalZoom;
    let n = x.len();
    let xw: Vec<f64> = x
        .iter()
        .zip(Taper::Hann.weights(n))
        .map(|(v, w)| v * w)
        .collect();
    let bin = fs / n as f64;
    let mut pts: Vec<(f64, f64)> = Vec::new();
    for k in 1..=orders {
        if !present(k, r0) {
            continue;
        }
        let fc = k as f64 * fr0 * r0;
        let h = 0.05 * bin;
        let steps = ((REFINE_WINDOW * fc / h).ceil() as i64).max(2);
        // every power of this order from one set of block moments about fc (the grid and the
        // parabola's neighbours reach one step beyond the window)
        let zoom = LocalZoom::new(&xw, fs, fc, (steps + 1) as f64 * h);
        let p = |j: i64| zoom.power(fc + j as f64 * h).max(1e-300).ln();
        let argmax = |js: &mut dyn Iterator<Item = i64>| {
            js.map(|j| (j, p(j)))
                .fold((0, f64::NEG_INFINITY), |b, c| if c.1 > b.1 { c } else { b })
        };
        // coarse to fine: the largest power on a grid of a quarter bin (and the window's
        // edges), then on the twentieth-bin grid within a quarter bin of it — the same largest
        // point as the whole fine grid's wherever the window holds one line (a Hann line's
        // power falls monotonically from its peak over more than a bin), at a fifth of the
        // DFT evaluations (a 10 s, 20 kHz record's 10th order at 1500 rpm: 201 → 51)
        let (jc, _) = argmax(&mut (-steps..=steps).step_by(COARSE as usize).chain([steps]));
        let (jb, _) = argmax(&mut ((jc - COARSE + 1).max(-steps)..=(jc + COARSE - 1).min(steps)));
        let (a, b, c) = (p(jb - 1), p(jb), p(jb + 1));
        // a line is a local maximum: the largest power on the window's edge that still rises
        // beyond it is the flank of a line outside the window, and every order whose line lies
        // beyond the same side ends on that edge at the same ratio r0·(1 ± REFINE_WINDOW), so
        // those placements agree by construction (a 6203's inner-race family k·BPFI ± m·fr, a
        // near-comb at 0.99 fr, was refined to 0.99 fr on the flanks of the true 1× and 2×
        // lines, `refine_ignores_lines_outside_their_windows`). A line peaking on the edge
        // stays: at the first order the window spans less than a bin
        if (jb == steps && c > b) || (jb == -steps && a > b) {
            continue;
        }
        let den = a - 2.0 * b + c;
        let d = if den < 0.0 {
            (0.5 * (a - c) / den).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        let f = fc + (jb as f64 + d) * h;
        // a line, not the largest noise in the window: it stands out where it was placed
        if stands_out(k, f / (k as f64 * fr0)) {
            pts.push((k as f64, f));
        }
    }
    let agree = |rho: f64| -> Vec<(f64, f64)> {
        pts.iter()
            .copied()
            .filter(|&(k, f)| (f - k * fr0 * rho).abs() <= REFINE_CONSISTENCY * k * fr0 + 0.1 * bin)
            .collect()
    };
    let best = pts
        .iter()
        .map(|&(k, f)| agree(f / (k * fr0)))
        .filter(|set| set.first().is_some_and(|p| p.0 == 1.0))
        .max_by_key(Vec::len)
        .unwrap_or_default();
    if best.len() < REFINE_MIN_ORDERS {
        return None;
    }
    let (num, den) = best
        .iter()
        .fold((0.0, 0.0), |(u, v), &(k, f)| (u + k * f, v + k * k));
    Some(num / (den * fr0))
}

/// Measure the shaft speed near `rpm` from `x` (sampled at `fs_hz`). `None` when no comb order
/// lies below the Nyquist frequency or the record is too short for its comb to resolve the speed
/// to half of [`SPEED_TOL`] (bin width > ½ SPEED_TOL × top order × fr).
///
/// # Errors
/// The spectral engine's errors (non-finite input).
pub fn estimate_speed(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm: f64,
) -> Result<Option<SpeedEstimate>> {
    comb_speed(
        engine,
        x,
        fs_hz,
        rpm,
        SPEED_SEARCH,
        REFINE_RESOLUTION,
        false,
    )
}

/// [`estimate_speed`] over the range `[rpm_low, rpm_high]` instead of ± [`SPEED_SEARCH`] of one
/// declared speed, also on a record too short to resolve the speed to half of [`SPEED_TOL`] (a
/// coarse speed, [`SpeedEstimate::resolution`] says how coarse, beats a set point several per
/// cent off): a set point or nameplate speed off by up to ± 10 %, or no declared speed at
/// all (a search from 300 to 3600 rpm). Over a range wider than an octave the comb at twice the
/// shaft rate is as complete as the shaft's own (its orders are the shaft's even ones): of the
/// accepted combs among the best-scoring candidates, the one at the lowest speed whose score is
/// at least half the best is taken — a complete comb at half a speed holds that speed's odd
/// orders too, so it is the fundamental — unless its first order stands more than
/// [`FUNDAMENTAL_MARGIN`] under its 2nd or 3rd (a loose machine's half orders make a complete
/// comb at half the speed, under the shaft's 1×): then the comb at that multiple.
///
/// # Errors
/// The spectral engine's errors (non-finite input).
pub fn estimate_speed_in(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm_low: f64,
    rpm_high: f64,
) -> Result<Option<SpeedEstimate>> {
    let (centre, search) = range_search(rpm_low, rpm_high);
    comb_speed(engine, x, fs_hz, centre, search, REFINE_RESOLUTION, true)
}

/// The centre and relative half-width of a speed range.
pub(crate) fn range_search(rpm_low: f64, rpm_high: f64) -> (f64, f64) {
    let (lo, hi) = (rpm_low.min(rpm_high), rpm_low.max(rpm_high));
    let centre = 0.5 * (lo + hi);
    (centre, ((hi - lo) / (hi + lo)).max(1e-6))
}

/// Measure the shaft speed near `rpm` from the shaft comb of squared envelopes (of the bands a
/// residual was demodulated in, [`crate::SpectralEngine::band_squared_envelopes`]), for a
/// recording whose own spectrum shows no comb [`estimate_speed`] accepts.
///
/// A defect that turns with the shaft (an inner-race spall, a ball passing it) or a load that
/// does modulates the impacts at the shaft rate: their squared envelope carries the comb `k·fr`
/// even when the vibration's own shaft lines are buried under gear, flow or electrical lines
/// (MFPT's rig: the raw comb scores 9–12 over ten orders, below [`COMB_MIN_PER_ORDER`], while
/// the envelope of an inner-race record holds fr ×1–5 at 20–35 dB). Each band's squared envelope
/// (mean removed) of the [`ENVELOPE_BANDS`] most impulsive bands (largest spectral kurtosis) is
/// searched as [`estimate_speed`] searches a recording, with the same
/// acceptance rules, and one more: the speed must be *refined* — the comb's first order and at
/// least [`REFINE_MIN_ORDERS`] orders placed by the zoom DFT tell one speed within
/// [`REFINE_CONSISTENCY`]. That rule is what keeps a fault's own line family out: k·BPFI ± m·fr
/// forms a near-comb (0.989 fr on a 6203) whose orders sit on lines at different ratios, so no
/// three of them agree. The refinement's resolution gate ([`REFINE_RESOLUTION`]) is not asked
/// here: an envelope's shaft lines stand alone in their neighbourhood, and 3 s records (74
/// turns at 1480 rpm) are common. Of the bands whose comb passes, the one with the highest comb
/// score gives the speed ([`SpeedEstimate::envelope_band_hz`] names it; `rpm` is the refined
/// speed). When no band's comb refines, the best-scoring accepted comb is returned unrefined
/// ([`SpeedEstimate::refined_rpm`] `None`, `rpm` the search's): it is not a speed by itself — a
/// fault's near-comb can pass the search's rules — but another, independent reading of the shaft
/// that agrees with it (the recording's own spectrum, `diagnosis`) confirms it; a machine whose
/// speed wanders spreads its envelope lines beyond [`REFINE_CONSISTENCY`] and refines in no
/// band. `None` when no band passes.
///
/// # Errors
/// The spectral engine's errors (non-finite input).
pub fn estimate_envelope_speed(
    engine: &mut SpectralEngine,
    envelopes: &[crate::BandEnvelope],
    rpm: f64,
) -> Result<Option<SpeedEstimate>> {
    envelope_speed(engine, envelopes, rpm, SPEED_SEARCH, false)
}

/// [`estimate_envelope_speed`] over the range `[rpm_low, rpm_high]` (see [`estimate_speed_in`]).
///
/// # Errors
/// The spectral engine's errors (non-finite input).
pub fn estimate_envelope_speed_in(
    engine: &mut SpectralEngine,
    envelopes: &[crate::BandEnvelope],
    rpm_low: f64,
    rpm_high: f64,
) -> Result<Option<SpeedEstimate>> {
    let (rpm, search) = range_search(rpm_low, rpm_high);
    envelope_speed(engine, envelopes, rpm, search, true)
}

fn envelope_speed(
    engine: &mut SpectralEngine,
    envelopes: &[crate::BandEnvelope],
    rpm: f64,
    search: f64,
    coarse: bool,
) -> Result<Option<SpeedEstimate>> {
    // the most impulsive bands: where the impacts, and so their modulation, stand out
    let mut ranked: Vec<(f64, &crate::BandEnvelope)> = envelopes
        .iter()
        .filter(|be| be.squared_envelope.len() >= 4)
        .map(|be| (be.spectral_kurtosis(), be))
        .collect();
    ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    ranked.truncate(ENVELOPE_BANDS);
    // the comb and its background need no more than the orders searched and one shaft order
    let max_hz = (COMB_ORDERS as f64 * (1.0 + search) + 1.0) * rpm / 60.0;
    let mut accepted = Vec::new();
    for (_, be) in ranked {
        // mean removed, band-limited and resampled (a wide band's envelope holds 10⁵ samples)
        let (low, rate) = engine.low_pass_resample(&be.squared_envelope, be.rate_hz, max_hz)?;
        // the search alone first (no refinement: 0 admits no resolution)
        if let Some(m) = comb_speed(engine, &low, rate, rpm, search, 0.0, coarse)?
            && m.accepted
        {
            accepted.push((m.comb_score, be.band, low, rate));
        }
    }
    // the best comb that refines: refinements (a zoom DFT per line) only as far as needed
    accepted.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut best_unrefined = None;
    for (_, band, low, rate) in accepted {
        if let Some(m) = comb_speed(engine, &low, rate, rpm, search, f64::INFINITY, coarse)? {
            let band_hz = Some([band.low_hz(), band.high_hz()]);
            if let Some(refined) = m.refined_rpm {
                return Ok(Some(SpeedEstimate {
                    rpm: refined,
                    envelope_band_hz: band_hz,
                    ..m
                }));
            }
            if best_unrefined.is_none() && m.accepted {
                best_unrefined = Some(SpeedEstimate {
                    envelope_band_hz: band_hz,
                    ..m
                });
            }
        }
    }
    // no band refines: the best-scoring accepted comb, unrefined (`refined_rpm` is `None`), for
    // the caller to confirm by other evidence
    Ok(best_unrefined)
}

/// Bands [`estimate_envelope_speed`] searches: the most impulsive ones (largest spectral
/// kurtosis, [`crate::BandEnvelope::spectral_kurtosis`]). A comb search per band costs a real
/// FFT of its squared envelope; every band (34 at 12 kHz) at the envelopes' full rate added
/// 50–60 ms to a 10 s, 12 kHz diagnosis; with 4 bands two of MFPT's inner-race records lose
/// their speed (docs/equations/diagnosis.md).
pub const ENVELOPE_BANDS: usize = 8;

/// The log amplitude spectrum of a record a shaft comb is scored in, and what scoring it needs.
struct CombSpectrum {
    /// The record, its mean removed and cut to a 7-smooth length (what the refinement reads).
    centred: Vec<f64>,
    /// Declared shaft rate, Hz.
    fr0: f64,
    /// Bin width, Hz.
    df: f64,
    /// `log10` of each bin's squared amplitude (floored 240 dB under the largest).
    l: Vec<f64>,
    /// Cumulative sums of `l`: `cum[k] = Σ_{j<k} l[j]`.
    cum: Vec<f64>,
    /// Half-width of an order's background, bins (0.3 fr, at least 3).
    half: usize,
    /// Orders scored (those below the spectrum's top at the search's fastest speed).
    orders: usize,
}

/// How a comb at one speed ratio reads: [`CombSpectrum::assess`].
struct CombAssessment {
    /// Its score over the median score within ± [`CONTRAST_HALF_WIDTH`] of its ratio.
    contrast: f64,
    /// Its first order's score.
    first_order: f64,
    /// Orders scoring at least [`COMB_MIN_ORDER_PRESENT`].
    present: usize,
    /// Orders off every mains multiple.
    scored: usize,
    /// First order standing out and almost every scored order there.
    complete: bool,
    /// Complete, strong enough per order and contrasted enough.
    accepted: bool,
}

impl CombSpectrum {
    /// The spectrum of `x` (sampled at `fs_hz`) for a comb search at `rpm` ± `search`; `None`
    /// when the record is too short, no order fits under the spectrum's top, or (unless
    /// `coarse`) the comb cannot resolve the speed to half the lines' own tolerance.
    fn read(
        engine: &mut SpectralEngine,
        x: &[f64],
        fs_hz: f64,
        rpm: f64,
        search: f64,
        coarse: bool,
    ) -> Result<Option<Self>> {
        let fr0 = rpm / 60.0;
        // a 7-smooth length (≤ 2 % shorter) keeps the real FFT fast
        let n = 2 * crate::smooth_floor(x.len() / 2);
        if n < 64 {
            return Ok(None);
        }
        let df = fs_hz / n as f64;
        let mean = x[..n].iter().sum::<f64>() / n as f64;
        let centred: Vec<f64> = x[..n].iter().map(|v| v - mean).collect();
        let spec = engine.amplitude_spectrum(&centred, fs_hz, Taper::Hann)?;
        let floor = spec.values.iter().fold(0.0_f64, |m, v| m.max(*v)) * 1e-12 + 1e-300;
        let l: Vec<f64> = spec
            .values
            .iter()
            .map(|a| (a * a + floor * floor).log10())
            .collect();
        let mut cum = vec![0.0; l.len() + 1];
        for (k, v) in l.iter().enumerate() {
            cum[k + 1] = cum[k] + v;
        }
        let half = ((0.3 * fr0 / df).round() as usize).max(3);
        let top = l.len().saturating_sub(half + 2);
        let orders = (1..=COMB_ORDERS)
            .filter(|&k| (k as f64 * fr0 * (1.0 + search) / df).round() as usize <= top)
            .count();
        // the comb must resolve the speed to half the lines' own tolerance at its top order
        if orders == 0 || (!coarse && df > 0.5 * SPEED_TOL * orders as f64 * fr0) {
            return Ok(None);
        }
        Ok(Some(Self {
            centred,
            fr0,
            df,
            l,
            cum,
            half,
            orders,
        }))
    }

    /// An order within [`MAINS_REACH_BINS`] of a multiple of a mains frequency (50 or 60 Hz) is
    /// no evidence of the shaft: the supply's harmonics sit there on any electrically driven
    /// machine.
    fn mains(&self, f: f64) -> bool {
        MAINS_HZ.iter().any(|&m| {
            let k = (f / m).round();
            k >= 1.0 && (f - k * m).abs() <= MAINS_REACH_BINS * self.df
        })
    }

    /// Order `k`'s score at speed ratio `r`: its peak (the largest of three bins) over its
    /// background's mean `log10`, at least 0; 0 on a mains multiple.
    fn order_score(&self, k: usize, r: f64) -> f64 {
        let (fr0, df, l, cum, half) = (self.fr0, self.df, &self.l, &self.cum, self.half);
        if self.mains(k as f64 * fr0 * r) {
            return 0.0;
        }
        let i = (k as f64 * fr0 * r / df).round() as usize;
        let (lo, hi) = (i.saturating_sub(half).max(1), i + half + 1);
        let bg = (cum[hi] - cum[lo]) / (hi - lo) as f64;
        let peak = l[i - 1].max(l[i]).max(l[i + 1]);
        (peak - bg).max(0.0)
    }

    /// The comb's score at speed ratio `r`: its orders' scores summed.
    /// Orders on a mains multiple are not scored, and which orders those are changes with `r`:
    /// the sum is taken as the mean over the orders scored times the orders searched, so a
    /// ratio does not gain by an order stepping out of the exclusion, nor lose by one stepping
    /// in (without mains multiples among the orders, the plain sum).
    fn score(&self, r: f64) -> f64 {
        let scored: Vec<usize> = (1..=self.orders)
            .filter(|&k| !self.mains(k as f64 * self.fr0 * r))
            .collect();
        if scored.is_empty() {
            return 0.0;
        }
        let sum: f64 = scored.iter().map(|&k| self.order_score(k, r)).sum();
        sum * self.orders as f64 / scored.len() as f64
    }

    /// The comb at `r_best` (score `s_best`) against the search's `scores`. Its contrast is
    /// against its own neighbourhood (± [`CONTRAST_HALF_WIDTH`] of the ratio), so it does not
    /// grow with the width of the search; a shaft comb is complete: its first order stands out
    /// and almost every order is there (mains harmonics fill only the even orders of a comb at
    /// half the line frequency; a fault line family k·f ± m·fr forms a near-comb without the
    /// first order).
    fn assess(&self, scores: &[(f64, f64)], r_best: f64, s_best: f64) -> CombAssessment {
        let (fr0, orders) = (self.fr0, self.orders);
        let mut sorted: Vec<f64> = scores
            .iter()
            .filter(|c| (c.0 - r_best).abs() <= CONTRAST_HALF_WIDTH)
            .map(|c| c.1)
            .collect();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        let contrast = s_best / median.max(1e-9);
        let first_order = self.order_score(1, r_best);
        let scored = (1..=orders)
            .filter(|&k| !self.mains(k as f64 * fr0 * r_best))
            .count();
        let present = (1..=orders)
            .filter(|&k| self.order_score(k, r_best) >= COMB_MIN_ORDER_PRESENT)
            .count();
        let complete = comb_complete(first_order, present, scored);
        let accepted = complete
            && s_best >= COMB_MIN_PER_ORDER * orders as f64
            && contrast >= COMB_MIN_CONTRAST;
        CombAssessment {
            contrast,
            first_order,
            present,
            scored,
            complete,
            accepted,
        }
    }

    /// Over a range wider than an octave the comb at 2·fr is as complete as fr's: of the
    /// best-scoring accepted combs (the [`WIDE_CANDIDATES`] highest accepted local maxima of
    /// `scores`, none within [`CONTRAST_HALF_WIDTH`] of a higher one), the lowest whose score is
    /// at least half the best — unless its first order stands more than [`FUNDAMENTAL_MARGIN`]
    /// under its `n`-th (n = 2, 3) and the comb at `n` times its rate is complete: then that one
    /// (the best-scoring ratio within [`SUBHARMONIC_TOL`] of it). `None` when none is accepted.
    fn lowest_strong_comb(&self, scores: &[(f64, f64)]) -> Option<(f64, f64)> {
        let mut peaks: Vec<(f64, f64)> = scores
            .windows(3)
            .filter(|w| w[1].1 >= w[0].1 && w[1].1 > w[2].1)
            .map(|w| w[1])
            .collect();
        peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
        // one candidate per comb: a comb's score is jagged over a few quarter-bin steps, and
        // its side peaks would take every candidate's place; each accepted comb is the best
        // accepted one within its own contrast neighbourhood
        let mut accepted: Vec<(f64, f64)> = Vec::new();
        for p in peaks {
            // below half the best accepted comb's score no candidate is taken
            if accepted.len() == WIDE_CANDIDATES
                || accepted.first().is_some_and(|a| p.1 < 0.5 * a.1)
            {
                break;
            }
            if accepted
                .iter()
                .all(|d| (p.0 / d.0 - 1.0).abs() > CONTRAST_HALF_WIDTH)
                && self.assess(scores, p.0, p.1).accepted
            {
                accepted.push(p);
            }
        }
        let top = accepted.first().map(|c| c.1)?;
        let low = accepted
            .iter()
            .filter(|c| c.1 >= 0.5 * top)
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .copied()
            .unwrap_or(accepted[0]);
        // a comb of fractional orders (looseness' halves, a rub's thirds) is as complete as the
        // shaft's: its first order, far under the shaft's 1×, says it is not the fundamental
        let first = self.order_score(1, low.0);
        let up = (2..=3usize)
            .filter(|&n| self.order_score(n, low.0) - first > FUNDAMENTAL_MARGIN)
            .filter_map(|n| {
                let at = n as f64 * low.0;
                scores
                    .iter()
                    .filter(|c| (c.0 / at - 1.0).abs() <= SUBHARMONIC_TOL)
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .copied()
                    .filter(|&(r, s)| self.assess(scores, r, s).complete)
            })
            .max_by(|a, b| {
                self.order_score(1, a.0)
                    .total_cmp(&self.order_score(1, b.0))
            });
        Some(up.unwrap_or(low))
    }

    /// The strongest line within ± [`SPEED_SEARCH`] of the declared shaft rate, or of the comb
    /// found at `r_best` when the `search` reaches further, Hz: a refined speed must put its
    /// first order on it (within a bin).
    fn strongest_1x(&self, search: f64, r_best: f64) -> Option<f64> {
        let (fr0, df, l) = (self.fr0, self.df, &self.l);
        let c = if search > SPEED_SEARCH {
            fr0 * r_best
        } else {
            fr0
        };
        let lo = ((c * (1.0 - SPEED_SEARCH) / df).floor() as usize).max(1);
        let hi = ((c * (1.0 + SPEED_SEARCH) / df).ceil() as usize).min(l.len() - 1);
        (lo..=hi)
            .max_by(|&a, &b| l[a].total_cmp(&l[b]))
            .map(|j| j as f64 * df)
    }
}

/// The shaft comb of `x` (sampled at `fs_hz`) searched over `rpm` ± `search` in quarter-bin
/// steps of its top order, the best ratio assessed ([`CombSpectrum::assess`]) and, when the
/// bins are at most `refine_resolution` × fr wide, refined by the zoom DFT ([`refine`]).
pub(crate) fn comb_speed(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm: f64,
    search: f64,
    refine_resolution: f64,
    coarse: bool,
) -> Result<Option<SpeedEstimate>> {
    comb_speed_refining(
        engine,
        x,
        fs_hz,
        rpm,
        (search, refine_resolution, coarse),
        false,
    )
}

/// [`estimate_speed`], the speed refined from the comb's leading lines whether or not the comb
/// is complete over its orders ([`SpeedEstimate::is_complete`]): its first order standing
/// [`COMB_MIN_FIRST_ORDER`] over its background and [`REFINE_MIN_ORDERS`] of its lines agreeing
/// within [`REFINE_CONSISTENCY`], as [`SpeedEstimate::refined_rpm`] asks otherwise. A machine's
/// shaft comb often falls a few dB an order after the second, so that only its first three to
/// five orders stand; the order tracking (`order`) asks this of a record tracked along a speed
/// profile — its lines sharp at the mean speed — where the completeness rule of a steady
/// recording's speed would refuse most real combs. The comb is searched within ± `search` of
/// `rpm` ([`SPEED_SEARCH`] for a declared speed); with `search` 0 it is read at `rpm` itself
/// and refined from there — a tracked record's lines stand at whole orders of its mean speed
/// when it was tracked right, and a comb search of a record of a few dozen turns places its comb
/// only to a bin at its top order, up to a few tenths of a per cent off: its lines' refinement
/// windows (± [`REFINE_WINDOW`]) then missed the first order. The record need resolve the shaft rate only
/// to [`LEADING_RESOLUTION`], not to [`REFINE_RESOLUTION`] (nor the comb search to half of
/// [`SPEED_TOL`]).
///
/// # Errors
/// As [`estimate_speed`].
pub fn leading_lines_speed(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm: f64,
    search: f64,
) -> Result<Option<SpeedEstimate>> {
    comb_speed_refining(
        engine,
        x,
        fs_hz,
        rpm,
        (search, LEADING_RESOLUTION, true),
        true,
    )
}

/// The bin a record read by [`leading_lines_speed`] may have, as a fraction of the shaft rate:
/// the order tracking's fewest turns ([`crate::order::MIN_TURNS`]). A tracked record's speed is
/// the profile's mean, known before its comb is looked at; what the check asks is that three of
/// its leading lines agree on one speed within [`REFINE_CONSISTENCY`], which a line placed by
/// the zoom DFT does to a small part of a bin. Until 2026-12-08 [`REFINE_RESOLUTION`] (100 turns)
/// and the search's resolution (67 turns at ten orders): every tracked record of a 6 s sweep
/// at 600 rpm (60 turns) was refused however sharp its comb, and most sweeping machines of the
/// corpus at 1000 rpm too.
pub const LEADING_RESOLUTION: f64 = 1.0 / crate::order::MIN_TURNS;

/// What a frame's shaft comb at one speed shows ([`CombFrame::reading`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CombReading {
    /// The comb's score ([`SpeedEstimate::comb_score`]).
    pub score: f64,
    /// Orders scored below the spectrum's top.
    pub orders: usize,
    /// Its first order's score.
    pub first_order: f64,
    /// Orders standing [`COMB_MIN_ORDER_PRESENT`] over their background.
    pub present: usize,
    /// Orders off every mains multiple.
    pub scored: usize,
}

impl CombReading {
    /// What a comb search's best comb `m` shows.
    pub fn of(m: &SpeedEstimate) -> Self {
        Self {
            score: m.comb_score,
            orders: m.orders,
            first_order: m.first_order_score,
            present: m.orders_present,
            scored: m.orders_scored,
        }
    }

    /// Whether the comb is complete ([`SpeedEstimate::is_complete`]).
    pub fn is_complete(&self) -> bool {
        comb_complete(self.first_order, self.present, self.scored)
    }
}

/// A frame's log spectrum, for its shaft comb's score at any speed within a stated reach of a
/// centre speed: what a path of speeds through the frames is chosen on
/// (`order::speed_profile`).
pub(crate) struct CombFrame {
    spectrum: CombSpectrum,
    rpm: f64,
}

impl CombFrame {
    /// The frame `x` (at `fs_hz`) for combs at `rpm` ± `reach` (relative); `None` when it is too
    /// short or no order fits under its spectrum's top.
    pub fn read(
        engine: &mut SpectralEngine,
        x: &[f64],
        fs_hz: f64,
        rpm: f64,
        reach: f64,
    ) -> Result<Option<Self>> {
        Ok(CombSpectrum::read(engine, x, fs_hz, rpm, reach, true)?
            .map(|spectrum| Self { spectrum, rpm }))
    }

    /// The comb at `rpm`: its score ([`CombSpectrum::score`]) and what the frame rules ask.
    pub fn reading(&self, rpm: f64) -> CombReading {
        let c = &self.spectrum;
        let r = rpm / self.rpm;
        CombReading {
            score: c.score(r),
            orders: c.orders,
            first_order: c.order_score(1, r),
            present: (1..=c.orders)
                .filter(|&k| c.order_score(k, r) >= COMB_MIN_ORDER_PRESENT)
                .count(),
            scored: (1..=c.orders)
                .filter(|&k| !c.mains(k as f64 * c.fr0 * r))
                .count(),
        }
    }

    /// Each order's score at `rpm` ([`CombSpectrum::order_score`]), `None` for an order on a
    /// mains multiple ([`MAINS_REACH_BINS`]).
    pub fn order_scores(&self, rpm: f64) -> impl Iterator<Item = Option<f64>> + '_ {
        let c = &self.spectrum;
        let r = rpm / self.rpm;
        (1..=c.orders).map(move |k| (!c.mains(k as f64 * c.fr0 * r)).then(|| c.order_score(k, r)))
    }
}

/// [`comb_speed`] (its search, resolution and coarseness as one triple), refining an incomplete
/// comb too when `leading` ([`leading_lines_speed`]).
fn comb_speed_refining(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm: f64,
    (search, refine_resolution, coarse): (f64, f64, bool),
    leading: bool,
) -> Result<Option<SpeedEstimate>> {
    let Some(c) = CombSpectrum::read(engine, x, fs_hz, rpm, search, coarse)? else {
        return Ok(None);
    };
    let (fr0, df, orders) = (c.fr0, c.df, c.orders);
    // steps of a quarter bin at the highest order scored
    let step = 0.25 * df / (orders as f64 * fr0);
    let steps = (2.0 * search / step).ceil() as usize;
    let scores: Vec<(f64, f64)> = if steps == 0 {
        vec![(1.0, c.score(1.0))]
    } else {
        (0..=steps)
            .map(|j| {
                let r = 1.0 - search + 2.0 * search * j as f64 / steps as f64;
                (r, c.score(r))
            })
            .collect()
    };
    let (mut r_best, mut s_best) =
        scores.iter().copied().fold(
            (1.0, f64::NEG_INFINITY),
            |b, x| if x.1 > b.1 { x } else { b },
        );
    if search > WIDE_SEARCH
        && let Some(low) = c.lowest_strong_comb(&scores)
    {
        (r_best, s_best) = low;
    }
    let a = c.assess(&scores, r_best, s_best);
    // the refined speed: each present order's line placed by the zoom DFT of the Hann-windowed
    // record, the speed fitted over the largest set of orders that tell one speed, its first
    // order on the strongest line around the shaft rate
    let strongest_1x = c.strongest_1x(search, r_best);
    let refinable = a.complete || (leading && a.first_order >= COMB_MIN_FIRST_ORDER);
    let refined_rpm = if refinable && df <= refine_resolution * fr0 {
        refine(
            &c.centred,
            fs_hz,
            fr0,
            r_best,
            orders,
            &|k: usize, r: f64| {
                !c.mains(k as f64 * fr0 * r) && c.order_score(k, r) >= COMB_MIN_ORDER_PRESENT
            },
            &|k: usize, r: f64| c.order_score(k, r) >= COMB_MIN_FIRST_ORDER,
        )
        .filter(|r| strongest_1x.is_some_and(|f| (r * fr0 - f).abs() <= df))
        .map(|r| rpm * r)
    } else {
        None
    };
    Ok(Some(SpeedEstimate {
        refined_rpm,
        rpm: rpm * r_best,
        comb_score: s_best,
        contrast: a.contrast,
        orders,
        first_order_score: a.first_order,
        orders_present: a.present,
        orders_scored: a.scored,
        accepted: a.accepted,
        envelope_band_hz: None,
        resolution: 0.5 * df / (orders as f64 * fr0),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `secs` s at `fs` Hz of a steady comb: orders `1..=orders` of `fr` Hz, order `k` of
    /// amplitude `1/k`, and a tone of amplitude `tone` at 0.37 `fs` (off every order).
    fn few_orders(fs: f64, fr: f64, orders: i32, secs: f64, tone: f64) -> Vec<f64> {
        (0..(secs * fs) as usize)
            .map(|i| {
                let t = i as f64 / fs;
                (1..=orders)
                    .map(|k| {
                        let k = f64::from(k);
                        (2.0 * std::f64::consts::PI * k * fr * t + k).sin() / k
                    })
                    .sum::<f64>()
                    + tone * (2.0 * std::f64::consts::PI * 0.37 * t * fs).sin()
            })
            .collect()
    }

    /// A steady comb of three strong orders and nothing above them: incomplete over its ten
    /// orders, so the whole-record rule refines no speed; its leading lines refine it.
    #[test]
    fn a_comb_of_three_orders_refines_on_its_leading_lines() {
        let (fs, fr) = (12_000.0, 24.7);
        let x = few_orders(fs, fr, 3, 8.0, 0.05);
        let mut e = SpectralEngine::new();
        let m = estimate_speed(&mut e, &x, fs, 1500.0).unwrap().unwrap();
        assert!(!m.is_complete() && m.refined_rpm.is_none(), "{m:?}");
        let l = leading_lines_speed(&mut e, &x, fs, 1500.0, SPEED_SEARCH)
            .unwrap()
            .unwrap();
        let r = l.refined_rpm.expect("refined");
        assert!((r / (60.0 * fr) - 1.0).abs() < 1e-4, "{r}");
        assert_eq!((l.rpm, l.orders_present), (m.rpm, m.orders_present));
    }

    /// Read at a stated speed (`search` 0, as a tracked record is at its mean speed): a comb of
    /// 40 turns whose lines stand on that speed's whole orders refines to it; the same comb
    /// 1 % faster (a record tracked along a wrong profile) refines to nothing within the check's
    /// 0.5 % — its lines lie outside every order's refinement window.
    #[test]
    fn a_comb_read_at_a_stated_speed_refines_only_where_its_lines_stand() {
        let fs = 2_000.0;
        let comb = |fr: f64| few_orders(fs, fr, 4, 40.0 / 23.3, 0.02);
        let mut e = SpectralEngine::new();
        let on = leading_lines_speed(&mut e, &comb(23.3), fs, 1398.0, 0.0)
            .unwrap()
            .unwrap();
        let r = on.refined_rpm.unwrap_or_else(|| panic!("{on:?}"));
        assert!((r / 1398.0 - 1.0).abs() < 2e-4, "{r}");
        let off = leading_lines_speed(&mut e, &comb(23.533), fs, 1398.0, 0.0)
            .unwrap()
            .unwrap();
        assert!(
            off.refined_rpm
                .is_none_or(|r| (r / 1398.0 - 1.0).abs() > 0.005),
            "{off:?}"
        );
    }

    /// A shaft comb at `t` s: orders 1..=10 of `fr` Hz, each of amplitude `amp` and phase
    /// `phase · k` rad.
    fn shaft_comb(t: f64, fr: f64, amp: f64, phase: f64) -> f64 {
        (1..=10)
            .map(|k| {
                let k = f64::from(k);
                amp * (2.0 * std::f64::consts::PI * k * fr * t + phase * k).cos()
            })
            .sum()
    }

    /// The squared envelope of a 6203 inner-race fault at 900 rpm (fr = 15 Hz, BPFI = 4.9469 fr),
    /// 6 s at 1 kHz: the shaft's own lines at 1× and 2× and the fault's family k·BPFI ± m·fr
    /// (k = 1, 2; |m| ≤ 2), a near-comb at 0.989 fr whose orders 4–10 sit within a bin or two of
    /// its lines. The bins (1/6 Hz) are wider than the 1 % between the two combs. The speed must
    /// not be refined onto the family: before the refinement asked each placement to be a local
    /// maximum, the flanks of the 1× and 2× lines and of BPFI + 2fr on its windows' edges agreed
    /// at 0.9925 fr and the speed came back 0.99 × the declared one (`hybrid-fdd diagnose` then
    /// read the family as the ball-defect rate, which sits at 3.99 fr on a 6203).
    #[test]
    fn refine_ignores_lines_outside_their_windows() {
        let fs = 1000.0;
        let fr = 15.0;
        let bpfi = 4.946_880_570_409_98 * fr;
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut lines = vec![(fr, 1.0), (2.0 * fr, 0.7)];
        for k in 1..=2 {
            for m in -2..=2 {
                lines.push((f64::from(k) * bpfi + f64::from(m) * fr, 1.0));
            }
        }
        let x: Vec<f64> = (0..6000)
            .map(|i| {
                let t = f64::from(i) / fs;
                let s: f64 = lines
                    .iter()
                    .enumerate()
                    .map(|(j, &(f, a))| a * (2.0 * std::f64::consts::PI * f * t + j as f64).cos())
                    .sum();
                s + 0.2 * (rng.random::<f64>() - 0.5)
            })
            .collect();
        let m = comb_speed(
            &mut SpectralEngine::new(),
            &x,
            fs,
            900.0,
            SPEED_SEARCH,
            f64::INFINITY,
            false,
        )
        .unwrap()
        .expect("no estimate");
        if let Some(r) = m.refined_rpm {
            assert!(
                (r / 900.0 - 1.0).abs() < 2e-3,
                "refined onto the fault family: {m:?}"
            );
        }
    }

    /// A complete shaft comb (orders 1–10) of a shaft turning 0.07 % faster than declared, in
    /// white noise, 5 s at 12 kHz: the comb search is accepted and the refined speed comes back
    /// within 1e-4 (the search alone places it only to a bin at order 10, ± 8e-4 here).
    #[test]
    fn refined_speed_reads_the_comb_to_1e_4() {
        let fs = 12_000.0;
        let rpm = 1797.0;
        let truth = 1.0007;
        let fr = rpm / 60.0 * truth;
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12345);
        let mut uniform = move || rng.random::<f64>() - 0.5;
        let x: Vec<f64> = (0..60_000)
            .map(|i| {
                let t = i as f64 / fs;
                let comb = shaft_comb(t, fr, 0.2, 0.3);
                comb + uniform()
            })
            .collect();
        let m = estimate_speed(&mut SpectralEngine::new(), &x, fs, rpm)
            .unwrap()
            .expect("no estimate");
        assert!(m.accepted, "{m:?}");
        let r = m.refined_rpm.expect("not refined") / rpm;
        assert!((r / truth - 1.0).abs() < 1e-4, "{m:?}");
    }

    /// A complete shaft comb at 1000 rpm (orders 1–10) in white noise, 6 s at 12 kHz, searched
    /// over 300–3600 rpm: the comb at twice the speed is as complete (its orders are the
    /// shaft's even ones), the fundamental is taken; a range of ± 10 % around a speed 6 % off
    /// finds it within the lines' tolerance; a coarse record (2 s at
    /// 600 rpm) states its resolution.
    #[test]
    fn a_range_search_takes_the_comb_s_fundamental() {
        use rand::{Rng, SeedableRng};
        let fs = 12_000.0;
        let comb = |rpm: f64, secs: f64, seed: u64| {
            let fr = rpm / 60.0;
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            (0..(fs * secs) as usize)
                .map(|i| {
                    let t = i as f64 / fs;
                    let c = shaft_comb(t, fr, 0.2, 0.4);
                    c + (rng.random::<f64>() - 0.5)
                })
                .collect::<Vec<f64>>()
        };
        let x = comb(1000.0, 6.0, 1);
        let mut e = SpectralEngine::new();
        let wide = estimate_speed_in(&mut e, &x, fs, 300.0, 3600.0)
            .unwrap()
            .unwrap();
        assert!(wide.accepted, "{wide:?}");
        assert!((wide.rpm / 1000.0 - 1.0).abs() < SPEED_TOL, "{wide:?}");
        let near = estimate_speed_in(&mut e, &x, fs, 940.0 * 0.9, 940.0 * 1.1)
            .unwrap()
            .unwrap();
        // 6 s bins (0.17 Hz) are wider than REFINE_RESOLUTION of the range's centre rate: the
        // grid's estimate, within the lines' own tolerance
        assert!(
            (near.refined_rpm.unwrap_or(near.rpm) / 1000.0 - 1.0).abs() < SPEED_TOL,
            "{near:?}"
        );
        let short = comb(600.0, 2.0, 2);
        let coarse = estimate_speed_in(&mut e, &short, fs, 540.0, 660.0)
            .unwrap()
            .unwrap();
        assert!(coarse.resolution > 0.5 * SPEED_TOL, "{coarse:?}");
        // accepted or not, it states how coarse its grid is, and an accepted comb lies within it
        assert!(
            !coarse.accepted || (coarse.rpm / 600.0 - 1.0).abs() <= 2.0 * coarse.resolution,
            "{coarse:?}"
        );
    }

    /// A shaft at 600 rpm on a 50 Hz supply: its 5th and 10th orders on the supply's 50 and
    /// 100 Hz lines, its 6th on 60 Hz (not scored). Searched ± 10 % around 600 rpm, the comb is
    /// found at its speed within the lines' tolerance and complete over the orders scored.
    /// Before orders were kept [`MAINS_REACH_BINS`] (3.5) from a mains multiple and combs
    /// compared per scored order, it scored best 0.5 % fast, where those orders stepped out of a
    /// 1.5-bin exclusion and read the main lobes of the lines on the multiples.
    #[test]
    fn a_shaft_at_a_mains_submultiple_is_read_at_its_speed() {
        use rand::{Rng, SeedableRng};
        let fs = 12_000.0;
        let fr = 10.0;
        let mut e = SpectralEngine::new();
        for seed in 5..8 {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let x: Vec<f64> = (0..(fs * 6.0) as usize)
                .map(|i| {
                    let t = i as f64 / fs;
                    let shaft = shaft_comb(t, fr, 0.3, 0.4);
                    let supply = (2.0 * std::f64::consts::PI * 49.98 * t).cos()
                        + 0.5 * (2.0 * std::f64::consts::PI * 99.96 * t).cos();
                    shaft + supply + (rng.random::<f64>() - 0.5)
                })
                .collect();
            let m = estimate_speed_in(&mut e, &x, fs, 540.0, 660.0)
                .unwrap()
                .unwrap();
            assert!((m.rpm / 600.0 - 1.0).abs() < SPEED_TOL, "{m:?}");
            assert!(m.is_complete() && m.orders_scored == 7, "{m:?}");
        }
    }

    /// A loose machine: a shaft comb at 1000 rpm (orders 1–10) with half orders 0.5 … 5.5 8 dB
    /// under it, searched over 300–3600 rpm. The comb at half the speed is as complete (it
    /// holds the half orders and the shaft's), and its first order stands 8 dB under its second:
    /// the shaft is at 1000 rpm. A machine at 500 rpm whose 2× stands 2 dB over its 1×
    /// (misalignment), with its orders 1–20, is still read at 500 rpm.
    #[test]
    fn a_comb_of_half_orders_is_no_fundamental() {
        use rand::{Rng, SeedableRng};
        let fs = 12_000.0;
        let tones = |fr: f64, lines: &[(f64, f64)], seed: u64| {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            (0..(fs * 6.0) as usize)
                .map(|i| {
                    let t = i as f64 / fs;
                    let c: f64 = lines
                        .iter()
                        .map(|&(k, a)| {
                            a * (2.0 * std::f64::consts::PI * k * fr * t + 0.4 * k).cos()
                        })
                        .sum();
                    c + (rng.random::<f64>() - 0.5)
                })
                .collect::<Vec<f64>>()
        };
        let under = |db: f64| 0.2 * 10f64.powf(-db / 20.0);
        let loose: Vec<(f64, f64)> = (1..=10)
            .map(|k| (f64::from(k), 0.2))
            .chain((0..=5).map(|k| (f64::from(k) + 0.5, under(8.0))))
            .collect();
        let mut e = SpectralEngine::new();
        // the machine's speed within the lines' tolerance of the range search's reading
        let mut read_at = |x: &[f64], rpm: f64| {
            let m = estimate_speed_in(&mut e, x, fs, 300.0, 3600.0)
                .unwrap()
                .unwrap();
            let found = m.refined_rpm.unwrap_or(m.rpm);
            assert!((found / rpm - 1.0).abs() < SPEED_TOL, "{m:?}");
        };
        read_at(&tones(1000.0 / 60.0, &loose, 3), 1000.0);
        let misaligned: Vec<(f64, f64)> = (1..=20)
            .map(|k| (f64::from(k), if k == 2 { under(-2.0) } else { 0.2 }))
            .collect();
        read_at(&tones(500.0 / 60.0, &misaligned, 4), 500.0);
    }
}
