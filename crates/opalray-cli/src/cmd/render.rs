//! `opalray render`: render the opal to an image.

use std::path::PathBuf;

use anyhow::{Context, Result};
use serde_json::json;

use super::common::{check_extension, write_json, SceneArgs};

/// Render the opal (paper figs. 10–11) to a PNG, EXR or spectral EXR.
///
/// Renders the scene (default: the paper's, 640 × 480, light at 30° to the view direction)
/// and prints the time of each stage. Examples:
///
///   opalray render
///   opalray render --light-angle -45 --output flash.png
///   opalray render my-opal.toml --width 1280 --height 960 --stats stats.json
///   opalray render --diameter 220 --output blue-green.exr --spectral cube.exr
#[derive(clap::Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Angle between the view direction and the light-to-opal direction, degrees (fig. 10).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub light_angle: Option<f64>,
    /// Image width, pixels.
    #[arg(long, value_name = "PX")]
    pub width: Option<u32>,
    /// Image height, pixels.
    #[arg(long, value_name = "PX")]
    pub height: Option<u32>,
    /// Silica sphere diameter, nm (sets the colour: ~250 nm flashes orange face-on).
    #[arg(long, value_name = "NM", allow_hyphen_values = true)]
    pub diameter: Option<f64>,
    /// Wavelength bins over 380–780 nm.
    #[arg(long, value_name = "N")]
    pub bins: Option<usize>,
    /// Rays traced in the light pass.
    #[arg(long, value_name = "N")]
    pub rays: Option<u64>,
    /// Output image: .png (sRGB, 8/16-bit per color.bit_depth) or .exr (linear RGB).
    #[arg(long, short, value_name = "FILE", default_value = "opal.png")]
    pub output: PathBuf,
    /// Also write the spectral image as an OpenEXR with one channel per bin.
    #[arg(long, value_name = "FILE.exr")]
    pub spectral: Option<PathBuf>,
    /// Write timings and statistics as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
}

impl Args {
    /// The scene with this command's flags applied, validated.
    pub fn scene(&self) -> Result<opalray::Scene> {
        let mut scene = self.scene.load()?;
        if let Some(v) = self.light_angle {
            scene.light.angle_deg = v;
        }
        if let Some(v) = self.width {
            scene.render.width = v;
        }
        if let Some(v) = self.height {
            scene.render.height = v;
        }
        if let Some(v) = self.diameter {
            scene.crystal.sphere_diameter_nm = v;
        }
        if let Some(v) = self.bins {
            scene.spectrum.bins = v;
        }
        if let Some(v) = self.rays {
            scene.light.rays = v;
        }
        scene
            .validate()
            .context("after applying the command-line flags")?;
        Ok(scene)
    }
}

/// Run `opalray render`.
pub fn run(args: Args) -> Result<()> {
    check_extension("--output", &args.output, &["png", "exr"])?;
    if let Some(path) = &args.spectral {
        check_extension("--spectral", path, &["exr"])?;
    }
    let scene = args.scene()?;
    let frame = opalray::render::render(&scene)?;
    opalray::color::write_png(&args.output, &frame.rgb, &scene.color)?;
    let t = frame.times;
    eprintln!(
        "structure {:.1} ms | optics {:.1} ms | light pass {:.1} ms | view pass {:.1} ms | colour {:.1} ms | total {:.1} ms",
        t.structure * 1e3,
        t.optics * 1e3,
        t.light_pass * 1e3,
        t.view_pass * 1e3,
        t.color * 1e3,
        t.total() * 1e3
    );
    println!("wrote {}", args.output.display());
    if let Some(path) = &args.stats {
        write_json(
            path,
            &json!({
                "time_s": {"structure": t.structure, "optics": t.optics, "light_pass": t.light_pass,
                           "view_pass": t.view_pass, "color": t.color, "total": t.total()},
                "light_rays": frame.light.rays,
                "ledger": frame.light.ledger,
            }),
        )?;
    }
    Ok(())
}
