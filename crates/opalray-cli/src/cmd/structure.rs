//! `opalray structure`: draw one z slice of the stone that is rendered, coloured by
//! orientation (paper fig. 9), with optional statistics as JSON: the cluster/void cells its
//! two passes read (the paper's grown cells, §2.4, or a stone of grains read at the cell
//! centres), the stone's domains (grains or plates, [`super::stone_slice`]) for the other
//! methods.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{bail, Result};
use opalray::stone::Stone;
use opalray::structure::{self, map::MAX_SCALE};
use opalray::Scene;

use super::common::{write_json, SceneArgs};
use crate::outputs::{Output, Outputs};

const EXAMPLES: &str = "\
Examples:
  opalray structure
      the default scene's stone (black-opal, as `opalray render`: its settled plates),
      the slice through its colour bar, written to structure.png
  opalray structure --preset paper
      the paper's opal: its grown cells (100 × 75 × 25, R = 6, void ratio 0.2), z = 0
  opalray structure --seed 7 --slice-z 3 --output slice3.png --stats stats.json
  opalray structure my-opal.toml --scale 2
      a scene file (start one with `opalray scene > my-opal.toml`)";

/// Draw one slice of the stone that is rendered, coloured by orientation.
///
/// The paper's two passes (`--preset paper`) read grown cells: each cluster cell is coloured
/// by its (111) plane normal n as (|nx|, |ny|, |nz|) → (R, G, B), as in the paper's fig. 9,
/// voids dark grey. The other methods (every gem preset) read the stone's domains, grains or
/// settled plates: each coloured the same way by its normal, outlined in black where it meets
/// another, potch dark grey. Outside the stone is transparent. The image shows the stone from
/// +z with +y up over the scene's structure.grid, each cell a block of --scale pixels.
#[derive(clap::Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct Args {
    #[command(flatten)]
    scene: SceneArgs,
    /// Slice to draw, as a cell index along z from 0 (bottom) to nz − 1 [default: nz / 2,
    /// the paper's plane z = 0; for a stone's domains, the level cutting the most of them]
    #[arg(long, value_name = "K")]
    slice_z: Option<usize>,
    /// PNG file to write the orientation map to
    #[arg(long, short, value_name = "FILE.png", default_value = "structure.png")]
    output: PathBuf,
    /// Also write the statistics as JSON to this file (the two passes' cells: grid, cell
    /// counts, void ratio, the growth's steps and mean radius, time; a stone: its domains, those
    /// cut, the share of the slice in domains, time)
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
    let pixels = check_map(&args, config.grid)?;
    if opalray::integrator::of(scene.integrator.method()).renders_stone() {
        // The map's pixels: a domain id, the colour and the encoder's row (16 bytes), and
        // the stone as a render builds it.
        super::memory::check_structure(&scene, 2 * pixels)?;
        super::memory::check(&scene, super::memory::Extra::default())?;
        return run_stone(&args, &scene);
    }
    let slice_z = args.slice_z.unwrap_or(nz / 2);
    super::memory::check_structure(&scene, pixels)?;
    let (outputs, image, stats_out) = declare_outputs(&args)?;

    // Grow the paper's cells (or read a stone of grains at the cell centres: no growth steps
    // to tell of), then draw.
    let start = Instant::now();
    let grown = opalray::render::voxels(&scene)?;
    let grew = opalray::render::voxels_are_grown(&scene);
    let structure_s = start.elapsed().as_secs_f64();
    let map = structure::orientation_map(&grown, slice_z, args.scale)
        .map_err(|e| anyhow::anyhow!("--{}", e.to_string().replace('_', "-")))?;
    outputs.write(image, |path| {
        opalray::output::write_png_rgba8(path, map.width, map.height, &map.rgba)
    })?;

    let s = &grown.stats;
    if let Some(stats_out) = stats_out {
        let value = stats_json(&grown, config, grew, slice_z, structure_s);
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
    report_stats(&args)?;
    let how = if grew {
        format!(
            "{} seeds, mean radius {:.2} cells",
            s.seeds_placed, s.mean_radius_cells
        )
    } else {
        "read from the stone's domains at the cell centres".to_string()
    };
    crate::stdio::out(format_args!(
        "structure {nx} × {ny} × {nz}: {} inside cells, {} clusters, {} voids \
         (void ratio {:.4}), {how}, {:.1} ms",
        s.inside_cells,
        s.clusters,
        s.voids,
        s.void_ratio,
        structure_s * 1e3
    ))?;
    Ok(())
}

/// Check `--slice-z` and `--scale` against a `grid` of cells before growing; returns the
/// map's pixels.
fn check_map(args: &Args, [nx, ny, nz]: [usize; 3]) -> Result<u64> {
    if let Some(slice_z) = args.slice_z.filter(|&k| k >= nz) {
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
    Ok(pixels)
}

/// The statistics of the cells `grown` of `config` (`--stats`): their counts, the growth's own
/// and the configuration's targets where they were `grew` (else `read_at_cell_centres`), the
/// slice drawn and the time taken.
fn stats_json(
    grown: &opalray::structure::Structure,
    config: &opalray::scene::StructureConfig,
    grew: bool,
    slice_z: usize,
    structure_s: f64,
) -> serde_json::Value {
    let mut value = serde_json::to_value(&grown.stats).expect("stats serialise");
    let object = value.as_object_mut().expect("stats are an object");
    object.insert("grid".into(), serde_json::json!(config.grid));
    // The grid's box: a cut stone's own (`opalray::render::voxels`).
    object.insert("semi_axes_mm".into(), serde_json::json!(grown.semi_axes_mm));
    if grew {
        object.insert(
            "target_void_ratio".into(),
            serde_json::json!(config.void_ratio),
        );
        object.insert(
            "target_mean_radius_cells".into(),
            serde_json::json!(config.mean_radius_cells),
        );
    } else {
        object.remove("seeds_placed");
        object.remove("mean_radius_cells");
        object.insert("read_at_cell_centres".into(), serde_json::json!(true));
    }
    object.insert("seed".into(), serde_json::json!(config.seed));
    object.insert("slice_z".into(), serde_json::json!(slice_z));
    object.insert(
        "time_s".into(),
        serde_json::json!({ "structure": structure_s }),
    );
    value
}

/// The map (`--output`) and the statistics (`--stats`), checked before any work.
fn declare_outputs(args: &Args) -> Result<(Outputs, Output, Option<Output>)> {
    let mut outputs = Outputs::new();
    let image = outputs.add("--output", &args.output, &["png"])?;
    let stats = match &args.stats {
        Some(path) => Some(outputs.add("--stats", path, &["json"])?),
        None => None,
    };
    Ok((outputs, image, stats))
}

/// Say that the statistics were written, if asked for.
fn report_stats(args: &Args) -> Result<()> {
    if let Some(path) = &args.stats {
        crate::stdio::out(format_args!("wrote {}", path.display()))?;
    }
    Ok(())
}

/// Draw the slice of the stone the renderers read (`scene`'s method is not the two passes).
fn run_stone(args: &Args, scene: &Scene) -> Result<()> {
    let [nx, ny, nz] = scene.structure.grid;
    let (outputs, image, stats_out) = declare_outputs(args)?;

    // Build the stone, find the level, draw.
    let start = Instant::now();
    let stone = Stone::new(scene)?;
    let slice_z = args
        .slice_z
        .unwrap_or_else(|| super::stone_slice::busiest_level(&stone, nz));
    let z_mm = super::stone_slice::level_mm(&stone, slice_z, nz);
    let scale = args.scale as usize;
    let slice = super::stone_slice::draw(&stone, z_mm, nx * scale, ny * scale);
    let time_s = start.elapsed().as_secs_f64();
    outputs.write(image, |path| {
        opalray::output::write_png_rgba8(path, slice.width as u32, slice.height as u32, &slice.rgba)
    })?;
    if let Some(stats_out) = stats_out {
        let value = serde_json::json!({
            "method": scene.integrator.method().name(),
            "domains": stone.domains.len(),
            "domains_cut": slice.domains_cut,
            "domain_share": slice.domain_share,
            "grid": scene.structure.grid,
            "slice_z": slice_z,
            "slice_z_mm": z_mm,
            "time_s": { "structure": time_s },
        });
        outputs.write(stats_out, |path| write_json(path, &value))?;
    }
    outputs.commit()?;
    crate::stdio::out(format_args!(
        "wrote {} ({} × {} px, slice z = {slice_z} of 0..={}, {z_mm:.2} mm)",
        args.output.display(),
        slice.width,
        slice.height,
        nz - 1
    ))?;
    report_stats(args)?;
    crate::stdio::out(format_args!(
        "stone of the {} method: {} domains, {} cut by the slice, {:.0} % of it in domains \
         (the rest potch), {:.1} ms",
        scene.integrator.method().name(),
        stone.domains.len(),
        slice.domains_cut,
        100.0 * slice.domain_share,
        time_s * 1e3
    ))?;
    Ok(())
}
