//! A recording of the machine model: what the model says a recording of this machine is.

use super::MachineModel;
use crate::CloseLoopError;

/// Samples the structural path's filter runs before a synthesized recording starts (its
/// transient dies out).
const SYNTH_WARMUP: usize = 4096;

impl MachineModel {
    /// A recording of this machine model, `n` samples at its rate, shaft at `rpm` declared (the
    /// calibrated speed ratio applied), every random draw from `seed`: the structural path
    /// driven by white excitation at its calibrated level, the white floor, the lines at their
    /// calibrated amplitudes with seeded random phases, and the declared physics `model`
    /// (with the calibration's slip, housing mode and shaft forces and channel modes, scaled by
    /// the physics gain), the modulations acting on physics and background together — what the
    /// model says a recording of this machine is. A clean recording: the loop started from this model adds nothing to it (test
    /// `idempotence::simulated_recording_of_the_machine_model_48k`).
    ///
    /// # Errors
    /// The physics simulation's errors; [`CloseLoopError::Model`] when the physics is seen
    /// through a separately identified path (`physics_path`: its shaping is spectral, not a
    /// filter) or `rpm` is not finite and positive.
    pub fn simulate(
        &self,
        model: &dyn crate::DeclaredModel,
        rpm: f64,
        n: usize,
        seed: u64,
    ) -> Result<Vec<f64>, CloseLoopError> {
        use std::f64::consts::PI;
        if !(rpm.is_finite() && rpm > 0.0) {
            return Err(CloseLoopError::InvalidRpm { rpm });
        }
        let fs = self.fs_hz;
        let mut y = vec![0.0; n];
        if self.physics_gain > 0.0 {
            if self.physics_path.is_some() {
                return Err(CloseLoopError::Model {
                    reason: "a machine model whose physics is seen through its own path cannot \
                             be synthesised in the time domain"
                        .into(),
                });
            }
            let mut m: Option<Box<dyn crate::DeclaredModel>> = None;
            if let Some(frac) = self.slip_fraction {
                m = m.as_deref().unwrap_or(model).with_slip_fraction(frac).or(m);
            }
            if let Some(p) = self.contact_preload_m {
                m = m.as_deref().unwrap_or(model).with_contact_preload(p).or(m);
            }
            if let Some([f, z]) = self.housing_mode {
                m = m.as_deref().unwrap_or(model).with_housing_mode(f, z).or(m);
            }
            for &[order, amp, phase] in &self.shaft_forces {
                if order >= 1.0 && order.fract() == 0.0 {
                    m = m
                        .as_deref()
                        .unwrap_or(model)
                        .with_shaft_force(order as u32, amp, phase)
                        .or(m);
                }
            }
            let rates = super::calibration::named_bearing(&self.bearing)?;
            let fault = crate::parse_fault(&self.declared_fault)?;
            let op = crate::OperatingPoint::new(rpm, rates, fault)?
                .with_speed_ratio(self.speed_ratio * self.defect_rate_ratio);
            let mut x = m.as_deref().unwrap_or(model).simulate(&op, n, fs)?;
            for mode in &self.channel_modes {
                x = mode.apply(&x, fs);
            }
            let g = self.physics_gain.sqrt();
            for (a, b) in y.iter_mut().zip(&x) {
                *a += g * b;
            }
        }
        let mut g = crate::scenario::Gaussian::new(seed);
        if let Some(p) = &self.path {
            let sd = (p.excitation_variance * self.path_level).max(0.0).sqrt();
            let e: Vec<f64> = (0..n + SYNTH_WARMUP).map(|_| sd * g.sample()).collect();
            let mut f = p.filter(&e);
            // through the channel modes, as the physics
            for mode in &self.channel_modes {
                f = mode.apply(&f, fs);
            }
            for (a, b) in y.iter_mut().zip(&f[SYNTH_WARMUP..]) {
                *a += b;
            }
        }
        // the modulations act on the structural vibration (physics and background), not on the
        // white floor nor on the lines
        for md in &self.modulations {
            y = md.apply(&y, 0, fs);
        }
        let floor_sd = (self.noise_floor_psd * fs / 2.0).max(0.0).sqrt();
        y.iter_mut().for_each(|v| *v += floor_sd * g.sample());
        let fr = rpm / 60.0 * self.speed_ratio;
        for (l, f) in self.lines.iter().zip(self.line_frequencies(fr)) {
            let ph = 2.0 * PI * g.uniform();
            if f > 0.0 && f < 0.5 * fs {
                let w = 2.0 * PI * f / fs;
                let a = l.amplitude();
                for (k, v) in y.iter_mut().enumerate() {
                    *v += a * (w * k as f64 + ph).cos();
                }
            }
        }
        Ok(y)
    }

    /// A healthy recording of this machine ([`MachineModel::simulate`]) with the declared model
    /// rebuilt from the file: the healthy 5-DOF physics [`super::calibrate`] declares (the
    /// default parameter set on the model's bearing) when the physics enters the model, any
    /// model when it does not (gain 0: the physics is not simulated). What a diagnosis against
    /// this machine reads the healthy machine's envelope lines from.
    ///
    /// # Errors
    /// [`CloseLoopError::Model`] when the model cannot stand for the healthy machine: it was
    /// calibrated on a recording declared faulty (its synthesis would hold the fault), or its
    /// physics came from a declared model other than the 5-DOF physics (`arx-laguerre`,
    /// `phenomenological`: their parameters are not in the file);
    /// [`CloseLoopError::UnknownBearing`] for a bearing the physics does not simulate; as
    /// [`MachineModel::simulate`] otherwise (`physics_path` set, a bad `rpm`).
    pub fn simulate_healthy(
        &self,
        rpm: f64,
        n: usize,
        seed: u64,
    ) -> Result<Vec<f64>, CloseLoopError> {
        use crate::DeclaredModel as _;
        let fault = crate::parse_fault(&self.declared_fault)?;
        if fault != bearing_model::FaultClass::None {
            return Err(CloseLoopError::Model {
                reason: format!(
                    "the machine model was calibrated on a recording declared `{}`: its synthesis would hold that fault",
                    self.declared_fault
                ),
            });
        }
        let physics = if self.physics_gain > 0.0 {
            let m = crate::physics::PhysicsModel::for_bearing(
                &super::calibration::named_bearing(&self.bearing)?,
            )
            .ok_or_else(|| CloseLoopError::Model {
                reason: format!(
                    "the machine model's bearing `{}` gives no geometry to simulate its physics with",
                    self.bearing
                ),
            })?;
            if self.model != m.name() {
                return Err(CloseLoopError::Model {
                    reason: format!(
                        "the machine model's physics came from the declared model `{}`, whose parameters the file does not hold",
                        self.model
                    ),
                });
            }
            m
        } else {
            crate::physics::PhysicsModel::default()
        };
        self.simulate(&physics, rpm, n, seed)
    }
}
