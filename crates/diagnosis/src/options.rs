//! What a diagnosis is told besides the recording: the shaft speed (declared, a range to search,
//! or both) and the false-alarm probability per recording; checked once
//! ([`DiagnoseOptions::check`], linfa's `ParamGuard` shape), and how the speed used was found
//! ([`SpeedFinding`], written into every report).

use serde::{Deserialize, Serialize};

use crate::detect::DEFAULT_FALSE_ALARM;
use crate::speed::SpeedEstimate;
use crate::{DiagnosisError, MAX_RPM, MIN_RPM, Result, SPEED_TOL};

/// A declared speed is searched within ± this fraction of it: a motor's set point, a nameplate
/// speed or a rounded log is often several per cent off the running speed (a shared rig's
/// recordings run 4–6 % above their set speeds).
pub const DEFAULT_SPEED_SEARCH: f64 = 0.10;
/// When the recording shows no shaft comb, a speed range no wider than this ratio (high / low)
/// is searched by the fault templates themselves (their windows widened by the range); a wider
/// one is refused: a template spread over it would overlap the other faults' rates.
pub const MAX_BLIND_RANGE: f64 = 1.25;
/// Relative uncertainty of the fault rates of a bearing whose geometry is a catalogue's typical
/// one rather than its maker's (`bearing_model::catalog`, rows marked typical): makers differ by
/// a few per cent in ball size and pitch diameter, which moves BPFO and BPFI by as much (a
/// UC204 insert's BPFO is 3.05 fr on the typical geometry, 3.08 on an LDK UER204's); every
/// fault line's window is widened by it.
pub const TYPICAL_GEOMETRY_UNCERTAINTY: f64 = 0.03;
/// Relative uncertainty stated for a speed refined from the comb's lines (the refinement's
/// consistency, `speed::REFINE_CONSISTENCY`, rounded up).
pub const REFINED_UNCERTAINTY: f64 = 2e-4;

/// The options of [`crate::diagnose_with_options`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DiagnoseOptions {
    /// The speed the user states, rpm (a set point, a nameplate, a log).
    pub declared_rpm: Option<f64>,
    /// The range the running speed is searched in, rpm; by default ± [`DEFAULT_SPEED_SEARCH`]
    /// of the declared speed.
    pub rpm_range: Option<[f64; 2]>,
    /// False-alarm probability per recording, `0 < α ≤ 0.2`.
    pub false_alarm: f64,
    /// Relative uncertainty of the bearing's fault rates (`None`: [`TYPICAL_GEOMETRY_UNCERTAINTY`]
    /// for a catalogue row marked typical, 0 otherwise), `0 ≤ u ≤ 0.1`.
    #[serde(default)]
    pub rate_uncertainty: Option<f64>,
    /// Read the recording at one speed only, never order-tracked (default `false`: a recording
    /// with no shaft comb over its whole length whose comb frame by frame shows a speed that
    /// changes is order-tracked, [`crate::Diagnosis::order_tracking`]). For comparing the two
    /// readings, or for a recording known to run at one speed (the frame-by-frame look then
    /// costs nothing).
    #[serde(default)]
    pub steady_speed: bool,
}

impl DiagnoseOptions {
    /// A declared speed, searched within ± [`DEFAULT_SPEED_SEARCH`] of it.
    pub fn declared(rpm: f64) -> Self {
        Self {
            declared_rpm: Some(rpm),
            rpm_range: None,
            false_alarm: DEFAULT_FALSE_ALARM,
            rate_uncertainty: None,
            steady_speed: false,
        }
    }

    /// No declared speed: the running speed is searched in `[low, high]` rpm.
    pub fn search(low_rpm: f64, high_rpm: f64) -> Self {
        Self {
            declared_rpm: None,
            rpm_range: Some([low_rpm, high_rpm]),
            false_alarm: DEFAULT_FALSE_ALARM,
            rate_uncertainty: None,
            steady_speed: false,
        }
    }

    /// The relative uncertainty of the bearing's fault rates.
    pub fn with_rate_uncertainty(mut self, u: f64) -> Self {
        self.rate_uncertainty = Some(u);
        self
    }

    /// Search `[low, high]` rpm (a declared speed is kept and reported).
    pub fn with_rpm_range(mut self, low_rpm: f64, high_rpm: f64) -> Self {
        self.rpm_range = Some([low_rpm, high_rpm]);
        self
    }

    /// Read at one speed only, never order-tracked ([`DiagnoseOptions::steady_speed`]).
    pub fn with_steady_speed(mut self) -> Self {
        self.steady_speed = true;
        self
    }

    /// The false-alarm probability per recording.
    pub fn with_false_alarm(mut self, alpha: f64) -> Self {
        self.false_alarm = alpha;
        self
    }

    /// Check the options.
    ///
    /// # Errors
    /// [`DiagnosisError::RpmOutOfRange`] for a declared speed out of range,
    /// [`DiagnosisError::InvalidOptions`] for an empty, inverted or out-of-range speed range, a
    /// declared speed outside the range, neither a speed nor a range, or a false-alarm
    /// probability outside `(0, 0.2]`.
    pub fn check(&self) -> Result<CheckedOptions> {
        let bad = |reason: String| Err(DiagnosisError::InvalidOptions { reason });
        if !(self.false_alarm.is_finite() && self.false_alarm > 0.0 && self.false_alarm <= 0.2) {
            return bad(format!(
                "false-alarm probability {} must lie in (0, 0.2]",
                self.false_alarm
            ));
        }
        if let Some(u) = self.rate_uncertainty
            && !(u.is_finite() && (0.0..=0.1).contains(&u))
        {
            return bad(format!("fault-rate uncertainty {u} must lie in [0, 0.1]"));
        }
        if let Some(rpm) = self.declared_rpm
            && !(rpm.is_finite() && (MIN_RPM..=MAX_RPM).contains(&rpm))
        {
            return Err(DiagnosisError::RpmOutOfRange {
                rpm,
                min: MIN_RPM,
                max: MAX_RPM,
            });
        }
        let range = match (self.rpm_range, self.declared_rpm) {
            (Some([lo, hi]), _) => {
                if !(lo.is_finite() && hi.is_finite()) {
                    return bad(format!("speed range {lo}-{hi} rpm is not finite"));
                }
                if lo >= hi {
                    return bad(format!(
                        "speed range {lo}-{hi} rpm is empty or inverted (give low-high, low < high)"
                    ));
                }
                if lo < MIN_RPM || hi > MAX_RPM {
                    return bad(format!(
                        "speed range {lo}-{hi} rpm leaves {MIN_RPM}..={MAX_RPM} rpm"
                    ));
                }
                if let Some(d) = self.declared_rpm
                    && !(lo..=hi).contains(&d)
                {
                    return bad(format!(
                        "declared speed {d} rpm lies outside the speed range {lo}-{hi} rpm"
                    ));
                }
                [lo, hi]
            }
            (None, Some(d)) => [
                (d * (1.0 - DEFAULT_SPEED_SEARCH)).max(MIN_RPM),
                (d * (1.0 + DEFAULT_SPEED_SEARCH)).min(MAX_RPM),
            ],
            (None, None) => {
                return bad("give a declared speed or a speed range to search".into());
            }
        };
        Ok(CheckedOptions {
            declared_rpm: self.declared_rpm,
            range,
            false_alarm: self.false_alarm,
            rate_uncertainty: self.rate_uncertainty,
            steady_speed: self.steady_speed,
        })
    }
}

/// [`DiagnoseOptions`] after [`DiagnoseOptions::check`].
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedOptions {
    declared_rpm: Option<f64>,
    range: [f64; 2],
    /// False-alarm probability per recording.
    pub false_alarm: f64,
    rate_uncertainty: Option<f64>,
    /// Never order-track.
    pub steady_speed: bool,
}

/// How the speed a diagnosis used was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SpeedSource {
    /// The shaft-harmonic comb of the recording's own spectrum.
    SpectrumComb,
    /// The shaft comb of the residual's squared envelope in a demodulation band.
    EnvelopeComb,
    /// The declared speed: the recording shows no shaft comb in the range searched; the fault
    /// templates search the range themselves (their windows widened by it).
    Declared,
    /// No speed declared and no comb found: the middle of a narrow range, searched by the fault
    /// templates as for `declared`.
    RangeCentre,
}

/// The speed a diagnosis used, how it was found and how sure it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedFinding {
    /// The declared speed, rpm (`null` when only a range was given).
    pub declared_rpm: Option<f64>,
    /// The range searched, rpm.
    pub search_rpm: [f64; 2],
    /// The speed used, rpm.
    pub rpm_used: f64,
    /// How it was found.
    pub source: SpeedSource,
    /// Its uncertainty, ± rpm: the comb refinement's consistency, or the comb search's step, or
    /// the whole range when no comb was found.
    pub uncertainty_rpm: f64,
    /// The relative uncertainty the fault templates' windows were widened by (0 when a comb
    /// gave the speed).
    pub relative_uncertainty: f64,
    /// The found speed's offset from the declared one, % (`null` without a declared speed).
    pub offset_from_declared_percent: Option<f64>,
    /// Shaft orders present in the comb that gave the speed, of those scored.
    pub comb_orders: Option<[usize; 2]>,
    /// The comb's score over the median score around it.
    pub comb_contrast: Option<f64>,
    /// How sure, in words.
    pub note: String,
    /// Which reading of the speed the verdict comes from: `measured` (a comb gave the speed),
    /// `declared` (the declared speed taken as right, at α/2) or `searched` (the fault
    /// templates widened over the range, at α/2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub read_at: Option<crate::detect::SpeedStage>,
}

impl CheckedOptions {
    /// The relative uncertainty of `bearing`'s fault rates: as given, else
    /// [`TYPICAL_GEOMETRY_UNCERTAINTY`] for a catalogue row marked typical, else 0.
    pub fn rate_uncertainty(&self, bearing: &crate::BearingSpec) -> f64 {
        self.rate_uncertainty.unwrap_or_else(|| {
            let typical = bearing.geometry.is_some()
                && bearing_model::catalog::lookup(&bearing.name)
                    .is_ok_and(|e| e.is_typical() && e.geometry().orders() == bearing.orders);
            if typical {
                TYPICAL_GEOMETRY_UNCERTAINTY
            } else {
                0.0
            }
        })
    }

    /// The declared speed, rpm (`None` when only a range was given).
    pub fn declared_rpm(&self) -> Option<f64> {
        self.declared_rpm
    }

    /// The speed range searched, rpm.
    pub fn search_rpm(&self) -> [f64; 2] {
        self.range
    }

    /// The declared speed, or the middle of the range.
    pub fn centre_rpm(&self) -> f64 {
        self.declared_rpm
            .unwrap_or(0.5 * (self.range[0] + self.range[1]))
    }

    /// Decide the speed from the combs found in the spectrum and in the envelope.
    ///
    /// # Errors
    /// [`DiagnosisError::SpeedNotFound`] when neither comb was found, no speed was declared, and
    /// the range is wider than [`MAX_BLIND_RANGE`].
    /// `near_comb` is how far (relative) a fault's near-comb lies from the shaft comb
    /// ([`near_comb_distance`]): an unrefined envelope comb is confirmed by the spectrum's comb
    /// within half of it (`confirmed_by_spectrum`: the spectrum's complete comb at the same speed).
    pub fn find_speed(
        &self,
        spectrum: Option<SpeedEstimate>,
        envelope: Option<SpeedEstimate>,
        near_comb: f64,
    ) -> Result<SpeedFinding> {
        let [lo, hi] = self.range;
        let offset = |rpm: f64| self.declared_rpm.map(|d| 100.0 * (rpm / d - 1.0));
        let comb = |m: &SpeedEstimate, rpm: f64, refined: bool, source: SpeedSource, what: &str| {
            // a refined comb places the speed to its lines' consistency; the search alone to
            // half a bin at its top order (beyond the lines' own tolerance, their windows widen)
            let rel = if refined {
                REFINED_UNCERTAINTY
            } else {
                m.resolution.max(0.5 * SPEED_TOL)
            };
            let u = rel * rpm;
            SpeedFinding {
                declared_rpm: self.declared_rpm,
                search_rpm: self.range,
                rpm_used: rpm,
                source,
                uncertainty_rpm: u,
                relative_uncertainty: (rel - SPEED_TOL).max(0.0),
                offset_from_declared_percent: offset(rpm),
                comb_orders: Some([m.orders_present, m.orders]),
                comb_contrast: Some(m.contrast),
                note: format!(
                    "{what}: {} of {} orders present, contrast {:.1}{}",
                    m.orders_present,
                    m.orders,
                    m.contrast,
                    if refined {
                        ", refined from its lines"
                    } else {
                        ""
                    }
                ),
                read_at: None,
            }
        };
        // a comb refined from its lines (its first order and at least three more placed on one
        // speed within 2e-4) is a shaft comb even where the spectrum's other lines crowd its
        // neighbourhood and its contrast falls short
        if let Some(m) = spectrum.filter(|m| m.accepted || m.refined_rpm.is_some()) {
            let (rpm, refined) = match (m.refined_rpm, self.declared_rpm) {
                (Some(r), _) => (r, true),
                // the search alone places the comb to a quarter bin at its top order: a declared
                // speed it agrees with to half the lines' tolerance is the better reading
                (None, Some(d)) if (m.rpm / d - 1.0).abs() <= 0.5 * SPEED_TOL => (d, false),
                (None, _) => (m.rpm, false),
            };
            return Ok(comb(
                &m,
                rpm,
                refined,
                SpeedSource::SpectrumComb,
                "shaft comb of the recording's spectrum",
            ));
        }
        if let Some(m) = envelope.filter(|m| m.refined_rpm.is_some()) {
            return Ok(comb(
                &m,
                m.rpm,
                true,
                SpeedSource::EnvelopeComb,
                "shaft comb of the residual's squared envelope",
            ));
        }
        // an envelope comb that refines in no band (a wandering speed spreads its lines) is the
        // shaft's when the recording's own spectrum, an independent reading, puts its best comb
        // at the same speed: a fault's near-comb (k·BPFI ± m·fr, 0.989 fr on a 6203) lives in
        // the envelope only, and lies a percent from the shaft comb the spectrum shows
        if let Some(m) = envelope.filter(|m| confirmed_by_spectrum(m, spectrum.as_ref(), near_comb))
        {
            return Ok(comb(
                &m,
                m.rpm,
                false,
                SpeedSource::EnvelopeComb,
                "shaft comb of the residual's squared envelope (not refined: confirmed by the spectrum's comb at the same speed)",
            ));
        }
        let (rpm, source) = match self.declared_rpm {
            Some(d) => (d, SpeedSource::Declared),
            None if hi / lo <= MAX_BLIND_RANGE => (0.5 * (lo + hi), SpeedSource::RangeCentre),
            None => {
                return Err(DiagnosisError::SpeedNotFound {
                    low_rpm: lo,
                    high_rpm: hi,
                    max_ratio: MAX_BLIND_RANGE,
                });
            }
        };
        let rel = (hi / rpm - 1.0).max(1.0 - lo / rpm).max(0.0);
        Ok(SpeedFinding {
            declared_rpm: self.declared_rpm,
            search_rpm: self.range,
            rpm_used: rpm,
            source,
            uncertainty_rpm: rel * rpm,
            relative_uncertainty: rel,
            offset_from_declared_percent: offset(rpm),
            comb_orders: spectrum.map(|m| [m.orders_present, m.orders]),
            comb_contrast: spectrum.map(|m| m.contrast),
            note: format!(
                "no shaft comb in the spectrum or the envelope between {lo:.0} and {hi:.0} rpm: the fault lines are read at {rpm:.0} rpm and with the templates searching ± {:.1} % around it (each reading at half the false-alarm probability; the null read with the same windows; where both find a fault, the declared reading names it unless the searched one is 100 times rarer on a healthy machine)",
                100.0 * rel
            ),
            read_at: None,
        })
    }
}

/// How far, relative, the near-comb of an inner-race fault's line family lies from the shaft
/// comb: `k·BPFI ± m·fr` holds lines near every order of `BPFI/n · fr`, `n` the integer nearest
/// the BPFI order (0.989 fr on a 6203, 0.986 on a 6308), less the fault rates' uncertainty
/// `rate_uncertainty` (the near-comb moves with them); 0 when they could meet.
pub fn near_comb_distance(orders: &bearing_model::FaultOrders, rate_uncertainty: f64) -> f64 {
    let n = orders.bpfi.round().max(1.0);
    ((orders.bpfi / n - 1.0).abs() - rate_uncertainty).max(0.0)
}

/// Whether the recording's own spectrum confirms an unrefined envelope comb `m`: the best comb
/// of the spectrum's search, complete but not necessarily accepted
/// ([`SpeedEstimate::is_complete`]: its contrast not asked, on a machine whose speed wanders
/// the contrast falls), lies within [`COMB_AGREEMENT_BINS`] resolution steps of it, or within half the distance to a fault's
/// near-comb (`near_comb`, [`near_comb_distance`]) up to [`MAX_COMB_DISAGREEMENT`]: a
/// wandering speed moves the two readings apart by more than their resolution (0.5 % on a
/// simulated machine wandering 0.2 % RMS), and a near-comb in the envelope against the shaft
/// comb in the spectrum still disagrees. A spectrum that holds the fault family's low-frequency
/// lines itself (the 5-DOF model's 6203 inner race: its near-comb at 0.988 fr in the spectrum,
/// first order 7.9 dB) is no confirmation: its first order is not a shaft line's 10 dB.
fn confirmed_by_spectrum(
    m: &SpeedEstimate,
    spectrum: Option<&SpeedEstimate>,
    near_comb: f64,
) -> bool {
    spectrum.is_some_and(|s| {
        let tol = (COMB_AGREEMENT_BINS * m.resolution.max(s.resolution))
            .max((0.5 * near_comb).min(MAX_COMB_DISAGREEMENT));
        s.is_complete() && (s.rpm / m.rpm - 1.0).abs() <= tol
    })
}

/// An unrefined envelope comb and the spectrum's comb agree at least when their speeds lie
/// within this many of the coarser one's resolution steps (half a bin at the top order each).
pub const COMB_AGREEMENT_BINS: f64 = 2.0;
/// The widest relative disagreement between an unrefined envelope comb and the spectrum's comb
/// that still confirms it (the fault windows' slip allowance is 2 %).
pub const MAX_COMB_DISAGREEMENT: f64 = 0.01;

#[cfg(test)]
mod tests {
    use super::*;

    fn estimate(rpm: f64, refined: bool, first: f64, present: usize) -> SpeedEstimate {
        SpeedEstimate {
            rpm,
            comb_score: 12.0,
            contrast: 2.5,
            orders: 10,
            first_order_score: first,
            orders_present: present,
            orders_scored: 10,
            accepted: true,
            refined_rpm: refined.then_some(rpm),
            envelope_band_hz: None,
            resolution: 3e-4,
        }
    }

    #[test]
    fn an_unrefined_envelope_comb_needs_the_spectrum_s_comb_at_its_speed() {
        let o = DiagnoseOptions::declared(1575.0).check().unwrap();
        let env = SpeedEstimate {
            envelope_band_hz: Some([2000.0, 3000.0]),
            ..estimate(1504.0, false, 2.0, 9)
        };
        // the spectrum's comb, not accepted, at the same speed: the envelope comb is the shaft's
        let spec = SpeedEstimate {
            accepted: false,
            ..estimate(1503.8, false, 2.9, 9)
        };
        let f = o.find_speed(Some(spec), Some(env), 0.0).unwrap();
        assert_eq!(f.source, SpeedSource::EnvelopeComb);
        assert!((f.rpm_used - 1504.0).abs() < 1e-9);
        assert!(f.note.contains("not refined"), "{}", f.note);
        // 0.5 % apart (a wandering speed): confirmed where a fault's near-comb lies 1.44 % off
        let wander = SpeedEstimate {
            rpm: 1504.0 * 1.005,
            ..spec
        };
        assert_eq!(
            o.find_speed(Some(wander), Some(env), 0.0144)
                .unwrap()
                .source,
            SpeedSource::EnvelopeComb
        );
        assert_eq!(
            o.find_speed(Some(wander), Some(env), 0.0).unwrap().source,
            SpeedSource::Declared
        );
        // a near-comb's distance away (the near-comb in the envelope, the shaft comb in the
        // spectrum): the declared speed
        let far = SpeedEstimate {
            rpm: 1504.0 * 1.011,
            ..spec
        };
        let f = o.find_speed(Some(far), Some(env), 0.0144).unwrap();
        assert_eq!(f.source, SpeedSource::Declared);
        // a spectrum without its first order, or with most orders missing, confirms nothing
        for weak in [
            SpeedEstimate {
                first_order_score: 0.2,
                ..spec
            },
            SpeedEstimate {
                orders_present: 4,
                ..spec
            },
        ] {
            let f = o.find_speed(Some(weak), Some(env), 0.0).unwrap();
            assert_eq!(f.source, SpeedSource::Declared);
        }
        // completeness counts the orders scored: 7 of 8 off the mains multiples confirm
        let mains = SpeedEstimate {
            orders_present: 7,
            orders_scored: 8,
            ..spec
        };
        let f = o.find_speed(Some(mains), Some(env), 0.0).unwrap();
        assert_eq!(f.source, SpeedSource::EnvelopeComb);
        // no spectrum at all: the declared speed
        let f = o.find_speed(None, Some(env), 0.0).unwrap();
        assert_eq!(f.source, SpeedSource::Declared);
        // a refined envelope comb needs no confirmation
        let refined = SpeedEstimate {
            envelope_band_hz: Some([2000.0, 3000.0]),
            ..estimate(1504.0, true, 2.0, 9)
        };
        let f = o.find_speed(None, Some(refined), 0.0).unwrap();
        assert_eq!(f.source, SpeedSource::EnvelopeComb);
    }

    #[test]
    fn bad_options_are_typed_errors() {
        let msg = |o: DiagnoseOptions| o.check().unwrap_err().to_string();
        assert!(msg(DiagnoseOptions::search(3600.0, 300.0)).contains("inverted"));
        assert!(msg(DiagnoseOptions::search(1000.0, 1000.0)).contains("empty"));
        assert!(msg(DiagnoseOptions::search(5.0, 100.0)).contains("leaves"));
        assert!(msg(DiagnoseOptions::declared(1000.0).with_false_alarm(0.0)).contains("(0, 0.2]"));
        assert!(
            msg(DiagnoseOptions::declared(1000.0).with_rpm_range(300.0, 900.0)).contains("outside")
        );
        let none = DiagnoseOptions {
            declared_rpm: None,
            rpm_range: None,
            false_alarm: 0.01,
            rate_uncertainty: None,
            steady_speed: false,
        };
        assert!(msg(none).contains("give a declared speed"));
        let ok = DiagnoseOptions::declared(1000.0).check().unwrap();
        assert_eq!(ok.search_rpm(), [900.0, 1100.0]);
    }

    #[test]
    fn without_a_comb_a_wide_range_is_refused_and_a_narrow_one_searched() {
        let wide = DiagnoseOptions::search(300.0, 3600.0).check().unwrap();
        let e = wide.find_speed(None, None, 0.0).unwrap_err();
        assert!(matches!(e, DiagnosisError::SpeedNotFound { .. }), "{e}");
        let narrow = DiagnoseOptions::search(1000.0, 1100.0).check().unwrap();
        let f = narrow.find_speed(None, None, 0.0).unwrap();
        assert_eq!(f.source, SpeedSource::RangeCentre);
        assert!((f.relative_uncertainty - 50.0 / 1050.0).abs() < 1e-12);
    }
}
