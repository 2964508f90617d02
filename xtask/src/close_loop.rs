//! `cargo xtask` task module (work in progress).

use crate::common::Context;

/// Flags of this task.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run the task.
pub fn run(_ctx: &Context, _args: Args) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
