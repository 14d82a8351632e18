//! `opalray sweep`: the paper's fig. 11, the light swept from −60° to 60°.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use serde_json::json;

use super::common::{
    check_distinct, check_output, peak_memory_mb, progress, write_json, LookArgs, SceneArgs,
};

/// Render the light sweep of the paper's fig. 11 as a contact sheet and an animation.
///
/// The structure and optics are computed once; each frame redoes only the light pass, the
/// view pass and the colour. Frames default to 320 × 240.
#[derive(clap::Args, Debug)]
#[command(
    after_long_help = "Examples:\n  opalray sweep\n  opalray sweep --from -60 --to 60 --frames 25 --animation play.gif\n  opalray sweep --frames 7 --sheet fig11.png --width 480 --height 360\n  opalray sweep --animation play.png          (APNG: full colour)"
)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// First light angle, degrees.
    #[arg(long, value_name = "DEG", default_value_t = -60.0, allow_hyphen_values = true)]
    pub from: f64,
    /// Last light angle, degrees.
    #[arg(
        long,
        value_name = "DEG",
        default_value_t = 60.0,
        allow_hyphen_values = true
    )]
    pub to: f64,
    /// Number of frames (angles evenly spaced from --from to --to), 1 to 1000.
    #[arg(long, value_name = "N", default_value_t = 9)]
    pub frames: usize,
    /// Contact sheet of all frames with the angle under each (PNG).
    #[arg(long, value_name = "FILE.png", default_value = "sweep.png")]
    pub sheet: PathBuf,
    /// Frames per row of the contact sheet (default: up to 9 in a row).
    #[arg(long, value_name = "N")]
    pub columns: Option<usize>,
    /// Animation of the sweep: .gif, or .png for an APNG.
    #[arg(long, value_name = "FILE")]
    pub animation: Option<PathBuf>,
    /// Time per animation frame, milliseconds.
    #[arg(long, value_name = "MS", default_value_t = 120)]
    pub delay_ms: u32,
    /// Write timings as JSON: the light and view passes summed over the frames, and peak
    /// memory.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
}

/// Run `opalray sweep`.
pub fn run(args: Args) -> Result<()> {
    check_output("--sheet", &args.sheet, &["png"])?;
    if let Some(path) = &args.animation {
        check_output("--animation", path, &["gif", "png"])?;
    }
    if let Some(path) = &args.stats {
        check_output("--stats", path, &["json"])?;
    }
    if let Some(path) = &args.animation {
        check_distinct(&[("--sheet", &args.sheet), ("--animation", path)])?;
    }
    if !(1..=1000).contains(&args.frames) {
        anyhow::bail!("--frames {}: must be 1 to 1000; try 9", args.frames);
    }
    for (flag, v) in [("--from", args.from), ("--to", args.to)] {
        if !(v.is_finite() && (-89.0..=89.0).contains(&v)) {
            anyhow::bail!("{flag} {v}: the light angle must be within −89° … 89°; try −60 and 60");
        }
    }
    let mut scene = args.scene.load()?;
    if args.look.width.is_none() && args.look.height.is_none() {
        scene.render.width = 320;
        scene.render.height = 240;
    }
    args.look.apply(&mut scene)?;

    let start = Instant::now();
    let prepared = opalray::render::prepare(&scene)?;
    // The stone's cells are laid out once for all frames.
    let cells = opalray::light_pass::StoneCells::new(&prepared.structure);
    let angles: Vec<f64> = (0..args.frames)
        .map(|k| match args.frames {
            1 => args.from,
            n => args.from + (args.to - args.from) * k as f64 / (n - 1) as f64,
        })
        .collect();
    let bar = progress(angles.len() as u64, "sweep");
    let (w, h) = (scene.render.width as usize, scene.render.height as usize);
    let mut frames = Vec::with_capacity(angles.len());
    let mut per_frame = Vec::with_capacity(angles.len());
    // One frame at a time, each on all threads. (Two at once kept the cores a little busier,
    // 3.5 % off a 25-frame sweep on two cores, for a third more memory: `BENCHMARKS.md`.)
    for &angle in &angles {
        let frame = prepared.render_in(&cells, angle);
        per_frame.push(frame.times);
        frames.push(opalray::color::to_display_rgb8(&frame.rgb, &scene.color));
        bar.inc(1);
    }
    bar.finish_and_clear();
    let elapsed = start.elapsed().as_secs_f64();

    let labelled: Vec<(Vec<u8>, String)> = frames
        .iter()
        .zip(&angles)
        .map(|(f, a)| (f.clone(), format!("{a:.0}°")))
        .collect();
    let columns = args.columns.unwrap_or(angles.len().min(9));
    let sheet = opalray::output::contact_sheet(&labelled, w, h, columns);
    opalray::output::write_png_rgb8(
        &args.sheet,
        sheet.width as u32,
        sheet.height as u32,
        &sheet.rgb,
    )?;
    println!(
        "wrote {} ({} frames, {:.2} s)",
        args.sheet.display(),
        frames.len(),
        elapsed
    );
    if let Some(path) = &args.animation {
        let is_png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if is_png {
            opalray::output::write_apng(path, &frames, w as u32, h as u32, args.delay_ms)?;
        } else {
            opalray::output::write_gif(path, &frames, w as u32, h as u32, args.delay_ms)?;
        }
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.stats {
        let light: f64 = per_frame.iter().map(|t| t.light_pass).sum();
        let view: f64 = per_frame.iter().map(|t| t.view_pass).sum();
        write_json(
            path,
            &json!({
                "frames": angles.len(),
                "angles_deg": angles,
                "time_s": {"structure": prepared.times.structure, "optics": prepared.times.optics,
                           "light_pass": light, "view_pass": view, "total": elapsed},
                "peak_memory_mb": peak_memory_mb(),
            }),
        )?;
    }
    Ok(())
}
