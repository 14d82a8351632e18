//! What the subcommands share: choosing the scene, progress bars, JSON output.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use opalray::Scene;

/// Where the scene comes from: a TOML file, or a preset, with a seed on top.
#[derive(clap::Args, Debug, Clone)]
pub struct SceneArgs {
    /// Scene file (TOML); see `opalray scene` for a complete example.
    #[arg(value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Start from a named preset instead of a file: black-opal, harlequin, pinfire,
    /// broad-flash, ribbon, white, crystal, boulder, doublet, triplet (gem stones, the lobe
    /// integrator), paper (the paper's model), paper-path (its stone, path-traced), paper-stone
    /// (its stone, the stored method's two passes).
    #[arg(long, value_name = "NAME", conflicts_with = "scene")]
    pub preset: Option<String>,
    /// Seed of every random stream (overrides structure.seed), 0 to 2^63 − 1.
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u64).range(..=i64::MAX as u64))]
    pub seed: Option<u64>,
    /// Print the scene this command would run (the file or preset with every flag applied)
    /// as TOML, and stop there: nothing is rendered or written.
    #[arg(long)]
    pub show_scene: bool,
}

impl SceneArgs {
    /// Load the scene: the file if given, else the preset (default
    /// [`opalray::scene::DEFAULT_RENDER_PRESET`], the same for every command), then the seed.
    pub fn load(&self) -> Result<Scene> {
        let default = opalray::scene::DEFAULT_RENDER_PRESET;
        let mut scene = match (&self.scene, &self.preset) {
            (Some(path), _) => {
                let text = read_input("scene file", path, MAX_SCENE_BYTES).map_err(|err| {
                    match first_problem(path, MAX_SCENE_BYTES) {
                        Some(problem) if err.to_string().contains("larger than the limit") => {
                            anyhow::anyhow!("{err}; its first problem: {problem}")
                        }
                        _ => err,
                    }
                })?;
                let mut scene = Scene::from_toml_str(&text, &path.display().to_string())?;
                // A map named in the file lies beside it.
                scene.resolve_paths(path.parent().unwrap_or(Path::new("")));
                scene
            }
            (None, Some(name)) => opalray::scene::preset(name)?,
            (None, None) => opalray::scene::preset(default)?,
        };
        if let Some(seed) = self.seed {
            scene.structure.seed = seed;
        }
        Ok(scene)
    }
}

/// The first problem of the scene file `path` that is over `limit` bytes: the error of its
/// first `limit` bytes up to the last whole line, if they do not parse (a mistyped key, a
/// huge array), else `None`.
fn first_problem(path: &Path, limit: u64) -> Option<String> {
    use std::io::Read;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(limit)
        .read_to_end(&mut bytes)
        .ok()?;
    let end = bytes.iter().rposition(|&b| b == b'\n')?;
    let text = match std::str::from_utf8(&bytes[..end]) {
        Ok(text) => text,
        Err(e) => std::str::from_utf8(&bytes[..e.valid_up_to()]).ok()?,
    };
    let err = Scene::from_toml_str(text, &path.display().to_string()).err()?;
    Some(err.to_string().replace('\n', " "))
}

impl SceneArgs {
    /// With --show-scene, print `scene` as TOML and say so (the command then stops).
    pub fn shown(&self, scene: &Scene) -> Result<bool> {
        if self.show_scene {
            crate::stdio::out_raw(&scene.to_toml())?;
        }
        Ok(self.show_scene)
    }
}

/// Largest scene file read, bytes (a complete scene is about 1.5 kB).
pub const MAX_SCENE_BYTES: u64 = 1 << 20;

/// Largest spectrum CSV read, bytes (a million rows of `wavelength,value`).
pub const MAX_CSV_BYTES: u64 = 32 << 20;

/// Read the text file `path` of at most `limit` bytes; `what` names it in errors. Reads no
/// more than `limit + 1` bytes whatever the file (`/dev/zero` is refused at once).
pub fn read_input(what: &str, path: &Path, limit: u64) -> Result<String> {
    use std::io::Read;
    let shown = path.display();
    let file = std::fs::File::open(path)
        .map_err(|e| anyhow::anyhow!("{what} {shown}: {}", crate::outputs::plain_io(&e)))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        anyhow::bail!("{what} {shown}: is a directory; give a file");
    }
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| anyhow::anyhow!("{what} {shown}: {}", crate::outputs::plain_io(&e)))?;
    if bytes.len() as u64 > limit {
        anyhow::bail!(
            "{what} {shown}: larger than the limit of {} MiB; give a smaller file",
            limit >> 20
        );
    }
    String::from_utf8(bytes).map_err(|e| {
        anyhow::anyhow!(
            "{what} {shown}: not UTF-8 text (byte {}); save it as UTF-8",
            e.utf8_error().valid_up_to()
        )
    })
}

/// Refuse environment values the command would otherwise ignore or suffer from:
/// `RAYON_NUM_THREADS` must be a whole number 1 to [`MAX_THREADS`], `OPALRAY_SIMD` one of
/// the known copies.
pub fn check_environment() -> Result<()> {
    if let Some(value) = std::env::var_os("RAYON_NUM_THREADS") {
        let text = value.to_string_lossy();
        match text.trim().parse::<u64>() {
            Ok(n) if (1..=MAX_THREADS).contains(&n) => {}
            _ => anyhow::bail!(
                "RAYON_NUM_THREADS={text}: must be a whole number of threads from 1 to \
                 {MAX_THREADS}; unset it to use every core"
            ),
        }
    }
    if let Some(value) = std::env::var_os(opalray::simd::SIMD_ENV) {
        let text = value.to_string_lossy();
        if !["portable", "widest", "auto"].contains(&text.as_ref()) {
            anyhow::bail!(
                "{}={text}: unknown; use portable (the portable copy), or widest or auto \
                 (the fastest this processor runs)",
                opalray::simd::SIMD_ENV
            );
        }
    }
    Ok(())
}

/// Most worker threads accepted in `RAYON_NUM_THREADS` (each costs a stack and a share of
/// every per-thread buffer).
pub const MAX_THREADS: u64 = 256;

/// Flags that override the scene's look, shared by `render`, `sweep` and `bench`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct LookArgs {
    /// Image width, pixels (render.width).
    #[arg(long, value_name = "PX", allow_hyphen_values = true)]
    pub width: Option<u32>,
    /// Image height, pixels (render.height).
    #[arg(long, value_name = "PX", allow_hyphen_values = true)]
    pub height: Option<u32>,
    /// Silica sphere diameter, nm (crystal.sphere_diameter_nm): ~250 flashes orange face-on,
    /// smaller spheres green and blue.
    #[arg(long, value_name = "NM", allow_hyphen_values = true)]
    pub diameter: Option<f64>,
    /// Wavelength bins over the spectrum's range (spectrum.bins).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub bins: Option<usize>,
    /// Cells of the light pass's ray lattice: one ray each, 2 × 2 where the light is trapped
    /// near the rim (light.rays).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub rays: Option<u64>,
    /// Light weaker than this fraction of its ray's power is cut, or plays roulette
    /// (light.cutoff, default 0.02): smaller misses a little less light and costs more.
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub cutoff: Option<f64>,
    /// Russian roulette for light below the cutoff instead of cutting it (light.roulette):
    /// the unbiased estimate, slower and noisier; for reference renders.
    #[arg(long)]
    pub roulette: bool,
    /// Body tone, 1 (N1, black opal) … 9 (N9, white opal) (render.body_tone).
    #[arg(long, value_name = "N")]
    pub body_tone: Option<u8>,
    /// Exposure compensation in stops (color.exposure_ev).
    #[arg(long, value_name = "EV", allow_hyphen_values = true)]
    pub exposure: Option<f64>,
    /// Samples per pixel of the path integrator (integrator.spp): more for smoother edges and
    /// less noise, in proportion to the time; the stored method's camera rays per pixel; the
    /// lobe integrator's rays through each pixel at an edge.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub spp: Option<u32>,
    /// The renderer (integrator.method): lobe (the gem presets': every Bragg lobe integrated
    /// against the lights, seconds a frame, no noise), path (the reference path tracer: add
    /// --denoise and --spp 8 or more), stored, or two-pass (the paper's).
    #[arg(long, value_name = "NAME", value_parser = clap::builder::PossibleValuesParser::new(
        opalray::scene::Method::ALL.map(opalray::scene::Method::name)
    ))]
    pub method: Option<String>,
    /// Rock the stone: tilt it towards the camera about the picture's horizontal axis,
    /// degrees, the lights staying with the camera (camera.tilt_deg).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub tilt: Option<f64>,
    /// Path integrator: filter the noise after the last pass (integrator.denoise, off unless a
    /// scene sets it): non-local means between the even and the odd samples, about a second
    /// per million pixels; much smoother at a small bias. The spectral image stays unfiltered.
    #[arg(long, conflicts_with = "no_denoise")]
    pub denoise: bool,
    /// Path integrator: leave the image as the samples' mean (integrator.denoise = false):
    /// the unbiased estimate, for comparisons and references.
    #[arg(long)]
    pub no_denoise: bool,
}

impl LookArgs {
    /// Set `integrator.method` from `--method`, if given, keeping the `[integrator]` fields
    /// the new method takes and dropping the others (a file is refused them instead).
    pub fn apply_method(&self, scene: &mut Scene) -> Result<()> {
        if let Some(name) = &self.method {
            let method: opalray::scene::Method = serde_json::from_value(serde_json::json!(name))
                .map_err(|e| anyhow::anyhow!("--method {name}: {e}"))?;
            // The flag keeps the fields the new method takes and drops the others.
            scene.integrator = scene.integrator.switched(method);
        }
        Ok(())
    }

    /// Apply the flags to `scene` and validate the result.
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
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
        if let Some(v) = self.cutoff {
            scene.light.cutoff = v;
        }
        if self.roulette {
            scene.light.roulette = true;
        }
        if let Some(v) = self.body_tone {
            scene.render.body_tone = v;
        }
        if let Some(v) = self.exposure {
            scene.color.exposure_ev = v;
        }
        self.apply_method(scene)?;
        if let Some(v) = self.spp {
            // Checked whatever the method; the paper's two passes take no samples per pixel.
            opalray::scene::check_spp(v).map_err(|err| self.named(err))?;
            scene.integrator.set_spp(v);
        }
        if let Some(v) = self.tilt {
            scene.camera.tilt_deg = v;
        }
        if self.denoise || self.no_denoise {
            match &mut scene.integrator {
                opalray::scene::IntegratorConfig::Path(c) => c.denoise = self.denoise,
                // Without the filter there is nothing to switch off.
                _ if self.no_denoise => {}
                _ => {
                    return Err(self.named(opalray::Error::field(
                        "integrator.denoise",
                        "filters the path integrator's image only; set integrator.method = \
                         \"path\" (--method path) or drop the flag",
                    )))
                }
            }
        }
        opalray::integrator::check(scene).map_err(|err| self.named(err))?;
        Ok(())
    }

    /// `err`, a field the user set with a flag named by that flag.
    fn named(&self, err: opalray::Error) -> anyhow::Error {
        match &err {
            opalray::Error::InvalidField { field, message } => match self.flag_of(field) {
                Some(flag) => anyhow::anyhow!("{flag} ({field}): {message}"),
                None => anyhow::Error::new(err)
                    .context("checking the scene with the command-line flags applied"),
            },
            _ => anyhow::Error::new(err)
                .context("checking the scene with the command-line flags applied"),
        }
    }

    /// The flag that set scene field `field`, if one did.
    fn flag_of(&self, field: &str) -> Option<&'static str> {
        let given = [
            ("render.width", "--width", self.width.is_some()),
            ("render.height", "--height", self.height.is_some()),
            (
                "crystal.sphere_diameter_nm",
                "--diameter",
                self.diameter.is_some(),
            ),
            ("spectrum.bins", "--bins", self.bins.is_some()),
            ("light.rays", "--rays", self.rays.is_some()),
            ("light.cutoff", "--cutoff", self.cutoff.is_some()),
            ("render.body_tone", "--body-tone", self.body_tone.is_some()),
            ("color.exposure_ev", "--exposure", self.exposure.is_some()),
            ("integrator.spp", "--spp", self.spp.is_some()),
            ("integrator.method", "--method", self.method.is_some()),
            ("camera.tilt_deg", "--tilt", self.tilt.is_some()),
            ("integrator.denoise", "--denoise", self.denoise),
        ];
        given
            .iter()
            .find(|(f, _, set)| *set && *f == field)
            .map(|(_, flag, _)| *flag)
    }
}

/// Peak resident memory of this process so far, MiB, where the system reports it.
pub fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The machine's processor time so far, all processors together (`/proc/stat`, in clock
/// ticks): `(total, stolen)`, stolen being the time a virtual processor was ready to run
/// while the hypervisor ran something else on its core. `None` where the system does not
/// report it.
pub fn cpu_ticks() -> Option<(u64, u64)> {
    parse_cpu_ticks(&std::fs::read_to_string("/proc/stat").ok()?)
}

/// [`cpu_ticks`] from the text of `/proc/stat`: the first line's user, nice, system, idle,
/// iowait, irq, softirq and steal times (guest time is already counted in user time).
fn parse_cpu_ticks(stat: &str) -> Option<(u64, u64)> {
    let line = stat.lines().next()?.strip_prefix("cpu ")?;
    let ticks: Vec<u64> = line
        .split_whitespace()
        .take(8)
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    (ticks.len() == 8).then(|| (ticks.iter().sum(), ticks[7]))
}

/// The share of the machine's processor time stolen between two [`cpu_ticks`] readings, or
/// `None` if either is missing or no time passed.
pub fn stolen_share(before: Option<(u64, u64)>, after: Option<(u64, u64)>) -> Option<f64> {
    let ((t0, s0), (t1, s1)) = (before?, after?);
    (t1 > t0).then(|| s1.saturating_sub(s0) as f64 / (t1 - t0) as f64)
}

/// Whether stderr is a terminal: progress is a bar there, else lines (a log, CI, an IDE).
pub fn stderr_is_terminal() -> bool {
    std::io::IsTerminal::is_terminal(&std::io::stderr())
}

/// One line of progress on stderr where no bar is drawn (stderr not a terminal), so that a
/// long render is never silent.
pub fn progress_line(text: std::fmt::Arguments<'_>) {
    if !stderr_is_terminal() {
        crate::stdio::note(text);
    }
}

/// `seconds` as a person reads a duration: "2.5 s", "42 s", "3.5 min", "1.2 h".
pub fn duration_words(seconds: f64) -> String {
    if seconds < 10.0 {
        format!("{seconds:.1} s")
    } else if seconds < 90.0 {
        format!("{seconds:.0} s")
    } else if seconds < 5400.0 {
        format!("{:.1} min", seconds / 60.0)
    } else {
        format!("{:.1} h", seconds / 3600.0)
    }
}

/// A progress bar drawn on stderr only when it is a terminal (else see [`progress_line`]).
pub fn progress(len: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if !stderr_is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar.set_style(
        ProgressStyle::with_template("{msg:>12} [{bar:30}] {pos}/{len} {elapsed}")
            .expect("valid template")
            .progress_chars("=> "),
    );
    bar.set_message(what.to_string());
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}

/// Write `value` as pretty JSON to `path`, atomically.
pub fn write_json(path: &Path, value: &serde_json::Value) -> opalray::Result<()> {
    let text = serde_json::to_string_pretty(value).unwrap_or_default();
    opalray::output::write_atomic(path, |w| {
        w.write_all(text.as_bytes())?;
        w.write_all(b"\n")
    })
}

/// Refuse an output path whose extension is not one of `allowed`, before any work is done.
pub fn check_extension(flag: &str, path: &Path, allowed: &[&str]) -> Result<()> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if allowed.contains(&ext.as_str()) {
        Ok(())
    } else {
        anyhow::bail!(
            "{flag} {}: unsupported file type; use a name ending in .{}",
            path.display(),
            allowed.join(" or .")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stolen_time_is_the_steal_column_over_the_first_eight() {
        // A line as Linux writes it: user nice system idle iowait irq softirq steal guest
        // guest_nice; the total is the first eight (guest time is inside user time).
        let stat = "cpu  100 0 20 600 5 0 3 72 9 0\ncpu0 50 0 10 300 2 0 1 36 4 0\n";
        assert_eq!(parse_cpu_ticks(stat), Some((800, 72)));
        assert_eq!(parse_cpu_ticks("cpu0 1 2 3 4 5 6 7 8\n"), None);
        assert_eq!(parse_cpu_ticks("cpu  1 2 3\n"), None);
        let share = stolen_share(Some((800, 72)), Some((1800, 322))).unwrap();
        assert!((share - 0.25).abs() < 1e-12, "{share}");
        assert_eq!(stolen_share(Some((800, 72)), Some((800, 72))), None);
        assert_eq!(stolen_share(None, Some((800, 72))), None);
    }
}
