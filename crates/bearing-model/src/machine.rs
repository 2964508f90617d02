//! Phenomenological machine recordings: what an accelerometer on the housing of a bearing in a
//! running machine records, **in m/s²**, healthy or with one localized bearing fault — fast
//! enough for corpora of hundreds of 10 s recordings at up to 51.2 kHz (no ODE: every component
//! is a closed-form signal, or white noise or an impact train through a two-pole modal
//! resonance; 5–26 ms per 10 s at 12 kHz and 17–106 ms at 51.2 kHz on one core, release,
//! `examples/machine_speed.rs`).
//!
//! A [`MachineRecipe`] states what is fixed by a corpus design (bearing, speed, sampling rate,
//! duration, which nuisances, SNR, level, ADC, fault, seed); [`MachineRecipe::draw`] draws every
//! other parameter from the seed into [`MachineParams`] (physically plausible ranges, the
//! constants of this module; each component from its own ChaCha8 stream, so switching a
//! nuisance or a fault on does not change any other component's draws or samples), which can be
//! inspected or edited before [`MachineParams::synthesize`] renders the [`MachineRecording`].
//!
//! # Components
//!
//! * **Structure** (always): white-noise excitation through 2–5 structural modes (two-pole
//!   resonances, damping ζ 1–5 %, frequencies stratified log-uniformly over
//!   400 Hz … min(0.4·fs, 20 kHz)), plus a smooth low-frequency floor (white noise through a
//!   first-order low-pass at 20–200 Hz, 6–20 dB under the modes). Its power is the reference of
//!   the nuisance levels.
//! * **Shaft comb** ([`Nuisances::shaft_comb`]): 1× (unbalance), 2× (misalignment, −10…+3 dB
//!   re 1×), orders 3 … 10–20 decaying 1.5–4 dB per order (± 3 dB), with probability ½ half
//!   orders 0.5 … 5.5 (looseness) 5–15 dB under 1×; random phases.
//! * **Once-per-revolution impacts** ([`Nuisances::once_per_rev`]): a rub, a keyway, a loose
//!   part: one impact per shaft turn at a fixed shaft angle with timing jitter (0.2–2 % of a
//!   turn) and amplitude spread (10–30 %), ringing one of the structural modes. In the squared
//!   envelope they put lines at every shaft order.
//! * **Another shaft's impacts** ([`Nuisances::other_shaft`]): a belt joint, a coupling or a loose
//!   part on a second shaft driven from the measured one (belt, chain, gears): one impact per
//!   turn of that shaft, which turns at a non-integer order ρ₂ of fr (0.3–9, at least 0.1 from
//!   an integer), at a fixed angle of it with timing jitter (0.2–2 % of its turn, not
//!   accumulating: it is locked to the shafts, unlike a bearing fault's slip) and amplitude
//!   spread (10–30 %), ringing one of the structural modes. In the squared envelope they put a
//!   comb at ρ₂·fr and its harmonics: to an envelope analysis, the pattern of an outer-race
//!   fault at an order nobody listed.
//! * **Gear mesh** ([`Nuisances::gear_mesh`]): a mesh tone at z₁·fr (z₁ 15–60) with 1–3
//!   harmonics, amplitude- (depth 5–40 %) and phase-modulated (0.05–0.5 rad) by the shaft (fr)
//!   and by a second shaft at fr₂ = fr·z₁/z₂ (z₂ 15–90, z₁/z₂ not an integer, so fr₂ is a
//!   non-integer order of fr), plus that second shaft's 1× and 2×.
//! * **Electrical lines** ([`Nuisances::electrical`]): mains 50 or 60 Hz (± 0.02 Hz grid
//!   drift) and harmonics to 7×, odd ones stronger; the 2× line frequency magnetic pull, the
//!   strongest; with probability ½ sidebands 2·f_line ± f_pp at the pole-pass frequency
//!   f_pp = 2·s·f_line (slip s 1–5 %).
//! * **Sensor noise** (always): white Gaussian noise at [`MachineRecipe::snr_db`], the power of
//!   everything above over the noise's.
//! * **Localized fault** ([`MachineRecipe::fault`]): impacts at the fault order × the shaft
//!   rate (BPFO, BPFI, ball-defect rate of the geometry's [`FaultOrders`]) with 1–2 % random
//!   slip (each interval jittered, Gaussian, standard deviation the slip), ringing one of the
//!   structural modes above 1 kHz; inner-race impacts amplitude-modulated by the load zone once
//!   per shaft turn, ball-fault impacts once per cage turn (FTF), outer-race impacts not by the
//!   load zone. A race defect is struck by each rolling element in turn, and no two elements
//!   strike alike (diameter within a grade, load sharing, the cage pocket's clearance): each
//!   element's impacts carry its own gain, log-normal with a spread of 5–30 % drawn per
//!   machine, so the impacts repeat exactly only once per element cycle — once per cage turn
//!   on an outer race (lines at the orders of FTF, BPFO = Z·FTF), once per turn of the shaft
//!   relative to the cage on an inner race (orders of fr − FTF = BPFI/Z). Severity:
//!   20·log₁₀ of the impacts' RMS over the RMS of the healthy recording (everything else,
//!   sensor noise included), dB.
//! * **ADC** ([`MachineRecipe::adc`]): optional quantisation to a 16- or 24-bit (any 8–32)
//!   converter of a stated full scale, after everything else. A noise-only recording
//!   ([`MachineRecipe::noise_only`]) is a few LSB of sensor noise with hum and a faint structure.
//!
//! The speed wanders slowly (1–3 sinusoids at 0.05–0.5 Hz, 0.05–0.3 % RMS, the mean over the
//! recording exactly the recipe's rpm); the shaft comb, once-per-rev impacts, gear mesh and
//! fault impacts all follow that one shaft angle. A recipe may also sweep its speed
//! ([`MachineRecipe::with_sweep`]: a run-up, a coast-down or a triangle of a stated span, the
//! mean kept). Lines above 0.45·fs (at the fastest turn) are left out.
//!
//! ```
//! use bearing_model::machine::{LocalizedFault, MachineRecipe, Nuisances};
//! use bearing_model::{BearingGeometry, FaultLocation};
//! let rec = MachineRecipe::healthy(BearingGeometry::skf_6205(), 1800.0, 12_000.0, 1.0, 7)?
//!     .with_nuisances(Nuisances::ALL)
//!     .with_snr_db(10.0)
//!     .with_fault(LocalizedFault { location: FaultLocation::Inner, severity_db: -10.0 })
//!     .synthesize()?;
//! assert_eq!(rec.accel.len(), 12_000); // m/s²
//! # Ok::<(), bearing_model::ModelError>(())
//! ```

use crate::error::{ModelError, Result, check_positive, check_range};
use crate::fault::FaultLocation;
use crate::geometry::{BearingGeometry, FaultOrders};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Lowest structural mode frequency, Hz.
pub const MODE_MIN_HZ: f64 = 400.0;
/// Highest structural mode frequency, Hz (also at most [`MODE_MAX_FS_FRACTION`] × fs).
pub const MODE_MAX_HZ: f64 = 20_000.0;
/// Highest structural mode frequency as a fraction of the sampling rate.
pub const MODE_MAX_FS_FRACTION: f64 = 0.4;
/// Modes a fault rings lie at or above this frequency when the structure has one, Hz.
pub const FAULT_MODE_MIN_HZ: f64 = 1_000.0;
/// Number of structural modes drawn: 2 ..= 5.
pub const MODE_COUNT: (usize, usize) = (2, 5);
/// Modal damping ratio range.
pub const DAMPING: (f64, f64) = (0.01, 0.05);
/// Lines (tones, harmonics, sidebands) at or above this fraction of fs are left out.
pub const LINE_MAX_FS_FRACTION: f64 = 0.45;
/// Slow speed wander, RMS as a fraction of the mean speed.
pub const SPEED_WANDER: (f64, f64) = (0.0005, 0.003);
/// Slow speed wander frequencies, Hz.
pub const SPEED_WANDER_HZ: (f64, f64) = (0.05, 0.5);
/// Element-to-element spread of a race defect's impacts: the range of the standard deviation
/// of each rolling element's log gain.
pub const ELEMENT_SPREAD: (f64, f64) = (0.05, 0.3);
/// Fault impact slip: standard deviation of each impact interval, as a fraction of it.
pub const FAULT_SLIP: (f64, f64) = (0.01, 0.02);
/// Nuisance powers relative to the structural background, dB: shaft comb.
pub const SHAFT_COMB_DB: (f64, f64) = (-10.0, 10.0);
/// Once-per-revolution impacts' power relative to the structural background, dB.
pub const ONCE_PER_REV_DB: (f64, f64) = (-15.0, 0.0);
/// Another shaft's impacts' power relative to the structural background, dB (as
/// [`ONCE_PER_REV_DB`]).
pub const OTHER_SHAFT_DB: (f64, f64) = (-15.0, 0.0);
/// Orders (× fr) the other shaft may turn at (log-uniform).
pub const OTHER_SHAFT_ORDER: (f64, f64) = (0.3, 9.0);
/// The other shaft's order is at least this far from an integer (at an integer order it would
/// be the measured shaft's once-per-rev impacts).
pub const OTHER_SHAFT_OFF_INTEGER: f64 = 0.1;
/// Gear mesh power relative to the structural background, dB.
pub const GEAR_MESH_DB: (f64, f64) = (-10.0, 10.0);
/// Electrical lines' power relative to the structural background, dB (running machine).
pub const ELECTRICAL_DB: (f64, f64) = (-20.0, 0.0);
/// Hum power relative to the faint structure of a noise-only recording, dB.
pub const NOISE_ONLY_HUM_DB: (f64, f64) = (10.0, 20.0);
/// Sensor-noise SNR of a noise-only recording (structure and hum over the noise), dB.
pub const NOISE_ONLY_SNR_DB: f64 = -10.0;
/// Longest recording, samples.
pub const MAX_SAMPLES: usize = 1 << 26;
/// Shortest recording, samples.
pub const MIN_SAMPLES: usize = 256;

// ---------------------------------------------------------------------------------------------
// recipe

/// Which nuisance components a machine has (the structure and the sensor noise always are).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
pub struct Nuisances {
    /// Shaft-harmonic comb (unbalance, misalignment, looseness).
    pub shaft_comb: bool,
    /// Once-per-revolution impacts (rub, keyway, loose part).
    pub once_per_rev: bool,
    /// Gear mesh modulated by two shafts.
    pub gear_mesh: bool,
    /// Mains hum, magnetic pull, pole-pass sidebands.
    pub electrical: bool,
    /// Impacts once per turn of another shaft at a non-integer order (belt joint, coupling).
    #[serde(default)]
    pub other_shaft: bool,
}

impl Nuisances {
    /// None: structure and sensor noise only.
    pub const NONE: Self = Self {
        shaft_comb: false,
        once_per_rev: false,
        gear_mesh: false,
        electrical: false,
        other_shaft: false,
    };
    /// The shaft comb only.
    pub const SHAFT_COMB: Self = Self {
        shaft_comb: true,
        ..Self::NONE
    };
    /// Once-per-revolution impacts only.
    pub const ONCE_PER_REV: Self = Self {
        once_per_rev: true,
        ..Self::NONE
    };
    /// The gear mesh only.
    pub const GEAR_MESH: Self = Self {
        gear_mesh: true,
        ..Self::NONE
    };
    /// Electrical lines only.
    pub const ELECTRICAL: Self = Self {
        electrical: true,
        ..Self::NONE
    };
    /// Another shaft's impacts only.
    pub const OTHER_SHAFT: Self = Self {
        other_shaft: true,
        ..Self::NONE
    };
    /// The first four together (shaft comb, once-per-rev, gear mesh, electrical): the mix the
    /// first corpora were drawn with, kept as it was when [`Nuisances::other_shaft`] came.
    pub const ALL: Self = Self {
        shaft_comb: true,
        once_per_rev: true,
        gear_mesh: true,
        electrical: true,
        other_shaft: false,
    };
    /// Every component: [`Nuisances::ALL`] and another shaft's impacts.
    pub const EVERY: Self = Self {
        other_shaft: true,
        ..Self::ALL
    };

    /// `none`, `all` (the four of [`Nuisances::ALL`]), `all+other-shaft`, or the components
    /// present joined by `+` (`shaft-comb`, `once-per-rev`, `gear-mesh`, `electrical`,
    /// `other-shaft`).
    pub fn label(&self) -> String {
        if *self == Self::NONE {
            return "none".into();
        }
        if *self == Self::ALL {
            return "all".into();
        }
        if *self == Self::EVERY {
            return "all+other-shaft".into();
        }
        let mut parts = Vec::new();
        for (on, name) in [
            (self.shaft_comb, "shaft-comb"),
            (self.once_per_rev, "once-per-rev"),
            (self.gear_mesh, "gear-mesh"),
            (self.electrical, "electrical"),
            (self.other_shaft, "other-shaft"),
        ] {
            if on {
                parts.push(name);
            }
        }
        parts.join("+")
    }
}

/// The shape of a [`SpeedSweep`]: how the speed moves through the recording.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SweepShape {
    /// A linear run-up: slowest at the start, fastest at the end.
    RunUp,
    /// A linear coast-down: fastest at the start, slowest at the end.
    CoastDown,
    /// Up, then down (a triangle): fastest halfway.
    UpDown,
    /// Down, then up: slowest halfway.
    DownUp,
}

impl SweepShape {
    /// Every shape, in declaration order.
    pub const ALL: [Self; 4] = [Self::RunUp, Self::CoastDown, Self::UpDown, Self::DownUp];

    /// `run-up`, `coast-down`, `up-down`, `down-up`.
    pub fn name(self) -> &'static str {
        match self {
            Self::RunUp => "run-up",
            Self::CoastDown => "coast-down",
            Self::UpDown => "up-down",
            Self::DownUp => "down-up",
        }
    }

    /// The profile at `u` ∈ [0, 1] (the fraction of the recording elapsed), between −½ and ½
    /// with mean 0 over `u`: linear in `u` (a ramp) or piecewise linear (a triangle).
    pub fn profile(self, u: f64) -> f64 {
        let tri = 0.5 - (2.0 * u - 1.0).abs(); // −½ at the ends, ½ halfway
        match self {
            Self::RunUp => u - 0.5,
            Self::CoastDown => 0.5 - u,
            Self::UpDown => tri,
            Self::DownUp => -tri,
        }
    }
}

/// A speed that changes through the recording, on top of the slow wander: `fr(t) = fr·(1 +
/// span·shape(t/T) + w(t) − mean)` — the mean over the recording still the recipe's rpm, the
/// fastest and slowest turn `span` of it apart (a variable-speed drive's ramp; the University
/// of Ottawa's rig sweeps 40–60 % in 10 s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SpeedSweep {
    /// How the speed moves.
    pub shape: SweepShape,
    /// (fastest − slowest) / mean, 0 ..= 1.
    pub span: f64,
}

/// A localized bearing fault of a recipe.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LocalizedFault {
    /// Where the spall is: its impacts come at BPFI, BPFO or the ball-defect rate.
    pub location: FaultLocation,
    /// 20·log₁₀(impacts' RMS / RMS of the healthy recording), dB (−60 ..= 40).
    pub severity_db: f64,
}

/// An analogue-to-digital converter: the recording is quantised to its codes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Adc {
    /// Resolution, bits (8 ..= 32).
    pub bits: u32,
    /// Full scale: the converter spans ± this, m/s².
    pub full_scale_ms2: f64,
}

impl Adc {
    /// The least-significant bit, m/s²: `2·full_scale / 2^bits`.
    pub fn lsb_ms2(&self) -> f64 {
        2.0 * self.full_scale_ms2 / 2f64.powi(self.bits as i32)
    }

    /// Check the resolution (8 ..= 32 bits) and the full scale (finite, > 0).
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] naming the value.
    pub fn validate(&self) -> Result<()> {
        check_range("adc bits", f64::from(self.bits), 8.0, 32.0, "8 ..= 32")?;
        check_positive("adc full_scale_ms2", self.full_scale_ms2)
    }

    /// Quantise `x` (m/s²) in place: each sample rounded to the nearest code, codes clipped to
    /// `−2^(bits−1) ..= 2^(bits−1) − 1`.
    pub fn quantise(&self, x: &mut [f64]) {
        let lsb = self.lsb_ms2();
        let hi = 2f64.powi(self.bits as i32 - 1);
        for v in x {
            *v = (*v / lsb).round().clamp(-hi, hi - 1.0) * lsb;
        }
    }
}

/// How loud a recording is.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Level {
    /// A running machine: the RMS of the healthy recording (machine and sensor noise), m/s².
    Running {
        /// RMS, m/s².
        rms_ms2: f64,
    },
    /// A noise-only recording: sensor noise with hum and a faint structure whose RMS is this
    /// many least-significant bits of the recipe's ADC (which it requires).
    NoiseOnly {
        /// RMS in LSB (0.1 ..= 1e6).
        rms_lsb: f64,
    },
}

/// What a corpus design fixes about one recording; everything else is drawn from `seed`
/// ([`MachineRecipe::draw`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MachineRecipe {
    /// The bearing under the sensor (its fault orders place a fault's impacts).
    pub geometry: BearingGeometry,
    /// Mean shaft speed over the recording, rpm (30 ..= 30 000).
    pub rpm: f64,
    /// Sampling rate, Hz (2 kHz ..= 1 MHz).
    pub fs_hz: f64,
    /// Duration, s (256 ..= 2²⁶ samples).
    pub duration_s: f64,
    /// Nuisance components present.
    pub nuisances: Nuisances,
    /// Power of everything but the sensor noise over the sensor noise's, dB (−40 ..= 100).
    pub snr_db: f64,
    /// Level of the healthy recording.
    pub level: Level,
    /// Quantisation (required by [`Level::NoiseOnly`]).
    pub adc: Option<Adc>,
    /// A localized bearing fault, if any.
    pub fault: Option<LocalizedFault>,
    /// Seed of every draw.
    pub seed: u64,
    /// A speed that changes through the recording (`None`: only the slow wander).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SpeedSweep>,
}

impl MachineRecipe {
    /// A healthy running machine: no nuisance, SNR 20 dB, RMS 1 m/s², no ADC, no fault.
    ///
    /// # Errors
    /// [`ModelError`] for an unphysical geometry or a speed, rate or duration out of range.
    pub fn healthy(
        geometry: BearingGeometry,
        rpm: f64,
        fs_hz: f64,
        duration_s: f64,
        seed: u64,
    ) -> Result<Self> {
        let r = Self {
            geometry,
            rpm,
            fs_hz,
            duration_s,
            nuisances: Nuisances::NONE,
            snr_db: 20.0,
            level: Level::Running { rms_ms2: 1.0 },
            adc: None,
            fault: None,
            seed,
            sweep: None,
        };
        r.validate()?;
        Ok(r)
    }

    /// A noise-only recording: sensor noise at [`NOISE_ONLY_SNR_DB`] under a faint structure
    /// and mains hum ([`NOISE_ONLY_HUM_DB`] over that structure), `rms_lsb` LSB of `adc` in all,
    /// quantised by it. `rpm` is the machine's (it sets nothing audible here).
    ///
    /// # Errors
    /// As [`MachineRecipe::healthy`], and for an invalid `adc` or `rms_lsb`.
    pub fn noise_only(
        geometry: BearingGeometry,
        rpm: f64,
        fs_hz: f64,
        duration_s: f64,
        adc: Adc,
        rms_lsb: f64,
        seed: u64,
    ) -> Result<Self> {
        let r = Self {
            geometry,
            rpm,
            fs_hz,
            duration_s,
            nuisances: Nuisances::ELECTRICAL,
            snr_db: NOISE_ONLY_SNR_DB,
            level: Level::NoiseOnly { rms_lsb },
            adc: Some(adc),
            fault: None,
            seed,
            sweep: None,
        };
        r.validate()?;
        Ok(r)
    }

    /// The same recipe with these nuisances.
    pub fn with_nuisances(mut self, nuisances: Nuisances) -> Self {
        self.nuisances = nuisances;
        self
    }

    /// The same recipe at this SNR, dB.
    pub fn with_snr_db(mut self, snr_db: f64) -> Self {
        self.snr_db = snr_db;
        self
    }

    /// The same running machine at this RMS, m/s².
    pub fn with_rms_ms2(mut self, rms_ms2: f64) -> Self {
        self.level = Level::Running { rms_ms2 };
        self
    }

    /// The same recipe quantised by `adc`.
    pub fn with_adc(mut self, adc: Adc) -> Self {
        self.adc = Some(adc);
        self
    }

    /// The same machine with a localized fault.
    pub fn with_fault(mut self, fault: LocalizedFault) -> Self {
        self.fault = Some(fault);
        self
    }

    /// The same recipe with another seed.
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// The same machine with its speed sweeping through the recording.
    pub fn with_sweep(mut self, sweep: SpeedSweep) -> Self {
        self.sweep = Some(sweep);
        self
    }

    /// Number of samples: `round(duration · fs)`.
    pub fn samples(&self) -> usize {
        (self.duration_s * self.fs_hz).round() as usize
    }

    /// Mean shaft rate, Hz.
    pub fn shaft_hz(&self) -> f64 {
        self.rpm / 60.0
    }

    /// Fastest shaft rate of the sweep (the mean rate without one), Hz: lines above
    /// [`LINE_MAX_FS_FRACTION`] of fs at this rate are left out.
    pub fn top_shaft_hz(&self) -> f64 {
        match self.sweep {
            Some(s) => self.shaft_hz() * (1.0 + 0.5 * s.span),
            None => self.shaft_hz(),
        }
    }

    /// Check every field (see the field docs for the ranges).
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`], [`ModelError::BadLength`] or [`ModelError::InvalidRecipe`].
    pub fn validate(&self) -> Result<()> {
        self.geometry.validate()?;
        check_range("rpm", self.rpm, 30.0, 30_000.0, "30 ..= 30000 rpm")?;
        check_range("fs_hz", self.fs_hz, 2_000.0, 1.0e6, "2 kHz ..= 1 MHz")?;
        check_positive("duration_s", self.duration_s)?;
        let n = self.duration_s * self.fs_hz;
        if !(n.round() >= MIN_SAMPLES as f64 && n.round() <= MAX_SAMPLES as f64) {
            return Err(ModelError::BadLength {
                samples: n,
                max: MAX_SAMPLES as f64,
            });
        }
        check_range("snr_db", self.snr_db, -40.0, 100.0, "-40 ..= 100 dB")?;
        if let Some(adc) = &self.adc {
            adc.validate()?;
        }
        match self.level {
            Level::Running { rms_ms2 } => {
                check_range("rms_ms2", rms_ms2, 1e-12, 1e6, "1e-12 ..= 1e6 m/s²")?
            }
            Level::NoiseOnly { rms_lsb } => {
                check_range("rms_lsb", rms_lsb, 0.1, 1e6, "0.1 ..= 1e6 LSB")?;
                if self.adc.is_none() {
                    return Err(ModelError::InvalidRecipe(
                        "a noise-only level in LSB needs an ADC".into(),
                    ));
                }
            }
        }
        if let Some(f) = &self.fault {
            check_range("severity_db", f.severity_db, -60.0, 40.0, "-60 ..= 40 dB")?;
        }
        if let Some(w) = &self.sweep {
            check_range("sweep span", w.span, 0.0, 1.0, "0 ..= 1")?;
        }
        Ok(())
    }

    /// Draw every parameter of the machine from the seed (ranges: the module constants).
    ///
    /// # Errors
    /// As [`MachineRecipe::validate`].
    pub fn draw(&self) -> Result<MachineParams> {
        self.validate()?;
        let noise_only = matches!(self.level, Level::NoiseOnly { .. });
        let rng = |stream: u64| {
            let mut r = ChaCha8Rng::seed_from_u64(self.seed);
            r.set_stream(stream);
            r
        };
        let structure = Structure::draw(&mut rng(Stream::Structure as u64), self.fs_hz);
        let fault = self.fault.map(|f| {
            FaultImpacts::draw(
                &mut rng(Stream::FaultParams as u64),
                f,
                &self.geometry.orders(),
                &structure,
            )
        });
        Ok(MachineParams {
            recipe: *self,
            speed: SpeedWander::draw(&mut rng(Stream::Speed as u64)),
            shaft_comb: ShaftComb::draw(&mut rng(Stream::ShaftComb as u64)),
            once_per_rev: OncePerRev::draw(&mut rng(Stream::OncePerRev as u64), &structure),
            gear_mesh: GearMesh::draw(&mut rng(Stream::GearMesh as u64)),
            electrical: Electrical::draw(&mut rng(Stream::Electrical as u64), noise_only),
            other_shaft: OtherShaft::draw(&mut rng(Stream::OtherShaft as u64), &structure),
            structure,
            fault,
        })
    }

    /// [`MachineRecipe::draw`], then [`MachineParams::synthesize`].
    ///
    /// # Errors
    /// As those two.
    pub fn synthesize(&self) -> Result<MachineRecording> {
        self.draw()?.synthesize()
    }
}

/// An impact train locked to a shaft's angle (see `MachineParams::render_locked`).
struct LockedImpacts {
    order: f64,
    angle_rad: f64,
    jitter_fraction: f64,
    amplitude_spread: f64,
    mode: usize,
    stream: Stream,
}

/// The ChaCha8 streams of one seed: parameters and samples of each component apart.
#[derive(Clone, Copy)]
enum Stream {
    Speed = 1,
    Structure = 2,
    ShaftComb = 3,
    OncePerRev = 4,
    GearMesh = 5,
    Electrical = 6,
    FaultParams = 7,
    Excitation = 10,
    SensorNoise = 11,
    OncePerRevTiming = 12,
    FaultTiming = 13,
    OtherShaft = 8,
    OtherShaftTiming = 14,
    FaultElements = 15,
}

// ---------------------------------------------------------------------------------------------
// drawn parameters

/// One sinusoidal line: `amplitude · cos(multiple · φ(t) + phase)`, φ the component's base
/// phase (shaft angle, mesh angle or mains angle): a tone at an order of that phase.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OrderTone {
    /// Multiple of the base frequency (an order).
    pub multiple: f64,
    /// Relative amplitude (the component is scaled to its level as a whole).
    pub amplitude: f64,
    /// Phase, rad.
    pub phase_rad: f64,
}

/// The former name of [`OrderTone`], kept so that code written against it still compiles.
#[deprecated(
    note = "renamed to `OrderTone`: a sinusoid at a multiple of a component's base phase (other \
            crates' lines are `diagnosis::SearchedLine` and `close_loop::effect::CoherentLine`)"
)]
pub type Line = OrderTone;

/// Slow speed wander: `fr(t) = fr·(1 + w(t) − mean w)`, `w` a sum of slow sinusoids.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SpeedWander {
    /// RMS of `w`, fraction of the speed.
    pub rms_fraction: f64,
    /// The sinusoids: frequency (Hz), amplitude (fraction of the speed), phase (rad).
    pub tones: Vec<[f64; 3]>,
}

/// One structural mode.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// Natural frequency, Hz.
    pub freq_hz: f64,
    /// Damping ratio ζ.
    pub damping: f64,
    /// Share of the background's modal power.
    pub power_share: f64,
}

/// The structural background: modes driven by one white excitation, and a low-frequency floor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Structure {
    /// The modes, ascending in frequency.
    pub modes: Vec<Mode>,
    /// Corner of the first-order low-pass floor, Hz.
    pub floor_corner_hz: f64,
    /// Floor power relative to the modes' total, dB.
    pub floor_db: f64,
}

/// The shaft-harmonic comb.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShaftComb {
    /// Power relative to the structural background, dB.
    pub level_db: f64,
    /// Integer orders 1 ..= K and, for a loose machine, half orders.
    pub lines: Vec<OrderTone>,
}

/// Once-per-revolution impacts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OncePerRev {
    /// Power relative to the structural background, dB.
    pub level_db: f64,
    /// The structural mode they ring (index into [`Structure::modes`]).
    pub mode: usize,
    /// Shaft angle of the impact, rad.
    pub angle_rad: f64,
    /// Timing jitter: standard deviation of each impact's time, fraction of a turn.
    pub jitter_fraction: f64,
    /// Amplitude spread: standard deviation of the log amplitude.
    pub amplitude_spread: f64,
}

/// Impacts once per turn of another shaft, which turns at `order` × the measured shaft's rate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OtherShaft {
    /// Power relative to the structural background, dB.
    pub level_db: f64,
    /// The other shaft's speed as an order of the measured shaft (not an integer).
    pub order: f64,
    /// The structural mode they ring (index into [`Structure::modes`]).
    pub mode: usize,
    /// The other shaft's angle at the impact, rad.
    pub angle_rad: f64,
    /// Timing jitter: standard deviation of each impact's time, fraction of the other shaft's
    /// turn (around its locked angle: the jitter does not accumulate).
    pub jitter_fraction: f64,
    /// Amplitude spread: standard deviation of the log amplitude.
    pub amplitude_spread: f64,
}

impl Default for OtherShaft {
    /// What parameters written before the component existed read as (the component is off in
    /// their recipes).
    fn default() -> Self {
        Self {
            level_db: OTHER_SHAFT_DB.0,
            order: 2.5,
            mode: 0,
            angle_rad: 0.0,
            jitter_fraction: 0.01,
            amplitude_spread: 0.2,
        }
    }
}

/// The gear mesh: `a(t)·Σ_h A_h cos(h·ψ(t) + φ_h)`, `ψ = z₁θ + β₁ sin(θ + γ₁) + β₂ sin(θ₂ + γ₂)`,
/// `a = 1 + m₁ cos(θ + α₁) + m₂ cos(θ₂ + α₂)`, `θ₂ = θ·z₁/z₂`, plus the second shaft's lines.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GearMesh {
    /// Power relative to the structural background, dB.
    pub level_db: f64,
    /// Teeth of the gear on the measured shaft (the mesh is at z₁ × fr).
    pub z1: u32,
    /// Teeth of the mating gear (its shaft turns at fr·z₁/z₂).
    pub z2: u32,
    /// Mesh harmonics (multiples of the mesh frequency).
    pub harmonics: Vec<OrderTone>,
    /// Amplitude-modulation depths by the shaft and by the second shaft.
    pub am_depth: [f64; 2],
    /// Amplitude-modulation phases, rad.
    pub am_phase: [f64; 2],
    /// Phase-modulation indices by the shaft and by the second shaft, rad.
    pub pm_index: [f64; 2],
    /// Phase-modulation phases, rad.
    pub pm_phase: [f64; 2],
    /// The second shaft's own lines (multiples of fr₂), amplitudes relative to the mesh's.
    pub second_shaft: Vec<OrderTone>,
}

impl GearMesh {
    /// The second shaft's speed as an order of the measured shaft, z₁/z₂.
    pub fn second_shaft_order(&self) -> f64 {
        f64::from(self.z1) / f64::from(self.z2)
    }
}

/// Electrical lines.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Electrical {
    /// Power relative to the structural background, dB.
    pub level_db: f64,
    /// Mains frequency, Hz (50 or 60 plus a small drift).
    pub line_hz: f64,
    /// Harmonics of the mains frequency (multiple 2 is the magnetic pull).
    pub harmonics: Vec<OrderTone>,
    /// Pole-pass frequency, Hz, when the 2× line is modulated by it.
    pub pole_pass_hz: Option<f64>,
    /// Depth of that modulation (sidebands at 2·f_line ± f_pp of half this relative amplitude).
    pub pole_pass_depth: f64,
    /// Phase of that modulation, rad.
    pub pole_pass_phase: f64,
}

/// A localized fault's impact train.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct FaultImpacts {
    /// Where the spall is.
    pub location: FaultLocation,
    /// Impact rate as an order of the shaft rate (from the geometry).
    pub order: f64,
    /// The cage order (FTF), which modulates a ball fault.
    pub cage_order: f64,
    /// 20·log₁₀(impacts' RMS / healthy recording's RMS), dB.
    pub severity_db: f64,
    /// Standard deviation of each impact interval, fraction of it.
    pub slip: f64,
    /// The structural mode the impacts ring (index into [`Structure::modes`]).
    pub mode: usize,
    /// Load-zone extent ε of `q(ψ) = max(0, 1 − (1 − cos ψ)/(2ε))^(10/9)` (0.5: half the
    /// circumference).
    pub load_zone: f64,
    /// Relative amplitude of impacts outside the load zone (inner race and ball).
    pub outside_load: f64,
    /// Angle of the defect at t = 0 relative to the load direction (shaft angle for the inner
    /// race, cage angle for a ball), rad.
    pub angle_rad: f64,
    /// Amplitude spread: standard deviation of the log amplitude of each impact.
    pub amplitude_spread: f64,
    /// Rolling elements striking a race defect in turn (0: not a race fault, or a recipe drawn
    /// before elements were told apart).
    #[serde(default)]
    pub elements: usize,
    /// Element-to-element spread: standard deviation of the log gain each rolling element
    /// gives its impacts on a race defect (the gains drawn from a stream of their own).
    #[serde(default)]
    pub element_spread: f64,
}

/// Every parameter of one machine recording (the recipe and what was drawn from its seed).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineParams {
    /// The recipe.
    pub recipe: MachineRecipe,
    /// Slow speed wander.
    pub speed: SpeedWander,
    /// Structural background.
    pub structure: Structure,
    /// Shaft comb (used when the recipe's nuisances name it).
    pub shaft_comb: ShaftComb,
    /// Once-per-revolution impacts (used when named).
    pub once_per_rev: OncePerRev,
    /// Gear mesh (used when named).
    pub gear_mesh: GearMesh,
    /// Electrical lines (used when named).
    pub electrical: Electrical,
    /// Another shaft's impacts (used when named).
    #[serde(default)]
    pub other_shaft: OtherShaft,
    /// The fault's impacts, when the recipe has a fault.
    pub fault: Option<FaultImpacts>,
}

fn uniform(rng: &mut ChaCha8Rng, (lo, hi): (f64, f64)) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

fn log_uniform(rng: &mut ChaCha8Rng, (lo, hi): (f64, f64)) -> f64 {
    (lo.ln() + (hi.ln() - lo.ln()) * rng.random::<f64>()).exp()
}

fn phase(rng: &mut ChaCha8Rng) -> f64 {
    TAU * rng.random::<f64>()
}

fn db(v: f64) -> f64 {
    10f64.powf(v / 20.0)
}

impl SpeedWander {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let rms_fraction = uniform(rng, SPEED_WANDER);
        let n = rng.random_range(1..=3usize);
        let mut tones: Vec<[f64; 3]> = (0..n)
            .map(|_| {
                [
                    log_uniform(rng, SPEED_WANDER_HZ),
                    uniform(rng, (0.3, 1.0)),
                    phase(rng),
                ]
            })
            .collect();
        let ms: f64 = tones.iter().map(|t| 0.5 * t[1] * t[1]).sum();
        for t in &mut tones {
            t[1] *= rms_fraction / ms.sqrt();
        }
        Self {
            rms_fraction,
            tones,
        }
    }
}

impl Structure {
    fn draw(rng: &mut ChaCha8Rng, fs_hz: f64) -> Self {
        let n = rng.random_range(MODE_COUNT.0..=MODE_COUNT.1);
        let hi = (MODE_MAX_FS_FRACTION * fs_hz).min(MODE_MAX_HZ);
        let (l0, l1) = (MODE_MIN_HZ.ln(), hi.ln());
        // stratified: one mode per equal slice of the log band, so they spread over it
        let mut modes: Vec<Mode> = (0..n)
            .map(|k| {
                let u = (k as f64 + rng.random::<f64>()) / n as f64;
                Mode {
                    freq_hz: (l0 + (l1 - l0) * u).exp(),
                    damping: uniform(rng, DAMPING),
                    power_share: 10f64.powf(uniform(rng, (-10.0, 0.0)) / 10.0),
                }
            })
            .collect();
        let total: f64 = modes.iter().map(|m| m.power_share).sum();
        for m in &mut modes {
            m.power_share /= total;
        }
        Self {
            modes,
            floor_corner_hz: log_uniform(rng, (20.0, 200.0)),
            floor_db: uniform(rng, (-20.0, -6.0)),
        }
    }
}

impl ShaftComb {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let level_db = uniform(rng, SHAFT_COMB_DB);
        let top = rng.random_range(10..=20u32);
        let decay = uniform(rng, (1.5, 4.0));
        let mut lines = vec![
            OrderTone {
                multiple: 1.0,
                amplitude: 1.0,
                phase_rad: phase(rng),
            },
            OrderTone {
                multiple: 2.0,
                amplitude: db(uniform(rng, (-10.0, 3.0))),
                phase_rad: phase(rng),
            },
        ];
        let a2 = lines[1].amplitude.min(1.0);
        for k in 3..=top {
            let d = -decay * f64::from(k - 2) + uniform(rng, (-3.0, 3.0));
            lines.push(OrderTone {
                multiple: f64::from(k),
                amplitude: a2 * db(d),
                phase_rad: phase(rng),
            });
        }
        let loose = rng.random::<f64>() < 0.5;
        let half = db(uniform(rng, (-15.0, -5.0)));
        for j in 0..6u32 {
            let d = uniform(rng, (-3.0, 3.0)) - 3.0 * f64::from(j);
            let p = phase(rng);
            if loose {
                lines.push(OrderTone {
                    multiple: f64::from(j) + 0.5,
                    amplitude: half * db(d),
                    phase_rad: p,
                });
            }
        }
        Self { level_db, lines }
    }
}

impl OncePerRev {
    fn draw(rng: &mut ChaCha8Rng, s: &Structure) -> Self {
        Self {
            level_db: uniform(rng, ONCE_PER_REV_DB),
            mode: rng.random_range(0..s.modes.len()),
            angle_rad: phase(rng),
            jitter_fraction: uniform(rng, (0.002, 0.02)),
            amplitude_spread: uniform(rng, (0.1, 0.3)),
        }
    }
}

impl OtherShaft {
    fn draw(rng: &mut ChaCha8Rng, s: &Structure) -> Self {
        let level_db = uniform(rng, OTHER_SHAFT_DB);
        let order = loop {
            let o = log_uniform(rng, OTHER_SHAFT_ORDER);
            if (o - o.round()).abs() >= OTHER_SHAFT_OFF_INTEGER {
                break o;
            }
        };
        Self {
            level_db,
            order,
            mode: rng.random_range(0..s.modes.len()),
            angle_rad: phase(rng),
            jitter_fraction: uniform(rng, (0.002, 0.02)),
            amplitude_spread: uniform(rng, (0.1, 0.3)),
        }
    }
}

impl GearMesh {
    fn draw(rng: &mut ChaCha8Rng) -> Self {
        let level_db = uniform(rng, GEAR_MESH_DB);
        let z1 = rng.random_range(15..=60u32);
        let z2 = loop {
            let z = rng.random_range(15..=90u32);
            if z1 % z != 0 {
                break z;
            }
        };
        let n_h = rng.random_range(1..=3u32);
        let step = uniform(rng, (3.0, 12.0));
        let harmonics = (1..=n_h)
            .map(|h| OrderTone {
                multiple: f64::from(h),
                amplitude: db(-step * f64::from(h - 1)),
                phase_rad: phase(rng),
            })
            .collect();
        let am_depth = [uniform(rng, (0.05, 0.4)), uniform(rng, (0.05, 0.4))];
        let am_phase = [phase(rng), phase(rng)];
        let pm_index = [uniform(rng, (0.05, 0.5)), uniform(rng, (0.05, 0.5))];
        let pm_phase = [phase(rng), phase(rng)];
        let second_shaft = (1..=2u32)
            .map(|k| OrderTone {
                multiple: f64::from(k),
                amplitude: db(uniform(rng, (-20.0, -6.0))),
                phase_rad: phase(rng),
            })
            .collect();
        Self {
            level_db,
            z1,
            z2,
            harmonics,
            am_depth,
            am_phase,
            pm_index,
            pm_phase,
            second_shaft,
        }
    }
}

impl Electrical {
    fn draw(rng: &mut ChaCha8Rng, noise_only: bool) -> Self {
        let level_db = uniform(
            rng,
            if noise_only {
                NOISE_ONLY_HUM_DB
            } else {
                ELECTRICAL_DB
            },
        );
        let base = if rng.random::<f64>() < 0.5 {
            50.0
        } else {
            60.0
        };
        let line_hz = base + uniform(rng, (-0.02, 0.02));
        let harmonics = (1..=7u32)
            .map(|k| {
                let d = match k {
                    1 => 0.0,
                    2 => uniform(rng, (0.0, 10.0)),
                    k if k % 2 == 1 => uniform(rng, (-20.0, -6.0)),
                    _ => uniform(rng, (-30.0, -15.0)),
                };
                OrderTone {
                    multiple: f64::from(k),
                    amplitude: db(d),
                    phase_rad: phase(rng),
                }
            })
            .collect();
        let has_pp = rng.random::<f64>() < 0.5;
        let slip = uniform(rng, (0.01, 0.05));
        let depth = uniform(rng, (0.1, 0.6));
        let pp_phase = phase(rng);
        Self {
            level_db,
            line_hz,
            harmonics,
            pole_pass_hz: has_pp.then_some(2.0 * slip * base),
            pole_pass_depth: depth,
            pole_pass_phase: pp_phase,
        }
    }
}

impl FaultImpacts {
    fn draw(rng: &mut ChaCha8Rng, f: LocalizedFault, orders: &FaultOrders, s: &Structure) -> Self {
        let slip = uniform(rng, FAULT_SLIP);
        let high: Vec<usize> = (0..s.modes.len())
            .filter(|&i| s.modes[i].freq_hz >= FAULT_MODE_MIN_HZ)
            .collect();
        let pick = rng.random_range(0..high.len().max(1));
        let mode = high.get(pick).copied().unwrap_or(s.modes.len() - 1);
        Self {
            location: f.location,
            order: orders.of(f.location),
            cage_order: orders.ftf,
            severity_db: f.severity_db,
            slip,
            mode,
            load_zone: uniform(rng, (0.3, 0.5)),
            outside_load: uniform(rng, (0.0, 0.2)),
            angle_rad: phase(rng),
            amplitude_spread: uniform(rng, (0.05, 0.15)),
            // BPFO = Z·FTF: the number of elements from the orders (a geometry's are exact)
            elements: match f.location {
                FaultLocation::Outer | FaultLocation::Inner if orders.ftf > 0.0 => {
                    (orders.bpfo / orders.ftf).round().max(1.0) as usize
                }
                _ => 0,
            },
            element_spread: uniform(rng, ELEMENT_SPREAD),
        }
    }

    /// Relative amplitude of an impact when the shaft has turned `theta` rad.
    fn modulation(&self, theta: f64) -> f64 {
        let psi = match self.location {
            FaultLocation::Outer => return 1.0,
            FaultLocation::Inner => theta + self.angle_rad,
            FaultLocation::Ball => self.cage_order * theta + self.angle_rad,
        };
        let q = (1.0 - (1.0 - psi.cos()) / (2.0 * self.load_zone))
            .max(0.0)
            .powf(10.0 / 9.0);
        self.outside_load + (1.0 - self.outside_load) * q
    }
}

// ---------------------------------------------------------------------------------------------
// synthesis

/// RMS of each component in the recording, m/s² (0 when absent).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ComponentRms {
    /// Structural background (modes and floor).
    pub structure: f64,
    /// Shaft comb.
    pub shaft_comb: f64,
    /// Once-per-revolution impacts.
    pub once_per_rev: f64,
    /// Gear mesh.
    pub gear_mesh: f64,
    /// Electrical lines.
    pub electrical: f64,
    /// Another shaft's impacts.
    #[serde(default)]
    pub other_shaft: f64,
    /// Sensor noise (its standard deviation as drawn).
    pub sensor_noise: f64,
    /// The healthy recording (everything above together).
    pub healthy: f64,
    /// The fault's impacts.
    pub fault: f64,
}

/// A synthesised machine recording.
#[derive(Debug, Clone, PartialEq)]
pub struct MachineRecording {
    /// Sampling rate, Hz.
    pub fs_hz: f64,
    /// Housing acceleration, m/s² (quantised when the recipe has an ADC).
    pub accel: Vec<f64>,
    /// RMS of each component, m/s².
    pub rms: ComponentRms,
    /// Number of fault impacts within the recording.
    pub fault_impacts: usize,
    /// Every parameter it was made from.
    pub params: MachineParams,
}

/// Minimal complex arithmetic for the recurrences.
#[derive(Debug, Clone, Copy, PartialEq)]
struct C {
    re: f64,
    im: f64,
}

impl C {
    fn polar(r: f64, phi: f64) -> Self {
        let (s, c) = phi.sin_cos();
        Self {
            re: r * c,
            im: r * s,
        }
    }
    fn mul(self, o: Self) -> Self {
        Self {
            re: self.re * o.re - self.im * o.im,
            im: self.re * o.im + self.im * o.re,
        }
    }
    fn add(self, o: Self) -> Self {
        Self {
            re: self.re + o.re,
            im: self.im + o.im,
        }
    }
    fn scale(self, k: f64) -> Self {
        Self {
            re: self.re * k,
            im: self.im * k,
        }
    }
    /// `exp(self)`.
    fn exp(self) -> Self {
        Self::polar(self.re.exp(), self.im)
    }
}

/// `Σ_k c_k z^k` for `k = 1 ..= c.len()` (Horner).
fn horner(c: &[C], z: C) -> C {
    let mut acc = C { re: 0.0, im: 0.0 };
    for &ck in c.iter().rev() {
        acc = acc.add(ck).mul(z);
    }
    acc
}

/// A mode's discrete pole `λ = exp((−ζω + iω_d)/fs)` and its decay rate ζω (1/s).
fn pole(m: &Mode, fs: f64) -> (C, f64) {
    let w = TAU * m.freq_hz;
    let sigma = m.damping * w;
    let wd = w * (1.0 - m.damping * m.damping).sqrt();
    (
        C {
            re: -sigma / fs,
            im: wd / fs,
        }
        .exp(),
        sigma,
    )
}

/// A locked impact train's `[mode, jitter, spread, angle]`, each checked under its name in
/// `names`: a mode index below `n_modes`, jitter 0 ..= 0.2, spread 0 ..= 2, a finite angle.
fn validate_locked(names: [&'static str; 4], values: [f64; 4], n_modes: usize) -> Result<()> {
    let [mode, jitter, spread, angle] = values;
    check_range(names[0], mode, 0.0, (n_modes - 1) as f64, "a mode index")?;
    check_range(names[1], jitter, 0.0, 0.2, "0 ..= 0.2")?;
    check_range(names[2], spread, 0.0, 2.0, "0 ..= 2")?;
    check_range(names[3], angle, -1e3, 1e3, "finite")
}

fn mean_square(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64
}

impl MachineParams {
    /// Check the drawn (or edited) parameters against the recipe.
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] or [`ModelError::InvalidRecipe`] naming the parameter.
    pub fn validate(&self) -> Result<()> {
        let r = &self.recipe;
        r.validate()?;
        let fs = r.fs_hz;
        self.validate_structure(fs)?;
        self.validate_speed(fs)?;
        self.validate_lines_and_levels()?;
        let n_modes = self.structure.modes.len();
        self.validate_once_per_rev(n_modes)?;
        self.validate_other_shaft(n_modes)?;
        self.validate_gear_mesh()?;
        self.validate_electrical()?;
        self.validate_fault(n_modes)
    }

    /// The structure at `fs` Hz: at least one mode, each in range, not every power share zero;
    /// the floor's corner and level.
    fn validate_structure(&self, fs: f64) -> Result<()> {
        if self.structure.modes.is_empty() {
            return Err(ModelError::InvalidRecipe(
                "the structure needs at least one mode".into(),
            ));
        }
        for m in &self.structure.modes {
            check_range(
                "mode freq_hz",
                m.freq_hz,
                1.0,
                0.49 * fs,
                "1 Hz ..= 0.49 fs",
            )?;
            check_range("mode damping", m.damping, 1e-4, 0.5, "1e-4 ..= 0.5")?;
            check_range("mode power_share", m.power_share, 0.0, 1.0, "0 ..= 1")?;
        }
        if self.structure.modes.iter().all(|m| m.power_share == 0.0) {
            return Err(ModelError::InvalidRecipe(
                "the modes' power shares are all zero".into(),
            ));
        }
        check_range(
            "floor_corner_hz",
            self.structure.floor_corner_hz,
            0.1,
            0.49 * fs,
            "0.1 Hz ..= 0.49 fs",
        )?;
        check_range(
            "floor_db",
            self.structure.floor_db,
            -200.0,
            40.0,
            "-200 ..= 40 dB",
        )?;
        Ok(())
    }

    /// The speed at `fs` Hz: its RMS fluctuation and each wander tone.
    fn validate_speed(&self, fs: f64) -> Result<()> {
        check_range(
            "speed rms_fraction",
            self.speed.rms_fraction,
            0.0,
            0.2,
            "0 ..= 0.2",
        )?;
        for t in &self.speed.tones {
            check_range(
                "wander freq_hz",
                t[0],
                1e-4,
                0.49 * fs,
                "1e-4 Hz ..= 0.49 fs",
            )?;
            check_range("wander amplitude", t[1].abs(), 0.0, 0.2, "|a| <= 0.2")?;
            check_range("wander phase", t[2], -1e3, 1e3, "finite")?;
        }
        Ok(())
    }

    /// Every line of the shaft comb, the gear mesh and the electrical harmonics, and the
    /// components' levels.
    fn validate_lines_and_levels(&self) -> Result<()> {
        let lines_ok = |name: &'static str, lines: &[OrderTone]| -> Result<()> {
            for l in lines {
                check_range(name, l.multiple, 0.0, 1e6, "0 ..= 1e6")?;
                check_range(name, l.amplitude.abs(), 0.0, 1e6, "|a| <= 1e6")?;
                check_range(name, l.phase_rad, -1e3, 1e3, "finite")?;
            }
            Ok(())
        };
        lines_ok("shaft comb line", &self.shaft_comb.lines)?;
        lines_ok("gear mesh harmonic", &self.gear_mesh.harmonics)?;
        lines_ok("second shaft line", &self.gear_mesh.second_shaft)?;
        lines_ok("electrical harmonic", &self.electrical.harmonics)?;
        for (name, v) in [
            ("shaft comb level_db", self.shaft_comb.level_db),
            ("once-per-rev level_db", self.once_per_rev.level_db),
            ("gear mesh level_db", self.gear_mesh.level_db),
            ("electrical level_db", self.electrical.level_db),
            ("other shaft level_db", self.other_shaft.level_db),
        ] {
            check_range(name, v, -200.0, 80.0, "-200 ..= 80 dB")?;
        }
        Ok(())
    }

    /// The once-per-rev component: its mode (an index below `n_modes`), jitter, spread, angle.
    fn validate_once_per_rev(&self, n_modes: usize) -> Result<()> {
        let o = &self.once_per_rev;
        let train = [
            o.mode as f64,
            o.jitter_fraction,
            o.amplitude_spread,
            o.angle_rad,
        ];
        let names = [
            "once-per-rev mode",
            "once-per-rev jitter",
            "once-per-rev spread",
            "once-per-rev angle",
        ];
        validate_locked(names, train, n_modes)
    }

    /// The other shaft's impacts: its order (positive), mode, jitter, spread, angle.
    fn validate_other_shaft(&self, n_modes: usize) -> Result<()> {
        let o = &self.other_shaft;
        check_range("other shaft order", o.order, 1e-3, 1e3, "0.001 ..= 1000")?;
        let train = [
            o.mode as f64,
            o.jitter_fraction,
            o.amplitude_spread,
            o.angle_rad,
        ];
        let names = [
            "other shaft mode",
            "other shaft jitter",
            "other shaft spread",
            "other shaft angle",
        ];
        validate_locked(names, train, n_modes)
    }

    /// The gear mesh: tooth counts and the two modulations' depths, indices and phases.
    fn validate_gear_mesh(&self) -> Result<()> {
        let g = &self.gear_mesh;
        check_range("gear z1", f64::from(g.z1), 1.0, 1e4, "1 ..= 10000")?;
        check_range("gear z2", f64::from(g.z2), 1.0, 1e4, "1 ..= 10000")?;
        for k in 0..2 {
            check_range("gear am_depth", g.am_depth[k], 0.0, 1.0, "0 ..= 1")?;
            check_range("gear pm_index", g.pm_index[k], 0.0, 10.0, "0 ..= 10 rad")?;
            check_range("gear am_phase", g.am_phase[k], -1e3, 1e3, "finite")?;
            check_range("gear pm_phase", g.pm_phase[k], -1e3, 1e3, "finite")?;
        }
        Ok(())
    }

    /// The electrical component: line frequency, pole-pass frequency, depth and phase.
    fn validate_electrical(&self) -> Result<()> {
        let e = &self.electrical;
        check_range("line_hz", e.line_hz, 1.0, 1e4, "1 ..= 10000 Hz")?;
        if let Some(pp) = e.pole_pass_hz {
            check_range("pole_pass_hz", pp, 1e-3, 1e3, "1e-3 ..= 1000 Hz")?;
        }
        check_range("pole_pass_depth", e.pole_pass_depth, 0.0, 1.0, "0 ..= 1")?;
        check_range("pole_pass_phase", e.pole_pass_phase, -1e3, 1e3, "finite")?;
        Ok(())
    }

    /// The drawn fault against the recipe's: both absent, or both present with the drawn one's
    /// order, rates, severity, mode (an index below `n_modes`), load zone and spread in range.
    fn validate_fault(&self, n_modes: usize) -> Result<()> {
        match (&self.fault, &self.recipe.fault) {
            (None, None) => {}
            (Some(f), Some(_)) => {
                check_range("fault order", f.order, 0.01, 1e3, "0.01 ..= 1000")?;
                check_range("fault cage_order", f.cage_order, 0.0, 1.0, "0 ..= 1")?;
                check_range(
                    "fault severity_db",
                    f.severity_db,
                    -60.0,
                    40.0,
                    "-60 ..= 40 dB",
                )?;
                check_range("fault slip", f.slip, 0.0, 0.2, "0 ..= 0.2")?;
                check_range(
                    "fault mode",
                    f.mode as f64,
                    0.0,
                    (n_modes - 1) as f64,
                    "a mode index",
                )?;
                check_range("fault load_zone", f.load_zone, 0.05, 10.0, "0.05 ..= 10")?;
                check_range("fault outside_load", f.outside_load, 0.0, 1.0, "0 ..= 1")?;
                check_range("fault angle", f.angle_rad, -1e3, 1e3, "finite")?;
                check_range("fault spread", f.amplitude_spread, 0.0, 2.0, "0 ..= 2")?;
                check_range(
                    "fault element_spread",
                    f.element_spread,
                    0.0,
                    2.0,
                    "0 ..= 2",
                )?;
            }
            _ => {
                return Err(ModelError::InvalidRecipe(
                    "the drawn fault and the recipe's fault disagree (draw again)".into(),
                ));
            }
        }
        Ok(())
    }

    /// Render the recording (see the module documentation for the components and the order in
    /// which they are scaled).
    ///
    /// # Errors
    /// [`MachineParams::validate`]'s; [`ModelError::Diverged`] if a component came out
    /// non-finite (it cannot with validated parameters).
    pub fn synthesize(&self) -> Result<MachineRecording> {
        self.validate()?;
        let r = &self.recipe;
        let fs = r.fs_hz;
        let n = r.samples();
        let fr = r.shaft_hz();
        let theta = self.shaft_angle(n);
        let mut out = vec![0.0; n];
        self.render_structure(&mut out);
        let p_ref = mean_square(&out);
        let mut rms = ComponentRms {
            structure: p_ref.sqrt(),
            ..Default::default()
        };
        let mut scratch = vec![0.0; n];
        let nu = r.nuisances;
        for (on, level_db, which) in [
            (nu.shaft_comb, self.shaft_comb.level_db, 0),
            (nu.once_per_rev, self.once_per_rev.level_db, 1),
            (nu.gear_mesh, self.gear_mesh.level_db, 2),
            (nu.electrical, self.electrical.level_db, 3),
            (nu.other_shaft, self.other_shaft.level_db, 4),
        ] {
            if !on {
                continue;
            }
            scratch.fill(0.0);
            match which {
                0 => self.render_comb(&theta, &mut scratch),
                1 => self.render_once_per_rev(&theta, &mut scratch),
                2 => self.render_gear(&theta, &mut scratch),
                3 => self.render_electrical(&mut scratch),
                _ => self.render_other_shaft(&theta, &mut scratch),
            }
            let ms = mean_square(&scratch);
            // every line above 0.45 fs left out: the component is silent
            let g = if ms > 0.0 {
                (p_ref * 10f64.powf(level_db / 10.0) / ms).sqrt()
            } else {
                0.0
            };
            for (o, s) in out.iter_mut().zip(&scratch) {
                *o += g * s;
            }
            let v = g * ms.sqrt();
            match which {
                0 => rms.shaft_comb = v,
                1 => rms.once_per_rev = v,
                2 => rms.gear_mesh = v,
                3 => rms.electrical = v,
                _ => rms.other_shaft = v,
            }
        }
        // sensor noise at the SNR
        let p_machine = mean_square(&out);
        let sigma = (p_machine / 10f64.powf(r.snr_db / 10.0)).sqrt();
        let mut rng = ChaCha8Rng::seed_from_u64(r.seed);
        rng.set_stream(Stream::SensorNoise as u64);
        for o in out.iter_mut() {
            let z: f64 = StandardNormal.sample(&mut rng);
            *o += sigma * z;
        }
        rms.sensor_noise = sigma;
        // level
        let target = match r.level {
            Level::Running { rms_ms2 } => rms_ms2,
            Level::NoiseOnly { rms_lsb } => rms_lsb * r.adc.map_or(1.0, |a| a.lsb_ms2()),
        };
        let k = target / mean_square(&out).sqrt();
        for o in out.iter_mut() {
            *o *= k;
        }
        for v in [
            &mut rms.structure,
            &mut rms.shaft_comb,
            &mut rms.once_per_rev,
            &mut rms.gear_mesh,
            &mut rms.electrical,
            &mut rms.other_shaft,
            &mut rms.sensor_noise,
        ] {
            *v *= k;
        }
        rms.healthy = target;
        // the fault
        let mut fault_impacts = 0;
        if let Some(f) = &self.fault {
            scratch.fill(0.0);
            fault_impacts = self.render_fault(f, &theta, fr, &mut scratch);
            let ms = mean_square(&scratch);
            let g = if ms > 0.0 {
                target * db(f.severity_db) / ms.sqrt()
            } else {
                0.0
            };
            for (o, s) in out.iter_mut().zip(&scratch) {
                *o += g * s;
            }
            rms.fault = g * ms.sqrt();
        }
        if let Some(adc) = &r.adc {
            adc.quantise(&mut out);
        }
        if let Some(i) = out.iter().position(|v| !v.is_finite()) {
            return Err(ModelError::Diverged {
                time_s: i as f64 / fs,
            });
        }
        Ok(MachineRecording {
            fs_hz: fs,
            accel: out,
            rms,
            fault_impacts,
            params: self.clone(),
        })
    }

    /// A tachometer recorded beside the machine's samples: `pulses_per_rev` square pulses a
    /// shaft turn (0 and 5 V, rising at each `1/pulses_per_rev` of a turn from θ = 0), on the
    /// shaft angle the recording's every component follows — an encoder's lines, or 1 for a
    /// key. As many samples as [`MachineRecipe::samples`].
    ///
    /// # Errors
    /// [`ModelError::OutOfRange`] for `pulses_per_rev` outside 1 ..= 100 000.
    pub fn tachometer(&self, pulses_per_rev: f64) -> Result<Vec<f64>> {
        check_range("pulses_per_rev", pulses_per_rev, 1.0, 1e5, "1 ..= 100000")?;
        Ok(self
            .shaft_angle(self.recipe.samples())
            .into_iter()
            .map(|th| {
                if (th / TAU * pulses_per_rev).fract() < 0.5 {
                    5.0
                } else {
                    0.0
                }
            })
            .collect())
    }

    /// Shaft angle θ at each sample, rad (θ₀ = 0): the integral of `2π fr (1 + w − mean w)`.
    fn shaft_angle(&self, n: usize) -> Vec<f64> {
        let fs = self.recipe.fs_hz;
        let mut w = vec![0.0; n];
        for t in &self.speed.tones {
            let rot = C::polar(1.0, TAU * t[0] / fs);
            let mut z = C::polar(t[1], t[2]);
            for v in w.iter_mut() {
                *v += z.im;
                z = z.mul(rot);
            }
        }
        if let Some(sw) = self.recipe.sweep {
            let last = (n.max(2) - 1) as f64;
            for (i, v) in w.iter_mut().enumerate() {
                *v += sw.span * sw.shape.profile(i as f64 / last);
            }
        }
        let mean = w.iter().sum::<f64>() / n as f64;
        let step = TAU * self.recipe.shaft_hz() / fs;
        let mut acc = 0.0;
        for v in w.iter_mut() {
            let inc = step * (1.0 + *v - mean);
            *v = acc;
            acc += inc;
        }
        w
    }

    /// Structural modes (one white excitation) and the low-frequency floor, unscaled.
    fn render_structure(&self, out: &mut [f64]) {
        let fs = self.recipe.fs_hz;
        let s = &self.structure;
        let modes: Vec<(C, f64)> = s
            .modes
            .iter()
            .map(|m| {
                let (lambda, _) = pole(m, fs);
                // variance of Im(s) under unit white input: ½/(1−r²) − ½ Re 1/(1−λ²)
                let r2 = lambda.re * lambda.re + lambda.im * lambda.im;
                let l2 = lambda.mul(lambda);
                let d = C {
                    re: 1.0 - l2.re,
                    im: -l2.im,
                };
                let re_inv = d.re / (d.re * d.re + d.im * d.im);
                let gain = 0.5 / (1.0 - r2) - 0.5 * re_inv;
                (lambda, (m.power_share / gain).sqrt())
            })
            .collect();
        let a = (-TAU * s.floor_corner_hz / fs).exp();
        let floor_gain = (1.0 - a) / (1.0 + a);
        let total_modes: f64 = s.modes.iter().map(|m| m.power_share).sum();
        let g_floor = (total_modes * 10f64.powf(s.floor_db / 10.0) / floor_gain).sqrt();
        // settle: ten time constants of the slowest pole before t = 0
        let slowest = s
            .modes
            .iter()
            .map(|m| pole(m, fs).1)
            .chain(std::iter::once(TAU * s.floor_corner_hz))
            .fold(f64::INFINITY, f64::min);
        let settle = (10.0 / slowest * fs).ceil() as usize;
        let mut rng = ChaCha8Rng::seed_from_u64(self.recipe.seed);
        rng.set_stream(Stream::Excitation as u64);
        let mut state = vec![C { re: 0.0, im: 0.0 }; modes.len()];
        let mut lp = 0.0;
        let mut step = |rng: &mut ChaCha8Rng| -> f64 {
            let e: f64 = StandardNormal.sample(rng);
            let f: f64 = StandardNormal.sample(rng);
            let mut y = 0.0;
            for (st, (lambda, g)) in state.iter_mut().zip(&modes) {
                let z = st.mul(*lambda);
                *st = C {
                    re: z.re + e,
                    im: z.im,
                };
                y += g * st.im;
            }
            lp = a * lp + (1.0 - a) * f;
            y + g_floor * lp
        };
        for _ in 0..settle {
            step(&mut rng);
        }
        for o in out.iter_mut() {
            *o = step(&mut rng);
        }
    }

    /// Shaft comb, unscaled.
    fn render_comb(&self, theta: &[f64], out: &mut [f64]) {
        let r = &self.recipe;
        let fmax = LINE_MAX_FS_FRACTION * r.fs_hz;
        // the fastest turn's lines are the highest (the mean's, without a sweep)
        let fr = r.top_shaft_hz();
        // integer orders as powers of z = e^{iθ}; half orders as odd powers of e^{iθ/2}
        let top = self
            .shaft_comb
            .lines
            .iter()
            .map(|l| l.multiple.round() as usize)
            .max()
            .unwrap_or(0);
        let mut whole = vec![C { re: 0.0, im: 0.0 }; top];
        let mut half = vec![C { re: 0.0, im: 0.0 }; top + 1];
        for l in &self.shaft_comb.lines {
            if l.multiple * fr >= fmax || l.multiple <= 0.0 {
                continue;
            }
            let c = C::polar(l.amplitude, l.phase_rad);
            if (l.multiple - l.multiple.round()).abs() < 1e-9 {
                let k = l.multiple.round() as usize;
                whole[k - 1] = whole[k - 1].add(c);
            } else if (2.0 * l.multiple - (2.0 * l.multiple).round()).abs() < 1e-9 {
                // (j + ½) = (2j + 1)/2: odd power 2j + 1 of e^{iθ/2} = e^{iθ/2}·z^j
                let j = (l.multiple - 0.5).round() as usize;
                half[j] = half[j].add(c);
            }
        }
        let any_half = half.iter().any(|c| c.re != 0.0 || c.im != 0.0);
        for (o, &t) in out.iter_mut().zip(theta) {
            let hw = C::polar(1.0, 0.5 * t);
            let z = hw.mul(hw);
            let mut v = horner(&whole, z).re;
            if any_half {
                // Σ_j h_j e^{iθ/2} z^j = e^{iθ/2}(h_0 + z Σ_{j≥1} h_j z^{j−1})
                let tail = horner(&half[1..], z);
                v += hw.mul(half[0].add(tail)).re;
            }
            *o = v;
        }
    }

    /// Once-per-revolution impacts, unscaled.
    fn render_once_per_rev(&self, theta: &[f64], out: &mut [f64]) {
        let o = &self.once_per_rev;
        let train = LockedImpacts {
            order: 1.0,
            angle_rad: o.angle_rad,
            jitter_fraction: o.jitter_fraction,
            amplitude_spread: o.amplitude_spread,
            mode: o.mode,
            stream: Stream::OncePerRevTiming,
        };
        self.render_locked(&train, theta, out);
    }

    /// Another shaft's impacts, unscaled: one per turn of θ₂ = order·θ, at its angle.
    fn render_other_shaft(&self, theta: &[f64], out: &mut [f64]) {
        let o = &self.other_shaft;
        let train = LockedImpacts {
            order: o.order,
            angle_rad: o.angle_rad,
            jitter_fraction: o.jitter_fraction,
            amplitude_spread: o.amplitude_spread,
            mode: o.mode,
            stream: Stream::OtherShaftTiming,
        };
        self.render_locked(&train, theta, out);
    }

    /// Impacts locked to a shaft turning at `order` × the measured one's angle θ: one per turn
    /// of `order·θ` at its angle, each with jitter (a fraction of that shaft's turn, not
    /// accumulating) and amplitude spread drawn from the train's stream, ringing its mode.
    /// Order 1 is the once-per-rev component, bit for bit as it was before other orders came.
    fn render_locked(&self, train: &LockedImpacts, theta: &[f64], out: &mut [f64]) {
        let fs = self.recipe.fs_hz;
        let m = &self.structure.modes[train.mode];
        let (lambda, sigma) = pole(m, fs);
        let fr = self.recipe.shaft_hz();
        let f2 = fr * train.order;
        let turn = 1.0 / f2;
        let mut rng = ChaCha8Rng::seed_from_u64(self.recipe.seed);
        rng.set_stream(train.stream as u64);
        let pre = 10.0 / sigma;
        let end = theta.len() as f64 / fs;
        let mut times = Vec::new();
        // turns whose nominal impact falls in [−pre, end + a jitter's reach)
        let k0 = -((pre * f2).ceil() as i64) - 1;
        let k1 = (end * f2).ceil() as i64 + 1;
        for k in k0..=k1 {
            // order·θ reaches 2πk + angle where θ = (2πk + angle)/order
            let target = (TAU * k as f64 + train.angle_rad.rem_euclid(TAU)) / train.order;
            let t = time_at_angle(theta, fs, fr, target);
            let z: f64 = StandardNormal.sample(&mut rng);
            let a: f64 = StandardNormal.sample(&mut rng);
            times.push((
                t + train.jitter_fraction * turn * z,
                (train.amplitude_spread * a).exp(),
            ));
        }
        ring(&mut times, lambda, sigma, fs, out);
    }

    /// Gear mesh, unscaled.
    fn render_gear(&self, theta: &[f64], out: &mut [f64]) {
        let g = &self.gear_mesh;
        let r = &self.recipe;
        let fmax = LINE_MAX_FS_FRACTION * r.fs_hz;
        let fr = r.top_shaft_hz();
        let ratio = g.second_shaft_order();
        let mesh_hz = f64::from(g.z1) * fr;
        // a harmonic's reach: its frequency plus three shaft-rate sidebands
        let reach = 3.0 * fr.max(ratio * fr);
        let harm: Vec<C> = {
            let top = g
                .harmonics
                .iter()
                .filter(|h| h.multiple * mesh_hz + reach < fmax && h.multiple >= 1.0)
                .map(|h| h.multiple.round() as usize)
                .max()
                .unwrap_or(0);
            let mut c = vec![C { re: 0.0, im: 0.0 }; top];
            for h in &g.harmonics {
                let k = h.multiple.round() as usize;
                if k >= 1 && k <= top {
                    c[k - 1] = c[k - 1].add(C::polar(h.amplitude, h.phase_rad));
                }
            }
            c
        };
        let second: Vec<C> = {
            let mut c = vec![C { re: 0.0, im: 0.0 }; 2];
            for l in &g.second_shaft {
                let k = l.multiple.round() as usize;
                if (1..=2).contains(&k) && l.multiple * ratio * fr < fmax {
                    c[k - 1] = c[k - 1].add(C::polar(l.amplitude, l.phase_rad));
                }
            }
            c
        };
        if harm.is_empty() && second.iter().all(|c| c.re == 0.0 && c.im == 0.0) {
            return;
        }
        let z1 = f64::from(g.z1);
        // cos(θ + α) = Re(e^{iθ}·e^{iα}), sin(θ + γ) = Im(e^{iθ}·e^{iγ}): three sin_cos a sample
        let am_rot = [C::polar(1.0, g.am_phase[0]), C::polar(1.0, g.am_phase[1])];
        let pm_rot = [C::polar(1.0, g.pm_phase[0]), C::polar(1.0, g.pm_phase[1])];
        for (o, &t) in out.iter_mut().zip(theta) {
            let z = C::polar(1.0, t);
            let z2 = C::polar(1.0, t * ratio);
            let am =
                1.0 + g.am_depth[0] * z.mul(am_rot[0]).re + g.am_depth[1] * z2.mul(am_rot[1]).re;
            let pm = g.pm_index[0] * z.mul(pm_rot[0]).im + g.pm_index[1] * z2.mul(pm_rot[1]).im;
            let zm = C::polar(1.0, z1 * t + pm);
            *o = am * horner(&harm, zm).re + horner(&second, z2).re;
        }
    }

    /// Electrical lines, unscaled.
    fn render_electrical(&self, out: &mut [f64]) {
        let e = &self.electrical;
        let fs = self.recipe.fs_hz;
        let fmax = LINE_MAX_FS_FRACTION * fs;
        let pp = e.pole_pass_hz.unwrap_or(0.0);
        let top = e
            .harmonics
            .iter()
            .map(|h| h.multiple.round() as usize)
            .max()
            .unwrap_or(0);
        let mut c = vec![C { re: 0.0, im: 0.0 }; top];
        let mut pull = C { re: 0.0, im: 0.0 };
        for h in &e.harmonics {
            let k = h.multiple.round() as usize;
            if k == 0 || h.multiple * e.line_hz + pp >= fmax {
                continue;
            }
            let v = C::polar(h.amplitude, h.phase_rad);
            if k == 2 && e.pole_pass_hz.is_some() {
                pull = pull.add(v);
            } else {
                c[k - 1] = c[k - 1].add(v);
            }
        }
        let w = TAU * e.line_hz / fs;
        let wp = TAU * pp / fs;
        for (i, o) in out.iter_mut().enumerate() {
            let z = C::polar(1.0, (w * i as f64).rem_euclid(TAU));
            let mut v = horner(&c, z).re;
            if e.pole_pass_hz.is_some() {
                let m = 1.0 + e.pole_pass_depth * (wp * i as f64 + e.pole_pass_phase).cos();
                v += m * pull.mul(z.mul(z)).re;
            }
            *o = v;
        }
    }

    /// The fault's impact train, unscaled; returns the number of impacts inside the recording.
    fn render_fault(&self, f: &FaultImpacts, theta: &[f64], fr: f64, out: &mut [f64]) -> usize {
        let fs = self.recipe.fs_hz;
        let m = &self.structure.modes[f.mode];
        let (lambda, sigma) = pole(m, fs);
        let n = theta.len();
        let end = n as f64 / fs;
        let mut rng = ChaCha8Rng::seed_from_u64(self.recipe.seed);
        rng.set_stream(Stream::FaultTiming as u64);
        // shaft rate and angle at time t (linear before the start and after the end)
        let rate_at = |t: f64| -> f64 {
            let i = (t * fs).floor();
            if i < 0.0 || i as usize + 1 >= n {
                fr
            } else {
                let i = i as usize;
                (theta[i + 1] - theta[i]) * fs / TAU
            }
        };
        let pre = 10.0 / sigma;
        let mut t = -pre - rng.random::<f64>() / (f.order * fr);
        let mut times = Vec::new();
        let mut inside = 0;
        // each rolling element's gain on a race defect, struck in turn (its own stream, so the
        // impacts' timing and spread draws are those of a train without it)
        let gains: Vec<f64> = {
            let mut g = ChaCha8Rng::seed_from_u64(self.recipe.seed);
            g.set_stream(Stream::FaultElements as u64);
            (0..f.elements)
                .map(|_| {
                    let z: f64 = StandardNormal.sample(&mut g);
                    (f.element_spread * z).exp()
                })
                .collect()
        };
        let mut struck = 0usize;
        while t < end {
            let a: f64 = StandardNormal.sample(&mut rng);
            let element = if gains.is_empty() {
                1.0
            } else {
                gains[struck % gains.len()]
            };
            struck += 1;
            let amp =
                element * f.modulation(angle_at(theta, fs, fr, t)) * (f.amplitude_spread * a).exp();
            times.push((t, amp));
            if t >= 0.0 {
                inside += 1;
            }
            let z: f64 = StandardNormal.sample(&mut rng);
            let interval = (1.0 + f.slip * z).max(0.05) / (f.order * rate_at(t));
            t += interval;
        }
        ring(&mut times, lambda, sigma, fs, out);
        inside
    }
}

/// Shaft angle at time `t`, rad: interpolated in `theta`, extrapolated at the mean rate outside.
fn angle_at(theta: &[f64], fs: f64, fr: f64, t: f64) -> f64 {
    let n = theta.len();
    let x = t * fs;
    if x <= 0.0 {
        return TAU * fr * t;
    }
    let i = x.floor() as usize;
    if i + 1 >= n {
        return theta[n - 1] + TAU * fr * (t - (n - 1) as f64 / fs);
    }
    let u = x - i as f64;
    theta[i] + u * (theta[i + 1] - theta[i])
}

/// Time at which the shaft angle reaches `target`, s (the inverse of [`angle_at`]; θ increases).
fn time_at_angle(theta: &[f64], fs: f64, fr: f64, target: f64) -> f64 {
    let n = theta.len();
    if target <= 0.0 {
        return target / (TAU * fr);
    }
    if target >= theta[n - 1] {
        return (n - 1) as f64 / fs + (target - theta[n - 1]) / (TAU * fr);
    }
    let i = theta.partition_point(|&v| v <= target) - 1;
    let u = (target - theta[i]) / (theta[i + 1] - theta[i]);
    (i as f64 + u) / fs
}

/// Add the ringing of mode `lambda` (decay `sigma`, 1/s) to unit impulses at `(time s,
/// amplitude)`: `a·e^{−σ(t−t₀)} sin(ω_d (t−t₀))` from each `t₀` on, exact at every sample
/// (a complex one-pole recurrence fed with each impact's phasor at its first sample).
fn ring(impacts: &mut [(f64, f64)], lambda: C, sigma: f64, fs: f64, out: &mut [f64]) {
    impacts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let wd = lambda.im.atan2(lambda.re) * fs;
    let s = C { re: -sigma, im: wd };
    let mut state = C { re: 0.0, im: 0.0 };
    let mut next = 0;
    // impacts before the first sample: their state at t = 0
    while next < impacts.len() && impacts[next].0 < 0.0 {
        let (t0, a) = impacts[next];
        state = state.add(s.scale(-t0).exp().scale(a));
        next += 1;
    }
    for (i, o) in out.iter_mut().enumerate() {
        if i > 0 {
            state = state.mul(lambda);
        }
        // impacts in (t_{i−1}, t_i]: enter at sample i with their phase advanced to t_i
        let ti = i as f64 / fs;
        while next < impacts.len() && impacts[next].0 <= ti {
            let (t0, a) = impacts[next];
            state = state.add(s.scale(ti - t0).exp().scale(a));
            next += 1;
        }
        *o += state.im;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recipe(seed: u64) -> MachineRecipe {
        MachineRecipe::healthy(BearingGeometry::skf_6205(), 1500.0, 12_000.0, 2.0, seed).unwrap()
    }

    #[test]
    fn same_seed_same_samples_other_seed_other_samples() {
        let r = recipe(3)
            .with_nuisances(Nuisances::ALL)
            .with_fault(LocalizedFault {
                location: FaultLocation::Ball,
                severity_db: -10.0,
            });
        let a = r.synthesize().unwrap();
        let b = r.synthesize().unwrap();
        assert_eq!(a.accel, b.accel);
        assert_eq!(a.params, b.params);
        let c = r.with_seed(4).synthesize().unwrap();
        assert_ne!(a.accel, c.accel);
    }

    #[test]
    fn switching_a_component_on_leaves_the_others_draws_alone() {
        let a = recipe(9).draw().unwrap();
        let b = recipe(9)
            .with_nuisances(Nuisances::GEAR_MESH)
            .with_fault(LocalizedFault {
                location: FaultLocation::Outer,
                severity_db: 0.0,
            })
            .draw()
            .unwrap();
        assert_eq!(a.structure, b.structure);
        assert_eq!(a.shaft_comb, b.shaft_comb);
        assert_eq!(a.electrical, b.electrical);
        assert_eq!(a.speed, b.speed);
    }

    #[test]
    fn a_fault_adds_to_the_same_healthy_machine() {
        let h = recipe(5).with_nuisances(Nuisances::ALL);
        let f = h.with_fault(LocalizedFault {
            location: FaultLocation::Inner,
            severity_db: -6.0,
        });
        let (a, b) = (h.synthesize().unwrap(), f.synthesize().unwrap());
        let d: Vec<f64> = b.accel.iter().zip(&a.accel).map(|(x, y)| x - y).collect();
        let rd = mean_square(&d).sqrt();
        assert!((rd - b.rms.fault).abs() < 1e-9 * rd, "{rd} {}", b.rms.fault);
        // severity: impacts' RMS over the healthy RMS
        assert!((20.0 * (b.rms.fault / a.rms.healthy).log10() + 6.0).abs() < 1e-9);
        assert!(b.fault_impacts > 0);
    }

    #[test]
    fn rms_and_snr_as_stated() {
        for snr in [0.0, 10.0, 20.0] {
            let rec = recipe(11)
                .with_nuisances(Nuisances::ALL)
                .with_snr_db(snr)
                .with_rms_ms2(3.5)
                .synthesize()
                .unwrap();
            let rms = mean_square(&rec.accel).sqrt();
            assert!((rms - 3.5).abs() < 1e-9, "{rms}");
            let noise = rec.rms.sensor_noise;
            let snr_got = 10.0 * ((rms * rms - noise * noise) / (noise * noise)).log10();
            assert!((snr_got - snr).abs() < 0.3, "{snr_got} vs {snr}");
        }
    }

    #[test]
    fn quantised_noise_only_has_few_levels() {
        let adc = Adc {
            bits: 16,
            full_scale_ms2: 500.0,
        };
        let rec = MachineRecipe::noise_only(
            BearingGeometry::skf_6203(),
            1000.0,
            20_000.0,
            2.0,
            adc,
            2.0,
            1,
        )
        .unwrap()
        .synthesize()
        .unwrap();
        let lsb = adc.lsb_ms2();
        let mut codes: Vec<i64> = rec
            .accel
            .iter()
            .map(|v| {
                let c = v / lsb;
                assert!((c - c.round()).abs() < 1e-9, "not on a code: {c}");
                c.round() as i64
            })
            .collect();
        codes.sort_unstable();
        codes.dedup();
        // ±5σ of 2 LSB RMS: at most 21 codes (a handful more only by chance of the tails)
        assert!(codes.len() <= 25, "{} levels", codes.len());
        assert!(codes.len() >= 5, "{} levels", codes.len());
        let rms = mean_square(&rec.accel).sqrt() / lsb;
        assert!((rms - 2.0).abs() < 0.2, "{rms} LSB");
    }

    #[test]
    fn bad_recipes_are_errors() {
        let g = BearingGeometry::skf_6205();
        assert!(MachineRecipe::healthy(g, f64::NAN, 12_000.0, 1.0, 0).is_err());
        assert!(MachineRecipe::healthy(g, 1500.0, 500.0, 1.0, 0).is_err());
        assert!(MachineRecipe::healthy(g, 1500.0, 12_000.0, 0.0, 0).is_err());
        assert!(MachineRecipe::healthy(g, 1500.0, 12_000.0, 1e-3, 0).is_err());
        let r = recipe(0).with_snr_db(f64::INFINITY);
        assert!(r.synthesize().is_err());
        let r = recipe(0).with_fault(LocalizedFault {
            location: FaultLocation::Inner,
            severity_db: f64::NAN,
        });
        assert!(r.draw().is_err());
        let mut r = recipe(0);
        r.level = Level::NoiseOnly { rms_lsb: 2.0 };
        assert!(matches!(r.validate(), Err(ModelError::InvalidRecipe(_))));
        let mut p = recipe(0).draw().unwrap();
        p.structure.modes[0].freq_hz = 7_000.0;
        assert!(p.synthesize().is_err());
        let mut p = recipe(0).draw().unwrap();
        p.fault = Some(
            recipe(0)
                .with_fault(LocalizedFault {
                    location: FaultLocation::Inner,
                    severity_db: 0.0,
                })
                .draw()
                .unwrap()
                .fault
                .unwrap(),
        );
        assert!(matches!(p.synthesize(), Err(ModelError::InvalidRecipe(_))));
    }

    #[test]
    fn ringing_is_exact_at_every_sample() {
        let fs = 10_000.0;
        let m = Mode {
            freq_hz: 1_000.0,
            damping: 0.02,
            power_share: 1.0,
        };
        let (lambda, sigma) = pole(&m, fs);
        let wd = TAU * 1_000.0 * (1.0f64 - 0.0004).sqrt();
        let mut out = vec![0.0; 200];
        let mut imp = [(0.00123, 2.0), (-0.0005, 1.0)];
        ring(&mut imp, lambda, sigma, fs, &mut out);
        for (i, v) in out.iter().enumerate() {
            let t = i as f64 / fs;
            let want: f64 = imp
                .iter()
                .filter(|(t0, _)| t >= *t0)
                .map(|(t0, a)| a * (-sigma * (t - t0)).exp() * (wd * (t - t0)).sin())
                .sum();
            assert!((v - want).abs() < 1e-9, "sample {i}: {v} vs {want}");
        }
    }

    /// A sweep moves the speed by its span in its shape and keeps the mean speed; without one
    /// the samples are those of the recipe before sweeps existed (the same draw, bit for bit).
    #[test]
    fn a_sweep_spans_its_range_and_keeps_the_mean_speed() {
        for shape in SweepShape::ALL {
            let r = recipe(5).with_sweep(SpeedSweep { shape, span: 0.4 });
            let p = r.draw().unwrap();
            let n = r.samples();
            let th = p.shaft_angle(n);
            let rate: Vec<f64> = th
                .windows(2)
                .map(|w| (w[1] - w[0]) * r.fs_hz / TAU)
                .collect();
            let mean_rate = (th[n - 1] - th[0]) / ((n - 1) as f64 / r.fs_hz) / TAU;
            assert!((mean_rate / r.shaft_hz() - 1.0).abs() < 1e-3, "{shape:?}");
            let (lo, hi) = rate
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
            let spread = (hi - lo) / r.shaft_hz();
            assert!((spread - 0.4).abs() < 0.02, "{shape:?}: {spread}");
            let (first, mid, last) = (rate[0], rate[n / 2], rate[n - 2]);
            let ok = match shape {
                SweepShape::RunUp => first < mid && mid < last,
                SweepShape::CoastDown => first > mid && mid > last,
                SweepShape::UpDown => mid > first && mid > last,
                SweepShape::DownUp => mid < first && mid < last,
            };
            assert!(ok, "{shape:?}: {first} {mid} {last}");
            assert!((r.top_shaft_hz() / r.shaft_hz() - 1.2).abs() < 1e-12);
        }
        // its tachometer: one rising edge a turn, as many as the turns
        let r = recipe(5).with_sweep(SpeedSweep {
            shape: SweepShape::RunUp,
            span: 0.4,
        });
        let tach = r.draw().unwrap().tachometer(1.0).unwrap();
        assert_eq!(tach.len(), r.samples());
        let rises = tach.windows(2).filter(|w| w[1] > w[0]).count() as f64;
        let turns = r.duration_s * r.shaft_hz();
        assert!((rises - turns).abs() <= 1.0, "{rises} rises, {turns} turns");
        assert!(r.draw().unwrap().tachometer(0.5).is_err());
        let bad = recipe(5).with_sweep(SpeedSweep {
            shape: SweepShape::RunUp,
            span: 1.5,
        });
        assert!(bad.validate().is_err());
        assert_eq!(recipe(5).top_shaft_hz(), recipe(5).shaft_hz());
    }

    #[test]
    fn speed_wander_keeps_the_mean_speed() {
        let p = recipe(2).draw().unwrap();
        let n = p.recipe.samples();
        let th = p.shaft_angle(n);
        let mean_rate = (th[n - 1] - th[0]) / ((n - 1) as f64 / p.recipe.fs_hz) / TAU;
        assert!((mean_rate / p.recipe.shaft_hz() - 1.0).abs() < 1e-4);
        assert!(p.speed.rms_fraction >= SPEED_WANDER.0 && p.speed.rms_fraction <= SPEED_WANDER.1);
    }
}
