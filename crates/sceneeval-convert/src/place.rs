//! Placing a generator's object: its rotation (and scale) as a sceneState transform in the
//! convention of its model id, and its position as the generators give it: where its **box
//! centre** is, or for objects standing on the floor, where its lowest point is. The box is
//! the object's mesh bounds (its OBB), so placement does not depend on where an asset file puts
//! its origin.

use std::path::Path;

use sceneeval_geom::na::Translation3;
use sceneeval_geom::{Isometry3, Point3, Real, Rotation3, Vector3};
use sceneeval_io::AssetLibrary;
use sceneeval_io::frames::{ObjectFront, TransformFrame, compose_sstk};
use sceneeval_scene::SceneObject;

use crate::ConvertError;

/// Where an object goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Target {
    /// Its OBB centre at this point.
    Centre(Point3),
    /// Its OBB centre above `(x, y)` and its lowest point at `floor_z`.
    OnFloor {
        /// World x of the OBB centre.
        x: Real,
        /// World y of the OBB centre.
        y: Real,
        /// World z of its lowest point.
        floor_z: Real,
    },
}

/// The object showing asset `model_id` with the transform `[rotation * diag(scale) | t]` in the
/// convention of its model id ([`TransformFrame::for_model_id`]), the declared `front`, and the
/// translation `t` that puts it at `target`. `file` and `pointer` name the generator's object
/// in errors.
#[allow(clippy::too_many_arguments)]
pub(crate) fn place(
    library: &AssetLibrary,
    id: &str,
    model_id: &str,
    rotation: &Rotation3,
    scale: &Vector3,
    front: ObjectFront,
    target: Target,
    (file, pointer): (&Path, &str),
) -> Result<SceneObject, ConvertError> {
    let data = compose_sstk(rotation, scale, &Vector3::zeros());
    let placed = TransformFrame::for_model_id(model_id)
        .placed(&data)
        .map_err(|e| sceneeval_io::IoError::InvalidValue {
            path: file.to_owned(),
            pointer: pointer.to_owned(),
            reason: format!("the object's rotation and scale give no transform: {e}"),
        })?;
    let mut object = library
        .object_facing(id, model_id, &placed, front)
        .map_err(|e| ConvertError::asset(file, pointer, model_id, e))?;
    // At the origin, the OBB centre is where the translation must move from.
    let centre = object.obb().center;
    let translation = match target {
        Target::Centre(p) => p - centre,
        Target::OnFloor { x, y, floor_z } => {
            Vector3::new(x - centre.x, y - centre.y, floor_z - object.world_aabb().min.z)
        }
    };
    let pose = Isometry3::from_parts(Translation3::from(translation), object.pose().rotation);
    object
        .set_pose(pose)
        .map_err(|e| ConvertError::scene(file, pointer, e))?;
    Ok(object)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sceneeval_io::assets::PlainFolderSource;
    use sceneeval_io::{GlbMesh, write_glb};

    /// A 1 x 0.5 x 0.6 m box asset (x, y-up, z) with its origin at its bottom centre.
    fn library(dir: &Path) -> AssetLibrary {
        let (mut p, mut i) = (Vec::new(), Vec::new());
        for k in 0..8u32 {
            p.push([
                if k & 1 == 0 { -0.5 } else { 0.5 },
                if k & 2 == 0 { 0.0 } else { 0.5 },
                if k & 4 == 0 { -0.3 } else { 0.3 },
            ]);
        }
        for t in [
            [0, 2, 1],
            [1, 2, 3],
            [4, 5, 6],
            [5, 7, 6],
            [0, 1, 4],
            [1, 5, 4],
            [2, 6, 3],
            [3, 6, 7],
            [0, 4, 2],
            [2, 4, 6],
            [1, 3, 5],
            [3, 7, 5],
        ] {
            i.extend(t);
        }
        write_glb(&dir.join("crate.glb"), &[GlbMesh::new("crate", p, i)]).unwrap();
        AssetLibrary::new().with_source("fixture", PlainFolderSource::new(dir))
    }

    #[test]
    fn box_centres_and_floors_land_where_asked() {
        let dir = tempfile::tempdir().unwrap();
        let lib = library(dir.path());
        // Upright: Rx(+90) maps the asset's y-up to z-up. Object frame: x in [-0.5, 0.5],
        // y in [-0.3, 0.3], z in [0, 0.5]; local box centre (0, 0, 0.25).
        let upright = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        let at = (Path::new("layout.json"), "/crate-0");
        let o = place(
            &lib,
            "a",
            "fixture.crate",
            &upright,
            &Vector3::repeat(1.0),
            ObjectFront::MinusY,
            Target::Centre(Point3::new(2.0, 1.0, 1.25)),
            at,
        )
        .unwrap();
        assert!((o.obb().center - Point3::new(2.0, 1.0, 1.25)).norm() < 1e-7);
        // The translation is the origin's place: 0.25 below the centre.
        assert!((o.pose().translation.vector - Vector3::new(2.0, 1.0, 1.0)).norm() < 1e-7);
        // Tilted by 90 degrees about world y: the box lies on its side; on the floor, its
        // lowest point is at z = 0 and its centre half its width (0.5) up.
        let tilted = Rotation3::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2) * upright;
        let o = place(
            &lib,
            "b",
            "fixture.crate",
            &tilted,
            &Vector3::repeat(1.0),
            ObjectFront::MinusY,
            Target::OnFloor {
                x: 1.0,
                y: 1.0,
                floor_z: 0.0,
            },
            at,
        )
        .unwrap();
        assert!(o.world_aabb().min.z.abs() < 1e-7);
        assert!((o.obb().center - Point3::new(1.0, 1.0, 0.5)).norm() < 1e-7);
    }
}
