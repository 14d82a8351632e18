//! `opalray structure` (being built).

use anyhow::Result;

/// Arguments of `opalray structure`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run `opalray structure`.
pub fn run(_args: Args) -> Result<()> {
    anyhow::bail!("`opalray structure` is not available in this build yet")
}
