//! `opalray structure`: grow the cluster/void structure (paper §2.4) and write the
//! orientation map of one z slice (paper fig. 9), with optional statistics as JSON.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Result};
use opalray::structure::{self, map::MAX_SCALE};

use super::common::{write_json, SceneArgs};
use crate::outputs::Outputs;

const EXAMPLES: &str = "\
Examples:
  opalray structure
      the default scene's grid (black-opal, as `opalray render`: 100 × 75 × 25 cells,
      R = 6, void ratio 0.2), slice z = 0, written to structure.png
  opalray structure --preset paper
      the paper's opal
  opalray structure --seed 7 --slice-z 3 --output slice3.png --stats stats.json
  opalray structure my-opal.toml --scale 2
      a scene file (start one with `opalray scene > my-opal.toml`)";

/// Grow the opal's cluster/void structure and draw one slice coloured by orientation.
///
/// Each cluster cell is coloured by its (111) plane normal n as (|nx|, |ny|, |nz|) → (R, G,
/// B), as in the paper's fig. 9; voids are dark grey, cells outside the stone transparent.
/// The image shows the stone from +z with +y up, each cell a block of --scale pixels.
#[derive(clap::Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Slice to draw, as a cell index along z from 0 (bottom) to nz − 1 [default: nz / 2,
    /// the paper's plane z = 0]
    #[arg(long, value_name = "K")]
    slice_z: Option<usize>,
    /// PNG file to write the orientation map to
    #[arg(long, short, value_name = "FILE.png", default_value = "structure.png")]
    output: PathBuf,
    /// Also write the growth statistics (grid, cell counts, void ratio, steps, mean radius,
    /// time) as JSON to this file
    #[arg(long, value_name = "FILE.json")]
    stats: Option<PathBuf>,
    /// Pixels per cell edge in the image (nearest neighbour), 1 to 64
    #[arg(long, value_name = "PX", default_value_t = 6,
          value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SCALE)))]
    scale: u32,
}

/// Run `opalray structure`.
pub fn run(args: Args) -> Result<()> {
    // Check every input and output before growing.
    let scene = args.scene.load()?;
    if args.scene.shown(&scene)? {
        return Ok(());
    }
    let config = &scene.structure;
    let [nx, ny, nz] = config.grid;
    let slice_z = args.slice_z.unwrap_or(nz / 2);
    if slice_z >= nz {
        bail!(
            "--slice-z {slice_z}: the grid has {nz} cells along z; give a value in 0..={}",
            nz - 1
        );
    }
    // The map's size is known before growing: refuse a --scale it cannot draw.
    let pixels = (nx as u64 * u64::from(args.scale)) * (ny as u64 * u64::from(args.scale));
    if pixels > structure::map::MAX_PIXELS as u64 {
        let largest = ((structure::map::MAX_PIXELS as f64 / (nx * ny) as f64).sqrt()) as u64;
        bail!(
            "--scale {}: the map of {nx} × {ny} cells would be {pixels} pixels, more than the \
             limit of {}; use --scale {} or less",
            args.scale,
            structure::map::MAX_PIXELS,
            largest.max(1)
        );
    }
    super::memory::check_structure(&scene, pixels)?;
    let mut outputs = Outputs::new();
    let image = outputs.add("--output", &args.output, &["png"])?;
    let stats_out = match &args.stats {
        Some(path) => Some(outputs.add("--stats", path, &["json"])?),
        None => None,
    };

    // Grow and draw.
    let start = Instant::now();
    let grown = opalray::grow_structure(config)?;
    let structure_s = start.elapsed().as_secs_f64();
    let map = structure::orientation_map(&grown, slice_z, args.scale)
        .map_err(|e| anyhow::anyhow!("--{}", e.to_string().replace('_', "-")))?;
    outputs.write(image, |path| {
        opalray::output::write_png_rgba8(path, map.width, map.height, &map.rgba)
    })?;

    let s = &grown.stats;
    if let Some(stats_out) = stats_out {
        let mut value = serde_json::to_value(s).expect("stats serialise");
        let object = value.as_object_mut().expect("stats are an object");
        object.insert("grid".into(), serde_json::json!(config.grid));
        object.insert(
            "semi_axes_mm".into(),
            serde_json::json!(config.semi_axes_mm),
        );
        object.insert(
            "target_void_ratio".into(),
            serde_json::json!(config.void_ratio),
        );
        object.insert(
            "target_mean_radius_cells".into(),
            serde_json::json!(config.mean_radius_cells),
        );
        object.insert("seed".into(), serde_json::json!(config.seed));
        object.insert("slice_z".into(), serde_json::json!(slice_z));
        object.insert(
            "time_s".into(),
            serde_json::json!({ "structure": structure_s }),
        );
        outputs.write(stats_out, |path| write_json(path, &value))?;
    }
    outputs.commit()?;
    crate::stdio::out(format_args!(
        "wrote {} ({} × {} px, slice z = {slice_z} of 0..={})",
        args.output.display(),
        map.width,
        map.height,
        nz - 1
    ))?;
    if let Some(path) = &args.stats {
        crate::stdio::out(format_args!("wrote {}", path.display()))?;
    }
    crate::stdio::out(format_args!(
        "structure {nx} × {ny} × {nz}: {} inside cells, {} clusters, {} voids \
         (void ratio {:.4}), {} seeds, mean radius {:.2} cells, {:.1} ms",
        s.inside_cells,
        s.clusters,
        s.voids,
        s.void_ratio,
        s.seeds_placed,
        s.mean_radius_cells,
        structure_s * 1e3
    ))?;
    Ok(())
}
