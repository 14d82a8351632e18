//! The two scene models agree where both are defined: the stone model (`Stone`, the paper's
//! growth kept as analytic balls inside the body's outline) evaluated at every cell centre
//! gives the paper's grown cell structure (`grow_structure`, what the two passes read):
//! the same cells outside, void and cluster, and each cluster the same orientation, bit for
//! bit. This is what a voxel view of the one stone for the two passes rests on
//! (`docs/architecture.md`, "One world").

use glam::Vec3;
use opalray::geometry::CellGrid;
use opalray::light_pass::voxel_geometry;
use opalray::prepare;
use opalray::scene::{preset, EnvironmentKind, LightKind, Method};
use opalray::stone::Stone;
use opalray::structure::{grow_structure, Cell};

/// Per preset: `(cells whose inside/outside differs, kind differs, orientation differs)`,
/// and the cluster and void cells compared.
fn disagreements(name: &str) -> ((usize, usize, usize), [usize; 2]) {
    let scene = preset(name).unwrap();
    let structure = grow_structure(&scene.structure).unwrap();
    let stone = Stone::new(&scene).unwrap();
    let (_, grid) = voxel_geometry(&structure);
    let [nx, ny, nz] = structure.grid;
    let (mut outside, mut kind, mut orientation) = (0, 0, 0);
    let mut compared = [0usize; 2];
    for i in 0..nx * ny * nz {
        let (x, y, z) = (i % nx, i / nx % ny, i / (nx * ny));
        let centre = grid.min + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * grid.cell;
        let cell = structure.cells[i];
        let inside = stone.shape.contains(centre);
        if inside != (cell != Cell::Outside) {
            outside += 1;
            continue;
        }
        match (inside.then(|| stone.domain_at(centre)).flatten(), cell) {
            (Some(k), Cell::Cluster) => {
                compared[0] += 1;
                let q = stone.domains[k as usize].orientation;
                if q.to_array() != structure.orientations[i].to_array() {
                    orientation += 1;
                }
            }
            (None, Cell::Void) => compared[1] += 1,
            (None, Cell::Outside) => {}
            _ => kind += 1,
        }
    }
    ((outside, kind, orientation), compared)
}

#[test]
fn the_stone_at_the_cell_centres_is_the_grown_structure() {
    for name in ["paper", "paper-path"] {
        let (differ, [clusters, voids]) = disagreements(name);
        assert_eq!(differ, (0, 0, 0), "{name}");
        // Both kinds are met in numbers on the 100 × 75 × 25 grid.
        assert!(
            clusters > 10_000 && voids > 10_000,
            "{name}: {clusters} {voids}"
        );
    }
}

#[test]
fn reading_the_paper_stone_at_the_cell_centres_gives_its_grown_cells() {
    // `Stone::sample_voxels`, the view of a stone that holds no grown cells, against the
    // growth itself on the stone of the paper's balls: every cell, kind and orientation.
    let scene = preset("paper").unwrap();
    let grown = grow_structure(&scene.structure).unwrap();
    let read = Stone::new(&scene)
        .unwrap()
        .sample_voxels(&scene.structure)
        .unwrap();
    assert_eq!(read.cells, grown.cells);
    let bits = |s: &opalray::Structure| -> Vec<[u32; 4]> {
        s.orientations
            .iter()
            .map(|q| q.to_array().map(f32::to_bits))
            .collect()
    };
    assert!(bits(&read) == bits(&grown), "orientations differ");
    assert_eq!(
        (
            read.stats.inside_cells,
            read.stats.clusters,
            read.stats.voids
        ),
        (
            grown.stats.inside_cells,
            grown.stats.clusters,
            grown.stats.voids
        )
    );
    assert_eq!(read.stats.void_ratio, grown.stats.void_ratio);
}

#[test]
fn the_two_passes_read_a_grain_stone_s_own_domains() {
    // A grain stone under the paper's two passes: the cells they read are that stone's
    // domains at the cell centres (they used to be the paper's growth, another stone).
    let mut scene = preset("harlequin").unwrap();
    scene.light.kind = LightKind::Directional;
    scene.environment.kind = EnvironmentKind::None;
    scene.integrator = scene.integrator.switched(Method::TwoPass);
    let prepared = prepare(&scene).unwrap();
    let stone = prepared
        .stone
        .clone()
        .expect("the two passes build the stone");
    let cells = prepared.structure().unwrap();
    let axes = scene.body.box_semi_axes(scene.structure.semi_axes_mm);
    assert_eq!(cells.semi_axes_mm, axes, "the grid is over the stone's box");
    let grid = CellGrid::centered(cells.grid, Vec3::from_array(axes.map(|v| v as f32)));
    let [nx, ny, _] = cells.grid;
    let (mut same, mut clusters, mut voids_in_domains) = (0, 0, 0);
    for (i, cell) in cells.cells.iter().enumerate() {
        let (x, y, z) = (i % nx, i / nx % ny, i / (nx * ny));
        let centre = grid.min + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * grid.cell;
        match (cell, stone.domain_at(centre)) {
            (Cell::Cluster, Some(d)) => {
                clusters += 1;
                same += usize::from(stone.domains[d as usize].orientation == cells.orientations[i]);
            }
            (Cell::Cluster, None) => clusters += 1,
            (Cell::Void, Some(_)) => voids_in_domains += 1,
            _ => {}
        }
    }
    assert!(clusters > 10_000, "{clusters} cluster cells");
    assert_eq!(
        same, clusters,
        "cells whose orientation is the stone's domain's there"
    );
    assert_eq!(
        voids_in_domains, 0,
        "void cells whose centre is in a domain"
    );
    // Voids no growth would stop at: the potch under the colour bar, and the ellipsoid's
    // ring beyond the cabochon's dome near the girdle.
    assert!(cells.stats.void_ratio > 0.3, "{}", cells.stats.void_ratio);
}
