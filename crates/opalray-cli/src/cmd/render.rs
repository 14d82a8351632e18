//! `opalray render` (being built).

use anyhow::Result;

/// Arguments of `opalray render`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run `opalray render`.
pub fn run(_args: Args) -> Result<()> {
    anyhow::bail!("`opalray render` is not available in this build yet")
}
