//! The two scene models agree where both are defined: the stone model (`Stone`, the paper's
//! growth kept as analytic balls inside the body's outline) evaluated at every cell centre
//! gives the paper's grown cell structure (`grow_structure`, what the two passes read):
//! the same cells outside, void and cluster, and each cluster the same orientation, bit for
//! bit. This is what a voxel view of the one stone for the two passes rests on
//! (`docs/architecture.md`, "One world").

use glam::Vec3;
use opalray::light_pass::voxel_geometry;
use opalray::scene::preset;
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
