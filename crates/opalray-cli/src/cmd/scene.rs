//! `opalray scene`: print a complete scene as TOML.

use anyhow::Result;

use super::common::SceneArgs;

/// Print the complete scene (every field, defaults filled in) as TOML.
///
/// Start a scene file with `opalray scene --preset paper > my.toml`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
}

/// Run `opalray scene`.
pub fn run(args: Args) -> Result<()> {
    let scene = args.scene.load()?;
    crate::stdio::out_raw(&scene.to_toml())?;
    Ok(())
}
