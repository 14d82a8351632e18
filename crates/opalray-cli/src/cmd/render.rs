//! `opalray render`: render the opal to an image.

use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::json;

use opalray::integrator::{PassReport, Passes, RowsReport};
use opalray::scene::{LightKind, MAX_SPP};
use opalray::Scene;

use super::common::{
    duration_words, peak_memory_mb, progress, progress_line, write_json, LookArgs, SceneArgs,
};
use crate::outputs::Outputs;

/// Render the opal (paper figs. 10–11) to a PNG or EXR, and optionally its spectral image.
///
/// Renders the scene (default: the `black-opal` preset, a black opal cabochon under the
/// studio environment, by the lobe integrator at 640 × 480 in seconds; `--method path` renders
/// it by the reference path tracer; `--preset paper` is the paper's opal with
/// the light at 30° to the view direction) and prints the time of each stage.
#[derive(clap::Args, Debug)]
#[command(
    after_long_help = "Examples:\n  opalray render\n  opalray render --preset white --output white.png\n  opalray render --method path --denoise --spp 16 --output reference.png\n  opalray render --preset paper --light-angle -45 --output flash.png\n  opalray render my-opal.toml --width 1280 --height 960 --stats stats.json\n  opalray render --diameter 220 --output linear.exr --spectral cube.exr\n  opalray render --preset harlequin --time-limit 60 --stats stats.json\n\nLimits:\n  Memory: a run estimated over OPALRAY_MAX_MEMORY_MB MiB (unset: 80 % of this machine's\n  memory) is refused before any work, naming the value to lower and the largest that fits.\n  Time: --time-limit SECONDS bounds every stage, the stone's preparation included."
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
    /// Write stage timings and statistics as JSON (the light's angle and rays, null for a
    /// scene without a light; the stored method's: rays per pixel and the stored light's
    /// cells; the path integrator's: samples per pixel rendered, the noise over the stone and
    /// its light by Bragg order).
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Bound the whole command to this many seconds, the stone's preparation included: a
    /// stage not done in time ends the command (exit 2, nothing written). The path integrator
    /// stops after the pass (of doubling samples per pixel) in which the time has passed, even
    /// short of --spp (default then the most, 65536), once its first pass is done; the image is
    /// the one `--spp N` gives for the N reached (see --stats).
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub time_limit: Option<f64>,
}

/// Run `opalray render`.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
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
        set_light_angle(&mut scene, angle)?;
    }
    // The renderer first: what --time-limit may do depends on it.
    args.look.apply_method(&mut scene)?;
    let time_limit = super::deadline::checked(args.time_limit)?;
    if time_limit.is_some()
        && opalray::integrator::of(scene.integrator.method()).renders_in_passes()
        && args.look.spp.is_none()
    {
        scene.integrator.set_spp(MAX_SPP);
    }
    args.look.apply(&mut scene)?;
    if args.scene.shown(&scene)? {
        return Ok(());
    }
    super::memory::check(&scene, super::memory::Extra::default())?;
    if time_limit.is_none() {
        super::work::announce(&scene, 1);
    }
    let job = scene.clone();
    let mut frame = super::deadline::within(time_limit, started, TIME_LIMIT_FIX, move |stage| {
        render_frame(
            &job,
            time_limit.map(|t| t.saturating_sub(started.elapsed())),
            stage,
        )
    })?;
    if let Some(report) = &mut frame.report {
        // The passes had what the preparation left of it; the limit is the user's.
        report.set_time_limit(args.time_limit);
    }
    let is_exr = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    // Each file carries its scene, so that it can be rendered again from itself.
    let provenance = opalray::output::Provenance::of(&scene, &frame);
    outputs.write(image, |path| {
        if is_exr {
            opalray::output::write_exr(path, &frame.rgb, &provenance)
        } else {
            opalray::output::write_png(path, &frame.rgb, &scene.color, &provenance)
        }
    })?;
    if let Some(spectral) = spectral {
        outputs.write(spectral, |path| {
            opalray::output::write_spectral_exr(path, &frame.spectral, &provenance)
        })?;
    }
    note_frame(&scene, &frame);
    if let Some(stats) = stats {
        let value = stats_json(&scene, &frame);
        outputs.write(stats, |path| write_json(path, &value))?;
    }
    outputs.commit()?;
    crate::stdio::out(format_args!("wrote {}", args.output.display()))?;
    for path in [&args.spectral, &args.stats].into_iter().flatten() {
        crate::stdio::out(format_args!("wrote {}", path.display()))?;
    }
    Ok(())
}

/// `--light-angle`: `scene`'s light at `angle` (degrees), checked: within −89° … 89°, and a
/// scene with a light to turn.
fn set_light_angle(scene: &mut Scene, angle: f64) -> Result<()> {
    if !(angle.is_finite() && (-89.0..=89.0).contains(&angle)) {
        anyhow::bail!("--light-angle {angle} (light.angle_deg): must be within −89° … 89°; try 30");
    }
    super::motion::check_light_angle(scene)?;
    scene.light.angle_deg = angle;
    Ok(())
}

/// The notes on stderr after a render of `scene`: the stage times, and its method's own
/// (the path tracer's samples, passes and noise, the stored method's rays and stored light).
fn note_frame(scene: &Scene, frame: &opalray::Frame) {
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
    for note in frame.report.iter().flat_map(|r| r.notes(scene)) {
        crate::stdio::note(format_args!("{note}"));
    }
}

/// The `--stats` JSON of `frame`, rendered from `scene`: the stage times, the image's size,
/// the light's angle and rays (null for a scene lit by its environment alone, which has no
/// light angle and traces no light rays), the energy ledger, each method's own figures and
/// peak memory.
fn stats_json(scene: &Scene, frame: &opalray::Frame) -> serde_json::Value {
    let t = frame.times;
    let lit = scene.light.kind != LightKind::None;
    let mut stats = json!({
        "time_s": {"structure": t.structure, "optics": t.optics, "light_pass": t.light_pass,
                   "view_pass": t.view_pass, "color": t.color, "total": t.total()},
        "image": {"width": scene.render.width, "height": scene.render.height,
                  "bins": scene.spectrum.bins},
        "light_angle_deg": lit.then_some(scene.light.angle_deg),
        "void_ratio": frame.void_ratio(),
        "light_rays": lit.then_some(frame.light_rays()),
        "energy": frame.ledger(),
        "peak_memory_mb": peak_memory_mb(),
    });
    // Each method's own section ("path", "stored"), null but the frame's method's.
    if let serde_json::Value::Object(map) = &mut stats {
        map.extend(frame.method_stats(scene.integrator.method()));
    }
    stats
}

/// What to do when a stage overruns `--time-limit`.
const TIME_LIMIT_FIX: &str =
    "nothing was written; raise --time-limit, or render a lighter scene: fewer grains \
     (a larger domains.grain_size_mm), a smaller image (--width, --height), fewer --rays";

/// Prepare and render `scene`, the path integrator's passes within `budget` (the rest of
/// `--time-limit` when the preparation began), telling `stage` where the work stands.
fn render_frame(
    scene: &Scene,
    budget: Option<Duration>,
    stage: &super::deadline::Stage,
) -> Result<opalray::Frame> {
    let started = Instant::now();
    if opalray::integrator::of(scene.integrator.method()).renders_in_passes() {
        return render_in_passes(scene, budget, started, stage);
    }
    let bar = progress(2, "structure");
    let prepared = opalray::render::prepare(scene)?;
    progress_line(format_args!(
        "structure and optics ready ({}); light and view passes",
        duration_words(prepared.times.total())
    ));
    stage.enter("the light and view passes");
    bar.set_message("light, view");
    bar.inc(1);
    // The lobe integrator reports its rows (the two-pass and stored methods report none).
    let last_line = Mutex::new(0.0);
    let report = |r: &RowsReport| report_rows(r, &bar, &last_line);
    let passes = Passes {
        on_rows: Some(&report),
        ..Passes::default()
    };
    let frame = prepared.render_progressive(scene.light.angle_deg, &passes);
    bar.finish_and_clear();
    Ok(frame)
}

/// Seconds between two lines of the view pass's rows in a log (a terminal's bar moves with
/// every row).
const ROWS_LINE_EVERY_S: f64 = 5.0;

/// Show rows report `r` on `bar`, and as a line where stderr is not a terminal: the first
/// after [`ROWS_LINE_EVERY_S`], then at most one as often (`last_line` holds the time of the
/// last, seconds), and the last row's.
fn report_rows(r: &RowsReport, bar: &ProgressBar, last_line: &Mutex<f64>) {
    let done = r.rows >= r.total_rows;
    // Rows left at the pace so far (after a second: the first rows' pace says little).
    let left = match (done, r.elapsed_s >= 1.0) {
        (true, _) => "done".to_string(),
        (false, true) => {
            let rows_left = f64::from(r.total_rows - r.rows);
            let left = r.elapsed_s * rows_left / f64::from(r.rows);
            format!("about {} left", duration_words(left))
        }
        (false, false) => "time left unknown".to_string(),
    };
    if r.rows == 1 {
        bar.set_length(u64::from(r.total_rows));
        bar.set_style(
            ProgressStyle::with_template(
                "{msg:>12} [{bar:30}] {pos}/{len} rows {elapsed}, {prefix}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_message("view pass");
    }
    bar.set_position(u64::from(r.rows));
    bar.set_prefix(left.clone());
    let mut last = last_line.lock().unwrap_or_else(|e| e.into_inner());
    if done || r.elapsed_s - *last >= ROWS_LINE_EVERY_S {
        *last = r.elapsed_s;
        progress_line(format_args!(
            "view pass: {} of {} rows, {} elapsed, {left}",
            r.rows,
            r.total_rows,
            duration_words(r.elapsed_s)
        ));
    }
}

/// Prepare and render `scene` with the path integrator in passes, a progress bar showing the
/// samples per pixel (or, with a time limit, the seconds) and the noise so far; `budget`
/// counts from `started`. The first pass is bounded by the deadline, the rest by the passes'
/// own fit to the time left.
fn render_in_passes(
    scene: &Scene,
    budget: Option<Duration>,
    started: Instant,
    stage: &super::deadline::Stage,
) -> Result<opalray::Frame> {
    let bar = progress(1, "structure");
    let prepared = opalray::render::prepare(scene)?;
    progress_line(format_args!(
        "stone ready ({}); tracing paths",
        duration_words(prepared.times.total())
    ));
    stage.enter("the first pass of paths (2 samples per pixel)");
    let time_limit = budget.map(|t| t.saturating_sub(started.elapsed()));
    let (len, unit) = match time_limit {
        Some(limit) => (limit.as_secs_f64().ceil() as u64, "s"),
        None => (u64::from(scene.integrator.spp().unwrap_or(1)), "spp"),
    };
    bar.set_length(len.max(1));
    bar.set_position(0);
    bar.set_message(format!("paths ({unit})"));
    let report = |r: &PassReport| {
        if r.passes == 1 {
            stage.release();
        }
        let noise = r
            .noise
            .map_or(String::new(), |n| format!(", noise {:.1} %", 100.0 * n));
        bar.set_message(format!("{} spp{noise}", r.spp));
        progress_line(format_args!(
            "pass {}: {} of {} spp{noise}, {} elapsed, {}",
            r.passes,
            r.spp,
            r.target_spp,
            duration_words(r.elapsed_s),
            time_left(r, time_limit)
        ));
        bar.set_position(match time_limit {
            Some(_) => (r.elapsed_s as u64).min(len),
            None => u64::from(r.spp),
        });
    };
    let frame = prepared.render_progressive(
        scene.light.angle_deg,
        &Passes {
            time_limit,
            on_pass: Some(&report),
            ..Passes::default()
        },
    );
    bar.finish_and_clear();
    Ok(frame)
}

/// The time left after pass report `r`, in words: the passes double the samples, so the rest
/// costs about the time so far times the samples left over the samples done (and no more
/// than a time limit leaves).
fn time_left(r: &PassReport, time_limit: Option<Duration>) -> String {
    if r.spp >= r.target_spp {
        return "done".into();
    }
    let by_samples = r.elapsed_s * f64::from(r.target_spp - r.spp) / f64::from(r.spp.max(1));
    let left = match time_limit {
        Some(limit) => by_samples.min((limit.as_secs_f64() - r.elapsed_s).max(0.0)),
        None => by_samples,
    };
    format!("about {} left", duration_words(left))
}
