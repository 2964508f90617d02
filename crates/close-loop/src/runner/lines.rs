//! Line candidates: tones, shaft orders and half orders, shaft and line combs, shaft forces.

use super::Evaluated;
use crate::DeclaredModel;
use crate::effect::{CoherentLine, Effect, classify_line, nearest_mains};
use crate::engine::{Base, Ctx, ModelRef, State};
use crate::spectrum::{PeakRefiner, hann_windowed, running_median};
use std::sync::Arc;

/// Least-squares a·cos + b·sin at `f` on `x` (sample 0 of `x` is sample 0 of the recording).
pub(super) fn fit_line(x: &[f64], fs: f64, f: f64) -> CoherentLine {
    let w = 2.0 * std::f64::consts::PI * f / fs;
    let (mut cc, mut cs, mut ss, mut xc, mut xs) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let (sw, cw) = w.sin_cos();
    // phasor recurrence, re-anchored exactly every 256 samples
    for (j, chunk) in x.chunks(256).enumerate() {
        let (mut s, mut c) = (w * (256 * j) as f64).sin_cos();
        for v in chunk {
            cc += c * c;
            cs += c * s;
            ss += s * s;
            xc += v * c;
            xs += v * s;
            (s, c) = (s * cw + c * sw, c * cw - s * sw);
        }
    }
    let det = cc * ss - cs * cs;
    if det.abs() < 1e-12 {
        return CoherentLine {
            frequency_hz: f,
            a: 0.0,
            b: 0.0,
        };
    }
    CoherentLine {
        frequency_hz: f,
        a: (ss * xc - cs * xs) / det,
        b: (cc * xs - cs * xc) / det,
    }
}

/// Narrow lines of the fitting residual (y − the lines already in the model) that the model does
/// not carry: on the fine Welch grid, the residual's log PSD above its running median (±~25 Hz)
/// minus the same excess of the model's own simulated output (its fault lines), peaks above
/// `line_threshold_db`, ranked by the power they carry above the background — what they explain.
pub(super) fn line_candidates(ctx: &Ctx<'_>, st: &State, lr: &[f64]) -> Vec<Evaluated> {
    let c = ctx.cfg.get();
    if c.max_line_candidates == 0 {
        return Vec::new();
    }
    let resid = ctx.fit_residual(st);
    let Ok(s) = ctx.welch_hi.try_psd(&resid) else {
        return Vec::new();
    };
    let dfh = ctx.welch_hi.df();
    // the band's upper edge is inclusive: a line at exactly `band_high_fraction`·fs falls between
    // the band's last bin and the next, so peaks may sit one bin beyond the band, and two guard
    // bins give that bin the right-hand neighbour its peak test needs
    let in_band = ctx.bins_hi.len() + 1;
    let bins = ctx.bins_hi.start..(ctx.bins_hi.end + 2).min(s.len());
    let half = ((25.0 / dfh).round() as usize).max(6);
    let ly: Vec<f64> = bins
        .clone()
        .map(|k| 10.0 * s[k].max(1e-300).log10())
        .collect();
    let my = running_median(&ly, half);
    let lm: Vec<f64> = bins
        .clone()
        .map(|k| {
            10.0 * st
                .base
                .psd_hi
                .get(k)
                .copied()
                .unwrap_or(0.0)
                .max(1e-300)
                .log10()
        })
        .collect();
    let mm = running_median(&lm, half);
    // the model's lines count only where the model carries power near the measurement's level
    let gain_db = 10.0 * st.log_gain / std::f64::consts::LN_10;
    let ex: Vec<f64> = (0..ly.len())
        .map(|i| {
            // the model's own line counts only where the model holds the measured power there
            // (log ratio on the metric grid under 3 dB)
            let f = ctx.welch_hi.frequency(bins.start + i);
            let km = ((f / ctx.welch.df()).round() as usize).saturating_sub(ctx.bins.start);
            let explained = lr.get(km).is_none_or(|v| *v < 3.0);
            let model_ex = if explained && lm[i] + gain_db > my[i] - 3.0 {
                (lm[i] - mm[i]).max(0.0)
            } else {
                0.0
            };
            ly[i] - my[i] - model_ex
        })
        .collect();
    // the band's first bin has no left neighbour in the band: beyond the band nothing blocks a
    // peak there (as at the ends of `resonance::band_extrema`), so it is tested against its right
    // neighbour only. On a short record the line spectrum's bins are wide (174.mat, 1.33 s at
    // 48 kHz: 11.7 Hz) and a 0.5× line at 15 Hz falls into the first bin; skipping it let a
    // 12.5 Hz "resonance" of ζ 0.17 take the line (docs/equations/close-loop.md, "A fifth
    // black-box check")
    let mut peaks: Vec<(usize, f64)> = (0..in_band.min(ex.len().saturating_sub(1)))
        .filter(|&i| {
            ex[i] > c.line_threshold_db && (i == 0 || ly[i] >= ly[i - 1]) && ly[i] >= ly[i + 1]
        })
        .map(|i| {
            let k = bins.start + i;
            let above = s[k] - 10f64.powf(my[i] / 10.0);
            (i, above.max(0.0))
        })
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    let xw = hann_windowed(&resid);
    let refiner = PeakRefiner::new(&xw, ctx.fs);
    let fr = ctx.op.shaft_hz() * st.shaft_ratio();
    let mut out = Vec::new();
    // combs: every standing line refined once, then grouped
    let refined: Vec<(f64, f64)> = peaks
        .iter()
        .take(32)
        .map(|&(i, p)| {
            let f0 = ctx.welch_hi.frequency(bins.start + i);
            (
                refiner.refine((f0 - 1.5 * dfh).max(0.5 * dfh), f0 + 1.5 * dfh),
                p,
            )
        })
        .collect();
    out.extend(shaft_comb_candidate(ctx, st, &resid, &refined, fr));
    out.extend(line_comb_candidate(ctx, st, &resid, &refined, fr));
    let mut chosen: Vec<usize> = Vec::new();
    for &(i, _) in &peaks {
        if chosen.iter().all(|&j| j.abs_diff(i) > 2) {
            chosen.push(i);
        }
        if chosen.len() >= c.max_line_candidates {
            break;
        }
    }
    // a line standing PLAIN_LINE_DB over its neighbourhood is tried even where stronger, broader
    // lines fill the slots by power (135 at 48 kHz with a 9 kHz tone at 15 % of the RMS, 54 dB
    // over its neighbourhood: eight BPFO harmonics around the 3.4 kHz resonance, 0.3 % off the
    // declared speed and each stronger, took every slot, and a mode took the tone)
    let mut plain: Vec<(usize, f64)> = peaks
        .iter()
        .filter(|&&(i, _)| ex[i] >= PLAIN_LINE_DB)
        .map(|&(i, _)| (i, ex[i]))
        .collect();
    plain.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut extra = 0;
    for (i, _) in plain {
        if extra >= c.max_line_candidates / 2 {
            break;
        }
        if chosen.iter().all(|&j| j.abs_diff(i) > 2) {
            chosen.push(i);
            extra += 1;
        }
    }
    for i in chosen {
        let f0 = ctx.welch_hi.frequency(bins.start + i);
        let f = refiner.refine((f0 - 1.5 * dfh).max(0.5 * dfh), f0 + 1.5 * dfh);
        let line = fit_line(&resid, ctx.fs, f);
        // after a speed step the shaft's lines did not confirm, a line at an order of the
        // speed before it is a shaft line too (148 at 48 kHz with a 1.5 × line added at the
        // stored speed: a step of ×1.005 read from the fault's lines came first, the model's
        // 1.5 × moved 0.5 % away, and the line was named a tone)
        let effect = match classify_line(line, fr, c) {
            Effect::Tone { .. } if st.assumed_shaft_step != 1.0 => {
                classify_line(line, fr / st.assumed_shaft_step, c)
            }
            e => e,
        };
        let mut s2 = st.clone();
        s2.lines.push(line);
        if let Effect::ShaftHarmonic { order, .. } = effect
            && order.fract() == 0.0
        {
            s2.shaft_lines.push((order, f, line.amplitude()));
        }
        let (s2, lsd) = ctx.calibrate(s2, false);
        out.push(Evaluated {
            effect,
            state: s2,
            fit_lsd: lsd,
        });
    }
    out
}

/// Prominence over the running median of the residual's PSD (dB) from which a line is a
/// candidate whatever its power: a plain line that stronger, broader lines would crowd out of
/// the `max_line_candidates` slots taken by power.
pub(super) const PLAIN_LINE_DB: f64 = 30.0;

/// Largest distance of a comb member from its shaft order, in orders.
pub(super) const COMB_ORDER_TOLERANCE: f64 = 0.05;

/// Fewest lines that make a comb.
pub(super) const MIN_COMB_LINES: usize = 4;

/// A shaft-synchronous comb: the standing lines that sit at integer shaft orders (within
/// `harmonic_tolerance` and a quarter order), fr refined by weighted least squares of f_k = k·fr
/// over them, every order fitted as a phase-coherent line at k·fr̂ — what a time-synchronous
/// average of the shaft-synchronous part holds. Needs [`MIN_COMB_LINES`] orders.
pub(super) fn shaft_comb_candidate(
    ctx: &Ctx<'_>,
    st: &State,
    resid: &[f64],
    refined: &[(f64, f64)],
    fr: f64,
) -> Option<Evaluated> {
    let c = ctx.cfg.get();
    let mut members: Vec<(f64, f64, f64)> = Vec::new(); // (order, f, power)
    for &(f, p) in refined {
        let k = (f / fr).round();
        // within 5 % of an order: at high orders a relative tolerance would take in the
        // fault's own lines (k·BPFI ± m·fr falls within 0.4 % of some shaft order)
        if k >= 1.0
            && (f - k * fr).abs() <= (c.harmonic_tolerance * f).min(COMB_ORDER_TOLERANCE * fr)
            && !line_near_mains(f, fr, c)
            && members.iter().all(|m| m.0 != k)
        {
            members.push((k, f, p));
        }
    }
    if members.len() < MIN_COMB_LINES {
        return None;
    }
    let (num, den) = members.iter().fold((0.0, 0.0), |(a, b), (k, f, p)| {
        let w = p.sqrt();
        (a + w * k * f, b + w * k * k)
    });
    let fr_hat = num / den;
    let mut s2 = st.clone();
    for (k, _, _) in &members {
        s2.lines.push(fit_line(resid, ctx.fs, k * fr_hat));
    }
    let (s2, lsd) = ctx.calibrate(s2, false);
    let mut orders: Vec<f64> = members.iter().map(|m| m.0).collect();
    orders.sort_by(f64::total_cmp);
    Some(Evaluated {
        effect: Effect::ShaftComb {
            shaft_hz: fr_hat,
            declared_shaft_hz: ctx.op.shaft_hz(),
            orders,
            lines: s2.lines[st.lines.len()..].to_vec(),
        },
        state: s2,
        fit_lsd: lsd,
    })
}

/// Is `f` nearer a multiple of the declared mains frequency than a shaft order?
pub(super) fn line_near_mains(f: f64, fr: f64, c: &crate::LoopConfig) -> bool {
    let k = (f / fr).round();
    nearest_mains(f, c)
        .is_some_and(|g| (f - g).abs() < (f - k * fr).abs() && (f / g - 1.0).abs() < 1e-3)
}

/// Fewest lines that make a harmonic comb: lines at multiples m·Δ of their spacing (m ≤
/// [`MAX_HARMONIC_COMB_START`] for the lowest), the harmonics of one fundamental — a mains comb
/// (50, 100, 150 Hz), a motor's electrical frequency. Three equally spaced lines that also sit
/// on the spacing's own grid are unlikely by chance (the lowest must fall within 0.3 % of Δ·m
/// of a multiple); an arbitrary equally spaced set needs [`MIN_COMB_LINES`].
pub(super) const MIN_HARMONIC_COMB_LINES: usize = 3;

/// Highest multiple of the spacing the lowest line of a harmonic comb may sit at.
pub(super) const MAX_HARMONIC_COMB_START: f64 = 8.0;

/// Fewest lines `set` (at f₀ + m·d, lowest first or not) needs to make a comb: a harmonic comb
/// (its lowest line at a multiple of d, [`MIN_HARMONIC_COMB_LINES`]) or any equally spaced one
/// ([`MIN_COMB_LINES`]).
fn comb_needs(set: &[(f64, f64)], d: f64) -> usize {
    let lo = set.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
    let m0 = (lo / d).round();
    if (1.0..=MAX_HARMONIC_COMB_START).contains(&m0) && (lo - m0 * d).abs() <= 3e-3 * d * m0 {
        MIN_HARMONIC_COMB_LINES
    } else {
        MIN_COMB_LINES
    }
}

/// An equally spaced comb of lines not at shaft orders (an interference or mains comb): the
/// largest set of standing lines at f₀ + m·Δ (|m| ≤ 8, within 0.3 % of Δ), Δ from 10 Hz up,
/// over every pair of the strongest lines. Needs [`MIN_COMB_LINES`] lines, or
/// [`MIN_HARMONIC_COMB_LINES`] when they are harmonics of Δ ([`comb_needs`]).
pub(super) fn line_comb_candidate(
    ctx: &Ctx<'_>,
    st: &State,
    resid: &[f64],
    refined: &[(f64, f64)],
    fr: f64,
) -> Option<Evaluated> {
    let c = ctx.cfg.get();
    let free: Vec<(f64, f64)> = refined
        .iter()
        .copied()
        .filter(|&(f, _)| {
            let k = (f / fr).round();
            k < 1.0
                || (f - k * fr).abs() > (c.harmonic_tolerance * f).min(0.25 * fr)
                || line_near_mains(f, fr, c)
        })
        .take(24)
        .collect();
    // a spacing at a kinematic fault rate (within the speed search range) is the fault's own
    // comb at another speed: the speed candidate's business, not an interference comb. The
    // rate itself (m = 1) gets the whole speed search range; its multiples (a comb of every m-th
    // line) ± 2 %, the range before the search was widened to ± 5 %: wider, a 50 Hz mains comb
    // on a 1797 rpm 6205 (50 Hz = 4.19 × FTF, 4.8 % off the 4th multiple) was taken for the
    // cage's and never named (black-box check)
    let kinematic: Vec<f64> = crate::impact_orders(ctx.op.fault, &ctx.op.bearing)
        .into_iter()
        .chain([ctx.op.bearing.orders.ftf, 1.0])
        .map(|o| o * fr)
        .collect();
    let is_kinematic = |d: f64| {
        kinematic.iter().any(|&k| {
            let m = (d / k).round();
            let tol = if m == 1.0 {
                c.max_speed_offset
            } else {
                c.max_speed_offset.min(0.02)
            };
            m >= 1.0 && (d / (m * k) - 1.0).abs() <= tol
        })
    };
    // a spacing at the declared mains frequency or a multiple (within 0.1 %, the tolerance of
    // `line_near_mains`) is the mains comb even where it falls near a kinematic rate: a 60 Hz
    // comb on an 1800 rpm machine sits 0.2 % from 2 × fr (246.mat at 1796 rpm with 60, 120,
    // 180 and 240 Hz added named two tones and no comb)
    let mains_spacing = |d: f64| nearest_mains(d, c).is_some_and(|g| (d / g - 1.0).abs() < 1e-3);
    let mut best: Vec<(f64, f64)> = Vec::new();
    let mut best_spacing = 0.0;
    for i in 0..free.len() {
        for j in 0..free.len() {
            let (f0, f1) = (free[i].0, free[j].0);
            let d = f1 - f0;
            if d < 10.0 || (is_kinematic(d) && !mains_spacing(d)) {
                continue;
            }
            // one member per comb position m, the nearest: a cluster of lines within the
            // tolerance of one position is not a comb (226 at 48 kHz with a 21.6 kHz tone: four
            // lines at 2557–2620 Hz, all "m = 0" within 0.3 % of a 19 kHz spacing, made a
            // five-line comb with the tone)
            let tol = 3e-3 * d;
            let mut at: Vec<(f64, f64, (f64, f64))> = Vec::new(); // (m, distance, line)
            for &(f, p) in &free {
                let m = ((f - f0) / d).round();
                let dist = (f - f0 - m * d).abs();
                if m.abs() > 8.0 || dist > tol {
                    continue;
                }
                match at.iter_mut().find(|e| e.0 == m) {
                    Some(e) if e.1 <= dist => {}
                    Some(e) => *e = (m, dist, (f, p)),
                    None => at.push((m, dist, (f, p))),
                }
            }
            let set: Vec<(f64, f64)> = at.into_iter().map(|e| e.2).collect();
            if set.len() < comb_needs(&set, d) {
                continue;
            }
            let power = |v: &[(f64, f64)]| v.iter().map(|x| x.1).sum::<f64>();
            if set.len() > best.len() || (set.len() == best.len() && power(&set) > power(&best)) {
                best = set;
                best_spacing = d;
            }
        }
    }
    if best.is_empty() {
        return None;
    }
    // spacing refined by least squares over the members' offsets
    best.sort_by(|a, b| a.0.total_cmp(&b.0));
    let f0 = best[0].0;
    let (num, den) = best.iter().fold((0.0, 0.0), |(a, b), &(f, _)| {
        let m = ((f - f0) / best_spacing).round();
        (a + m * (f - f0), b + m * m)
    });
    let spacing = if den > 0.0 { num / den } else { best_spacing };
    let mut s2 = st.clone();
    for &(f, _) in &best {
        s2.lines.push(fit_line(resid, ctx.fs, f));
    }
    let (s2, lsd) = ctx.calibrate(s2, false);
    Some(Evaluated {
        effect: Effect::LineComb {
            spacing_hz: spacing,
            lines: s2.lines[st.lines.len()..].to_vec(),
        },
        state: s2,
        fit_lsd: lsd,
    })
}

/// Complex amplitude C = a − j·b of a line (a·cos + b·sin = Re(C·e^{jωt})).
pub(super) fn phasor(l: &CoherentLine) -> rustfft::num_complex::Complex<f64> {
    rustfft::num_complex::Complex::new(l.a, -l.b)
}

/// Largest distance, in bins of the fitting segment (1/T), between a measured shaft line and the
/// line a physics shaft force makes: a line fitted 0.1/T off its frequency leaves 18 % of its
/// amplitude (1 − sinc² of the offset, in amplitude), a line 0.87/T off (the ×1.003 of a defect
/// rate at 57 Hz on 5 s) nearly all of it.
pub(super) const MAX_FORCE_LINE_OFFSET: f64 = 0.1;

/// A shaft harmonic put into the physics: the model is re-simulated with a shaft force of order
/// k (bearing-model's `ShaftHarmonic`). The force follows from one unit-force run: the transfer
/// H = C₁ / (1 N) of the line the unit force adds at the sensor (fitted on the difference of the
/// two simulations), then F = C_measured / H (amplitude |F|, phase arg F), a run with F, one
/// secant correction F ← F·C_measured / C_response(F) and a run with that (3 simulations).
/// The response line of that run joins the phase-coherent prediction; its power is in the base.
/// `None` when the model has no shaft or a simulation fails (the line then stays a sensor term).
pub(super) fn shaft_force_candidate(
    ctx: &Ctx<'_>,
    st: &State,
    order: u32,
    measured: CoherentLine,
    fr: f64,
) -> Option<Evaluated> {
    let model = ctx.model_of(st);
    let f_sim = f64::from(order) * ctx.op.shaft_hz() * st.base.ratio;
    // the simulated force turns with the physics' shaft, at `base.ratio`: where that is not the
    // measured line's frequency (a defect rate ≠ 1 runs the physics off the shaft's speed; a
    // line off the model's order), its response cannot be the line, and the part it misses
    // came back as a second line of the same order beside it (160 with a 2× line added after a
    // ×1.003 defect rate: 57.467 Hz measured, 57.64 Hz simulated, a second "2×" at 57.567 Hz)
    let t_fit = ctx.n_fit as f64 / ctx.fs;
    if (f_sim - measured.frequency_hz).abs() > MAX_FORCE_LINE_OFFSET / t_fit {
        return None;
    }
    let response = |m: &dyn DeclaredModel| -> Option<(Arc<Base>, CoherentLine)> {
        let b = ctx.make_base_with(m, st.base.ratio).ok()?;
        let d: Vec<f64> = b
            .signal
            .iter()
            .zip(&st.base.signal)
            .map(|(x, x0)| x - x0)
            .collect();
        Some((b.clone(), fit_line(&d, ctx.fs, f_sim)))
    };
    let unit = model.with_shaft_force(order, 1.0, 0.0)?;
    let (_, l1) = response(unit.as_ref())?;
    let h = phasor(&l1);
    if !(h.norm() > 0.0 && h.norm().is_finite()) {
        return None;
    }
    let target = phasor(&measured);
    let mut f = target / h;
    // the contact is Hertzian, so the transfer at 1 N is not the transfer at F: one secant step
    // F ← F·C_measured / C_response(F) corrects it (measured: 229 N → within 2 % of 200 N)
    let mut run = None;
    for step in 0..2 {
        let (amp, phase) = (f.norm(), f.arg());
        if !(amp.is_finite() && amp > 0.0 && amp <= 1e6) {
            return None;
        }
        let forced: Arc<dyn DeclaredModel> = Arc::from(model.with_shaft_force(order, amp, phase)?);
        let (base, resp) = response(forced.as_ref())?;
        let r = phasor(&resp);
        if step == 0 && r.norm() > 0.0 && r.norm().is_finite() {
            f = f * target / r;
            run = Some((forced, base, resp, amp, phase));
            continue;
        }
        run = Some((forced, base, resp, amp, phase));
        break;
    }
    let (forced, base, resp, amp, phase) = run?;
    let mut s2 = st.clone();
    s2.model = Some(ModelRef(forced));
    ctx.rebase(&mut s2, base);
    s2.physics_lines.push(resp);
    s2.shaft_lines.push((
        f64::from(order),
        measured.frequency_hz,
        measured.amplitude(),
    ));
    let (s2, lsd) = ctx.calibrate(s2, false);
    Some(Evaluated {
        effect: Effect::ShaftHarmonic {
            order: f64::from(order),
            line: measured,
            shaft_hz: fr,
            force: Some((amp, phase)),
        },
        state: s2,
        fit_lsd: lsd,
    })
}
