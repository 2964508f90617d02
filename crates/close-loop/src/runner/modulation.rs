//! Modulation candidates: amplitude modulation of the physics at shaft or cage rate.

use super::Evaluated;
use crate::effect::{Effect, Modulation};
use crate::engine::{Ctx, State};
use crate::spectrum::{
    ModulationIndex, envelope, envelope_periodogram, hann_windowed, modulation_index, refine_peak,
    running_median,
};

/// The modulation index the model predicts at one frequency (`spectrum::modulation_index`):
/// the physics' own index times its share of the modelled power (the background and the white
/// floor are stationary), and what a modulation of depth μ of the structural vibration (physics
/// and background) adds in quadrature (its phase against the physics' own is unknown).
pub(super) struct IndexModel {
    /// The model's index without the new modulation.
    pub own: f64,
    /// Share of the modelled power a modulation acts on (physics and background; not the floor).
    pub modulated_share: f64,
}

impl IndexModel {
    /// The index model of `st` at `fm`, `msig` the state's physics signal with its modulations.
    pub fn of(ctx: &Ctx<'_>, st: &State, msig: &[f64], fm: f64) -> Option<Self> {
        let shaped = ctx.shaped(st);
        let g = st.log_gain.exp();
        let p_phys = g * shaped.iter().sum::<f64>();
        let p_bg = ctx
            .background_psd(st)
            .map_or(0.0, |b| st.log_bg.exp() * b.iter().sum::<f64>());
        let p_floor = st.log_floor.exp() * shaped.len() as f64;
        let total = p_phys + p_bg + p_floor;
        if !(total.is_finite() && total > 0.0) {
            return None;
        }
        let m_phys = if p_phys > 0.0 {
            modulation_index(msig, ctx.fs, fm).ok()?
        } else {
            0.0
        };
        Some(Self {
            own: m_phys * p_phys / total,
            modulated_share: (p_phys + p_bg) / total,
        })
    }

    /// The index with a modulation of depth `mu` added.
    pub fn with_depth(&self, mu: f64) -> f64 {
        let added = self.modulated_share * 2.0 * mu / (1.0 + 0.5 * mu * mu);
        (self.own * self.own + added * added).sqrt()
    }

    /// The depth that brings the model's index to `measured`: the excess over the model's own
    /// index (in quadrature) is 2μ/(1 + μ²/2) times the modulated share; capped at
    /// [`crate::effect::MODULATION_MAX_DEPTH`], at least 0.02.
    pub fn depth_for(&self, measured: f64) -> f64 {
        let excess = (measured * measured - self.own * self.own).max(0.0).sqrt();
        let a = excess / self.modulated_share.max(1e-12);
        let mu = if a >= 4.0 / 3.0 {
            crate::effect::MODULATION_MAX_DEPTH
        } else {
            (2.0 - (4.0 - 2.0 * a * a).sqrt()) / a.max(1e-12)
        };
        mu.clamp(0.02, crate::effect::MODULATION_MAX_DEPTH)
    }
}

/// Smallest modulation depth the loop names: 10 %. Below it, a fault record's own cage and
/// shaft sidebands (real, but part of the fault's signature) come up on nearly every record
/// (3–9 % on 105, 130 and 209 untouched) and say nothing an engineer would act on.
pub const MIN_MODULATION_DEPTH: f64 = 0.1;

/// How far above the scatter of the held-out residual's modulation index (the median of its
/// index at 10 frequencies 4–12 % away from fm) the index at fm must stand for the held-out
/// envelope to confirm a modulation ([`held_out_confirms`]): 4× (12 dB), the envelope-line
/// threshold of the detection.
pub const MODULATION_CONFIRM_FACTOR: f64 = 4.0;

/// Whether the held-out segment confirms `md` by itself: on the held-out residual alone (lines of
/// `st` removed) the modulation index at its rate stands [`MODULATION_CONFIRM_FACTOR`] above the
/// index's scatter nearby, and the model with the modulation predicts it better than the model
/// without (the held-out index lies nearer the depth fitted on the other half than the model's
/// own index). A machine's own modulation at the same rate drifts in phase against an added one,
/// so the two halves need not agree closely: 160 modulated 30 % at the cage rate reads 0.71 and
/// 0.47 on its halves (its own cage modulation, 0.17 / 0.23, adds on one and subtracts on the
/// other), which the former "twice as well" rule rejected. A modulation's sidebands barely move
/// the spectral distance of a broadband signal; the envelope is where it shows. Returns the
/// held-out index.
pub(super) fn held_out_confirms(ctx: &Ctx<'_>, st: &State, md: &Modulation) -> Option<f64> {
    let r = ctx.held_residual(st);
    let fm = md.frequency_hz;
    let (m_ho, scatter) = index_and_scatter(&ModulationIndex::new(&r, ctx.fs).ok()?, fm);
    let mut msig = st.base.signal.clone();
    for m in &st.mods {
        msig = m.apply(&msig, 0, ctx.fs);
    }
    let ix = IndexModel::of(ctx, st, &msig, fm)?;
    let better = (ix.with_depth(md.depth) - m_ho).abs() < (ix.own - m_ho).abs();
    (m_ho >= MODULATION_CONFIRM_FACTOR * scatter && better).then_some(m_ho)
}

/// The modulation index of `r` at `fm` and its scatter: the median of the index at 10
/// frequencies 4–12 % away from `fm`.
fn index_and_scatter(ix: &ModulationIndex, fm: f64) -> (f64, f64) {
    let mut off: Vec<f64> = [-6, -5, -4, -3, -2, 2, 3, 4, 5, 6]
        .iter()
        .map(|&j| ix.at(fm * (1.0 + 0.02 * j as f64)))
        .collect();
    off.sort_by(f64::total_cmp);
    (ix.at(fm), 0.5 * (off[4] + off[5]))
}

/// Highest harmonic of a modulating rate whose sideband of the impact rate
/// [`fault_sideband`] sets aside.
pub const SIDEBAND_HARMONICS: u32 = 4;

/// Whether `fm` is a sideband of the declared fault's envelope rather than a rate of its own:
/// within `tol` of |j·f_d − h·f_c| for an impact rate f_d (j = 1, 2), a carrier f_c (the shaft
/// rate or a modulation the model already holds) and h = 1 … [`SIDEBAND_HARMONICS`]. A shaft-rate
/// modulation of an impact train that is not a pure cosine (a load zone, a run-out) puts lines at
/// BPFO − 2·fr, BPFO − 3·fr, … into the envelope; read as modulation rates they would be named
/// "modulations" at 1.59 × fr that no machine has (235.mat untouched: 47.0 and 17.5 Hz, BPFO −
/// 2 fr and − 3 fr). A real modulation at exactly such a rate cannot be told from the fault's
/// own sideband by the envelope; the shaft, twice-shaft and cage rates are always judged.
pub(super) fn fault_sideband(fm: f64, impact_hz: &[f64], carriers: &[f64], tol: f64) -> bool {
    impact_hz.iter().any(|&fd| {
        carriers.iter().any(|&fc| {
            (1..=2).any(|j| {
                (1..=SIDEBAND_HARMONICS)
                    .any(|h| ((f64::from(j) * fd - f64::from(h) * fc).abs() - fm).abs() <= tol)
            })
        })
    })
}

pub(super) fn modulation_candidates(ctx: &Ctx<'_>, st: &State) -> Vec<Evaluated> {
    let c = ctx.cfg.get();
    let fr = ctx.op.shaft_hz() * st.shaft_ratio();
    let resid = ctx.fit_residual(st);
    // a residual without an envelope spectrum (cannot happen on checked, finite data) offers
    // no modulation candidate
    let Ok((ey, de)) = envelope_periodogram(&resid, ctx.fs) else {
        return Vec::new();
    };
    let mut msig = st.base.signal.clone();
    for m in &st.mods {
        msig = m.apply(&msig, 0, ctx.fs);
    }
    let Ok((em, _)) = envelope_periodogram(&msig, ctx.fs) else {
        return Vec::new();
    };
    let lo = ((0.5 * ctx.op.bearing.orders.ftf * fr / de).floor() as usize).max(2);
    let hi = ((2.5 * fr / de).ceil() as usize).min(ey.len() - 2);
    if hi <= lo + 4 {
        return Vec::new();
    }
    let half = ((0.25 * ctx.op.bearing.orders.ftf * fr / de).round() as usize).max(8);
    let ly: Vec<f64> = ey.iter().map(|v| 10.0 * v.max(1e-300).log10()).collect();
    let lm: Vec<f64> = em.iter().map(|v| 10.0 * v.max(1e-300).log10()).collect();
    let wlo = lo.saturating_sub(half);
    let whi = (hi + half).min(ey.len());
    let my = running_median(&ly[wlo..whi], half);
    let mm = running_median(&lm[wlo..whi], half);
    let mut peaks: Vec<(usize, f64)> = Vec::new();
    for k in lo..=hi {
        let xy = ly[k] - my[k - wlo];
        let xm = lm[k] - mm[k - wlo];
        if xy > c.envelope_threshold_db && ly[k] >= ly[k - 1] && ly[k] >= ly[k + 1] && xy > xm + 6.0
        {
            peaks.push((k, xy));
        }
    }
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    let Ok(env) = envelope(&resid) else {
        return Vec::new();
    };
    let envw = hann_windowed(&env);
    let mut out = Vec::new();
    let mut used: Vec<usize> = Vec::new();
    // the three strongest envelope peaks the model lacks, then the rates a modulation usually
    // has (shaft, twice shaft, cage), whose line the model's own may hide from the peak test
    let ftf = ctx.op.bearing.orders.ftf;
    let usual_orders = [1.0, 2.0, ftf];
    let named = usual_orders
        .map(|o| (o * fr / de).round() as usize)
        .into_iter()
        .filter(|&k| (lo..=hi).contains(&k));
    let Ok(resid_index) = ModulationIndex::new(&resid, ctx.fs) else {
        return Vec::new();
    };
    let mut picks = Vec::new();
    for k in peaks.into_iter().map(|(k, _)| k).take(3).chain(named) {
        if used.iter().any(|&j| j.abs_diff(k) <= 3) {
            continue;
        }
        used.push(k);
        picks.push(k);
    }
    // the declared fault's impact rates, where the physics runs (its defect rate included)
    let impact_hz: Vec<f64> = crate::impact_orders(ctx.op.fault, &ctx.op.bearing)
        .into_iter()
        .map(|o| o * ctx.op.shaft_hz() * st.base.ratio)
        .collect();
    let carriers: Vec<f64> = std::iter::once(fr)
        .chain(st.mods.iter().map(|m| m.frequency_hz))
        .collect();
    for k in picks {
        let f0 = k as f64 * de;
        let fm = refine_peak(&envw, ctx.fs, f0 - 1.5 * de, f0 + 1.5 * de);
        let usual = usual_orders.iter().any(|o| (o * fr - fm).abs() <= 3.0 * de);
        if !usual && fault_sideband(fm, &impact_hz, &carriers, 3.0 * de) {
            continue;
        }
        // a rate the model already modulates at is a setting taken, not re-fitted here; twice
        // or three times it is that modulation's own envelope harmonic ((1 + μ cos)² holds
        // μ²/2·cos 2ωt)
        if st
            .mods
            .iter()
            .any(|m| (1..=3).any(|h| (h as f64 * m.frequency_hz - fm).abs() <= 3.0 * de))
        {
            continue;
        }
        let Some(ix) = IndexModel::of(ctx, st, &msig, fm) else {
            continue;
        };
        let (m_y, scatter) = index_and_scatter(&resid_index, fm);
        // the fitting residual must itself show the modulation: above the index's scatter and
        // above what the model already makes there
        if m_y < MODULATION_CONFIRM_FACTOR * scatter || m_y < 1.25 * ix.own {
            continue;
        }
        let mu = ix.depth_for(m_y);
        if mu < MIN_MODULATION_DEPTH {
            continue;
        }
        let strength = m_y * m_y - ix.own * ix.own;
        let mut s2 = st.clone();
        s2.mods.push(Modulation {
            frequency_hz: fm,
            depth: mu,
        });
        let (s2, lsd) = ctx.calibrate(s2, false);
        let order = fm / fr;
        let rate = if (order - 1.0).abs() < 0.02 {
            "shaft"
        } else if (order - 2.0).abs() < 0.04 {
            "2x_shaft"
        } else if (order / ftf - 1.0).abs() < 0.02 {
            "cage"
        } else {
            "other"
        };
        out.push((
            strength,
            Evaluated {
                effect: Effect::Modulation {
                    modulation: Modulation {
                        frequency_hz: fm,
                        depth: mu,
                    },
                    shaft_order: order,
                    rate,
                },
                state: s2,
                fit_lsd: lsd,
            },
        ));
    }
    // strongest excess over the model first
    out.sort_by(|a, b| b.0.total_cmp(&a.0));
    out.into_iter().map(|(_, e)| e).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// BPFO − 2·fr and 2·BPFO − fr are sidebands; the cage rate and a rate 3 % off are not.
    #[test]
    fn fault_sidebands_are_told_from_other_rates() {
        let fr = 29.5;
        let bpfo = 3.5848 * fr;
        let tol = 0.3;
        assert!(fault_sideband(bpfo - 2.0 * fr, &[bpfo], &[fr], tol));
        assert!(fault_sideband(2.0 * bpfo - fr, &[bpfo], &[fr], tol));
        assert!(!fault_sideband(0.39828 * fr, &[bpfo], &[fr], tol));
        assert!(!fault_sideband(
            1.03 * (bpfo - 2.0 * fr),
            &[bpfo],
            &[fr],
            tol
        ));
        // no declared fault: nothing is a sideband
        assert!(!fault_sideband(bpfo - 2.0 * fr, &[], &[fr], tol));
    }
}
