//! `opalray scene`: print a complete scene as TOML.

use std::path::PathBuf;

use anyhow::Result;

use super::common::SceneArgs;

/// Print the complete scene (every field, defaults filled in) as TOML; without a file or a
/// preset, the default scene of every command (black-opal).
///
/// Start a scene file with `opalray scene --preset paper > my.toml`, or recover the scene of
/// an image `opalray render` wrote with `opalray scene --from opal.png > again.toml`.
#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Read the scene an image was rendered from (a PNG or EXR written by `opalray render`
    /// or Python's `Image.save`, which record it in their headers): rendering it again gives
    /// the same image.
    #[arg(long, value_name = "IMAGE", conflicts_with_all = ["scene", "preset"])]
    from: Option<PathBuf>,
}

/// Run `opalray scene`.
pub fn run(args: Args) -> Result<()> {
    let scene = match &args.from {
        Some(image) => {
            if !image.is_file() {
                anyhow::bail!(
                    "--from {}: no such image; give a PNG or EXR written by opalray render",
                    image.display()
                );
            }
            let mut scene = opalray::output::read_provenance(image)?.scene(image)?;
            if let Some(seed) = args.scene.seed {
                scene.structure.seed = seed;
            }
            scene
        }
        None => args.scene.load()?,
    };
    crate::stdio::out_raw(&scene.to_toml())?;
    Ok(())
}
