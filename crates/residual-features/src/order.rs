//! Computed order tracking: a recording whose shaft speed changes, resampled at equal shaft
//! angles from a tachometer channel recorded beside it.
//!
//! An envelope spectrum reads a bearing's fault lines at `order × fr`; when the speed sweeps
//! (a run-up, a coast-down, a variable-speed drive: the University of Ottawa's ER-16K records
//! sweep 40–60 % in 10 s) every line smears over the sweep and no fault can be read at any
//! one speed. Resampled at equal angles of the shaft — `S` samples per turn — the fault's
//! impacts recur at a fixed number of samples again, and its lines stand at fixed orders
//! (Fyfe & Munck 1997; Borghesani et al. 2013 applied it before envelope analysis of bearings at
//! variable speed). The resampled recording is then an ordinary one at the **equivalent rate**
//! `S × mean fr` Hz: a line at order `o` stands at `o × mean fr` Hz, so any analysis of a
//! constant-speed recording reads it at the mean speed.
//!
//! 1. **Pulses**: rising crossings of the tachometer's mid level (between its 5th and 95th
//!    percentiles; re-armed only after it falls below 30 % of that span: a noisy edge is one
//!    pulse), each placed by linear interpolation between its two samples. `pulses_per_rev`
//!    pulses make a turn (an encoder's lines, a key's 1).
//! 2. **Checks**: at least [`MIN_TURNS`] turns of pulses; no pulse interval more than
//!    [`MAX_INTERVAL_RATIO`] times the median of its neighbours (a missed or doubled pulse
//!    would put every later sample at a wrong angle).
//! 3. **Angle**: the shaft angle is linear in time between pulses (a turn of a once-per-turn
//!    key at its mean speed; 1/1024 turn of an encoder).
//! 4. **Resampling**: read at each angle's time by cubic (Catmull–Rom) interpolation at
//!    `⌈fs / min fr⌉` samples a turn (no turn coarser than the recording's own step: nothing
//!    aliases), then the order band every turn holds kept and nothing above it — up to
//!    [`ORDER_BAND_FRACTION`] of `fs / (2 max fr)`, the spectrum truncated there and the record
//!    decimated to it ([`crate::SpectralEngine::low_pass_resample`]). A band only the slow turns
//!    hold would be amplified without bound by a whitening (AR) filter fitted where it is empty:
//!    a coast-down's residual stood 80 times over the signal's RMS when the band was cut in time
//!    instead, and a band cut to exact zeros below the rate's Nyquist left the AR fit rank
//!    deficient. Only the span between the first and the last pulse is kept.
//!
//! What it cannot do: a speed that changes within one pulse interval (a key's once-per-turn at
//! a fast run-up) is taken as constant over it; structural resonances are fixed in Hz, not in
//! orders, so in the resampled record they smear by the speed's range (a band chosen for its
//! impulsiveness is still one, only wider).

use serde::{Deserialize, Serialize};

use crate::error::{FeatureError, Result, check_finite, check_positive};
use crate::{Band, SpectralEngine, speed};

/// Fewest shaft turns the pulses must span.
pub const MIN_TURNS: f64 = 20.0;
/// A pulse interval more than this many times the median of its neighbours (or less than its
/// inverse) is a missed or spurious pulse.
pub const MAX_INTERVAL_RATIO: f64 = 1.8;
/// Neighbours on each side whose median interval a pulse interval is compared with.
const NEIGHBOURS: usize = 8;
/// Share of the order band the fastest turn holds (`fs / (2 max fr)`) that is kept: a margin
/// for the recorder's anti-alias roll-off and the interpolation's loss near its step.
pub const ORDER_BAND_FRACTION: f64 = 0.9;
/// Fewest samples per turn a resampled recording may have.
pub const MIN_SAMPLES_PER_REV: usize = 32;

/// Where the shaft's angle came from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum AngleSource {
    /// A tachometer channel's pulses.
    Tachometer {
        /// Pulses found.
        pulses: usize,
        /// Pulses per turn, as given.
        pulses_per_rev: f64,
    },
    /// The recording's own shaft comb, read frame by frame ([`speed_profile`]).
    ShaftComb {
        /// Frames the recording was cut in.
        frames: usize,
        /// Frames whose comb was read.
        frames_read: usize,
        /// Frame length, s.
        frame_s: f64,
        /// The shaft order whose phase refined the angle ([`order_track_profile`]); `None` when
        /// no order's line stood out enough and the frames' speeds gave it alone.
        #[serde(default)]
        phase_order: Option<usize>,
    },
}

/// A recording resampled at equal shaft angles.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OrderTracked {
    /// The samples, one every `1 / samples_per_rev` of a turn.
    #[serde(skip)]
    pub samples: Vec<f64>,
    /// Samples per shaft turn.
    pub samples_per_rev: f64,
    /// Mean shaft speed over the span kept, rpm.
    pub mean_rpm: f64,
    /// Slowest speed (over a turn of pulses, or a frame of the comb), rpm.
    pub min_rpm: f64,
    /// Fastest speed, rpm.
    pub max_rpm: f64,
    /// The equivalent sampling rate, Hz: `samples_per_rev × mean fr`.
    pub equivalent_fs_hz: f64,
    /// Turns spanned.
    pub turns: f64,
    /// Highest order kept: the band every turn holds (see the module documentation).
    pub max_order: f64,
    /// Where the angle came from.
    pub source: AngleSource,
}

/// Times (s) of the tachometer's pulses: rising crossings of its mid level, see the module
/// documentation.
///
/// # Errors
/// Empty or non-finite input, a non-positive rate, or [`FeatureError::TachPulses`] for a
/// tachometer without a level span (a constant channel).
pub fn tach_pulse_times(tach: &[f64], fs_hz: f64) -> Result<Vec<f64>> {
    check_finite(tach)?;
    check_positive("fs_hz", fs_hz)?;
    let mut sorted = tach.to_vec();
    sorted.sort_by(f64::total_cmp);
    let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
    let (lo, hi) = (at(0.05), at(0.95));
    let span = hi - lo;
    if span <= f64::EPSILON * hi.abs().max(lo.abs()).max(1.0) {
        return Err(FeatureError::TachPulses {
            pulses: 0,
            turns: 0.0,
            needed_turns: MIN_TURNS,
        });
    }
    let mid = lo + 0.5 * span;
    let rearm = lo + 0.3 * span;
    let mut armed = tach[0] < rearm;
    let mut times = Vec::new();
    for (i, w) in tach.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        if b < rearm {
            armed = true;
        } else if armed && a < mid && b >= mid {
            let frac = (mid - a) / (b - a);
            times.push((i as f64 + frac) / fs_hz);
            armed = false;
        }
    }
    Ok(times)
}

/// Resample `x` (at `fs_hz`) at equal shaft angles from the tachometer `tach` recorded beside
/// it (same rate and length), `pulses_per_rev` pulses a turn; see the module documentation.
///
/// # Errors
/// Input errors; [`FeatureError::TachLength`] when the two channels differ in length;
/// [`FeatureError::TachPulses`] for pulses spanning fewer than [`MIN_TURNS`] turns;
/// [`FeatureError::TachIrregular`] for a missed or spurious pulse;
/// [`FeatureError::InvalidParameter`] when the fastest turn leaves fewer than
/// [`MIN_SAMPLES_PER_REV`] samples a turn.
pub fn order_track(
    engine: &mut SpectralEngine,
    x: &[f64],
    tach: &[f64],
    fs_hz: f64,
    pulses_per_rev: f64,
) -> Result<OrderTracked> {
    check_finite(x)?;
    check_positive("pulses_per_rev", pulses_per_rev)?;
    if tach.len() != x.len() {
        return Err(FeatureError::TachLength {
            signal: x.len(),
            tach: tach.len(),
        });
    }
    let t = tach_pulse_times(tach, fs_hz)?;
    let turns = t.len().saturating_sub(1) as f64 / pulses_per_rev;
    if t.len() < 2 || turns < MIN_TURNS {
        return Err(FeatureError::TachPulses {
            pulses: t.len(),
            turns,
            needed_turns: MIN_TURNS,
        });
    }
    let dt: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    check_intervals(&dt)?;
    // speed over each turn of pulses (a pulse interval of an encoder is too short to read one)
    let per_turn = (pulses_per_rev.round() as usize).max(1);
    let turn_rates: Vec<f64> = dt
        .chunks_exact(per_turn)
        .map(|c| per_turn as f64 / pulses_per_rev / c.iter().sum::<f64>())
        .collect();
    // the angle at each sample between the first and the last pulse, linear between pulses
    let first = (t[0] * fs_hz).ceil() as usize;
    let last = ((t[t.len() - 1] * fs_hz).floor() as usize).min(x.len() - 1);
    let theta: Vec<f64> = walk_linear(&t, |p| p as f64, (first..=last).map(|k| k as f64 / fs_hz))
        .into_iter()
        .map(|pulses| pulses / pulses_per_rev)
        .collect();
    let a = angular(&x[first..=last], fs_hz, &theta, &turn_rates)?;
    finish(
        engine,
        a,
        fs_hz,
        AngleSource::Tachometer {
            pulses: t.len(),
            pulses_per_rev,
        },
    )
}

/// The shaft speed through a recording, read from its shaft comb frame by frame
/// ([`speed_profile`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedProfile {
    /// Frame length, s.
    pub frame_s: f64,
    /// Frame centres, s.
    pub centres_s: Vec<f64>,
    /// Speed at each centre (the median of three neighbouring frames' path speeds, then a straight
    /// line through [`SMOOTH_HALF`] frames each side read at the frame), rpm.
    pub rpm: Vec<f64>,
    /// Frames whose comb is read at the path's speed (the others take the speed the path
    /// leads through them).
    pub frames_read: usize,
}

impl SpeedProfile {
    /// The fastest speed over the slowest, less one.
    pub fn spread(&self) -> f64 {
        let (lo, hi) = self
            .rpm
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
        hi / lo - 1.0
    }

    /// Speed at `t` s, Hz (linear between frame centres, held beyond the first and last).
    fn hz_at(&self, t: f64) -> f64 {
        let c = &self.centres_s;
        let i = c.partition_point(|&v| v <= t);
        let rpm = if i == 0 {
            self.rpm[0]
        } else if i >= c.len() {
            self.rpm[c.len() - 1]
        } else {
            let w = (t - c[i - 1]) / (c[i] - c[i - 1]);
            self.rpm[i - 1] + w * (self.rpm[i] - self.rpm[i - 1])
        };
        rpm / 60.0
    }
}

/// Shaft turns a profile frame holds at the slowest speed searched.
pub const FRAME_TURNS: f64 = 12.0;
/// Largest relative change of the speed from one frame to the next (half a frame apart).
pub const TRACK_SEARCH: f64 = 0.06;
/// Frames each side of a frame whose (median-of-three) readings are averaged into its speed:
/// one frame's reading scatters by about 1 % (its comb's top order smeared by the speed's
/// change within it), and the angle integrates that scatter.
pub const SMOOTH_HALF: usize = 2;
/// Fewest frames a profile is read from.
pub const MIN_FRAMES: usize = 6;
/// Share of the frames whose comb must be read at the path's speed ([`speed_profile`]). A path
/// chosen over all frames at once carries a frame whose comb is weak on its neighbours' (a
/// 12-turn frame of a comb at 0 dB SNR shows its first order at 10 dB in one frame of two or
/// three); what says a profile is a speed is the tracked record's own comb
/// (`diagnosis::driver::first_look`, [`crate::speed::leading_lines_speed`]), which refused every
/// path of the corpus's sweeping machines that strayed more than 10 % from the true speed. Until
/// 2026-12-08, with frames tracked one by one, 0.8.
pub const MIN_FRAMES_READ: f64 = 0.25;
/// A frame whose reading is this far (relative) from the median of it and its two neighbours
/// is an outlier; a profile with more than a fifth of them is not one. The path's frame at the
/// seed stays within this of the seed's own reading.
pub const FRAME_OUTLIER: f64 = 0.02;
/// Step of the speed grid the path through the frames is chosen on (relative, log-spaced).
pub const PATH_STEP: f64 = 0.002;
/// The grid reaches this far (relative) each way from the seed's speed: a sweep of a whole
/// mean speed's span from either end.
pub const PATH_REACH: f64 = 1.0;
/// What a change of the speed between neighbouring frames costs the path, per unit of relative
/// change, in the comb score's units (log₁₀ power: 1 = 10 dB at one order): a 6 % step costs
/// 0.3, a third of one order standing 10 dB; a frame's noise moves no path, a comb's order does.
pub const PATH_CHANGE_COST: f64 = 5.0;

/// The shaft speed through the recording `x`, read from its own shaft comb frame by frame:
/// frames of [`FRAME_TURNS`] turns at `rpm_low` (half overlapping); a seed, the frame whose comb
/// over `[rpm_low, rpm_high]` scores best (searched as a whole recording is, [`crate::speed`]'s
/// comb, the frame read by its rules); then the path of speeds through every frame, on a grid of
/// [`PATH_STEP`] within ± [`PATH_REACH`] of the seed's speed, that holds the most comb score
/// (each frame's comb scored at the path's speed, less [`PATH_CHANGE_COST`] per relative change
/// between frames; no change over [`TRACK_SEARCH`]; at the seed's frame within
/// [`FRAME_OUTLIER`] of its reading) — chosen over all frames at once by dynamic programming
/// (Viterbi), so a frame whose comb is weak or smeared takes the speed its neighbours' combs
/// lead through, and a sweep may leave the range searched. Until 2026-12-08 each frame was
/// searched around its neighbour's reading in turn and a frame not read kept the neighbour's
/// speed: one misread frame moved every later one, and the readings' scatter (a 12-turn frame
/// places a comb of three orders only to a few per cent) refused most sweeping machines. `None`
/// when fewer than [`MIN_FRAMES`] frames fit, fewer than [`MIN_FRAMES_READ`] of them show a comb
/// at the path's speed (read by the frame rules), or more than a fifth stand [`FRAME_OUTLIER`]
/// off their neighbours' median (no comb the frames agree on).
///
/// # Errors
/// Input errors.
pub fn speed_profile(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    rpm_low: f64,
    rpm_high: f64,
) -> Result<Option<SpeedProfile>> {
    check_finite(x)?;
    check_positive("fs_hz", fs_hz)?;
    check_positive("rpm_low", rpm_low)?;
    let len = (FRAME_TURNS * fs_hz * 60.0 / rpm_low).round() as usize;
    let hop = len / 2;
    if hop == 0 || x.len() < len {
        return Ok(None);
    }
    let frames = (x.len() - len) / hop + 1;
    if frames < MIN_FRAMES {
        return Ok(None);
    }
    let frame = |i: usize| &x[i * hop..i * hop + len];
    // the seed: the frame whose comb over the whole range scores best
    let (centre, search) = speed::range_search(rpm_low, rpm_high);
    let mut seed: Option<(usize, f64, f64)> = None;
    for i in 0..frames {
        if let Some(m) = speed::comb_speed(engine, frame(i), fs_hz, centre, search, 0.0, true)?
            && frame_read(&speed::CombReading::of(&m))
            && seed.is_none_or(|s| m.comb_score > s.2)
        {
            seed = Some((i, m.rpm, m.comb_score));
        }
    }
    let Some((i0, rpm0, _)) = seed else {
        return Ok(None);
    };
    let Some(rpm) = comb_path(engine, x, fs_hz, (len, hop, frames), (i0, rpm0))? else {
        return Ok(None);
    };
    let frames_read = rpm.iter().filter(|r| r.1).count();
    let rpm: Vec<f64> = rpm.iter().map(|r| r.0).collect();
    if (frames_read as f64) < MIN_FRAMES_READ * frames as f64 {
        return Ok(None);
    }
    let median: Vec<f64> = (0..frames)
        .map(|i| {
            let mut w = [
                rpm[i.saturating_sub(1)],
                rpm[i],
                rpm[(i + 1).min(frames - 1)],
            ];
            w.sort_by(f64::total_cmp);
            w[1]
        })
        .collect();
    // then a straight line through the 2·SMOOTH_HALF + 1 frames around each (shifted inside at
    // the ends), read at the frame: a ramp stays one, the ends included
    let w = (2 * SMOOTH_HALF + 1).min(frames);
    let smooth: Vec<f64> = (0..frames)
        .map(|i| {
            let a = i.saturating_sub(SMOOTH_HALF).min(frames - w);
            let xs = (a..a + w).map(|k| k as f64);
            let mx = xs.clone().sum::<f64>() / w as f64;
            let my = median[a..a + w].iter().sum::<f64>() / w as f64;
            let (sxy, sxx) = xs
                .zip(&median[a..a + w])
                .fold((0.0, 0.0), |(p, q), (x, y)| {
                    (p + (x - mx) * (y - my), q + (x - mx) * (x - mx))
                });
            my + sxy / sxx * (i as f64 - mx)
        })
        .collect();
    let outliers = rpm
        .iter()
        .zip(&median)
        .filter(|(r, s)| (*r / *s - 1.0).abs() > FRAME_OUTLIER)
        .count();
    if outliers * 5 > frames {
        return Ok(None);
    }
    Ok(Some(SpeedProfile {
        frame_s: len as f64 / fs_hz,
        centres_s: (0..frames)
            .map(|i| (i * hop) as f64 / fs_hz + 0.5 * len as f64 / fs_hz)
            .collect(),
        rpm: smooth,
        frames_read,
    }))
}

/// The path of speeds (rpm) through the `frames` frames of `len` samples `hop` apart that holds
/// the most comb score ([`speed_profile`]), through the seed's frame `i0` near its reading
/// `rpm0`, each with whether its comb is read there ([`frame_read`]); `None` when a frame's
/// spectrum cannot be read.
fn comb_path(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    (len, hop, frames): (usize, usize, usize),
    (i0, rpm0): (usize, f64),
) -> Result<Option<Vec<(f64, bool)>>> {
    let half = ((1.0 + PATH_REACH).ln() / PATH_STEP).floor() as i64;
    let grid: Vec<f64> = (-half..=half)
        .map(|j| rpm0 * (j as f64 * PATH_STEP).exp())
        .collect();
    let m = grid.len();
    let jump = ((1.0 + TRACK_SEARCH).ln() / PATH_STEP).floor() as usize;
    let mut combs = Vec::with_capacity(frames);
    let mut scores: Vec<Vec<f64>> = Vec::with_capacity(frames);
    for i in 0..frames {
        let Some(c) =
            speed::CombFrame::read(engine, &x[i * hop..i * hop + len], fs_hz, rpm0, PATH_REACH)?
        else {
            return Ok(None);
        };
        // each order's score at each grid speed; an order the mains hide there scores as the
        // frame's typical order (the median over the grid): neither evidence for the speed nor
        // against it. A short frame's mains exclusion (± 3.5 bins of 1–4 Hz around every
        // multiple of 50 and 60 Hz) hides most orders at some speeds — at 1500 rpm in a 0.54 s
        // frame seven of ten — and the whole-record score (the mean over the orders scored)
        // then rated those speeds by their strongest orders alone: the path held a frame's
        // speed near them.
        let per: Vec<Vec<Option<f64>>> =
            grid.iter().map(|&g| c.order_scores(g).collect()).collect();
        let mut all: Vec<f64> = per.iter().flatten().flatten().copied().collect();
        let typical = if all.is_empty() {
            0.0
        } else {
            let mid = all.len() / 2;
            *all.select_nth_unstable_by(mid, f64::total_cmp).1
        };
        let mut s: Vec<f64> = per
            .iter()
            .map(|o| o.iter().map(|v| v.unwrap_or(typical)).sum())
            .collect();
        if i == i0 {
            for (v, g) in s.iter_mut().zip(&grid) {
                if (g / rpm0 - 1.0).abs() > FRAME_OUTLIER {
                    *v = f64::NEG_INFINITY;
                }
            }
        }
        scores.push(s);
        combs.push(c);
    }
    // Viterbi: the best total up to each frame at each grid speed, and where it came from
    let cost = |d: usize| PATH_CHANGE_COST * d as f64 * PATH_STEP;
    let mut total = scores[0].clone();
    let mut from: Vec<Vec<u32>> = Vec::with_capacity(frames);
    for s in &scores[1..] {
        let mut next = vec![f64::NEG_INFINITY; m];
        let mut back = vec![0u32; m];
        for j in 0..m {
            let (lo, hi) = (j.saturating_sub(jump), (j + jump).min(m - 1));
            for (k, t) in total.iter().enumerate().take(hi + 1).skip(lo) {
                let v = t - cost(j.abs_diff(k));
                if v > next[j] {
                    next[j] = v;
                    back[j] = k as u32;
                }
            }
            next[j] += s[j];
        }
        total = next;
        from.push(back);
    }
    let mut j = (0..m)
        .max_by(|&a, &b| total[a].total_cmp(&total[b]))
        .unwrap_or(0);
    if !total[j].is_finite() {
        return Ok(None);
    }
    let mut path = vec![0usize; frames];
    path[frames - 1] = j;
    for i in (1..frames).rev() {
        j = from[i - 1][j] as usize;
        path[i - 1] = j;
    }
    Ok(Some(
        path.iter()
            .zip(&combs)
            .map(|(&j, c)| (grid[j], frame_read(&c.reading(grid[j]))))
            .collect(),
    ))
}

/// Orders a frame's comb must hold present ([`speed::COMB_MIN_ORDER_PRESENT`]), its first among
/// them at [`speed::COMB_MIN_FIRST_ORDER`], when it is not complete.
pub const FRAME_MIN_ORDERS: usize = 3;

/// A frame's comb is read when it is complete and strong ([`speed::SpeedEstimate::is_complete`],
/// [`speed::COMB_MIN_PER_ORDER`]), or when its first order stands and [`FRAME_MIN_ORDERS`]
/// orders are present: a shaft comb falling a few dB an order after the second shows three to
/// five orders in a frame of [`FRAME_TURNS`] turns, and the completeness rule over ten orders
/// refused most frames of such machines (the corpus's sweeping machines: a profile on 14 of 40
/// with a shaft comb). Its contrast is not asked — a frame resolves a shaft order to a twelfth
/// of the shaft rate, so the combs within ± [`speed::CONTRAST_HALF_WIDTH`] read the same bins and
/// score alike (the neighbouring frames' agreement, [`FRAME_OUTLIER`], is the check instead).
fn frame_read(c: &speed::CombReading) -> bool {
    (c.is_complete() && c.score >= speed::COMB_MIN_PER_ORDER * c.orders as f64)
        || (c.first_order >= speed::COMB_MIN_FIRST_ORDER && c.present >= FRAME_MIN_ORDERS)
}

/// Resample `x` at equal shaft angles along a [`speed_profile`]: the angle first the integral of
/// its speed (linear between frame centres), then — where one of the first [`PHASE_ORDERS`] shaft
/// orders stands [`PHASE_MIN_PROMINENCE_DB`] over its neighbourhood in the record so resampled —
/// that order's own phase (its line band-passed ± [`PHASE_HALF_WIDTH`] orders, the analytic
/// signal's unwrapped phase over `2π·k`; Bonnardot et al. 2005): the frames' speeds scatter by
/// about 1 %, which smears a fault's higher harmonics, while a clean shaft line carries the angle
/// sample by sample.
///
/// # Errors
/// Input errors; [`FeatureError::InvalidParameter`] when the fastest frame leaves fewer than
/// [`MIN_SAMPLES_PER_REV`] samples a turn.
pub fn order_track_profile(
    engine: &mut SpectralEngine,
    x: &[f64],
    fs_hz: f64,
    profile: &SpeedProfile,
) -> Result<OrderTracked> {
    check_finite(x)?;
    check_positive("fs_hz", fs_hz)?;
    let mut theta = Vec::with_capacity(x.len());
    let mut acc = 0.0;
    let mut prev = profile.hz_at(0.0);
    for k in 0..x.len() {
        let f = profile.hz_at(k as f64 / fs_hz);
        if k > 0 {
            acc += 0.5 * (prev + f) / fs_hz;
        }
        prev = f;
        theta.push(acc);
    }
    let rates: Vec<f64> = profile.rpm.iter().map(|r| r / 60.0).collect();
    let source = |phase_order| AngleSource::ShaftComb {
        frames: profile.rpm.len(),
        frames_read: profile.frames_read,
        frame_s: profile.frame_s,
        phase_order,
    };
    let coarse = angular(x, fs_hz, &theta, &rates)?;
    let at = &coarse.at;
    let Some((k, angle)) = phase_angle(engine, &coarse.samples, coarse.spr)? else {
        return finish(engine, coarse, fs_hz, source(None));
    };
    if at.len() < 2 {
        return finish(engine, coarse, fs_hz, source(None));
    }
    // the refined angle at each original sample: between the coarse samples' positions `at`
    let first = at[0].ceil() as usize;
    let last = (at[at.len() - 1].floor() as usize).min(x.len() - 1);
    let refined = walk_linear(at, |j| angle[j], (first..=last).map(|i| i as f64));
    if refined.windows(2).any(|w| w[1] <= w[0]) {
        return finish(engine, coarse, fs_hz, source(None));
    }
    // the speed the refined angle shows over each of the profile's frames: the record's range
    // (and so its band and its samples a turn) from the angle it is resampled along, not from
    // the frames' comb readings it corrected (a steady record's frames scatter by a few per
    // cent; its refined angle turns at one speed)
    let half = (0.5 * profile.frame_s * fs_hz).round() as usize;
    let refined_rates: Vec<f64> = profile
        .centres_s
        .iter()
        .filter_map(|c| {
            let mid = (c * fs_hz).round() as usize;
            let (a, b) = (mid.saturating_sub(half).max(first), (mid + half).min(last));
            (b > a + half)
                .then(|| (refined[b - first] - refined[a - first]) * fs_hz / (b - a) as f64)
        })
        .collect();
    let rates = if refined_rates.is_empty() {
        rates
    } else {
        refined_rates
    };
    let a = angular(&x[first..=last], fs_hz, &refined, &rates)?;
    finish(engine, a, fs_hz, source(Some(k)))
}

/// Shaft orders whose line may carry the angle ([`order_track_profile`]).
pub const PHASE_ORDERS: usize = 5;
/// Half-width of the band around the order whose phase is read, orders: wider than the speed
/// error left by the frames (about 1 % × the order), narrower than half an order.
pub const PHASE_HALF_WIDTH: f64 = 0.25;
/// The order's line must stand this far (dB, power) over the median of its neighbourhood
/// (± ½ order) to carry the angle.
pub const PHASE_MIN_PROMINENCE_DB: f64 = 20.0;

/// The angle (turns from the first sample) at each sample of `y` (`spr` samples a turn, nearly
/// equal angles) read from the phase of its most prominent shaft order among the first
/// [`PHASE_ORDERS`], with that order; `None` when none stands [`PHASE_MIN_PROMINENCE_DB`] out or
/// its phase does not advance.
fn phase_angle(
    engine: &mut SpectralEngine,
    y: &[f64],
    spr: usize,
) -> Result<Option<(usize, Vec<f64>)>> {
    let rate = spr as f64; // samples a turn: a line at order k stands at "k Hz"
    let sp = engine.amplitude_spectrum(y, rate, crate::Taper::Hann)?;
    let d = sp.resolution_hz;
    let bin = |o: f64| (o / d).round() as usize;
    let mut best: Option<(usize, f64)> = None;
    for k in 1..=PHASE_ORDERS {
        let kf = k as f64;
        if bin(kf + 0.5) >= sp.values.len() {
            break;
        }
        let peak = sp.values[bin(kf - 0.05)..=bin(kf + 0.05)]
            .iter()
            .copied()
            .fold(0.0, f64::max);
        let mut around: Vec<f64> = (bin(kf - 0.5)..=bin(kf + 0.5))
            .filter(|&i| (i as f64 * d - kf).abs() > 0.1)
            .map(|i| sp.values[i])
            .collect();
        if around.is_empty() {
            continue;
        }
        around.sort_by(f64::total_cmp);
        let median = around[around.len() / 2];
        let db = 20.0 * (peak / median.max(f64::MIN_POSITIVE)).log10();
        if db >= PHASE_MIN_PROMINENCE_DB && best.is_none_or(|b| db > b.1) {
            best = Some((k, db));
        }
    }
    let Some((k, _)) = best else {
        return Ok(None);
    };
    let kf = k as f64;
    let phase = engine.band_phase(
        y,
        rate,
        Band::new(kf - PHASE_HALF_WIDTH, kf + PHASE_HALF_WIDTH)?,
    )?;
    let angle: Vec<f64> = phase
        .iter()
        .map(|p| (p - phase[0]) / (2.0 * std::f64::consts::PI * kf))
        .collect();
    // the line must turn forward as the shaft does, at about its rate (within the band)
    let turns = angle[angle.len() - 1];
    let nominal = (y.len() - 1) as f64 / rate;
    if !(turns.is_finite() && (turns / nominal - 1.0).abs() < PHASE_HALF_WIDTH / kf) {
        return Ok(None);
    }
    Ok(Some((k, angle)))
}

/// A recording read at equal shaft angles, finely: [`angular`]'s output before [`finish`].
struct Angular {
    /// Samples, `spr` a turn.
    samples: Vec<f64>,
    /// Each sample's position in the recording (a fractional index).
    at: Vec<f64>,
    /// Samples a turn: `⌈fs / min fr⌉`, so that no turn is read coarser than the recording.
    spr: usize,
    turns: f64,
    mean_fr: f64,
    min_fr: f64,
    max_fr: f64,
}

/// `x` (at `fs_hz`) whose sample `k` stands at shaft angle `theta[k]` turns (increasing), read at
/// `⌈fs / min rate⌉` samples a turn by Catmull–Rom interpolation: never coarser than the
/// recording's own step, so nothing aliases and no time-domain filter is needed. `rates` (Hz)
/// are the speeds read along the way (turn by turn, or frame by frame) and give the range.
fn angular(x: &[f64], fs_hz: f64, theta: &[f64], rates: &[f64]) -> Result<Angular> {
    let n = x.len().min(theta.len());
    if n < 4 {
        return Err(FeatureError::TooShort {
            needed: 4,
            found: n,
        });
    }
    let turns = theta[n - 1] - theta[0];
    let mean_fr = turns / ((n - 1) as f64 / fs_hz);
    let (min_fr, max_fr) = rates
        .iter()
        .fold((mean_fr, mean_fr), |(a, b), &r| (a.min(r), b.max(r)));
    let spr = (fs_hz / min_fr).ceil() as usize;
    let total = (turns * spr as f64).floor() as usize;
    // each angle's position in the recording (a fractional index), then the sample there
    let at = walk_linear(
        &theta[..n],
        |k| k as f64,
        (0..total).map(|j| theta[0] + j as f64 / spr as f64),
    );
    let samples = at.iter().map(|&u| catmull_rom(&x[..n], u)).collect();
    Ok(Angular {
        samples,
        at,
        spr,
        turns,
        mean_fr,
        min_fr,
        max_fr,
    })
}

/// The order band every turn holds and the record decimated to it: at the fastest turn the
/// recording reaches order `fs / (2 max fr)`, so the orders up to [`ORDER_BAND_FRACTION`] of that
/// are kept (the spectrum truncated there, [`SpectralEngine::low_pass_resample`], on a 5-smooth
/// count of bins so that no empty band is left above them) and nothing above: a band that only
/// the slow turns hold would be amplified without bound by a whitening filter fitted where it
/// is empty (a coast-down's residual stood 80 times over the signal before this step).
fn finish(
    engine: &mut SpectralEngine,
    a: Angular,
    fs_hz: f64,
    source: AngleSource,
) -> Result<OrderTracked> {
    let max_order = ORDER_BAND_FRACTION * 0.5 * fs_hz / a.max_fr;
    // the turns `low_pass_resample` transforms (its 7-smooth length), so that the bins it keeps
    // are exactly `bins` and it transforms back on twice as many
    let duration = (2 * crate::smooth_floor(a.samples.len() / 2)) as f64 / a.spr as f64;
    let bins = crate::spectral::smooth5_floor((max_order * duration).floor() as usize);
    let kept_order = (bins as f64 - 1.5) / duration;
    let spr_out = 2.0 * bins as f64 / duration;
    if spr_out < MIN_SAMPLES_PER_REV as f64 || kept_order <= 0.0 {
        return Err(FeatureError::InvalidParameter {
            name: "samples_per_rev",
            value: spr_out,
            reason: "the fastest turn leaves fewer than 32 samples a turn: the sampling rate is too low for order tracking",
        });
    }
    let (samples, rate) = engine.low_pass_resample(&a.samples, a.spr as f64, kept_order)?;
    let equivalent_fs_hz = rate * a.mean_fr;
    Ok(OrderTracked {
        samples,
        samples_per_rev: rate,
        mean_rpm: 60.0 * a.mean_fr,
        min_rpm: 60.0 * a.min_fr,
        max_rpm: 60.0 * a.max_fr,
        equivalent_fs_hz,
        turns: a.turns,
        max_order: kept_order,
        source,
    })
}

/// A missed or spurious pulse: an interval far from the median of its neighbours.
fn check_intervals(dt: &[f64]) -> Result<()> {
    let n = dt.len();
    let mut window = Vec::with_capacity(2 * NEIGHBOURS + 1);
    for (i, &d) in dt.iter().enumerate() {
        window.clear();
        let (a, b) = (i.saturating_sub(NEIGHBOURS), (i + NEIGHBOURS + 1).min(n));
        window.extend(
            dt[a..b]
                .iter()
                .enumerate()
                .filter(|(k, _)| a + k != i)
                .map(|(_, v)| *v),
        );
        if window.is_empty() {
            continue;
        }
        window.sort_by(f64::total_cmp);
        let median = window[window.len() / 2];
        let ratio = d / median;
        if !(ratio.is_finite() && (1.0 / MAX_INTERVAL_RATIO..=MAX_INTERVAL_RATIO).contains(&ratio))
        {
            return Err(FeatureError::TachIrregular {
                pulse: i + 1,
                ratio,
            });
        }
    }
    Ok(())
}

/// The piecewise-linear function through the knots `(xs[i], y(i))` (`xs` increasing, at least
/// two) at each of the increasing `queries`, one pointer walked once through the knots (beyond
/// the last knot its last segment extends): a pulse's or a sample's angle, an angle's position.
fn walk_linear(
    xs: &[f64],
    y: impl Fn(usize) -> f64,
    queries: impl Iterator<Item = f64>,
) -> Vec<f64> {
    let mut i = 0;
    queries
        .map(|q| {
            while i + 2 < xs.len() && xs[i + 1] <= q {
                i += 1;
            }
            let w = (q - xs[i]) / (xs[i + 1] - xs[i]);
            y(i) + w * (y(i + 1) - y(i))
        })
        .collect()
}

/// `y` at fractional index `u` by Catmull–Rom cubic interpolation (the end samples repeated).
fn catmull_rom(y: &[f64], u: f64) -> f64 {
    let last = y.len() - 1;
    let u = u.clamp(0.0, last as f64);
    let i = (u.floor() as usize).min(last);
    let s = u - i as f64;
    let get = |k: isize| y[k.clamp(0, last as isize) as usize];
    let (p0, p1, p2, p3) = (
        get(i as isize - 1),
        get(i as isize),
        get(i as isize + 1),
        get(i as isize + 2),
    );
    0.5 * ((2.0 * p1)
        + (-p0 + p2) * s
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * s * s
        + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * s * s * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A shaft sweeping linearly from `f0` to `f1` Hz over `secs` at `fs`: its angle (turns) at
    /// each sample.
    fn sweep(f0: f64, f1: f64, secs: f64, fs: f64) -> Vec<f64> {
        let n = (secs * fs) as usize;
        (0..n)
            .map(|k| {
                let t = k as f64 / fs;
                f0 * t + 0.5 * (f1 - f0) / secs * t * t
            })
            .collect()
    }

    fn square(theta: &[f64], ppr: f64) -> Vec<f64> {
        theta
            .iter()
            .map(|a| if (a * ppr).fract() < 0.5 { 5.0 } else { 0.0 })
            .collect()
    }

    #[test]
    fn a_tone_at_a_fixed_order_stands_at_that_order_after_tracking() {
        let fs = 20_000.0;
        let theta = sweep(15.0, 25.0, 6.0, fs);
        // order 7.3: a non-integer order, as a bearing's
        let x: Vec<f64> = theta
            .iter()
            .map(|a| (2.0 * std::f64::consts::PI * 7.3 * a).sin())
            .collect();
        let tach = square(&theta, 60.0);
        let mut e = SpectralEngine::new();
        let o = order_track(&mut e, &x, &tach, fs, 60.0).unwrap();
        assert!((o.min_rpm - 900.0).abs() < 15.0 && (o.max_rpm - 1500.0).abs() < 15.0);
        assert!((o.mean_rpm - 1200.0).abs() < 5.0, "{}", o.mean_rpm);
        let sp = e
            .amplitude_spectrum(&o.samples, o.equivalent_fs_hz, crate::Taper::Hann)
            .unwrap();
        let peak = sp
            .frequencies()
            .into_iter()
            .zip(sp.values.iter())
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap();
        let order = peak.0 / (o.mean_rpm / 60.0);
        assert!((order - 7.3).abs() < 0.01, "peak at order {order}");
        // before tracking the tone spreads over the sweep: its peak is a small share of it
        let raw = e.amplitude_spectrum(&x, fs, crate::Taper::Hann).unwrap();
        let raw_peak = raw.values.iter().copied().fold(0.0, f64::max);
        let tracked_peak = *peak.1;
        assert!(
            tracked_peak > 5.0 * raw_peak,
            "{tracked_peak} vs {raw_peak}"
        );
    }

    #[test]
    fn a_missed_pulse_is_a_typed_error() {
        let fs = 20_000.0;
        let theta = sweep(20.0, 20.0, 3.0, fs);
        let mut tach = square(&theta, 4.0);
        // blank one pulse out
        let k = (1.0 / (4.0 * 20.0) * 30.5 * fs) as usize;
        for v in &mut tach[k - 200..k + 200] {
            *v = 0.0;
        }
        let x = vec![1.0; tach.len()];
        let mut e = SpectralEngine::new();
        let err = order_track(&mut e, &x, &tach, fs, 4.0).unwrap_err();
        assert!(matches!(err, FeatureError::TachIrregular { .. }), "{err}");
    }

    #[test]
    fn a_constant_or_short_tachometer_is_a_typed_error() {
        let mut e = SpectralEngine::new();
        let x = vec![0.5; 4000];
        let err = order_track(&mut e, &x, &vec![1.0; 4000], 1000.0, 1.0).unwrap_err();
        assert!(matches!(err, FeatureError::TachPulses { .. }), "{err}");
        let theta = sweep(2.0, 2.0, 4.0, 1000.0);
        let tach = square(&theta, 1.0);
        let err = order_track(&mut e, &x, &tach, 1000.0, 1.0).unwrap_err();
        assert!(
            matches!(err, FeatureError::TachPulses { pulses: 7, .. }),
            "{err}"
        );
        let err = order_track(&mut e, &x, &tach[..100], 1000.0, 1.0).unwrap_err();
        assert!(matches!(err, FeatureError::TachLength { .. }), "{err}");
    }

    /// A shaft comb (orders 1–10, decaying) on a shaft at angle `theta`, in white noise.
    fn comb(theta: &[f64], seed: u64) -> Vec<f64> {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let noise = Normal::new(0.0, 0.5).unwrap();
        theta
            .iter()
            .map(|a| {
                (1..=10)
                    .map(|k| {
                        0.8f64.powi(k - 1)
                            * (2.0 * std::f64::consts::PI * k as f64 * a + k as f64).sin()
                    })
                    .sum::<f64>()
                    + noise.sample(&mut rng)
            })
            .collect()
    }

    /// A 1500 rpm machine sweeping ± 5 % (up, then down) on 50 Hz mains territory: in a frame of
    /// 0.54 s the mains exclusion hides seven of its ten orders at 1500 rpm itself, and the
    /// path must still follow the sweep to its top (scored as the mean over the orders left,
    /// 1500 rpm outscored the sweep's own speeds and the profile read flat).
    #[test]
    fn a_sweep_through_a_mains_multiple_is_followed_to_its_top() {
        let fs = 25_600.0;
        let (secs, n) = (6.0, (6.0 * fs) as usize);
        let hz = |t: f64| 25.0 * (1.0 + 0.1 * (0.5 - (2.0 * t / secs - 1.0).abs()) - 0.025);
        let mut theta = Vec::with_capacity(n);
        let mut acc = 0.0;
        for k in 0..n {
            theta.push(acc);
            acc += hz(k as f64 / fs) / fs;
        }
        let x = comb(&theta, 9);
        let mut e = SpectralEngine::new();
        let p = speed_profile(&mut e, &x, fs, 0.9 * 1470.0, 1.1 * 1470.0)
            .unwrap()
            .expect("a profile");
        for (c, r) in p.centres_s.iter().zip(&p.rpm) {
            let truth = 60.0 * hz(*c);
            assert!(
                (r / truth - 1.0).abs() < 0.02,
                "{r:.0} rpm at {c:.2} s, truth {truth:.0}"
            );
        }
        assert!(p.spread() > 0.07, "{}", p.spread());
    }

    #[test]
    fn a_sweep_is_read_from_the_shaft_comb_frame_by_frame() {
        let fs = 12_000.0;
        // 15 → 25 Hz in 10 s, declared 1200 rpm ± 10 %: the sweep leaves the range searched
        let theta = sweep(15.0, 25.0, 10.0, fs);
        let mut x = comb(&theta, 5);
        for (v, a) in x.iter_mut().zip(&theta) {
            *v += 0.5 * (2.0 * std::f64::consts::PI * 7.3 * a).sin();
        }
        let mut e = SpectralEngine::new();
        let p = speed_profile(&mut e, &x, fs, 1080.0, 1320.0)
            .unwrap()
            .expect("a profile");
        for (c, r) in p.centres_s.iter().zip(&p.rpm) {
            let truth = 60.0 * (15.0 + c);
            assert!(
                (r / truth - 1.0).abs() < 0.02,
                "{r} rpm at {c} s, truth {truth}"
            );
        }
        assert!(p.spread() > 0.5, "{}", p.spread());
        let o = order_track_profile(&mut e, &x, fs, &p).unwrap();
        let sp = e
            .amplitude_spectrum(&o.samples, o.equivalent_fs_hz, crate::Taper::Hann)
            .unwrap();
        let fr = o.mean_rpm / 60.0;
        let near = |order: f64| {
            let k = (order * fr / sp.resolution_hz).round() as usize;
            sp.values[k - 3..=k + 3].iter().copied().fold(0.0, f64::max)
        };
        // the tone at order 7.3 stands sharp again: its peak over the tracked spectrum's median
        let mut sorted = sp.values.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[sorted.len() / 2];
        assert!(
            near(7.3) > 30.0 * median,
            "{} vs median {median}",
            near(7.3)
        );
        // the angle from the phase of a shaft order: the tone's power within a bin of its peak
        assert!(
            matches!(
                o.source,
                AngleSource::ShaftComb {
                    phase_order: Some(_),
                    ..
                }
            ),
            "{:?}",
            o.source
        );
        let k = (7.3 * fr / sp.resolution_hz).round() as usize;
        let power = |a: usize, b: usize| sp.values[a..=b].iter().map(|v| v * v).sum::<f64>();
        let share = power(k - 2, k + 2) / power(k - 40, k + 40);
        assert!(share > 0.9, "{share}");
    }

    /// A shaft comb that falls 6 dB an order after the second, in noise: the profile follows the
    /// run-up within 3 %, and the tracked record's leading lines refine its mean speed.
    #[test]
    fn a_sweep_of_a_comb_of_few_orders_is_read_on_its_leading_orders() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let fs = 20_000.0;
        let theta = sweep(15.0, 20.0, 6.0, fs);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let noise = Normal::new(0.0, 1.0).unwrap();
        let x: Vec<f64> = theta
            .iter()
            .map(|a| {
                (1..=12)
                    .map(|k| {
                        let db = if k <= 2 { 0.0 } else { -6.0 * f64::from(k - 2) };
                        10f64.powf(db / 20.0)
                            * (2.0 * std::f64::consts::PI * f64::from(k) * a + f64::from(k)).sin()
                    })
                    .sum::<f64>()
                    + noise.sample(&mut rng)
            })
            .collect();
        let mut e = SpectralEngine::new();
        let p = speed_profile(&mut e, &x, fs, 945.0, 1155.0)
            .unwrap()
            .expect("a profile");
        for (c, r) in p.centres_s.iter().zip(&p.rpm) {
            let truth = 60.0 * (15.0 + 5.0 * c / 6.0);
            assert!(
                (r / truth - 1.0).abs() < 0.03,
                "{r} rpm at {c} s, truth {truth}"
            );
        }
        let o = order_track_profile(&mut e, &x, fs, &p).unwrap();
        let m = speed::leading_lines_speed(&mut e, &o.samples, o.equivalent_fs_hz, o.mean_rpm, 0.0)
            .unwrap()
            .expect("a comb");
        let r = m.refined_rpm.expect("refined on its leading lines");
        assert!((r / o.mean_rpm - 1.0).abs() < 1e-3, "{r} vs {}", o.mean_rpm);
    }

    #[test]
    fn a_steady_speed_reads_as_a_flat_profile() {
        let fs = 12_000.0;
        let theta = sweep(20.0, 20.0, 10.0, fs);
        let x = comb(&theta, 6);
        let mut e = SpectralEngine::new();
        let p = speed_profile(&mut e, &x, fs, 1080.0, 1320.0)
            .unwrap()
            .expect("a profile");
        assert!(p.spread() < 0.02, "{}", p.spread());
        // white noise holds no comb: no profile
        let noise = comb(&theta, 7)
            .iter()
            .zip(&x)
            .map(|(a, b)| a - b)
            .collect::<Vec<_>>();
        assert!(
            speed_profile(&mut e, &noise, fs, 1080.0, 1320.0)
                .unwrap()
                .is_none()
        );
    }

    /// White noise through a coast-down: every turn holds the same band of orders and the
    /// tracked record's spectrum fills its band to the top (no empty band for a whitening filter
    /// to amplify or to be rank deficient on).
    #[test]
    fn a_tracked_record_fills_its_band_to_the_top() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let fs = 20_000.0;
        let theta = sweep(25.0, 15.0, 8.0, fs);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let noise = Normal::new(0.0, 1.0).unwrap();
        let x: Vec<f64> = theta.iter().map(|_| noise.sample(&mut rng)).collect();
        let mut e = SpectralEngine::new();
        let o = order_track(&mut e, &x, &square(&theta, 30.0), fs, 30.0).unwrap();
        assert!(o.max_order < 0.5 * o.samples_per_rev + 1e-9);
        let sp = e
            .welch_psd(
                &o.samples,
                o.equivalent_fs_hz,
                crate::WelchConfig::half_overlap(1024),
            )
            .unwrap();
        let n = sp.values.len();
        let mean = |a: usize, b: usize| sp.values[a..b].iter().sum::<f64>() / (b - a) as f64;
        let (top, middle) = (mean(n * 93 / 100, n * 97 / 100), mean(n / 4, n / 2));
        assert!(top > 0.3 * middle, "top {top} vs middle {middle}");
        // the slow end's time-domain reading would have held content the fast start lacks: the
        // band kept is the fast start's
        assert!(
            (o.max_order - 0.9 * 0.5 * fs / 25.0).abs() < 0.03 * o.max_order,
            "{}",
            o.max_order
        );
    }
}
