//! A sweep's frames folder (`--frames-dir`): each finished frame as `frame-0000.png` …, and
//! `sweep.json`, the manifest naming the sweep the frames belong to (a hash of the scene, the
//! angles and the frame size) and the checksum of every frame written.
//!
//! The folder is an output like the others: checked with them before any work. A folder is
//! ours when it is new or empty, or when its manifest is ours; a folder holding anything else
//! is refused. A frame is reused only when its bytes match the checksum in the manifest; a
//! damaged manifest of ours means every frame is rendered again, never mixed in. Frames and
//! the manifest are written nameless and linked into place when complete
//! ([`crate::anonymous`]).

use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use serde_json::json;

use crate::anonymous::write_file;

/// The file naming the sweep whose frames a folder holds.
pub const MANIFEST: &str = "sweep.json";

/// The manifest's `format`: what marks a folder as ours (written first, so that a manifest
/// cut short still shows it).
const FORMAT: &str = "opalray-frames-1";

/// A folder of finished frames of one sweep.
pub struct FramesDir {
    dir: PathBuf,
    /// The sweep's key and angles, written into the manifest.
    key: String,
    angles: Vec<f64>,
    /// The checksum (FNV-1a, 64 bit, hex) of each frame written, `None` where none is.
    checksums: Vec<Option<String>>,
}

impl FramesDir {
    /// Open (creating) `dir` for the sweep named `key` over `angles`, before any work.
    /// `resume`: refuse a folder without frames of this sweep.
    pub fn open(dir: &Path, key: String, angles: &[f64], resume: bool) -> Result<Self> {
        let shown = dir.display();
        if dir.exists() && !dir.is_dir() {
            bail!("--frames-dir {shown}: is a file, not a folder; choose another path");
        }
        let mut frames = FramesDir {
            dir: dir.to_path_buf(),
            key,
            angles: angles.to_vec(),
            checksums: vec![None; angles.len()],
        };
        match frames.read_manifest()? {
            Found::Ours(checksums) => frames.checksums = checksums,
            Found::Damaged if resume => bail!(
                "--resume: {shown}/{MANIFEST} is damaged, so no frame there can be trusted; \
                 run without --resume to render them again"
            ),
            Found::Damaged => {}
            Found::None if resume => bail!(
                "--resume: {shown} holds no frames of this sweep; run without --resume to \
                 start it"
            ),
            Found::None => {}
        }
        std::fs::create_dir_all(dir).map_err(|e| {
            anyhow::anyhow!(
                "--frames-dir {shown}: cannot create the folder: {}",
                crate::outputs::plain_io(&e)
            )
        })?;
        frames.write_manifest()?;
        Ok(frames)
    }

    /// What the folder holds: our manifest of this sweep, a damaged one of ours, or nothing
    /// (new or empty). Anything else is refused.
    fn read_manifest(&self) -> Result<Found> {
        let shown = self.dir.display();
        let path = self.dir.join(MANIFEST);
        if !path.exists() {
            let others = match std::fs::read_dir(&self.dir) {
                Ok(entries) => entries
                    .filter_map(|e| e.ok())
                    .any(|e| !is_our_temp(&e.file_name().to_string_lossy())),
                Err(_) => false,
            };
            if others {
                bail!(
                    "--frames-dir {shown}: holds files but no {MANIFEST} of opalray, so it is \
                     not a frames folder; choose a new or empty folder"
                );
            }
            return Ok(Found::None);
        }
        if !path.is_file() {
            bail!(
                "--frames-dir {shown}: its {MANIFEST} is not a regular file; choose a new or \
                 empty folder"
            );
        }
        let text = read_limited(&path, 1 << 20).unwrap_or_default();
        let text = String::from_utf8_lossy(&text);
        let value = serde_json::from_str::<serde_json::Value>(&text).ok();
        let ours = value
            .as_ref()
            .is_some_and(|v| v.get("format").and_then(|f| f.as_str()) == Some(FORMAT));
        if !ours {
            if text.contains(FORMAT) {
                return Ok(Found::Damaged);
            }
            bail!(
                "--frames-dir {shown}: its {MANIFEST} was not written by opalray; choose a new \
                 or empty folder"
            );
        }
        let value = value.unwrap_or_default();
        if value.get("sweep").and_then(|k| k.as_str()) != Some(self.key.as_str()) {
            bail!(
                "--frames-dir {shown}: holds the frames of another sweep (other scene, angles \
                 or size); remove them or choose another folder"
            );
        }
        let checksums: Option<Vec<Option<String>>> = value
            .get("checksums")
            .and_then(|c| serde_json::from_value(c.clone()).ok());
        match checksums {
            Some(c) if c.len() == self.angles.len() => Ok(Found::Ours(c)),
            _ => Ok(Found::Damaged),
        }
    }

    /// Write the manifest, atomically.
    fn write_manifest(&self) -> Result<()> {
        let value = json!({
            "sweep": self.key,
            "frames": self.angles.len(),
            "angles_deg": self.angles,
            "checksums": self.checksums,
        });
        // The format first, so that a manifest cut short still shows whose it is.
        let rest = serde_json::to_string_pretty(&value).unwrap_or_default();
        let text = format!(
            "{{\n  \"format\": \"{FORMAT}\",{}\n",
            rest.strip_prefix('{').unwrap_or(&rest)
        );
        write_file(&self.dir.join(MANIFEST), |path| {
            opalray::output::write_atomic(path, |w| w.write_all(text.as_bytes()))
        })
        .map_err(|e| anyhow::anyhow!("--frames-dir {}: {e}", self.dir.display()))
    }

    fn frame_path(&self, k: usize) -> PathBuf {
        self.dir.join(format!("frame-{k:04}.png"))
    }

    /// Frame `k`'s RGB8 pixels if it was finished: a regular file whose bytes match the
    /// manifest's checksum, a PNG of the right size.
    pub fn finished(&self, k: usize, w: usize, h: usize) -> Option<Vec<u8>> {
        let expected = self.checksums.get(k)?.as_deref()?;
        let path = self.frame_path(k);
        if !std::fs::metadata(&path).ok()?.is_file() {
            return None;
        }
        let bytes = read_limited(&path, (w * h * 4 + (1 << 16)) as u64)?;
        if checksum(&bytes) != expected {
            return None;
        }
        let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        decoder.set_transformations(png::Transformations::IDENTITY);
        let mut reader = decoder.read_info().ok()?;
        let info = reader.info();
        if (info.width as usize, info.height as usize) != (w, h)
            || info.color_type != png::ColorType::Rgb
            || info.bit_depth != png::BitDepth::Eight
        {
            return None;
        }
        let mut rgb = vec![0; reader.output_buffer_size()?];
        reader.next_frame(&mut rgb).ok()?;
        (rgb.len() == w * h * 3).then_some(rgb)
    }

    /// Write frame `k` atomically, then its checksum into the manifest.
    pub fn save(&mut self, k: usize, w: usize, h: usize, rgb8: &[u8]) -> Result<()> {
        let path = self.frame_path(k);
        write_file(&path, |to| {
            opalray::output::write_png_rgb8(to, w as u32, h as u32, rgb8)
        })
        .map_err(|e| anyhow::anyhow!("--frames-dir: {e}"))?;
        let bytes = std::fs::read(&path).map_err(|e| {
            anyhow::anyhow!(
                "--frames-dir {}: {}",
                path.display(),
                crate::outputs::plain_io(&e)
            )
        })?;
        self.checksums[k] = Some(checksum(&bytes));
        self.write_manifest()
    }
}

/// What a folder's manifest says.
enum Found {
    /// Ours, of this sweep: the checksums of the frames written.
    Ours(Vec<Option<String>>),
    /// Ours but unreadable: no frame there is trusted.
    Damaged,
    /// No manifest, and nothing else but our temporary files: a new folder.
    None,
}

/// Whether `name` is one of the temporary files a write of ours stages.
fn is_our_temp(name: &str) -> bool {
    name.starts_with(".opalray-") && name.ends_with(".tmp")
}

/// At most `limit` bytes of the regular file `path`; `None` if it is longer or unreadable.
fn read_limited(path: &Path, limit: u64) -> Option<Vec<u8>> {
    use std::io::Read;
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(limit + 1)
        .read_to_end(&mut bytes)
        .ok()?;
    (bytes.len() as u64 <= limit).then_some(bytes)
}

/// FNV-1a, 64 bit, as 16 hex digits.
pub fn checksum(bytes: &[u8]) -> String {
    format!("{:016x}", fnv(bytes))
}

/// FNV-1a, 64 bit: a stable hash of a sweep's description or a frame's bytes.
pub fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
