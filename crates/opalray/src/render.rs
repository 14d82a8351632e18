//! The orchestrator: scene → [`prepare`] (the scene checked, the structure and optics, then
//! what its integrator builds once) → [`Prepared::render`] per light angle (its integrator's
//! frame, through the table in [`crate::integrator`]) → colour, timing every stage. Also the
//! pieces the integrators share: the light and camera placed (`placement.rs`), the frame and
//! the colour stage (`frame.rs`).

use std::sync::OnceLock;
use std::time::Instant;

use crate::error::Result;
use crate::integrator::Passes;
use crate::light_pass::VoxelLayout;
use crate::lights::Environment;
use crate::optics::{build_optics, OpticsTables};
use crate::sampling::mix64;
use crate::scene::{Pattern, Scene, StructureConfig};
use crate::stone::Stone;
use crate::structure::{grow_structure, Structure};

mod frame;
mod placement;

pub(crate) use frame::rgb_of_xyz;
pub use frame::{Frame, Report, StageTimes};
pub(crate) use placement::camera_up;
pub use placement::LIGHT_DISC_RADIUS_DEG;

/// The light-independent part of a render, computed once and reused for every light angle.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The scene.
    pub scene: Scene,
    /// The grown structure ([`Prepared::structure`]): the prepared stone's voxel view
    /// ([`Stone::voxel_view`]), else grown; made by `prepare` for the paper's two passes, on
    /// first use for the other methods (which do not read it).
    structure: OnceLock<Structure>,
    /// The cluster optics tables ([`Prepared::optics`]), built as the structure is.
    optics: OnceLock<OpticsTables>,
    /// The stone model of the methods that render it (path, stored, lobe), and of the paper's
    /// two passes (they read its voxel view).
    pub stone: Option<std::sync::Arc<Stone>>,
    /// Their environment, its map read and its sampling distribution built (the stored
    /// method's: the backdrop).
    pub environment: Option<Environment>,
    /// Time of the structure and optics stages.
    pub times: StageTimes,
    /// The paper's two passes: the stone's cells, laid out at the first frame and shared by
    /// every later one (a sweep's).
    pub(crate) cells: OnceLock<VoxelLayout>,
}

/// Seconds since `since`.
pub(crate) fn seconds(since: Instant) -> f64 {
    since.elapsed().as_secs_f64()
}

/// Check `scene` (its fields, then what its method refuses) and build what its integrator
/// reads whatever the light angle: the structure and optics for the paper's two passes, the
/// stone model and environment for the others.
pub fn prepare(scene: &Scene) -> Result<Prepared> {
    crate::integrator::check(scene)?;
    let mut prepared = Prepared {
        scene: scene.clone(),
        structure: OnceLock::new(),
        optics: OnceLock::new(),
        stone: None,
        environment: None,
        times: StageTimes::default(),
        cells: OnceLock::new(),
    };
    prepared.integrator().prepare(&mut prepared)?;
    Ok(prepared)
}

impl Prepared {
    /// The grown structure (paper §2.4): the paper's two passes make it in `prepare`; for
    /// another method it is made now, on first use (not timed). Either way the prepared
    /// stone's voxel view ([`Stone::voxel_view`]: the growth's own cells for the paper's
    /// balls, any other stone read at the cell centres), else grown.
    pub fn structure(&self) -> Result<&Structure> {
        if let Some(structure) = self.structure.get() {
            return Ok(structure);
        }
        // The growth runs once: a stone of the paper's balls holds its cells, any other
        // stone is read at the cell centres.
        let structure = match self.stone.as_deref() {
            Some(stone) => stone.voxel_view(&voxel_grid(&self.scene))?.into_owned(),
            None => voxels(&self.scene)?,
        };
        Ok(self.structure.get_or_init(|| structure))
    }

    /// The cluster optics tables (paper §3.1), built as [`Prepared::structure`] is grown.
    pub fn optics(&self) -> Result<&OpticsTables> {
        if let Some(optics) = self.optics.get() {
            return Ok(optics);
        }
        let optics = build_optics(&self.scene.crystal, &self.scene.spectrum)?;
        Ok(self.optics.get_or_init(|| optics))
    }

    /// The structure to edit before rendering (tests of the passes on a structure made by
    /// hand); the cells laid out from the grown one are dropped.
    pub fn structure_mut(&mut self) -> Result<&mut Structure> {
        self.structure()?;
        self.cells = OnceLock::new();
        Ok(self.structure.get_mut().expect("grown just above"))
    }

    /// The optics tables to edit before rendering (tests: an index-matched furnace).
    pub fn optics_mut(&mut self) -> Result<&mut OpticsTables> {
        self.optics()?;
        Ok(self.optics.get_mut().expect("built just above"))
    }

    /// Grow the structure and build the optics now, timed as their stages: the paper's two
    /// passes' `prepare`.
    pub(crate) fn grow(&mut self) -> Result<()> {
        let start = Instant::now();
        // The passes read the stone's voxel view: the stone of the paper's balls holds the
        // grown cells, a grain stone is read at the cell centres.
        self.stone = Some(std::sync::Arc::new(Stone::new(&self.scene)?));
        self.structure()?;
        self.times.structure = seconds(start);
        let start = Instant::now();
        self.optics()?;
        self.times.optics = seconds(start);
        Ok(())
    }
}

impl Prepared {
    /// The same stone and optics seen in another pose: `scene`'s tilt, turn and environment
    /// rotation (`camera.tilt_deg`, `camera.turn_deg`, `environment.rotation_deg`) replace
    /// this one's. A sweep of the stone rocked and turned prepares it once.
    pub fn posed(
        &self,
        camera: &crate::scene::CameraConfig,
        rotation_deg: f64,
    ) -> Result<Prepared> {
        let mut posed = self.clone();
        posed.scene.camera = camera.clone();
        posed.scene.environment.rotation_deg = rotation_deg;
        crate::integrator::check(&posed.scene)?;
        posed.environment = posed
            .environment
            .map(|e| e.posed(&posed.scene.environment, &posed.scene.camera));
        Ok(posed)
    }
}

/// The cell grid the paper's two passes read a stone of grains on: the scene's grid over the
/// stone's own box (a cut stone's ellipsoid is the one in that box). The paper's balls keep
/// the grid they grew on, `[structure]`'s ellipsoid.
fn voxel_grid(scene: &Scene) -> StructureConfig {
    let mut grid = scene.structure.clone();
    grid.semi_axes_mm = scene.body.box_semi_axes(grid.semi_axes_mm);
    grid
}

/// Whether [`voxels`] grows `scene`'s cells (the paper's balls) rather than reading its
/// stone at the cell centres.
pub fn voxels_are_grown(scene: &Scene) -> bool {
    scene.domains.pattern == Pattern::Paper
}

/// The cells the paper's two passes read for `scene` ([`Stone::voxel_view`]): the grown
/// structure where the domains are the paper's balls, any other stone read at the cell
/// centres (`opalray structure` draws it).
pub fn voxels(scene: &Scene) -> Result<Structure> {
    if voxels_are_grown(scene) {
        return grow_structure(&scene.structure);
    }
    Stone::new(scene)?.sample_voxels(&voxel_grid(scene))
}

/// Render `scene` end to end.
pub fn render(scene: &Scene) -> Result<Frame> {
    let prepared = prepare(scene)?;
    Ok(prepared.render(scene.light.angle_deg))
}

impl Prepared {
    /// The frame for light angle `light_angle_deg`, by the scene's integrator.
    pub fn render(&self, light_angle_deg: f64) -> Frame {
        self.render_progressive(light_angle_deg, &Passes::default())
    }

    /// [`Prepared::render`], the path integrator's passes as `passes` says (a time limit, a
    /// report after each pass); the lobe integrator reports its rows (`passes.on_rows`), the
    /// other methods ignore `passes`.
    pub fn render_progressive(&self, light_angle_deg: f64, passes: &Passes) -> Frame {
        self.integrator().render(self, light_angle_deg, passes)
    }

    /// [`Prepared::render_progressive`] under `cancel` (see [`crate::cancel`]): the frame, or
    /// [`Error::Cancelled`](crate::error::Error::Cancelled) soon after `cancel` is set from
    /// another thread (the rows, tiles and passes not yet begun are skipped).
    pub fn render_cancellable(
        &self,
        light_angle_deg: f64,
        passes: &Passes,
        cancel: &crate::cancel::Cancel,
    ) -> Result<Frame> {
        let frame = cancel.scope(|| self.render_progressive(light_angle_deg, passes));
        cancel.check()?;
        Ok(frame)
    }

    /// The scene's integrator.
    pub fn integrator(&self) -> &'static dyn crate::integrator::Integrator {
        crate::integrator::of(self.scene.integrator.method())
    }

    /// Build the stone model and the environment (timed as structure and light pass): the
    /// inputs of the methods that render the stone.
    pub(crate) fn build_stone(&mut self) -> Result<()> {
        let scene = &self.scene;
        let start = Instant::now();
        let stone = Stone::new(scene)?;
        self.times.structure += seconds(start);
        // The lights are built once, for every frame: timed as the light pass.
        let start = Instant::now();
        let environment = Environment::new(&scene.environment, scene.render.background as f32)?
            .posed(&scene.environment, &scene.camera);
        self.times.light_pass = seconds(start);
        self.stone = Some(std::sync::Arc::new(stone));
        self.environment = Some(environment);
        Ok(())
    }
}

/// The path integrator's sample seed: `integrator.seed` mixed with `structure.seed`, so that
/// either changes every sample stream.
pub(crate) fn sample_seed(structure_seed: u64, integrator_seed: u64) -> u64 {
    mix64(structure_seed ^ mix64(integrator_seed))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{preset, IntegratorConfig, Method};

    /// `name` at 8 × 6.
    fn tiny(name: &str) -> Scene {
        let mut scene = preset(name).unwrap();
        scene.render.width = 8;
        scene.render.height = 6;
        scene
    }

    #[test]
    fn each_method_prepares_only_what_it_reads() {
        // The stone's methods grow no cell grid and build no optics tables.
        for method in [Method::Path, Method::Stored, Method::Lobe] {
            let mut scene = tiny("paper");
            scene.integrator = IntegratorConfig::of(method);
            let prepared = prepare(&scene).unwrap();
            assert!(prepared.stone.is_some(), "{method:?}");
            assert!(prepared.structure.get().is_none(), "{method:?}");
            assert!(prepared.optics.get().is_none(), "{method:?}");
            assert_eq!(prepared.render(30.0).void_ratio(), None, "{method:?}");
        }
        // The paper's two passes read the stone's voxel view: no environment, no second growth.
        let prepared = prepare(&tiny("paper")).unwrap();
        assert!(prepared.environment.is_none());
        assert!(prepared.structure.get().is_some() && prepared.cells.get().is_some());
        let voxels = prepared.stone.as_deref().and_then(Stone::voxels).unwrap();
        let structure = prepared.structure().unwrap();
        assert_eq!(voxels.cells, structure.cells);
        assert_eq!(voxels.orientations, structure.orientations);
    }

    #[test]
    fn a_frame_reports_its_own_methods_section_and_null_for_the_others() {
        let mut scene = tiny("paper");
        scene.integrator = IntegratorConfig::of(Method::Path);
        scene.integrator.set_spp(2);
        let frame = render(&scene).unwrap();
        assert_eq!(frame.path().map(|p| p.spp), Some(2));
        assert!(frame.stored().is_none());
        let sections = frame.method_stats(Method::Path);
        let keys: Vec<&str> = sections.keys().map(String::as_str).collect();
        assert_eq!(keys, ["path", "stored"]);
        assert_eq!(sections["path"]["spp"], 2);
        assert!(sections["stored"].is_null());
        // A method without a report of its own: every section null.
        scene.integrator = IntegratorConfig::of(Method::Lobe);
        let frame = render(&scene).unwrap();
        assert!(frame.report.is_none() && frame.path().is_none());
        assert!(frame
            .method_stats(Method::Lobe)
            .values()
            .all(|v| v.is_null()));
    }

    #[test]
    fn a_grain_stone_rendered_by_a_stone_method_reports_no_void_ratio() {
        // A grain stone is no voxel growth: no void ratio for `--stats` (issue 45 found the
        // paper's growth's reported for it), and no structure grown behind its back.
        for method in [Method::Path, Method::Lobe] {
            let mut scene = tiny("crystal");
            scene.integrator = IntegratorConfig::of(method);
            let prepared = prepare(&scene).unwrap();
            let stone = prepared.stone.as_deref().unwrap();
            assert!(stone.voxels().is_none(), "{method:?}");
            assert!(prepared.structure.get().is_none(), "{method:?}");
            assert_eq!(prepared.render(30.0).void_ratio(), None, "{method:?}");
        }
    }

    #[test]
    fn a_structure_asked_of_a_stone_method_is_the_two_passes_one() {
        let two_pass = prepare(&tiny("paper")).unwrap();
        let mut scene = tiny("paper");
        scene.integrator = IntegratorConfig::of(Method::Lobe);
        let lobe = prepare(&scene).unwrap();
        let (a, b) = (two_pass.structure().unwrap(), lobe.structure().unwrap());
        assert_eq!(a.cells, b.cells);
        assert_eq!(a.stats.void_ratio, b.stats.void_ratio);
        // Both are the stone's voxel view, which is the growth run on its own.
        let grown = grow_structure(&scene.structure).unwrap();
        assert_eq!(a.cells, grown.cells);
        assert_eq!(a.orientations, grown.orientations);
        assert_eq!(a.stats.seeds_placed, grown.stats.seeds_placed);
        assert_eq!(a.stats.mean_radius_cells, grown.stats.mean_radius_cells);
        let (a, b) = (two_pass.optics().unwrap(), lobe.optics().unwrap());
        assert_eq!(a.reflectance, b.reflectance);
    }
}
