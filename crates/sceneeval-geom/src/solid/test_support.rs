//! Open boxes for the solid tests.

use crate::{Mesh, Vector3};

/// A unit cube (half extent 0.5) without its bottom face (two triangles): an open box.
pub(super) fn open_box() -> Mesh {
    let cube = Mesh::cuboid(&Vector3::repeat(0.5)).unwrap();
    Mesh::new(cube.vertices().to_vec(), cube.triangles()[2..].to_vec()).unwrap()
}

/// A unit cube (half extent 0.5) whose faces are split into `n` x `n` squares, without its
/// bottom face: an open box.
pub(super) fn open_cube(n: u32) -> Mesh {
    let cube = Mesh::subdivided_box(&Vector3::repeat(0.5), n).unwrap();
    let tris: Vec<[u32; 3]> = (0..cube.triangles().len())
        .filter(|&k| cube.triangle(k).iter().any(|p| p.z > -0.49))
        .map(|k| cube.triangles()[k])
        .collect();
    Mesh::new(cube.vertices().to_vec(), tris).unwrap()
}
