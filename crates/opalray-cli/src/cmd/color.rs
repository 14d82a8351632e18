//! `opalray color` (being built).

use anyhow::Result;

/// Arguments of `opalray color`.
#[derive(clap::Args, Debug)]
pub struct Args {}

/// Run `opalray color`.
pub fn run(_args: Args) -> Result<()> {
    anyhow::bail!("`opalray color` is not available in this build yet")
}
