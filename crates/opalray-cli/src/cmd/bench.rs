//! `opalray bench`: time every stage of a render and report the medians.

use anyhow::Result;
use serde_json::json;

use super::common::{peak_memory_mb, LookArgs, SceneArgs};

/// Render the scene several times and print the median time of each stage and the peak
/// memory. The first run warms caches and is not counted.
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
    opalray::render::render(&scene)?;
    let mut times = Vec::with_capacity(args.runs);
    for _ in 0..args.runs {
        times.push(opalray::render::render(&scene)?.times);
    }
    let medians: Vec<(&str, f64)> = (0..6)
        .map(|k| {
            let name = times[0].named()[k].0;
            (name, median(times.iter().map(|t| t.named()[k].1).collect()))
        })
        .collect();
    let threads = rayon::current_num_threads();
    let memory = peak_memory_mb();
    if args.json {
        let mut map = serde_json::Map::new();
        for (name, v) in &medians {
            map.insert((*name).to_string(), json!(v));
        }
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "median_s": map, "runs": args.runs, "threads": threads,
                "image": {"width": scene.render.width, "height": scene.render.height, "bins": scene.spectrum.bins},
                "light_rays": scene.light.rays, "peak_memory_mb": memory,
            }))?
        );
    } else {
        println!(
            "opalray bench: {} × {}, {} bins, {} light rays, {} runs, {} threads",
            scene.render.width,
            scene.render.height,
            scene.spectrum.bins,
            scene.light.rays,
            args.runs,
            threads
        );
        for (name, v) in &medians {
            println!("  {name:<11} {:>9.1} ms", v * 1e3);
        }
        if let Some(mb) = memory {
            println!("  peak memory {mb:>7.0} MiB");
        }
    }
    Ok(())
}
