//! What the subcommands share: choosing the scene, progress bars, JSON output; the look
//! flags (`look.rs`) and the machine's measures (`machine.rs`).

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::Result;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use opalray::Scene;

mod look;
mod machine;

pub use look::LookArgs;
pub use machine::{cpu_ticks, peak_memory_mb, stolen_share};

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
