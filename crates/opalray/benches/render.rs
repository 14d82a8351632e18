//! Criterion benchmarks of the two passes at the paper's default scene (640 × 480, 40 bins,
//! 65 536 light rays, light at 30°): the light pass (§3.2), shading the stored light, the
//! view pass (§3.3) and a whole frame after `prepare` (what each frame of a sweep costs).

use criterion::Criterion;
use opalray::light_pass::{trace_light, ClusterOptics, LightSetup, Termination, VoxelLayout};
use opalray::render::prepare;
use opalray::scene::{Scene, BODY_EXTINCTION_PER_MM};
use opalray::view_pass::{trace_view, Shading, ViewSetup};

fn render(c: &mut Criterion) {
    let scene = Scene::default();
    let prepared = prepare(&scene).unwrap();
    let (camera, source) = prepared.placement(scene.light.angle_deg);
    let spectrum = prepared.light_spectrum();
    let albedo = scene.render.body_albedo();
    let light_setup = LightSetup {
        source,
        spectrum: &spectrum,
        rays: scene.light.rays,
        seed: scene.structure.seed,
        body_albedo: albedo,
        body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
        termination: Termination::DEFAULT,
    };
    let cells = VoxelLayout::new(prepared.structure().unwrap());
    let mut group = c.benchmark_group("render");
    group.sample_size(10);
    group.bench_function("light_pass_default", |b| {
        b.iter(|| {
            trace_light(
                prepared.structure().unwrap(),
                &cells,
                prepared.optics().unwrap(),
                &light_setup,
            )
        })
    });
    let light = trace_light(
        prepared.structure().unwrap(),
        &cells,
        prepared.optics().unwrap(),
        &light_setup,
    );
    let optics = ClusterOptics::new(prepared.optics().unwrap());
    let exponent = scene.render.phong_exponent as f32;
    let shade = || {
        Shading::new(
            prepared.structure().unwrap(),
            &cells,
            &optics,
            &light,
            exponent,
            albedo,
        )
    };
    group.bench_function("shading_default", |b| b.iter(shade));
    let shading = shade();
    let view_setup = ViewSetup {
        camera,
        width: scene.render.width as usize,
        height: scene.render.height as usize,
        source,
        light_spectrum: &spectrum,
        phong_exponent: exponent,
        gloss: scene.render.gloss as f32,
        background: scene.render.background as f32,
        body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
        reflection_block: scene.render.reflection_block as usize,
    };
    group.bench_function("view_pass_640x480", |b| {
        b.iter(|| {
            trace_view(
                prepared.structure().unwrap(),
                prepared.optics().unwrap(),
                &light,
                &shading,
                &view_setup,
            )
        })
    });
    group.bench_function("frame_after_prepare", |b| {
        b.iter(|| prepared.render_in(&cells, 30.0))
    });
    group.finish();
}

fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    render(&mut criterion);
    criterion.final_summary();
}
