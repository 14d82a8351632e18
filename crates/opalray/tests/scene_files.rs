//! The preset scene files in `scenes/` are the presets: complete (every field written out, in
//! the order `opalray scene` prints them), with comments, and the one for `paper` is the
//! default scene.

use opalray::scene::{
    preset, Backing, BodyConfig, Cut, DomainsConfig, EnvironmentKind, IntegratorConfig, LightKind,
    Method, OrientationLaw, Pattern, PRESET_NAMES,
};
use opalray::{Result, Scene};

/// A scene file less its comment lines and the blank line that follows its header.
fn without_comments(text: &str) -> String {
    let kept: Vec<&str> = text.lines().filter(|line| !line.starts_with('#')).collect();
    let joined = kept.join("\n") + "\n";
    joined.trim_start_matches('\n').to_string()
}

fn scene_file(name: &str) -> (std::path::PathBuf, String) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let path = dir.join(format!("{name}.toml"));
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

#[test]
fn scene_files_are_their_presets_written_out_in_full() {
    for name in PRESET_NAMES {
        let (path, text) = scene_file(name);
        let scene = preset(name).unwrap();
        assert_eq!(
            without_comments(&text),
            scene.to_toml(),
            "{} is not its preset written out in full",
            path.display()
        );
        assert_eq!(Scene::load(&path).unwrap(), scene);
    }
}

#[test]
fn paper_scene_file_is_the_default_scene() {
    let (_, text) = scene_file("paper");
    assert_eq!(without_comments(&text), Scene::default().to_toml());
    assert_eq!(preset("paper").unwrap(), Scene::default());
}

#[test]
fn preset_files_parse_to_the_scenes_built_in_code() {
    for name in PRESET_NAMES {
        assert_eq!(
            preset(name).unwrap(),
            built_preset(name).unwrap(),
            "preset {name}"
        );
    }
}

/// The presets as they were built in code before `scenes/*.toml` became the presets.
fn built_preset(name: &str) -> Result<Scene> {
    let gem = |domains: DomainsConfig, body: BodyConfig, tone: u8| {
        let mut scene = Scene {
            domains,
            body,
            integrator: IntegratorConfig {
                method: Method::Path,
                // A gem's picture denoised: at 8 samples per pixel its error against a long
                // reference is a raw render's at about 70 (10.3 %; 14.3 % with the ragged
                // outlines' heavier fireflies, `BENCHMARKS.md`).
                spp: 8,
                denoise: true,
                ..IntegratorConfig::default()
            },
            ..Scene::default()
        };
        scene.environment.kind = EnvironmentKind::Studio;
        // The studio's lights at 11 × the luminance of the light's white: a line of 1 % of
        // white light then shows at about a tenth of full scale, as a gem photographer
        // exposes an opal on black velvet (the softbox's gloss clips).
        scene.environment.intensity = 11.0;
        scene.color.exposure_ev = 0.0;
        // Under the studio's lights θ_h is 15–22°: D = 235 nm flashes green there (λ ≈ 2.36 D
        // cos θ_h), and sizes varying by 12 % across the stone, alike within 2 mm (zones of
        // about 4 mm: a few dozen over the face, so that each stone shows most of the
        // spectrum), put blue (D ≈ 205 nm) in some zones and orange-red (≈ 265 nm) in others,
        // each patch of one colour through the plates of the bar.
        scene.crystal.sphere_diameter_nm = 235.0;
        scene.domains.sphere_diameter_spread = 0.12;
        scene.domains.diameter_correlation_mm = 2.0;
        scene.light.kind = LightKind::None;
        scene.render.body_tone = tone;
        scene.crystal.diffuse_fraction = 0.0;
        scene
    };
    let grains = |size: f64| DomainsConfig {
        pattern: Pattern::Grains,
        grain_size_mm: size,
        void_fraction: 0.05,
        mosaic_spread_deg: 1.5,
        ..DomainsConfig::default()
    };
    let cabochon = |dome: f64, bar: f64| BodyConfig {
        cut: Cut::Cabochon,
        dome_height_mm: dome,
        colour_bar_mm: bar,
        ..BodyConfig::default()
    };
    // A black opal: its colour bar over black potch, which is also its flat back. Without the
    // backing the bar's shell reaches the polished back near the girdle, and there the eye saw
    // the room by total internal reflection, a grey ring over the outer third of the face
    // (`black-opal`, structure seeds 1–4 at 160 × 120: colour over 49.2 % of the face on
    // average, 54.8 % with the backing; BENCHMARKS.md, "2026-12-04: the black back").
    let black_cabochon = |dome: f64, bar: f64| BodyConfig {
        backing: Some(Backing::Black),
        ..cabochon(dome, bar)
    };
    // Sedimentary opal: thin plates of settled layers, 0.24 mm thick for a 2 mm grain, so a
    // colour bar holds several along the view, each reflecting its own part of the room. Their
    // outlines ragged (domains meet along wandering boundaries), not the power diagram's
    // straight edges: 1.7 × the time, bought back by denoising at 8 samples per pixel.
    let settled = |size: f64| DomainsConfig {
        stretch: [2.5, 2.5, 0.12],
        orientation: OrientationLaw::Settled,
        orientation_spread_deg: 20.0,
        boundary_roughness: 0.4,
        ..grains(size)
    };
    match name {
        "paper" => Ok(Scene::default()),
        "paper-path" => {
            let mut scene = Scene::default();
            scene.integrator.method = Method::Path;
            scene.crystal.diffuse_fraction = 0.0;
            // The paper's balls are large, single domains: an imperfect one tilts its planes
            // by a few degrees across its width.
            scene.domains.mosaic_spread_deg = 4.0;
            Ok(scene)
        }
        "paper-stone" => {
            let mut scene = built_preset("paper-path")?;
            scene.integrator.method = Method::Stored;
            scene.integrator.spp = 4;
            Ok(scene)
        }
        "black-opal" => {
            // The stone picked from a parcel: of the first eight draws (structure seeds 1–8),
            // the only one with all six hue sextants and colour over more than half its face,
            // a harlequin of cyan, green, red, blue, yellow and orange patches (BENCHMARKS.md,
            // "the default stone"; drawn with straight edges). With the ragged outlines, the
            // black back and zones of 2.5 mm it is still the draw of the most hues (five hold
            // 5 %; BENCHMARKS.md, "2026-12-04: the black back").
            let mut scene = gem(settled(2.0), black_cabochon(4.0, 2.0), 1);
            scene.structure.seed = 4;
            // Sphere sizes alike over 2.5 mm: the zones, and with them the patches of one
            // colour, a little larger than the other presets' (median 2.4 against 1.9 mm at
            // 160 × 120 over seeds 1–8; at 640 × 480 this stone's are 1.5 mm, its plates'
            // ragged outlines cutting them: docs/model.md).
            scene.domains.diameter_correlation_mm = 2.5;
            // Shown as a photographer shows a stone, rocked to where it plays: 10° towards the
            // softbox, colour over 72 % of the face at 640 × 480 (61 % face-on; 38.7–75.2 %
            // over ±30° at 160 × 120, `scripts/look-tilt.py --preset black-opal`;
            // BENCHMARKS.md, "2026-12-04: the black back").
            scene.camera.tilt_deg = -10.0;
            Ok(scene)
        }
        "harlequin" => {
            // Of the first eight draws, the most coloured (54 % of the face at 160 × 120, in
            // four sextants: red, orange, yellow and green; seed 1 showed 39 %, mostly green;
            // BENCHMARKS.md, "the default stone").
            let mut scene = gem(settled(3.0), black_cabochon(4.0, 2.5), 1);
            scene.structure.seed = 6;
            // The pattern is named for its angular patches: the grains' own straight edges.
            scene.domains.boundary_roughness = 0.0;
            Ok(scene)
        }
        "pinfire" => {
            // Pinpoints of every colour side by side: each tiny grain draws its own size.
            let mut scene = gem(grains(0.6), black_cabochon(4.0, 1.5), 1);
            scene.domains.diameter_correlation_mm = 0.0;
            Ok(scene)
        }
        // Broad sheets of settled layers, their tilts alike: few large flashes, which face-on
        // under the studio's softbox mostly miss it (29 % of the face in colour at 160 × 120).
        // Shown as a photographer shows such a stone, rocked to where its sheets flash: 10°
        // (51 %; `scripts/look-tilt.py --preset broad-flash`, BENCHMARKS.md).
        "broad-flash" => {
            let mut scene = gem(
                DomainsConfig {
                    orientation_spread_deg: 10.0,
                    ..settled(5.0)
                },
                black_cabochon(4.0, 2.0),
                1,
            );
            scene.camera.tilt_deg = -10.0;
            Ok(scene)
        }
        // Settled layers in long bands across the stone.
        "ribbon" => Ok(gem(
            DomainsConfig {
                stretch: [1.0, 6.0, 0.12],
                ..settled(2.0)
            },
            black_cabochon(4.0, 2.0),
            1,
        )),
        // A white opal: a 1.5 mm colour bar of faintly milky domains (scattering at a tenth of
        // the potch's 10 mm⁻¹) over white potch, thick to its light (a transport depth of about
        // 15 under the bar), followed for 128 events: its diffuse light needs many to come
        // back out. Under the tent it showed 0.735 face-on (N9: 0.767); the body milky
        // throughout it replaced (potch 4 mm⁻¹, domains at half of it, 32 events) showed 0.53
        // (docs/model.md, "The white preset's body"). The body is bright, so the camera gives a
        // stop less.
        "white" => {
            let mut scene = gem(
                settled(2.0),
                BodyConfig {
                    potch_extinction_per_mm: 10.0,
                    domain_haze: 0.1,
                    ..cabochon(4.0, 1.5)
                },
                9,
            );
            scene.integrator.max_depth = 128;
            scene.color.exposure_ev = -1.0;
            // The stone picked from a parcel and shown rocked to where it plays, as
            // `black-opal` is, with its zones of 2.5 mm: of structure seeds 1–5 so rocked
            // (160 × 120 × 4), seed 2's face is the most in pastel colour (`look-metrics.py`'s
            // tint, HSV saturation over 0.25, on 13 % of it, where the milky body sits at 0.2;
            // the preset before, seed 1 face-on, 4.5 %), and its body reads 0.689 under the tent (docs/model.md, "The
            // white preset's play").
            scene.structure.seed = 2;
            scene.camera.tilt_deg = -10.0;
            scene.domains.diameter_correlation_mm = 2.5;
            // The milky body veils the patches' edges, and every one of its events would walk
            // the outlines' columns: the grains' own edges.
            scene.domains.boundary_roughness = 0.0;
            Ok(scene)
        }
        // Rolling flash: large settled sheets of gently curved (imperfect) layers in clear
        // opal.
        "crystal" => Ok(gem(
            DomainsConfig {
                orientation_spread_deg: 12.0,
                mosaic_spread_deg: 3.0,
                ..settled(5.0)
            },
            BodyConfig {
                potch_extinction_per_mm: 0.05,
                ..cabochon(4.0, 0.0)
            },
            5,
        )),
        "boulder" => {
            let mut scene = gem(
                settled(1.5),
                BodyConfig {
                    backing: Some(Backing::Ironstone),
                    ..cabochon(1.6, 0.0)
                },
                3,
            );
            // The stone picked from a parcel and shown rocked to where it plays, as
            // `black-opal` is: of structure seeds 1–6 rocked by 10° (160 × 120 × 4), seed 2
            // shows colour over 43 % of the face in five sextants (yellow, orange, green,
            // cyan, blue); seed 1 face-on, the preset before, 27 % in three (BENCHMARKS.md,
            // "2026-12-05: the boulder and triplet presets' stones").
            scene.structure.seed = 2;
            scene.camera.tilt_deg = -10.0;
            Ok(scene)
        }
        "doublet" => Ok(gem(
            settled(2.0),
            BodyConfig {
                cut: Cut::Doublet,
                potch_extinction_per_mm: 1.0,
                ..cabochon(1.5, 0.0)
            },
            6,
        )),
        "triplet" => {
            let mut scene = gem(
                settled(2.0),
                BodyConfig {
                    cut: Cut::Triplet,
                    slice_mm: 0.8,
                    potch_extinction_per_mm: 1.0,
                    ..cabochon(3.0, 0.0)
                },
                6,
            );
            // The slice picked from a parcel and shown rocked to where it plays: of structure
            // seeds 1–6 rocked by 10° (160 × 120 × 4), seed 4 shows colour over 53 % of the
            // face in four sextants (blue, cyan, green, red); seed 1 face-on, the preset
            // before, 32 % (BENCHMARKS.md, "2026-12-05: the boulder and triplet presets'
            // stones").
            scene.structure.seed = 4;
            scene.camera.tilt_deg = -10.0;
            Ok(scene)
        }
        other => panic!("no built preset {other}"),
    }
}
