//! The peak memory of a whole command, estimated before anything is allocated, and the
//! refusal of a command that would not fit, naming the flag or field to lower and the
//! largest value of it that fits.
//!
//! The model was fitted to the peak resident memory that `--stats` reports (Linux `VmHWM`)
//! over grids of 0.19–3 M cells, images of 48 px – 4 M px, 40–128 bins and 64 – 1 M rays,
//! and rounded up: every measured run came in under it.

use anyhow::{bail, Result};
use opalray::Scene;

/// Memory the program takes besides the terms below, bytes (binary, allocator, CIE tables,
/// per-thread buffers, a GIF encoder's networks).
const BASE_BYTES: f64 = 96e6;
/// Per grid cell: the structure, the cell layout and the stored light of every bin.
const CELL_BYTES: f64 = 32.0;
const CELL_BIN_BYTES: f64 = 12.0;
/// Per pixel: the spectral image (4 bytes a bin) and the RGB and display buffers.
const PIXEL_BYTES: f64 = 32.0;
const PIXEL_BIN_BYTES: f64 = 4.0;
/// Per light ray: its lattice cell and its share of the deposits.
const RAY_BYTES: f64 = 64.0;
/// Per optics table entry (bin × angle): R, T and diffuse, both polarisations.
const TABLE_BYTES: f64 = 64.0;

/// What a command keeps besides one render.
#[derive(Clone, Copy, Debug, Default)]
pub struct Extra {
    /// Frames of a sweep: the contact sheet holds 3 bytes a pixel of each.
    pub frames: u64,
    /// An animation, written frame by frame: one frame's quantisation buffers (8 bytes a
    /// pixel).
    pub animation: bool,
    /// The environment map (`environment.kind = "file"`), bytes: filled by [`check`] from
    /// the map's header.
    pub map_bytes: f64,
}

/// Estimated peak bytes of one render of `scene` plus `extra`.
pub fn peak_bytes(scene: &Scene, extra: Extra) -> f64 {
    let cells = scene.structure.cell_count() as f64;
    let bins = scene.spectrum.bins as f64;
    let pixels = f64::from(scene.render.width) * f64::from(scene.render.height);
    let mut bytes = BASE_BYTES
        + cells * (CELL_BYTES + CELL_BIN_BYTES * bins)
        + pixels * (PIXEL_BYTES + PIXEL_BIN_BYTES * bins)
        + scene.light.rays as f64 * RAY_BYTES
        + bins * scene.crystal.angles as f64 * TABLE_BYTES;
    // The integrator's own data (the stored method's light grid).
    bytes += opalray::integrator::of(scene.integrator.method()).memory_bytes(scene);
    let frames = extra.frames as f64;
    bytes += frames * pixels * 3.0;
    if extra.animation {
        bytes += pixels * 8.0;
    }
    bytes + extra.map_bytes
}

/// The bytes of `scene`'s environment map while it is read and sampled, from the size in
/// its header (nothing of the picture read); 0 without a map. An unreadable header is an
/// error naming `environment.path`.
pub fn map_bytes(scene: &Scene) -> Result<f64> {
    use opalray::lights::env_map::{map_size, MAP_PIXEL_BYTES};
    if scene.environment.kind != opalray::scene::EnvironmentKind::File {
        return Ok(0.0);
    }
    let path = &scene.environment.path;
    let (width, height) = map_size(std::path::Path::new(path)).map_err(|message| {
        opalray::Error::field("environment.path", format!("{path}: {message}"))
    })?;
    Ok(width as f64 * height as f64 * MAP_PIXEL_BYTES as f64)
}

/// The most memory a command may plan for, bytes: `OPALRAY_MAX_MEMORY_MB` if set, else
/// 80 % of the machine's memory (on Linux, macOS and Windows alike), else 8 GiB.
pub fn limit_bytes() -> Result<f64> {
    if let Some(value) = std::env::var_os(LIMIT_ENV) {
        let text = value.to_string_lossy();
        return match text.trim().parse::<u64>() {
            Ok(mb) if (64..=1 << 24).contains(&mb) => Ok(mb as f64 * MIB),
            _ => bail!(
                "{LIMIT_ENV}={text}: must be a whole number of MiB from 64 to 16777216; \
                 unset it for 80 % of this machine's memory"
            ),
        };
    }
    Ok(match machine_memory_bytes() {
        0 => FALLBACK_BYTES,
        total => 0.8 * total as f64,
    })
}

/// The machine's memory, bytes (Linux's `MemTotal`, macOS's `hw.memsize`, Windows'
/// `ullTotalPhys`, through `sysinfo`); 0 where the system does not say.
fn machine_memory_bytes() -> u64 {
    use sysinfo::{MemoryRefreshKind, RefreshKind, System};
    let memory = RefreshKind::nothing().with_memory(MemoryRefreshKind::nothing().with_ram());
    System::new_with_specifics(memory).total_memory()
}

/// The limit where the machine's memory cannot be read: 8 GiB.
const FALLBACK_BYTES: f64 = 8.0 * 1024.0 * MIB;

/// The environment variable that sets the memory limit, MiB.
pub const LIMIT_ENV: &str = "OPALRAY_MAX_MEMORY_MB";

const MIB: f64 = 1024.0 * 1024.0;

/// One value the estimate depends on: how to name it, read it and set it.
struct Knob {
    name: &'static str,
    get: fn(&Scene, Extra) -> u64,
    set: fn(&mut Scene, &mut Extra, u64),
}

const KNOBS: [Knob; 6] = [
    Knob {
        name: "--width (render.width)",
        get: |s, _| s.render.width.into(),
        set: |s, _, v| s.render.width = v as u32,
    },
    Knob {
        name: "--height (render.height)",
        get: |s, _| s.render.height.into(),
        set: |s, _, v| s.render.height = v as u32,
    },
    Knob {
        name: "--bins (spectrum.bins)",
        get: |s, _| s.spectrum.bins as u64,
        set: |s, _, v| s.spectrum.bins = v as usize,
    },
    Knob {
        name: "--rays (light.rays)",
        get: |s, _| s.light.rays,
        set: |s, _, v| s.light.rays = v,
    },
    Knob {
        name: "structure.grid's z size",
        get: |s, _| s.structure.grid[2] as u64,
        set: |s, _, v| s.structure.grid[2] = v as usize,
    },
    Knob {
        name: "--frames",
        get: |_, e| e.frames,
        set: |_, e, v| e.frames = v,
    },
];

/// Refuse `scene` (with `extra`) if its estimated peak memory is over the limit, naming the
/// value whose lowering helps most and the largest value of it that fits.
pub fn check(scene: &Scene, extra: Extra) -> Result<()> {
    let extra = Extra {
        map_bytes: map_bytes(scene)?,
        ..extra
    };
    check_under(scene, extra, limit_bytes()?)
}

/// [`check`] against `limit` bytes.
fn check_under(scene: &Scene, extra: Extra, limit: f64) -> Result<()> {
    let need = peak_bytes(scene, extra);
    if need <= limit {
        return Ok(());
    }
    // The knob whose lowest setting (1) frees the most, and its largest value that fits.
    let mut best: Option<(&Knob, f64, u64)> = None;
    for knob in &KNOBS {
        let current = (knob.get)(scene, extra);
        if current <= 1 {
            continue;
        }
        let at = |v: u64| {
            let (mut s, mut e) = (scene.clone(), extra);
            (knob.set)(&mut s, &mut e, v);
            peak_bytes(&s, e)
        };
        let freed = need - at(1);
        if at(1) > limit || best.is_some_and(|(_, f, _)| f >= freed) {
            continue;
        }
        let (mut lo, mut hi) = (1, current);
        while lo + 1 < hi {
            let mid = lo + (hi - lo) / 2;
            if at(mid) <= limit {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        best = Some((knob, freed, lo));
    }
    let gib = |b: f64| b / (1024.0 * MIB);
    let fix = match best {
        Some((knob, _, largest)) => format!("the largest {} that fits is {largest}", knob.name),
        None if extra.map_bytes > 0.0 => format!(
            "the environment map alone takes {:.1} GiB: give a smaller map \
             (environment.path), or make the grid, the image and the bins smaller",
            gib(extra.map_bytes)
        ),
        None => "make the grid, the image and the bins smaller".to_string(),
    };
    bail!(
        "this run needs about {:.1} GiB of memory, more than the limit of {:.1} GiB \
         ({LIMIT_ENV}, or 80 % of this machine's); {fix}",
        gib(need),
        gib(limit)
    )
}

/// Refuse growing the structure of `scene` alone (`opalray structure`) with a map of
/// `map_pixels` if it would not fit.
pub fn check_structure(scene: &Scene, map_pixels: u64) -> Result<()> {
    let limit = limit_bytes()?;
    let need =
        BASE_BYTES + scene.structure.cell_count() as f64 * CELL_BYTES + map_pixels as f64 * 8.0;
    if need > limit {
        let per_z = (scene.structure.grid[0] * scene.structure.grid[1]) as f64 * CELL_BYTES;
        let largest = ((limit - BASE_BYTES - map_pixels as f64 * 8.0) / per_z)
            .floor()
            .max(0.0);
        bail!(
            "structure.grid {:?}: needs about {:.1} GiB of memory, more than the limit of \
             {:.1} GiB ({LIMIT_ENV}, or 80 % of this machine's); the largest z size that fits \
             is {largest}",
            scene.structure.grid,
            need / (1024.0 * MIB),
            limit / (1024.0 * MIB)
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On Linux the machine's memory is `MemTotal` of `/proc/meminfo`, as before the
    /// portable reader.
    #[cfg(target_os = "linux")]
    #[test]
    fn machine_memory_is_memtotal_on_linux() {
        let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap();
        let line = meminfo
            .lines()
            .find(|l| l.starts_with("MemTotal:"))
            .unwrap();
        let kib: u64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert_eq!(machine_memory_bytes(), kib * 1024);
    }

    #[test]
    fn default_render_is_about_what_was_measured() {
        // Measured: 121 MiB peak for the default scene at 8 × 6 px, 64 rays.
        let mut scene = Scene::default();
        scene.render.width = 8;
        scene.render.height = 6;
        scene.light.rays = 64;
        let mib = peak_bytes(&scene, Extra::default()) / MIB;
        assert!((121.0..250.0).contains(&mib), "{mib}");
    }

    #[test]
    fn the_largest_value_named_fits_and_one_more_does_not() {
        let mut scene = Scene::default();
        scene.render.width = 4000;
        scene.render.height = 4000;
        let limit = 512.0 * MIB;
        let err = check_under(&scene, Extra::default(), limit)
            .unwrap_err()
            .to_string();
        assert!(err.contains("--width"), "{err}");
        let largest: u32 = err.rsplit(' ').next().unwrap().parse().unwrap();
        scene.render.width = largest;
        assert!(check_under(&scene, Extra::default(), limit).is_ok());
        scene.render.width = largest + 1;
        assert!(check_under(&scene, Extra::default(), limit).is_err());
    }
}
