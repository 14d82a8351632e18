//! `opalray bench`: time every stage of a render and report the medians and the fastest runs.

use anyhow::Result;
use serde_json::json;

use super::common::{cpu_ticks, peak_memory_mb, stolen_share, LookArgs, SceneArgs};

/// Render the scene (default: the same as `opalray render`'s) several times and print the median and the fastest time of each stage,
/// and the peak memory. The first run warms caches and is not counted. On a shared or
/// virtual machine the fastest run is the steadier figure: other work only ever slows a run.
/// Where the system reports it (Linux), the share of processor time the hypervisor took for
/// other work during the timed runs is printed too: at 30 % the stages take about 1.4 times
/// as long as on an idle host. (Other guests also slow a run through the caches and memory
/// they share with it, which no counter here shows.)
#[derive(clap::Args, Debug)]
#[command(
    after_long_help = "Examples:\n  opalray bench\n  opalray bench --runs 11 --json\n  RAYON_NUM_THREADS=1 opalray bench        (one core)"
)]
pub struct Args {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Timed runs (after one warm-up run), 1 to 1000.
    #[arg(long, value_name = "N", default_value_t = 7)]
    pub runs: usize,
    /// Print the result as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Run `opalray bench`.
pub fn run(args: Args) -> Result<()> {
    if !(1..=1000).contains(&args.runs) {
        anyhow::bail!("--runs {}: must be 1 to 1000; try 7", args.runs);
    }
    let mut scene = args.scene.load()?;
    args.look.apply(&mut scene)?;
    if args.scene.shown(&scene)? {
        return Ok(());
    }
    super::memory::check(&scene, super::memory::Extra::default())?;
    opalray::render::render(&scene)?;
    let mut times = Vec::with_capacity(args.runs);
    let ticks = cpu_ticks();
    for _ in 0..args.runs {
        times.push(opalray::render::render(&scene)?.times);
    }
    let stolen = stolen_share(ticks, cpu_ticks());
    let stats: Vec<(&str, f64, f64)> = (0..6)
        .map(|k| {
            let name = times[0].named()[k].0;
            let all: Vec<f64> = times.iter().map(|t| t.named()[k].1).collect();
            let fastest = all.iter().copied().fold(f64::INFINITY, f64::min);
            (name, median(all), fastest)
        })
        .collect();
    // A scene lit by its environment alone has no light rays to count.
    let light_rays =
        (scene.light.kind != opalray::scene::LightKind::None).then_some(scene.light.rays);
    let threads = rayon::current_num_threads();
    let simd = opalray::simd::level().name();
    let memory = peak_memory_mb();
    if args.json {
        let (mut map, mut min) = (serde_json::Map::new(), serde_json::Map::new());
        for (name, median, fastest) in &stats {
            map.insert((*name).to_string(), json!(median));
            min.insert((*name).to_string(), json!(fastest));
        }
        crate::stdio::out(format_args!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "median_s": map, "min_s": min, "runs": args.runs, "threads": threads, "simd": simd,
                "image": {"width": scene.render.width, "height": scene.render.height, "bins": scene.spectrum.bins},
                "light_rays": light_rays, "peak_memory_mb": memory,
                "cpu_stolen_fraction": stolen,
            }))?
        ))?;
    } else {
        let light = light_rays.map_or("no light".to_string(), |n| format!("{n} light rays"));
        crate::stdio::out(format_args!(
            "opalray bench: {} × {}, {} bins, {light}, {} runs, {} threads, {simd}",
            scene.render.width, scene.render.height, scene.spectrum.bins, args.runs, threads
        ))?;
        crate::stdio::out(format_args!(
            "  {:<11} {:>9} {:>12}",
            "stage", "median", "fastest"
        ))?;
        for (name, median, fastest) in &stats {
            crate::stdio::out(format_args!(
                "  {name:<11} {:>6.1} ms {:>9.1} ms",
                median * 1e3,
                fastest * 1e3
            ))?;
        }
        if let Some(mb) = memory {
            crate::stdio::out(format_args!("  peak memory {mb:>7.0} MiB"))?;
        }
        if let Some(share) = stolen {
            crate::stdio::out(format_args!(
                "  cpu stolen  {:>7.0} %   (by the hypervisor for other work, while timing)",
                share * 100.0
            ))?;
        }
    }
    Ok(())
}
