//! The state-space model the observers run: the workspace's one state-space type,
//! `laguerre_id::StateSpace` (eqs 2.28–2.32, 4.11–4.15), re-exported with its Laguerre
//! structure; `LinearModel`, its former name here, is a deprecated alias.

pub use laguerre_id::{LAGUERRE_STRUCTURE_TOLERANCE, LaguerreStructure, StateSpace};

/// The linear one-step model the ARX-type observers run: the workspace's one state-space type,
/// [`StateSpace`] (`laguerre_id::StateSpace`; an identified ARX-Laguerre model's
/// `state_space()`, [`StateSpace::from_poles`] or, for the calibrated structural path of a
/// machine model in shift form, [`StateSpace::from_ar`]). Same fields and serialised form as
/// before.
#[deprecated(
    since = "0.1.0",
    note = "the one state-space type is `laguerre_id::StateSpace` (re-exported as \
            `observers::StateSpace`); `LinearModel::from_state_space(&m.state_space())` is \
            `m.state_space().validated()`"
)]
pub type LinearModel = StateSpace;
