//! `opalray spectrum` (being built).

use anyhow::Result;

/// Arguments of `opalray spectrum`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run `opalray spectrum`.
pub fn run(_args: Args) -> Result<()> {
    anyhow::bail!("`opalray spectrum` is not available in this build yet")
}
