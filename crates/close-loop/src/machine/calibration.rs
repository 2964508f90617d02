//! The calibration entry points: the loop on a healthy recording, verified from the model as saved.

use super::MachineModel;
use crate::CloseLoopError;

/// Most effects `hybrid-fdd calibrate` (and `cargo xtask calibrate`) lets the loop add by
/// default: a healthy machine holds many lines (the shaft comb, mains and interference tones)
/// and channel modes. 97.mat at 12 kHz takes 17 (since channel modes shape the background too)
/// and stops on its own; 16 cut it short.
pub const CALIBRATE_MAX_EFFECTS: usize = 24;

/// Calibrate a machine model on a healthy recording (a checked [`crate::Signal`], shaft at
/// `rpm`, `bearing` of the 5-DOF model): the loop from the declared healthy 5-DOF physics with default
/// slip, verified from the model as saved ([`calibrate_with`]), and the [`MachineModel`] it ends
/// with (what `cargo xtask calibrate` writes). The loop fits on the first part of the recording
/// and scores on the rest ([`crate::fit_len`]); pass only data the caller may fit on.
///
/// # Errors
/// As [`crate::close_loop`].
pub fn calibrate(
    signal: &crate::Signal<'_>,
    rpm: f64,
    bearing: bearing_model::Bearing,
    cfg: &crate::CheckedConfig,
) -> Result<MachineModel, CloseLoopError> {
    let rates = crate::BearingSpec::designated(bearing);
    let op = crate::OperatingPoint::new(rpm, rates, bearing_model::FaultClass::None)?;
    Ok(calibrate_with(&declared_healthy(bearing), signal, &op, cfg)?.machine)
}

/// The declared healthy 5-DOF physics [`calibrate`] starts from (default parameter set, slip
/// and seed): what a healthy synthesis of the model it writes must run the physics with
/// ([`MachineModel::simulate_healthy`]).
pub(crate) fn declared_healthy(bearing: bearing_model::Bearing) -> crate::physics::PhysicsModel {
    crate::physics::PhysicsModel {
        bearing,
        ..crate::physics::PhysicsModel::default()
    }
}

/// The bearing a machine model names (`MachineModel::bearing`: a built-in designation, or the
/// normalised spec of a bearing given by its geometry or its multiples).
///
/// # Errors
/// [`CloseLoopError::UnknownBearing`] when the name is neither.
pub(crate) fn named_bearing(name: &str) -> Result<crate::BearingSpec, CloseLoopError> {
    name.parse::<bearing_model::Bearing>()
        .map(crate::BearingSpec::designated)
        .or_else(|_| crate::BearingSpec::parse(name))
        .map_err(|_| CloseLoopError::UnknownBearing {
            name: name.to_string(),
        })
}

/// Verification passes a calibration runs at most ([`calibrate_with`]).
pub const MAX_VERIFICATION_PASSES: usize = 2;

/// A calibration: the loop on the recording `signal` from the declared `model` ([`crate::close_loop`]; on a
/// recording declared healthy the model is given a structural path if the loop added none,
/// [`MachineModel::ensure_path`]), then a verification pass — the loop again on the same recording, started from the machine model
/// as it is saved (JSON round trip, [`crate::close_loop_from`]). A clean recording must add
/// nothing to its own model: when the pass adds nothing, the saved model's own held-out error on
/// the recording (the pass's start) becomes the calibration's end error (`error_after`,
/// `provenance.error_after`), so a run from the saved model starts where the calibration ended;
/// when it adds effects (the last round of the first loop was judged on the loop's own state,
/// which the saved model rebuilds only up to the lines' re-fit), they join the ledger (marked
/// "verification pass k"), the model is the pass's end state, and it is verified again, at most
/// [`MAX_VERIFICATION_PASSES`] times (the stop reason says when the last pass still added
/// something). Each pass is recorded in `ledger.verification`.
///
/// # Errors
/// As [`crate::close_loop`].
pub fn calibrate_with(
    model: &dyn crate::DeclaredModel,
    signal: &crate::Signal<'_>,
    op: &crate::OperatingPoint,
    cfg: &crate::CheckedConfig,
) -> Result<crate::Outcome, CloseLoopError> {
    let y = signal.samples();
    let mut out = crate::close_loop(model, signal, op, cfg)?;
    if op.fault == bearing_model::FaultClass::None {
        // a healthy machine model always holds a path ([`MachineModel::ensure_path`]); it is
        // verified as it will be saved, path included
        let n_fit = crate::fit_len(y.len(), cfg);
        out.machine
            .ensure_path(&y[..n_fit], &y[n_fit..], cfg.get().max_path_order)?;
    }
    let declared_error = out.ledger.error_before;
    let mut converged = false;
    for pass in 1..=MAX_VERIFICATION_PASSES {
        let saved = MachineModel::from_json(&out.machine.to_json()?)?;
        let v = crate::close_loop_from(model, Some(&saved), signal, op, cfg)?;
        let added = v.ledger.effects.len();
        out.ledger.verification.push(crate::VerificationPass {
            pass,
            error_start: v.ledger.error_before,
            error_end: v.ledger.error_after,
            effects_added: added,
        });
        if added == 0 {
            out.ledger.error_after = v.ledger.error_before;
            out.ledger.secondary_after = v.ledger.secondary_before;
            out.ledger.residual_rms_after = v.ledger.residual_rms_before;
            out.machine.provenance.error_after = v.ledger.error_before;
            converged = true;
            break;
        }
        merge_pass(&mut out, v, pass, declared_error);
    }
    if !converged {
        out.ledger.stop_reason += &format!(
            "; the verification from the saved model still added effects after {MAX_VERIFICATION_PASSES} passes (the model is the last pass's end state)"
        );
    }
    Ok(out)
}

/// Append a verification pass's effects and end state to the calibration's outcome.
fn merge_pass(out: &mut crate::Outcome, v: crate::Outcome, pass: usize, declared_error: f64) {
    let offset = out.ledger.effects.len();
    let l = v.ledger;
    for mut e in l.effects {
        let own = e.replaces_step.map(|k| k + offset);
        if let (Some(k), Some(j)) = (own, e.replaces_step) {
            e.description = e.description.replace(
                &format!("replaces step {j}'s"),
                &format!("replaces step {k}'s"),
            );
        }
        let earlier = if own.is_none() && e.kind.is_setting() {
            out.ledger
                .effects
                .iter()
                .rposition(|p| p.kind == e.kind)
                .map(|i| i + 1)
        } else {
            None
        };
        if let Some(k) = earlier {
            e.description += &format!("; replaces step {k}'s value (a setting, not an added term)");
        }
        e.description += &format!(" (verification pass {pass})");
        e.replaces_step = own.or(earlier);
        out.ledger.effects.push(e);
    }
    out.ledger.error_after = l.error_after;
    out.ledger.secondary_after = l.secondary_after;
    out.ledger.residual_rms_after = l.residual_rms_after;
    out.ledger.rejected = l.rejected;
    out.ledger.stop_reason = l.stop_reason;
    out.ledger.structural_modes = l.structural_modes;
    out.spectra.model_after = v.spectra.model_after;
    out.machine = v.machine;
    out.machine.provenance.error_before = declared_error;
}
