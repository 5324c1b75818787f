//! The fixed configurations of the relation benchmarks, shared by `benches/relations.rs`
//! (criterion) and `examples/relations_profile.rs` (instruction counts): a nightstand
//! straddling a bed's left face, the same as meshes, and a bed 5 cm from the head wall of a
//! four-wall room with a door and a window.

use sceneeval_geom::{Isometry3, Mesh, Obb, Point3, Real, Side, Vector3};
use sceneeval_relations::{ArchElement, LongShort, ObjectGeom, Relation};
use sceneeval_scene::Room;

pub fn bx(c: [Real; 3], h: [Real; 3], yaw: Real) -> Obb {
    Obb::from_yaw(Point3::new(c[0], c[1], c[2]), Vector3::new(h[0], h[1], h[2]), yaw).expect("a valid box")
}

/// A mesh object: the mesh, its pose and its box.
pub struct MeshObject {
    pub mesh: Mesh,
    pub pose: Isometry3,
    pub obb: Obb,
}

impl MeshObject {
    pub fn new(mesh: Mesh, center: [Real; 3], yaw: Real) -> Self {
        let pose = Isometry3::new(Vector3::new(center[0], center[1], center[2]), Vector3::z() * yaw);
        let obb = Obb::from_local_aabb(mesh.aabb(), &pose);
        MeshObject { mesh, pose, obb }
    }

    pub fn view(&self) -> ObjectGeom<'_> {
        ObjectGeom::with_mesh(&self.obb, &self.mesh, &self.pose)
    }
}

/// The test bedroom with a window on wall 1 (x = 4), y in [1.5, 3.5], 0.9 to 2.0 m up.
pub fn room() -> Room {
    sceneeval_test_support::bedroom("bedroom")
        .window(1, [1.5, 3.5], [0.9, 2.0])
        .build()
        .expect("a valid room")
}

/// The bed (1.6 x 2 x 0.6 m) and the nightstand straddling its left face and height limit.
pub fn bed_and_stand() -> (Obb, Obb) {
    (
        bx([2.0, 4.0, 0.3], [0.8, 1.0, 0.3], 0.0),
        bx([1.0, 4.5, 0.35], [0.25, 0.2, 0.35], 0.3),
    )
}

/// The same as meshes: a 5,000-triangle ellipsoid and a box of 4,800 triangles, 6 cm apart.
pub fn mesh_bed_and_stand() -> (MeshObject, MeshObject) {
    (
        MeshObject::new(
            Mesh::uv_ellipsoid(&Vector3::new(0.8, 1.0, 0.3), 50, 51).expect("mesh"),
            [2.0, 4.0, 0.3],
            0.0,
        ),
        MeshObject::new(
            Mesh::subdivided_box(&Vector3::new(0.25, 0.2, 0.35), 20).expect("mesh"),
            [0.9, 4.5, 0.35],
            0.3,
        ),
    )
}

/// `face_to` where lines hit: a sofa (2 x 0.9 x 0.8 m) turned to face +y and a TV 3 m ahead of
/// it, 0.4 m to the side and turned a little, as boxes; and the TV as a 5,000-triangle mesh.
pub fn sofa_and_tv() -> (Obb, Obb, MeshObject) {
    let tv = ([0.4, 3.0, 1.0], [0.6, 0.05, 0.4], 0.2);
    (
        bx([0.0, 0.0, 0.4], [1.0, 0.45, 0.4], std::f64::consts::PI),
        bx(tv.0, tv.1, tv.2),
        MeshObject::new(
            Mesh::uv_ellipsoid(&Vector3::from(tv.1), 50, 51).expect("mesh"),
            tv.0,
            tv.2,
        ),
    )
}

/// The bed 5 cm from the head wall, a little turned, as a box and as a mesh.
pub fn wall_bed() -> (Obb, MeshObject) {
    (
        bx([2.0, 3.93, 0.3], [0.8, 1.0, 0.3], 0.05),
        MeshObject::new(
            Mesh::uv_ellipsoid(&Vector3::new(0.8, 1.0, 0.3), 50, 51).expect("mesh"),
            [2.0, 3.93, 0.3],
            0.05,
        ),
    )
}

/// The two-object relations benchmarked, one per base name (sides: one representative each).
pub fn pair_relations() -> [(&'static str, Relation); 12] {
    [
        ("inside_of", Relation::InsideOf),
        ("outside_of", Relation::OutsideOf),
        ("face_to", Relation::FaceTo),
        ("side_of", Relation::SideOf(Side::Left)),
        ("side_region", Relation::SideRegion(Side::Left)),
        ("long_short_side_of", Relation::LongShortSideOf(LongShort::Long)),
        ("on_top", Relation::OnTop),
        ("middle_of", Relation::MiddleOf),
        ("next_to", Relation::NextTo),
        ("near", Relation::Near),
        ("across_from", Relation::AcrossFrom),
        ("far", Relation::Far),
    ]
}

pub fn arch_relations() -> [(&'static str, Relation); 10] {
    [
        ("next_to_wall", Relation::NextToArch(ArchElement::Wall)),
        ("near_door", Relation::NearArch(ArchElement::Door)),
        (
            "across_from_window",
            Relation::AcrossFromArch(ArchElement::Window),
        ),
        ("far_wall", Relation::FarArch(ArchElement::Wall)),
        ("inside_room", Relation::InsideRoom),
        ("middle_of_room", Relation::MiddleOfRoom),
        ("corner_of_room", Relation::CornerOfRoom),
        ("on_wall", Relation::OnWall),
        ("against_wall", Relation::AgainstWall),
        ("hang_from_ceiling", Relation::HangFromCeiling),
    ]
}
