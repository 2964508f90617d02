//! Dissertation chapters as pipelines (work in progress).

use crate::common::Context;

/// Flags of the chapter tasks.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run the given chapters.
pub fn run(_ctx: &Context, _chapters: &[u8], _args: Args) -> anyhow::Result<()> {
    anyhow::bail!("not implemented yet")
}
