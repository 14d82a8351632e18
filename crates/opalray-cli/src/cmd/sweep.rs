//! `opalray sweep` (being built).

use anyhow::Result;

/// Arguments of `opalray sweep`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run `opalray sweep`.
pub fn run(_args: Args) -> Result<()> {
    anyhow::bail!("`opalray sweep` is not available in this build yet")
}
