//! What the subcommands share: choosing the scene, progress bars, JSON output.

use std::path::{Path, PathBuf};
use std::time::Duration;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use opalray::Scene;

/// Where the scene comes from: a TOML file, or a preset, with a seed on top.
#[derive(clap::Args, Debug, Clone)]
pub struct SceneArgs {
    /// Scene file (TOML); see `opalray scene` for a complete example.
    #[arg(value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Start from a named preset instead of a file (presets: paper).
    #[arg(long, value_name = "NAME", conflicts_with = "scene")]
    pub preset: Option<String>,
    /// Seed of every random stream (overrides structure.seed), 0 to 2^63 − 1.
    #[arg(long, value_name = "N",
          value_parser = clap::value_parser!(u64).range(..=i64::MAX as u64))]
    pub seed: Option<u64>,
}

impl SceneArgs {
    /// Load the scene: the file if given, else the preset (default `paper`), then the seed.
    pub fn load(&self) -> Result<Scene> {
        let mut scene = match (&self.scene, &self.preset) {
            (Some(path), _) => Scene::load(path)?,
            (None, Some(name)) => opalray::scene::preset(name)?,
            (None, None) => opalray::scene::preset("paper")?,
        };
        if let Some(seed) = self.seed {
            scene.structure.seed = seed;
        }
        Ok(scene)
    }
}

/// A progress bar drawn on stderr only when it is a terminal.
pub fn progress(len: u64, what: &str) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
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
pub fn write_json(path: &Path, value: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(value).expect("JSON values serialise");
    opalray::output::write_atomic(path, |w| {
        w.write_all(text.as_bytes())?;
        w.write_all(b"\n")
    })
    .with_context(|| format!("writing --stats {}", path.display()))
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
