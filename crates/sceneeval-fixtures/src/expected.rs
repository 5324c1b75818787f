//! The expected answers of `fixtures/expected.json`, derived from the same specs that built the
//! scenes and measured on the built scenes (so the numbers are those of the files as written,
//! with the assets' `f32` vertex coordinates).
//!
//! Lists are complete: an empty `collisions` list claims that no pair of objects
//! interpenetrates, an empty `floating` list that every object touches what holds it up, and so
//! on. Lengths are in metres, rounded to 1e-6 (the assets' `f32` coordinates move faces by up
//! to about 1e-7 m).
//!
//! The fields (this table is also in the generated `fixtures/README.md`):
//!
#![doc = include_str!("expected_fields.md")]

use serde::{Deserialize, Serialize};

use sceneeval_geom::{Point3, Real, Vector3};
use sceneeval_scene::{OpeningKind, Room, Scene, SceneObject, SupportType};

use crate::FixtureError;
use crate::spec::{Flaw, Model, SceneSpec, Support};

/// The `format` value of `expected.json`.
pub const FORMAT: &str = "sceneeval-fixtures-expected";
/// The `version` value of `expected.json`.
pub const VERSION: u32 = 1;
/// Rounding step of every length in `expected.json` (metres).
pub const ROUNDING: Real = 1e-6;

/// The whole `expected.json` document.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Expected {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u32,
    /// Rounding step of the lengths (metres): compare with at least this tolerance.
    pub rounding: Real,
    /// The asset prefix of the model ids (`fixture`).
    pub asset_prefix: String,
    /// The asset folder, relative to the fixtures folder (`assets`, plain layout).
    pub asset_dir: String,
    /// One entry per scene, in number order.
    pub scenes: Vec<ExpectedScene>,
}

/// What a test can check on one scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedScene {
    /// The scene number (annotation ID).
    pub id: u32,
    /// The scene file, relative to the fixtures folder.
    pub file: String,
    /// Short title.
    pub title: String,
    /// One-sentence description.
    pub description: String,
    /// Whether the scene was built without deliberate flaws.
    pub clean: bool,
    /// Rooms with their doors and windows.
    pub rooms: Vec<ExpectedRoom>,
    /// Every object, in file order.
    pub objects: Vec<ExpectedObject>,
    /// Interpenetrating or nested object pairs (complete list).
    pub collisions: Vec<ExpectedCollision>,
    /// Objects hovering above the floor (complete list).
    pub floating: Vec<ExpectedFloating>,
    /// Objects sticking out of the rooms (complete list).
    pub out_of_bounds: Vec<ExpectedOutOfBounds>,
    /// Doors blocked on their room side (complete list).
    pub blocked_doors: Vec<ExpectedBlockedDoor>,
    /// Objects lying entirely inside another (complete list).
    pub inside: Vec<ExpectedInside>,
    /// See the module docs; `None` when not claimed.
    pub navigable: Option<bool>,
}

/// A room of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedRoom {
    /// Room id.
    pub id: String,
    /// Room type, if set.
    pub kind: Option<String>,
    /// Floor element id.
    pub floor_id: String,
    /// Floor area in square metres.
    pub floor_area: Real,
    /// Number of walls.
    pub walls: usize,
    /// Door opening ids.
    pub doors: Vec<String>,
    /// Window opening ids.
    pub windows: Vec<String>,
}

/// One object of a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedObject {
    /// Object id as read from the file (`idx<index>_<modelId>` or `idx<index>_box`).
    pub id: String,
    /// Category (from the asset's metadata or the box entry).
    pub category: String,
    /// Model id, for asset objects.
    pub model_id: Option<String>,
    /// The room the object's bottom centre stands in.
    pub room: Option<String>,
    /// World position of the bottom centre (metres).
    pub position: [Real; 3],
    /// Yaw in degrees, in (-180, 180].
    pub yaw_deg: Real,
    /// OBB size in the object frame: width x, depth y, height z (metres, scale applied).
    pub size: [Real; 3],
    /// Support type: `ground`, `object`, `wall` or `ceiling` (what it should rest on; the scene
    /// file states the same as the object's `supportType`).
    pub support_type: SupportType,
    /// What it touches: a floor id, an object id, a wall id or `ceiling_<room>`; `None` when
    /// it touches nothing.
    pub supported_by: Option<String>,
    /// Whether its support holds it: it touches it, and for `ground` and `object` its centre
    /// of mass lies over its contacts.
    pub supported: bool,
}

/// A colliding pair.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedCollision {
    /// First object id.
    pub a: String,
    /// Second object id.
    pub b: String,
    /// `penetration` (surfaces cross) or `containment` (`b` lies entirely inside `a`).
    pub kind: String,
    /// Penetration depth in metres (see the module docs); `None` for containment.
    pub depth: Option<Real>,
    /// The world axis of the separating translation (`x`, `y` or `z`).
    pub axis: Option<String>,
}

/// A floating object.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedFloating {
    /// Object id.
    pub object: String,
    /// Gap between its lowest point and the floor (metres).
    pub gap: Real,
    /// The floor below it.
    pub floor: String,
}

/// An object partly outside the rooms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedOutOfBounds {
    /// Object id.
    pub object: String,
    /// The wall it crosses.
    pub wall: String,
    /// Share of its surface area beyond the wall, in [0, 1].
    pub outside_share: Real,
}

/// A blocked door.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedBlockedDoor {
    /// The door's opening id.
    pub door: String,
    /// Its room.
    pub room: String,
    /// The blocking objects.
    pub blocked_by: Vec<String>,
    /// Share of the door rectangle the blockers cover, in [0, 1].
    pub occluded_fraction: Real,
    /// Distance from the wall's inner face to the blocker (metres).
    pub gap_to_wall: Real,
}

/// An object inside another.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExpectedInside {
    /// The enclosed object.
    pub inner: String,
    /// The enclosing object.
    pub outer: String,
    /// Smallest distance between the two surfaces (metres).
    pub clearance: Real,
}

/// Rounds to [`ROUNDING`] (the nearest double to a whole number of micrometres, so that
/// 0.1 prints as `0.1`) and turns `-0` into `0`.
pub fn round(x: Real) -> Real {
    const STEPS_PER_METRE: Real = 1e6;
    (x * STEPS_PER_METRE).round() / STEPS_PER_METRE + 0.0
}

fn round3(v: &Vector3) -> [Real; 3] {
    [round(v.x), round(v.y), round(v.z)]
}

/// Category of a placement: the asset's (from the catalog that wrote its metadata) or the box's.
fn category(model: &Model) -> String {
    match model {
        Model::Asset(id) => {
            crate::assets::asset(id).map_or_else(|| (*id).to_owned(), |a| a.category.to_owned())
        }
        Model::Box { category, .. } => (*category).to_owned(),
    }
}

struct Ctx<'a> {
    spec: &'a SceneSpec,
    scene: &'a Scene,
    name: String,
}

impl Ctx<'_> {
    fn object(&self, key: &str) -> Result<&SceneObject, FixtureError> {
        self.spec
            .index_of(key)
            .and_then(|i| self.scene.objects().get(i))
            .ok_or_else(|| FixtureError::spec(&self.name, format!("unknown object key {key:?}")))
    }

    fn id(&self, key: &str) -> Result<String, FixtureError> {
        Ok(self.object(key)?.id().to_string())
    }

    fn room_of(&self, o: &SceneObject) -> Option<&Room> {
        let p = o.pose().translation.vector;
        self.scene.room_at(&sceneeval_geom::Point2::new(p.x, p.y))
    }

    fn wall(&self, id: &str) -> Result<(&Room, &sceneeval_scene::Wall), FixtureError> {
        self.scene
            .walls()
            .find(|(_, w)| w.id() == id)
            .ok_or_else(|| FixtureError::spec(&self.name, format!("unknown wall {id:?}")))
    }
}

/// The expected answers for one scene built from `spec`.
///
/// # Errors
/// [`FixtureError::Spec`] when a flaw names an unknown object, wall or door, or cannot be
/// measured (e.g. a collision between objects that are not axis-aligned).
pub fn expected_scene(spec: &SceneSpec, scene: &Scene) -> Result<ExpectedScene, FixtureError> {
    let ctx = Ctx {
        spec,
        scene,
        name: spec.name(),
    };
    let rooms = scene.rooms().iter().map(expected_room).collect();
    let objects = spec
        .objects
        .iter()
        .zip(scene.objects())
        .map(|(p, o)| expected_object(&ctx, p, o))
        .collect::<Result<Vec<_>, _>>()?;
    let mut out = ExpectedScene {
        id: spec.number,
        file: format!("scenes/{}.json", spec.name()),
        title: spec.title.to_owned(),
        description: spec.description.to_owned(),
        clean: spec.flaws.is_empty(),
        rooms,
        objects,
        collisions: vec![],
        floating: vec![],
        out_of_bounds: vec![],
        blocked_doors: vec![],
        inside: vec![],
        navigable: spec.navigable,
    };
    for flaw in &spec.flaws {
        match flaw {
            Flaw::Collision { a, b } => out.collisions.push(collision(&ctx, a, b)?),
            Flaw::Floating { object } => out.floating.push(floating(&ctx, object)?),
            Flaw::OutOfBounds { object, wall } => out.out_of_bounds.push(out_of_bounds(&ctx, object, wall)?),
            Flaw::BlockedDoor { door, by } => out.blocked_doors.push(blocked_door(&ctx, door, by)?),
            Flaw::Inside { inner, outer } => {
                let inside = inside(&ctx, inner, outer)?;
                out.collisions.push(ExpectedCollision {
                    a: inside.outer.clone(),
                    b: inside.inner.clone(),
                    kind: "containment".into(),
                    depth: None,
                    axis: None,
                });
                out.inside.push(inside);
            }
        }
    }
    Ok(out)
}

fn expected_room(room: &Room) -> ExpectedRoom {
    let mut doors = Vec::new();
    let mut windows = Vec::new();
    for w in room.walls() {
        for o in w.openings() {
            match o.kind {
                OpeningKind::Door => doors.push(o.id.clone()),
                OpeningKind::Window => windows.push(o.id.clone()),
            }
        }
    }
    ExpectedRoom {
        id: room.id().to_string(),
        kind: room.kind().map(str::to_owned),
        floor_id: room.floor_id().to_owned(),
        floor_area: round(room.floor().area()),
        walls: room.walls().len(),
        doors,
        windows,
    }
}

fn expected_object(
    ctx: &Ctx<'_>,
    p: &crate::spec::Placement,
    o: &SceneObject,
) -> Result<ExpectedObject, FixtureError> {
    let room = ctx.room_of(o);
    let supported_by = match &p.support {
        Support::Floor => room.map(|r| r.floor_id().to_owned()),
        Support::On(key) => Some(ctx.id(key)?),
        Support::Wall(wall) => Some(ctx.wall(wall)?.1.id().to_owned()),
        Support::Ceiling => room.map(|r| {
            r.explicit_ceiling()
                .map_or_else(|| format!("ceiling_{}", r.id()), |c| c.id.clone())
        }),
        Support::Nothing => None,
    };
    let mut yaw = round(o.yaw().to_degrees());
    if yaw <= -180.0 {
        yaw += 360.0;
    }
    let position = o.pose().translation.vector;
    Ok(ExpectedObject {
        id: o.id().to_string(),
        category: category(&p.model),
        model_id: p.model_id(),
        room: room.map(|r| r.id().to_string()),
        position: round3(&position),
        yaw_deg: yaw,
        size: round3(&o.obb().extents()),
        support_type: p.support.support_type(p.intended_support),
        supported_by,
        supported: p.support != Support::Nothing && p.held,
    })
}

/// Whether the object's yaw is a multiple of 90 degrees (its world AABB is its OBB).
fn axis_aligned(o: &SceneObject) -> bool {
    let q = o.yaw() / std::f64::consts::FRAC_PI_2;
    (q - q.round()).abs() < 1e-9
}

fn collision(ctx: &Ctx<'_>, a: &str, b: &str) -> Result<ExpectedCollision, FixtureError> {
    let (oa, ob) = (ctx.object(a)?, ctx.object(b)?);
    if !axis_aligned(oa) || !axis_aligned(ob) {
        return Err(FixtureError::spec(
            &ctx.name,
            format!("collision {a}/{b}: the depth is only measured for axis-aligned objects"),
        ));
    }
    let overlap = oa.world_aabb().intersection(ob.world_aabb()).ok_or_else(|| {
        FixtureError::spec(
            &ctx.name,
            format!("collision {a}/{b}: the objects do not overlap"),
        )
    })?;
    let e = overlap.extents();
    let (axis, depth) =
        [("x", e.x), ("y", e.y), ("z", e.z)]
            .into_iter()
            .fold(
                ("x", Real::INFINITY),
                |best, c| if c.1 < best.1 { c } else { best },
            );
    if depth <= 0.0 {
        return Err(FixtureError::spec(
            &ctx.name,
            format!("collision {a}/{b}: only touching"),
        ));
    }
    Ok(ExpectedCollision {
        a: ctx.id(a)?,
        b: ctx.id(b)?,
        kind: "penetration".into(),
        depth: Some(round(depth)),
        axis: Some(axis.into()),
    })
}

fn floating(ctx: &Ctx<'_>, key: &str) -> Result<ExpectedFloating, FixtureError> {
    let o = ctx.object(key)?;
    let room = ctx
        .room_of(o)
        .ok_or_else(|| FixtureError::spec(&ctx.name, format!("{key} stands over no floor")))?;
    Ok(ExpectedFloating {
        object: o.id().to_string(),
        gap: round(o.world_aabb().min.z - room.floor_z()),
        floor: room.floor_id().to_owned(),
    })
}

/// Area of the part of triangle `t` where `plane(p) < 0`, by clipping the triangle against the
/// plane (Sutherland-Hodgman with one plane) and fanning the clipped polygon.
fn area_below(t: [Point3; 3], plane: impl Fn(&Point3) -> Real) -> Real {
    let mut poly: Vec<Point3> = Vec::with_capacity(4);
    for i in 0..3 {
        let (p, q) = (t[i], t[(i + 1) % 3]);
        let (dp, dq) = (plane(&p), plane(&q));
        if dp < 0.0 {
            poly.push(p);
        }
        if (dp < 0.0) != (dq < 0.0) {
            let s = dp / (dp - dq);
            poly.push(p + (q - p) * s);
        }
    }
    (1..poly.len().saturating_sub(1))
        .map(|i| (poly[i] - poly[0]).cross(&(poly[i + 1] - poly[0])).norm() * 0.5)
        .sum()
}

/// Share of the object's surface area on the outer side of `wall`'s inner face.
pub fn share_beyond_wall(o: &SceneObject, wall: &sceneeval_scene::Wall) -> Real {
    let plane = wall.inner_plane();
    let pose = o.pose();
    let mesh = o.mesh();
    let mut outside = 0.0;
    for i in 0..mesh.triangles().len() {
        let t = mesh.triangle(i).map(|p| pose * p);
        outside += area_below(t, |p| plane.signed_distance(p));
    }
    outside / mesh.surface_area()
}

fn out_of_bounds(ctx: &Ctx<'_>, key: &str, wall_id: &str) -> Result<ExpectedOutOfBounds, FixtureError> {
    let o = ctx.object(key)?;
    let (_, wall) = ctx.wall(wall_id)?;
    Ok(ExpectedOutOfBounds {
        object: o.id().to_string(),
        wall: wall_id.to_owned(),
        outside_share: round(share_beyond_wall(o, wall)),
    })
}

fn blocked_door(ctx: &Ctx<'_>, door: &str, by: &str) -> Result<ExpectedBlockedDoor, FixtureError> {
    let o = ctx.object(by)?;
    let (room, wall, opening) = ctx
        .scene
        .openings()
        .find(|(_, _, op)| op.id == door && op.kind == OpeningKind::Door)
        .ok_or_else(|| FixtureError::spec(&ctx.name, format!("unknown door {door:?}")))?;
    // The blocker's box seen along the wall normal, in wall coordinates (along, up), and its
    // distance from the inner face into the room.
    let mut along = [Real::INFINITY, Real::NEG_INFINITY];
    let mut up = [Real::INFINITY, Real::NEG_INFINITY];
    let mut gap = Real::INFINITY;
    let start = wall.start();
    let inward = wall.inward_normal();
    for c in o.obb().corners() {
        let d = sceneeval_geom::Vector2::new(c.x - start.x, c.y - start.y);
        let u = d.dot(&wall.direction());
        let h = c.z - wall.base_z();
        along = [along[0].min(u), along[1].max(u)];
        up = [up[0].min(h), up[1].max(h)];
        gap = gap.min(d.dot(&inward));
    }
    let w = (along[1].min(opening.along[1]) - along[0].max(opening.along[0])).max(0.0);
    let h = (up[1].min(opening.height[1]) - up[0].max(opening.height[0])).max(0.0);
    if w * h <= 0.0 || gap < 0.0 || gap > opening.width() {
        return Err(FixtureError::spec(
            &ctx.name,
            format!("{by} does not stand in front of door {door:?} on its room side"),
        ));
    }
    Ok(ExpectedBlockedDoor {
        door: door.to_owned(),
        room: room.id().to_string(),
        blocked_by: vec![o.id().to_string()],
        occluded_fraction: round(w * h / (opening.width() * opening.hole_height())),
        gap_to_wall: round(gap),
    })
}

fn inside(ctx: &Ctx<'_>, inner: &str, outer: &str) -> Result<ExpectedInside, FixtureError> {
    let (i, o) = (ctx.object(inner)?, ctx.object(outer)?);
    let mut clearance = Real::INFINITY;
    for v in i.mesh().vertices() {
        let p = i.pose() * v;
        if !o.mesh().contains_point(o.pose(), &p) {
            return Err(FixtureError::spec(
                &ctx.name,
                format!("{inner} is not entirely inside {outer}: vertex {p} is outside"),
            ));
        }
        clearance = clearance.min(o.mesh().distance_to_point(o.pose(), &p));
    }
    Ok(ExpectedInside {
        inner: i.id().to_string(),
        outer: o.id().to_string(),
        clearance: round(clearance),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_to_micrometres_without_negative_zero() {
        assert_eq!(round(0.1000000149), 0.1);
        assert_eq!(round(-1e-9).to_bits(), 0.0f64.to_bits());
        assert_eq!(round(0.9523809523809523), 0.952381);
    }

    #[test]
    fn clipped_triangle_area() {
        // Right triangle (0,0)-(2,0)-(0,2), area 2, cut by x < 1: the part left of x = 1 is
        // the triangle minus the corner triangle (1,0)-(2,0)-(1,1) of area 0.5, so 1.5.
        let t = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
            Point3::new(0.0, 2.0, 0.0),
        ];
        let a = area_below(t, |p| p.x - 1.0);
        assert!((a - 1.5).abs() < 1e-15, "{a}");
        assert_eq!(area_below(t, |p| p.x + 1.0), 0.0);
        assert!((area_below(t, |p| p.x - 3.0) - 2.0).abs() < 1e-15);
    }
}
