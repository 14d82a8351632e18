//! `opalray render`: render the opal to an image.

use std::path::PathBuf;

use anyhow::Result;
use serde_json::json;

use super::common::{peak_memory_mb, progress, write_json, LookArgs, SceneArgs};
use crate::outputs::Outputs;

/// Render the opal (paper figs. 10–11) to a PNG or EXR, and optionally its spectral image.
///
/// Renders the scene (default: the paper's opal, 640 × 480, light at 30° to the view
/// direction) and prints the time of each stage, as the paper reports them.
#[derive(clap::Args, Debug)]
#[command(
    after_long_help = "Examples:\n  opalray render\n  opalray render --light-angle -45 --output flash.png\n  opalray render my-opal.toml --width 1280 --height 960 --stats stats.json\n  opalray render --diameter 220 --output linear.exr --spectral cube.exr"
)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Angle between the view direction and the light-to-opal direction, degrees (fig. 10);
    /// positive puts the light on the right.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub light_angle: Option<f64>,
    /// Output image: .png (sRGB, 8 or 16 bits per color.bit_depth) or .exr (linear RGB).
    #[arg(long, short, value_name = "FILE", default_value = "opal.png")]
    pub output: PathBuf,
    /// Also write the spectral image as OpenEXR, one channel per wavelength bin.
    #[arg(long, value_name = "FILE.exr")]
    pub spectral: Option<PathBuf>,
    /// Write stage timings and statistics as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
}

/// Run `opalray render`.
pub fn run(args: Args) -> Result<()> {
    // Every output checked and staged before any work.
    let mut outputs = Outputs::new();
    let image = outputs.add("--output", &args.output, &["png", "exr"])?;
    let spectral = match &args.spectral {
        Some(path) => Some(outputs.add("--spectral", path, &["exr"])?),
        None => None,
    };
    let stats = match &args.stats {
        Some(path) => Some(outputs.add("--stats", path, &["json"])?),
        None => None,
    };
    let mut scene = args.scene.load()?;
    if let Some(angle) = args.light_angle {
        if !(angle.is_finite() && (-89.0..=89.0).contains(&angle)) {
            anyhow::bail!(
                "--light-angle {angle} (light.angle_deg): must be within −89° … 89°; try 30"
            );
        }
        scene.light.angle_deg = angle;
    }
    args.look.apply(&mut scene)?;
    super::memory::check(&scene, super::memory::Extra::default())?;
    let bar = progress(2, "structure");
    let prepared = opalray::render::prepare(&scene)?;
    bar.set_message("light, view");
    bar.inc(1);
    let frame = prepared.render(scene.light.angle_deg);
    bar.finish_and_clear();
    let is_exr = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    outputs.write(image, |path| {
        if is_exr {
            opalray::output::write_exr(path, &frame.rgb)
        } else {
            opalray::output::write_png(path, &frame.rgb, &scene.color)
        }
    })?;
    if let Some(spectral) = spectral {
        outputs.write(spectral, |path| {
            opalray::output::write_spectral_exr(path, &frame.spectral)
        })?;
    }
    let t = frame.times;
    crate::stdio::note(format_args!(
        "structure {:.1} ms | optics {:.1} ms | light pass {:.1} ms | view pass {:.1} ms | colour {:.1} ms | total {:.1} ms",
        t.structure * 1e3,
        t.optics * 1e3,
        t.light_pass * 1e3,
        t.view_pass * 1e3,
        t.color * 1e3,
        t.total() * 1e3
    ));
    if let Some(stats) = stats {
        let value = json!({
            "time_s": {"structure": t.structure, "optics": t.optics, "light_pass": t.light_pass,
                       "view_pass": t.view_pass, "color": t.color, "total": t.total()},
            "image": {"width": scene.render.width, "height": scene.render.height,
                      "bins": scene.spectrum.bins},
            "light_angle_deg": scene.light.angle_deg,
            "void_ratio": frame.void_ratio,
            "light_rays": frame.light_rays,
            "energy": frame.ledger,
            "peak_memory_mb": peak_memory_mb(),
        });
        outputs.write(stats, |path| write_json(path, &value))?;
    }
    outputs.commit()?;
    crate::stdio::out(format_args!("wrote {}", args.output.display()))?;
    for path in [&args.spectral, &args.stats].into_iter().flatten() {
        crate::stdio::out(format_args!("wrote {}", path.display()))?;
    }
    Ok(())
}
