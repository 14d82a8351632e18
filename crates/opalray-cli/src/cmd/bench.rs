//! `opalray bench` (being built).

use anyhow::Result;

/// Arguments of `opalray bench`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run `opalray bench`.
pub fn run(_args: Args) -> Result<()> {
    anyhow::bail!("`opalray bench` is not available in this build yet")
}
