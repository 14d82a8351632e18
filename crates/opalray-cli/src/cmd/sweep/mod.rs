//! `opalray sweep`: the play of colour as a series of frames: the light swept about the stone
//! (the paper's fig. 11), or the stone rocked or turned, or the environment turned.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use serde_json::json;

use super::common::{
    duration_words, peak_memory_mb, progress, progress_line, write_json, LookArgs, SceneArgs,
};
use super::frames::{fnv, FramesDir};
use super::motion::{pose, MotionArgs, Moves};
use crate::outputs::Outputs;
use writers::{Staged, Writers};

mod writers;

/// Render a sweep as a contact sheet and an animation: the light's angle where the scene has
/// a light (the paper's fig. 11), else the stone rocked from −30° to 30°; or what the
/// --tilt-*, --turn-*, --env-* or --light-* flags move.
///
/// The structure and optics are computed once; each frame redoes only the lights, the passes
/// and the colour. Frames default to 320 × 240. A flag that moves nothing in the scene is
/// refused, naming what would move.
#[derive(clap::Args, Debug)]
#[command(
    after_long_help = "Examples:\n  opalray sweep                                  (the black opal rocked, −30° to 30°)\n  opalray sweep --turn-from 0 --turn-to 80 --frames 9 --animation turn.png\n  opalray sweep --preset paper --light-from -60 --light-to 60 --frames 25 --animation play.gif\n  opalray sweep --preset paper --frames 7 --sheet fig11.png --width 480 --height 360\n  opalray sweep --animation play.png          (APNG: full colour)\n\nLimits:\n  Memory: a run estimated over OPALRAY_MAX_MEMORY_MB MiB (unset: 80 % of this machine's\n  memory) is refused before any work, naming the value to lower and the largest that fits.\n  Time: --time-limit SECONDS bounds the whole sweep, the stone's preparation included."
)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub look: LookArgs,
    #[command(flatten)]
    pub motion: MotionArgs,
    /// Number of frames (evenly spaced from the first value to the last), 1 to 1000.
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
    /// Video of the sweep through ffmpeg (which must be installed): .mp4 (H.264) or .webm
    /// (VP9), full colour, frames streamed to it as they complete.
    #[arg(long, value_name = "FILE")]
    pub video: Option<PathBuf>,
    /// Time per animation or video frame, milliseconds.
    #[arg(long, value_name = "MS", default_value_t = 120)]
    pub delay_ms: u32,
    /// Write timings as JSON: the light and view passes summed over the frames, and peak
    /// memory.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Write each frame to this folder as it completes (`frame-0000.png`, …); a run with the
    /// same arguments keeps the frames already there and renders only the rest.
    #[arg(long, value_name = "DIR")]
    pub frames_dir: Option<PathBuf>,
    /// Continue a sweep killed half-way: like a plain re-run with --frames-dir, but refuses
    /// to start when the folder holds no frames of this sweep.
    #[arg(long, requires = "frames_dir")]
    pub resume: bool,
    /// Bound the whole sweep to this many seconds, the stone's preparation and every frame
    /// included: past it the command stops (exit 2) and writes no sheet, animation, video or
    /// stats; frames already finished in --frames-dir stay there for --resume.
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub time_limit: Option<f64>,
}

/// Run `opalray sweep`: check the counts, stage the outputs, plan the sweep, prepare the
/// stone once, render the frames into the sheet and animations, then write and report.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    check_counts(&args)?;
    let time_limit = super::deadline::checked(args.time_limit)?;
    let mut outputs = Outputs::new();
    let staged = Staged::add(&args, &mut outputs)?;
    let Some(plan) = plan(&args, time_limit)? else {
        return Ok(());
    };
    let mut frames_dir = match &args.frames_dir {
        Some(dir) => {
            outputs.check_folder("--frames-dir", dir)?;
            Some(FramesDir::open(
                dir,
                sweep_key(&plan.scene, plan.moves, &plan.angles),
                &plan.angles,
                args.resume,
            )?)
        }
        None => None,
    };

    let start = Instant::now();
    let fix = time_limit_fix(args.frames_dir.is_some());
    let job = plan.scene.clone();
    let prepared = super::deadline::within(time_limit, started, &fix, move |_| {
        Ok(Arc::new(opalray::render::prepare(&job)?))
    })?;
    let limit = Limit {
        time_limit,
        started,
        fix: &fix,
    };
    let bar = progress(plan.angles.len() as u64, "sweep");
    let mut writers = Writers::open(&args, &outputs, &staged, &plan)?;
    let per_frame = render_frames(
        &prepared,
        &plan,
        &limit,
        frames_dir.as_mut(),
        &mut writers,
        (&outputs, &staged),
        (&bar, start),
    )?;
    bar.finish_and_clear();
    let elapsed = start.elapsed().as_secs_f64();
    writers.finish(&outputs, &staged)?;
    if let Some(stats_out) = staged.stats {
        let value = stats_json(&prepared, &plan, &per_frame, elapsed);
        outputs.write(stats_out, |path| write_json(path, &value))?;
    }
    outputs.commit()?;
    report_written(&args, &plan, per_frame.len(), elapsed)
}

/// Refuse a number of frames, columns or a frame delay out of range, before any work.
fn check_counts(args: &Args) -> Result<()> {
    if !(1..=1000).contains(&args.frames) {
        anyhow::bail!("--frames {}: must be 1 to 1000; try 9", args.frames);
    }
    if let Some(columns) = args.columns {
        if !(1..=args.frames).contains(&columns) {
            anyhow::bail!(
                "--columns {columns}: must be 1 to the number of frames ({}); try {}",
                args.frames,
                args.frames.min(9)
            );
        }
    }
    if args.delay_ms > 65_535 {
        anyhow::bail!(
            "--delay-ms {}: must be at most 65535 ms per frame; try 120",
            args.delay_ms
        );
    }
    Ok(())
}

/// The sweep to render: the scene, what moves and each frame's value of it.
struct Plan {
    scene: opalray::Scene,
    moves: Moves,
    /// The first and the last value, degrees.
    ends: [f64; 2],
    /// Every frame's value, degrees, evenly spaced over `ends`.
    angles: Vec<f64>,
    /// Frame width and height, pixels.
    size: (usize, usize),
}

/// The scene (320 × 240 unless sized) and what `args` moves in it, within the memory limit
/// (and announced when long, without a `time_limit`); `None` once `--show-scene` has shown it.
fn plan(args: &Args, time_limit: Option<Duration>) -> Result<Option<Plan>> {
    let mut scene = args.scene.load()?;
    if args.look.width.is_none() && args.look.height.is_none() {
        scene.render.width = 320;
        scene.render.height = 240;
    }
    args.look.apply(&mut scene)?;
    let (moves, [from, to]) = args.motion.choose(&scene)?;
    if args.scene.shown(&scene)? {
        return Ok(None);
    }
    super::memory::check(
        &scene,
        super::memory::Extra {
            frames: args.frames as u64,
            animation: args.animation.is_some(),
            ..Default::default()
        },
    )?;
    if time_limit.is_none() {
        super::work::announce(&scene, args.frames as u64);
    }
    let angles: Vec<f64> = (0..args.frames)
        .map(|k| match args.frames {
            1 => from,
            n => from + (to - from) * k as f64 / (n - 1) as f64,
        })
        .collect();
    let size = (scene.render.width as usize, scene.render.height as usize);
    Ok(Some(Plan {
        scene,
        moves,
        ends: [from, to],
        angles,
        size,
    }))
}

/// Render every frame of `plan` not already in `frames_dir` (saving each there), pushing
/// each into `writers` and telling the progress of each (on `bar`, or a line in a log;
/// `start` began the sweep); the stage times of the frames rendered.
fn render_frames(
    prepared: &Arc<opalray::Prepared>,
    plan: &Plan,
    limit: &Limit,
    mut frames_dir: Option<&mut FramesDir>,
    writers: &mut Writers,
    staged: (&Outputs, &Staged),
    (bar, start): (&indicatif::ProgressBar, Instant),
) -> Result<Vec<opalray::StageTimes>> {
    let (w, h) = plan.size;
    let n = plan.angles.len();
    let mut per_frame = Vec::with_capacity(n);
    // One frame at a time, each on all threads. (Two at once kept the cores a little busier,
    // 3.5 % off a 25-frame sweep on two cores, for a third more memory: `BENCHMARKS.md`.)
    for (k, &angle) in plan.angles.iter().enumerate() {
        let done = match &frames_dir {
            Some(dir) => dir.finished(k, w, h),
            None => None,
        };
        let rgb8 = match done {
            Some(rgb8) => rgb8,
            None => {
                let stage = format!("frame {} of {n}", k + 1);
                let frame = render_frame(prepared, &plan.scene, plan.moves, angle, limit, &stage)?;
                per_frame.push(frame.times);
                let rgb8 = opalray::color::to_display_rgb8(&frame.rgb, &plan.scene.color);
                if let Some(dir) = frames_dir.as_deref_mut() {
                    dir.save(k, w, h, &rgb8)?;
                }
                rgb8
            }
        };
        writers.push(staged, k, angle, &rgb8, plan.size)?;
        bar.inc(1);
        let elapsed = start.elapsed().as_secs_f64();
        let left = elapsed * (n - k - 1) as f64 / (k + 1) as f64;
        progress_line(format_args!(
            "frame {} of {n}: {} {angle:.1}°, {} elapsed, about {} left",
            k + 1,
            plan.moves.name(),
            duration_words(elapsed),
            duration_words(left)
        ));
    }
    Ok(per_frame)
}

/// The `--stats` JSON: the frames, what moved, the stage times (the light and view passes
/// summed over the frames rendered, `per_frame`; `elapsed` the sweep's) and peak memory.
fn stats_json(
    prepared: &opalray::Prepared,
    plan: &Plan,
    per_frame: &[opalray::StageTimes],
    elapsed: f64,
) -> serde_json::Value {
    let light: f64 = per_frame.iter().map(|t| t.light_pass).sum();
    let view: f64 = per_frame.iter().map(|t| t.view_pass).sum();
    json!({
        "frames": plan.angles.len(),
        "frames_rendered": per_frame.len(),
        "moves": plan.moves.name(),
        "angles_deg": plan.angles,
        "time_s": {"structure": prepared.times.structure, "optics": prepared.times.optics,
                   "light_pass": light, "view_pass": view, "total": elapsed},
        "peak_memory_mb": peak_memory_mb(),
    })
}

/// Print what was written: the sheet (with the frames, how many were rendered, the time
/// and what moved), then the animation, video and stats.
fn report_written(args: &Args, plan: &Plan, rendered: usize, elapsed: f64) -> Result<()> {
    let [from, to] = plan.ends;
    crate::stdio::out(format_args!(
        "wrote {} ({} frames, {} rendered, {:.2} s; the {} from {from}° to {to}°)",
        args.sheet.display(),
        plan.angles.len(),
        rendered,
        elapsed,
        plan.moves.name()
    ))?;
    for path in [&args.animation, &args.video, &args.stats]
        .into_iter()
        .flatten()
    {
        crate::stdio::out(format_args!("wrote {}", path.display()))?;
    }
    Ok(())
}

/// `--time-limit` as the frames see it: the limit, when the command began, and what to do
/// when a stage overruns it.
struct Limit<'a> {
    time_limit: Option<Duration>,
    started: Instant,
    fix: &'a str,
}

/// What to do when the sweep overruns `--time-limit`, and what is kept: the frames folder's
/// finished frames (each written whole when it completes), which a resumed sweep reuses.
fn time_limit_fix(frames_dir: bool) -> String {
    let (kept, tip) = if frames_dir {
        (
            "no sheet, animation, video or stats was written (the frames finished in \
             --frames-dir stay: --resume renders only the rest)",
            "",
        )
    } else {
        (
            "nothing was written",
            "; --frames-dir DIR keeps each frame as it completes",
        )
    };
    format!(
        "{kept}; raise --time-limit, or sweep fewer --frames or a smaller image (--width, \
         --height){tip}"
    )
}

/// Render the sweep frame that poses `scene` at `angle` of `moves` from `prepared`, within
/// `limit` (the stage named `stage` in the error).
fn render_frame(
    prepared: &Arc<opalray::Prepared>,
    scene: &opalray::Scene,
    moves: Moves,
    angle: f64,
    limit: &Limit,
    stage: &str,
) -> Result<opalray::Frame> {
    let prepared = Arc::clone(prepared);
    let posed = pose(scene, moves, angle);
    let work = move |_: &super::deadline::Stage| match moves {
        Moves::Light => Ok(prepared.render(angle)),
        _ => Ok(prepared
            .posed(&posed.camera, posed.environment.rotation_deg)?
            .render(posed.light.angle_deg)),
    };
    super::deadline::within_stage(limit.time_limit, limit.started, stage, limit.fix, work)
}

/// The key of the sweep of `scene` moving `moves` over `angles`: a hash of the scene, the angles and the
/// frame size, naming the sweep a frames folder belongs to.
fn sweep_key(scene: &opalray::Scene, moves: Moves, angles: &[f64]) -> String {
    let text = format!(
        "{}\n{}\n{angles:?}\n{}x{}",
        scene.to_toml(),
        moves.name(),
        scene.render.width,
        scene.render.height
    );
    format!("{:016x}", fnv(text.as_bytes()))
}
