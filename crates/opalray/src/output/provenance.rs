//! What made an image, carried in its file: the scene as TOML, its seed, the samples per
//! pixel, the method and opalray's version, as PNG text chunks (`iTXt`, UTF-8) and OpenEXR
//! header attributes (`software`, and `opalray.scene`: the scene after a comment line with
//! the rest). [`read_provenance`] reads them back, so that a picture can be
//! rendered again from itself (`opalray scene --from IMAGE`).

use std::path::Path;

use crate::error::{Error, Result};
use crate::render::Frame;
use crate::Scene;

/// Key of the scene's TOML.
pub const SCENE_KEY: &str = "opalray.scene";

/// The text entries written into an image's header, in order: `(key, value)`. Empty for an
/// image that records nothing (a sweep's frame, a contact sheet).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Provenance {
    /// `(key, value)` pairs; keys are ASCII, values UTF-8.
    pub entries: Vec<(String, String)>,
}

impl Provenance {
    /// What made `frame` of `scene`: `Software` ("opalray VERSION"), `opalray.scene` (the
    /// scene as TOML; a path-traced render's `integrator.spp` is the samples it reached, so
    /// that a time-limited render is rendered again exactly), `opalray.seed`
    /// (`structure.seed`), `opalray.spp` (samples per pixel rendered, the path and stored
    /// methods; the lobe integrator's rays per edge pixel), `opalray.method` and
    /// `opalray.version`.
    pub fn of(scene: &Scene, frame: &Frame) -> Self {
        Provenance::of_samples(scene, frame.report.as_ref().and_then(|r| r.spp()))
    }

    /// [`Provenance::of`] from the samples per pixel the frame's method reports it rendered
    /// (`rendered_spp`: its report's, `Report::spp`), for a frame known only by its
    /// statistics; without them, the scene's (the lobe integrator's rays per edge pixel).
    pub fn of_samples(scene: &Scene, rendered_spp: Option<u32>) -> Self {
        let mut scene = scene.clone();
        if let Some(spp) = rendered_spp {
            scene.integrator.set_spp(spp);
        }
        let method = scene.integrator.method();
        let spp = rendered_spp.or(scene.integrator.spp());
        let version = env!("CARGO_PKG_VERSION");
        let method = method.name().to_string();
        let mut entries = vec![
            ("Software".to_string(), format!("opalray {version}")),
            (SCENE_KEY.to_string(), scene.to_toml()),
            ("opalray.seed".to_string(), scene.structure.seed.to_string()),
        ];
        if let Some(spp) = spp {
            entries.push(("opalray.spp".to_string(), spp.to_string()));
        }
        entries.push(("opalray.method".to_string(), method));
        entries.push(("opalray.version".to_string(), version.to_string()));
        Provenance { entries }
    }

    /// The scene's TOML after a comment line with the other entries but `Software`
    /// (`# opalray.seed = 7, opalray.spp = 8, …`): the whole record as one text, for a header
    /// that keeps one attribute (OpenEXR). `None` if no scene is recorded.
    pub fn scene_with_summary(&self) -> Option<String> {
        let scene = self.get(SCENE_KEY)?;
        let summary: Vec<String> = self
            .entries
            .iter()
            .filter(|(k, _)| k != SCENE_KEY && k != "Software")
            .map(|(k, v)| format!("{k} = {v}"))
            .collect();
        Some(format!("# {}\n{scene}", summary.join(", ")))
    }

    /// The entries of a [`Provenance::scene_with_summary`] text: the summary's, then the
    /// scene's TOML (the comment line is a TOML comment: the text parses as it is).
    fn from_summary(text: &str) -> Vec<(String, String)> {
        let (first, scene) = text.split_once('\n').unwrap_or(("", text));
        let mut entries: Vec<(String, String)> = first
            .strip_prefix("# ")
            .unwrap_or_default()
            .split(", ")
            .filter_map(|pair| pair.split_once(" = "))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        entries.push((SCENE_KEY.to_string(), scene.to_string()));
        entries
    }

    /// The value of `key`, if recorded.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// The recorded scene, parsed and validated; `path` names the image in errors.
    pub fn scene(&self, path: &Path) -> Result<Scene> {
        let text = self.get(SCENE_KEY).ok_or_else(|| Error::InvalidData {
            path: path.to_path_buf(),
            message: format!(
                "holds no scene (no `{SCENE_KEY}` in its header); give an image written by \
                 `opalray render` or Python's Image.save"
            ),
        })?;
        Scene::from_toml_str(text, &format!("{} ({SCENE_KEY})", path.display()))
    }
}

/// The provenance recorded in the PNG or OpenEXR file at `path` (by its extension); empty
/// where the file records none.
pub fn read_provenance(path: &Path) -> Result<Provenance> {
    let bad = |message: String| Error::InvalidData {
        path: path.to_path_buf(),
        message,
    };
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let entries = match ext.as_str() {
        "png" => read_png_text(path).map_err(bad)?,
        "exr" => read_exr_text(path).map_err(bad)?,
        _ => return Err(bad("not a .png or .exr image; give one".into())),
    };
    Ok(Provenance { entries })
}

/// Every text chunk before the PNG's image data (tEXt, zTXt, iTXt).
fn read_png_text(path: &Path) -> std::result::Result<Vec<(String, String)>, String> {
    let file = std::fs::File::open(path).map_err(|e| e.to_string())?;
    let decoder = png::Decoder::new(std::io::BufReader::new(file));
    let reader = decoder
        .read_info()
        .map_err(|e| format!("not a readable PNG ({e})"))?;
    let info = reader.info();
    let mut entries: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect();
    for t in &info.compressed_latin1_text {
        if let Ok(text) = t.get_text() {
            entries.push((t.keyword.clone(), text));
        }
    }
    for t in &info.utf8_text {
        if let Ok(text) = t.get_text() {
            entries.push((t.keyword.clone(), text));
        }
    }
    Ok(entries)
}

/// Every text attribute of the OpenEXR file's first header (its metadata only).
fn read_exr_text(path: &Path) -> std::result::Result<Vec<(String, String)>, String> {
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| format!("not a readable OpenEXR file ({e})"))?;
    let header = meta
        .headers
        .first()
        .ok_or_else(|| "an OpenEXR file without a header".to_string())?;
    let text = |t: &exr::meta::attribute::Text| String::from_utf8_lossy(t.bytes()).into_owned();
    let mut entries = Vec::new();
    if let Some(software) = &header.own_attributes.software_name {
        entries.push(("Software".to_string(), text(software)));
    }
    let recorded = header
        .own_attributes
        .other
        .iter()
        .chain(&header.shared_attributes.other)
        .find(|(key, _)| key.bytes() == SCENE_KEY.as_bytes());
    if let Some((_, exr::meta::attribute::AttributeValue::Text(scene))) = recorded {
        entries.extend(Provenance::from_summary(&text(scene)));
    }
    Ok(entries)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::RgbImage;

    fn recorded() -> (Scene, Provenance) {
        let mut scene = crate::scene::preset("black-opal").unwrap();
        scene.structure.seed = 11;
        scene.integrator.set_spp(3);
        // A name beyond Latin-1 travels as UTF-8 in both headers.
        scene.environment.kind = crate::scene::EnvironmentKind::File;
        scene.environment.path = "maps/atelier-ü-光.hdr".into();
        let provenance = Provenance::of_samples(&scene, Some(3));
        (scene, provenance)
    }

    #[test]
    fn png_and_exr_headers_give_back_the_scene_and_its_entries() {
        let (scene, provenance) = recorded();
        let dir = tempfile::tempdir().unwrap();
        let rgb = RgbImage {
            width: 3,
            height: 2,
            data: vec![[0.2, 0.4, 0.6]; 6],
        };
        let png = dir.path().join("a.png");
        let exr = dir.path().join("a.exr");
        super::super::write_png(&png, &rgb, &scene.color, &provenance).unwrap();
        super::super::write_exr(&exr, &rgb, &provenance).unwrap();
        for path in [&png, &exr] {
            let back = read_provenance(path).unwrap();
            assert_eq!(back.scene(path).unwrap(), scene, "{}", path.display());
            for key in ["Software", "opalray.seed", "opalray.spp", "opalray.method"] {
                assert_eq!(
                    back.get(key),
                    provenance.get(key),
                    "{key} in {}",
                    path.display()
                );
            }
            assert_eq!(back.get("opalray.seed"), Some("11"));
            assert_eq!(back.get("opalray.spp"), Some("3"));
            assert_eq!(back.get("opalray.method"), Some("lobe"));
        }
    }

    #[test]
    fn an_exr_header_is_the_same_bytes_every_time() {
        // Several attributes in the `exr` crate's hash maps would be written in a different
        // order by each process; each map holds one, so the bytes repeat.
        let (_, provenance) = recorded();
        let dir = tempfile::tempdir().unwrap();
        let rgb = RgbImage {
            width: 2,
            height: 2,
            data: vec![[1.0, 0.5, 0.25]; 4],
        };
        let grid = crate::spectrum::WavelengthGrid::new(380.0, 780.0, 4).unwrap();
        let mut spectral = crate::spectrum::SpectralImage::new(2, 2, grid);
        spectral.data.iter_mut().for_each(|v| *v = 0.5);
        let write = |name: &str| {
            let path = dir.path().join(name);
            super::super::write_spectral_exr(&path, &spectral, &provenance).unwrap();
            let cube = std::fs::read(&path).unwrap();
            super::super::write_exr(&path, &rgb, &provenance).unwrap();
            (cube, std::fs::read(&path).unwrap())
        };
        let first = write("a.exr");
        for k in 0..4 {
            assert!(write(&format!("b{k}.exr")) == first, "write {k} differs");
        }
    }

    #[test]
    fn an_image_without_a_record_names_what_is_missing() {
        let provenance = Provenance::default();
        let err = provenance
            .scene(Path::new("x.png"))
            .unwrap_err()
            .to_string();
        assert!(err.contains("x.png") && err.contains(SCENE_KEY), "{err}");
    }
}
