//! Scores a nightstand, a bed and a ball in a bedroom, with gradients, using
//! `sceneeval-relations` alone.

use std::error::Error;
use std::io::Write;

use sceneeval_relations::prelude::*;

fn main() -> Result<(), Box<dyn Error>> {
    let params = RelationParams::default();
    // A 4 x 5 m bedroom with 2.8 m walls and a door in wall 0 (the wall along y = 0).
    let room = RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
        .wall_height(2.8)
        .wall_thickness(0.1)
        .door(0, [2.6, 3.5], [0.0, 2.1])
        .build()?;
    // Boxes: centre and half extents in metres, yaw in radians (front = local -y).
    let bed = Obb::from_yaw(Point3::new(2.0, 4.0, 0.3), Vector3::new(0.8, 1.0, 0.3), 0.0)?;
    let stand = Obb::from_yaw(Point3::new(0.9, 4.6, 0.3), Vector3::new(0.25, 0.2, 0.3), 0.0)?;
    // A mesh object: a ball placed by its pose; its box is the mesh's bounds.
    let ball = Mesh::uv_ellipsoid(&Vector3::repeat(0.25), 16, 9)?;
    let ball_pose = pose_from_yaw(Point3::new(2.0, 2.0, 0.25), 0.0);
    let ball_box = Obb::from_local_aabb(ball.aabb(), &ball_pose);

    let bed = ObjectGeom::from_box(&bed);
    let stand = ObjectGeom::from_box(&stand);
    let ball = ObjectGeom::with_mesh(&ball_box, &ball, &ball_pose);
    let rooms = [room];
    let mut out = std::io::stdout().lock();

    // Any relation by name: the target first, then the anchor (or the rooms).
    for name in ["side_of(left)", "next_to", "face_to"] {
        let relation: Relation = name.parse()?;
        let score = batch::score_pair(relation, &stand, &bed, &params)?;
        writeln!(out, "nightstand {name} bed: {score:.3}")?;
    }
    let against = arch::score_rooms(Relation::AgainstWall, &bed, &rooms, &params)?;
    writeln!(
        out,
        "bed against_wall: {against:.3} (holds: {})",
        params.holds(against)
    )?;

    // A score with its gradient: d score / d (cx, cy, cz, hx, hy, hz, yaw) of each object
    // (for a mesh object, with respect to its pose).
    let g = grad::pair(Relation::NextTo, &ball, &bed, &params)?;
    writeln!(
        out,
        "ball next_to bed: {:.3}, d/d ball {:.3?}",
        g.score,
        g.target.to_array()
    )?;
    let door = Relation::AcrossFromArch(ArchElement::Door);
    let g = grad::arch_rooms(door, &stand, &rooms, &params)?;
    writeln!(
        out,
        "nightstand across_from(door): {:.3}, d/d nightstand {:.3?}",
        g.score,
        g.target.to_array()
    )?;
    Ok(())
}
