//! The views of the reference and how each one is set up (reference-notes section 9):
//! which objects are drawn, where the camera goes, where the human stands.

use std::fmt;
use std::str::FromStr;

use sceneeval_geom::na::Translation3;
use sceneeval_geom::{Isometry3, Point3, Ray, Real, Rotation3, Vector3};

use crate::human::HUMAN_HALF_WIDTH_M;
use crate::prepared::{Owner, PreparedScene, Shot, object_points};
use crate::{Camera, RenderError, RenderSettings};

/// Camera tilt of the front and surroundings views: Blender X-Euler 60 degrees, i.e. 30
/// degrees below the horizon.
pub const FRONT_TILT_DEG: Real = 60.0;
/// Camera tilt of the size-reference view: X-Euler 80 degrees, 10 degrees below the horizon.
pub const SIZE_TILT_DEG: Real = 80.0;
/// Gap between an object's box and the human figure in the size view, metres (the
/// reference puts the figure against the box; a gap keeps the two apart in the image).
pub const HUMAN_GAP_M: Real = 0.1;
/// Surroundings: other objects count as "on or around" the object when their world boxes are
/// closer than this (metres)...
pub const SURROUNDINGS_GAP_M: Real = 0.2;
/// ... and the unit direction from the object's centre to theirs rises at least this much.
pub const SURROUNDINGS_MIN_UP: Real = 0.25;
/// Surroundings: the fitted camera backs off by this fraction of the length of the object's
/// world box diagonal.
pub const SURROUNDINGS_BACK_OFF: Real = 0.25;
/// Surroundings: a wall is hidden when it blocks more than this many of the 8 rays to the
/// object's box corners.
pub const SURROUNDINGS_WALL_RAYS: usize = 4;

/// An image of a prepared scene.
///
/// The per-object views and the top views follow the reference (reference-notes section 9);
/// their file names are [`View::file_name`].
#[derive(Debug, Clone, PartialEq)]
pub enum View {
    /// `front_<id>.png`: the object alone, the camera facing its front (local -y) from 30
    /// degrees above the horizon, fitted to its bounds. Used to match objects and to judge
    /// attributes and support.
    Front(String),
    /// `size_<id>.png`: the object and a 170 cm human figure standing at its local -x side
    /// (the left of the image), the camera 10 degrees above the horizon, fitted to both.
    Size(String),
    /// `surroundings_<id>.png`: the scene around the object from the front camera's
    /// direction, fitted to the object and what stands on it (objects within 0.2 m whose
    /// centre lies above), backed off by a quarter of its box diagonal; objects between the
    /// camera and the object's box corners are hidden, and walls blocking more than 4 of
    /// those 8 rays.
    Surroundings(String),
    /// `top.png`: the whole scene from straight above, fitted to everything, walls cut at
    /// [`RenderSettings::wall_cut_height`] above their base so the interior shows.
    Top,
    /// The top view's camera with only these objects (and the architecture) drawn, to show
    /// the candidates of a relation in the context of the room.
    TopOf(Vec<String>),
    /// Any camera: the listed objects (every object when `None`), with or without floors and
    /// walls (uncut).
    Custom {
        /// The camera.
        camera: Camera,
        /// The objects to draw; `None` draws every object.
        objects: Option<Vec<String>>,
        /// Whether floors and walls are drawn.
        architecture: bool,
    },
}

impl View {
    /// The file name the reference gives this view: `front_<id>.png`, `size_<id>.png`,
    /// `surroundings_<id>.png`, `top.png`; `top_<id>+<id>....png` for [`View::TopOf`] and
    /// `custom.png` for a custom camera. Ids are used as they are (dots included) except
    /// that characters unsafe in file names (`/ \ : * ? " < > |`, `%` and control
    /// characters) are percent-encoded, so no id can name a file outside the output folder.
    ///
    /// ```
    /// use sceneeval_render::View;
    /// assert_eq!(View::Front("idx3_fixture.bed".into()).file_name(), "front_idx3_fixture.bed.png");
    /// assert_eq!(View::Size("a/../b".into()).file_name(), "size_a%2F..%2Fb.png");
    /// assert_eq!(View::Top.file_name(), "top.png");
    /// ```
    pub fn file_name(&self) -> String {
        match self {
            View::Front(id) => format!("front_{}.png", file_safe(id)),
            View::Size(id) => format!("size_{}.png", file_safe(id)),
            View::Surroundings(id) => format!("surroundings_{}.png", file_safe(id)),
            View::Top => "top.png".to_owned(),
            View::TopOf(ids) => format!(
                "top_{}.png",
                ids.iter().map(|id| file_safe(id)).collect::<Vec<_>>().join("+")
            ),
            View::Custom { .. } => "custom.png".to_owned(),
        }
    }

    /// The per-object and top views of `kinds`, for the objects `objects` in the given
    /// order: for each object its front, size and surroundings views (those of `kinds`),
    /// then `top.png` if asked for.
    pub fn standard<'a>(kinds: &[ViewKind], objects: impl IntoIterator<Item = &'a str>) -> Vec<View> {
        let mut out = Vec::new();
        for id in objects {
            for kind in ViewKind::ALL {
                if kinds.contains(&kind) && kind != ViewKind::Top {
                    out.push(kind.view(id));
                }
            }
        }
        if kinds.contains(&ViewKind::Top) {
            out.push(View::Top);
        }
        out
    }
}

impl fmt::Display for View {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file_name())
    }
}

/// The kinds of standard views (the names the CLI's `--views` takes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ViewKind {
    /// [`View::Front`].
    Front,
    /// [`View::Size`].
    Size,
    /// [`View::Surroundings`].
    Surroundings,
    /// [`View::Top`].
    Top,
}

impl ViewKind {
    /// Every kind, in file order.
    pub const ALL: [ViewKind; 4] = [
        ViewKind::Front,
        ViewKind::Size,
        ViewKind::Surroundings,
        ViewKind::Top,
    ];

    /// The name: `front`, `size`, `surroundings`, `top`.
    pub const fn name(self) -> &'static str {
        match self {
            ViewKind::Front => "front",
            ViewKind::Size => "size",
            ViewKind::Surroundings => "surroundings",
            ViewKind::Top => "top",
        }
    }

    /// The view of this kind for object `id` ([`View::Top`] ignores it).
    pub fn view(self, id: &str) -> View {
        match self {
            ViewKind::Front => View::Front(id.to_owned()),
            ViewKind::Size => View::Size(id.to_owned()),
            ViewKind::Surroundings => View::Surroundings(id.to_owned()),
            ViewKind::Top => View::Top,
        }
    }
}

impl fmt::Display for ViewKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ViewKind {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ViewKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| {
                format!(
                    "unknown view {s:?} (expected one of {})",
                    ViewKind::ALL.map(ViewKind::name).join(", ")
                )
            })
    }
}

/// `id` with the characters that are unsafe in file names percent-encoded.
fn file_safe(id: &str) -> String {
    let mut out = String::with_capacity(id.len());
    for c in id.chars() {
        if c.is_control() || matches!(c, '/' | '\\' | ':' | '*' | '?' | '"' | '<' | '>' | '|' | '%') {
            let mut buf = [0u8; 4];
            for b in c.encode_utf8(&mut buf).bytes() {
                out.push_str(&format!("%{b:02X}"));
            }
        } else {
            out.push(c);
        }
    }
    out
}

impl PreparedScene {
    fn object(&self, id: &str) -> Result<usize, RenderError> {
        self.input
            .object_index(id)
            .ok_or_else(|| RenderError::UnknownObject { id: id.to_owned() })
    }

    fn items_of(&self, keep: impl Fn(Owner) -> bool) -> Vec<usize> {
        (0..self.items.len())
            .filter(|&i| keep(self.items[i].owner))
            .collect()
    }

    /// The camera rotation of an object view: the object's Blender Euler angles with X
    /// replaced by `tilt_deg` (the reference copies the object's matrix into the camera and
    /// overwrites its X rotation).
    fn object_camera_rotation(&self, i: usize, tilt_deg: Real) -> Rotation3 {
        let rotation = self.input.objects[i].pose.rotation.to_rotation_matrix();
        let (_, y, z) = Camera::euler_of(&rotation);
        Camera::euler_xyz(tilt_deg.to_radians(), y, z)
    }

    fn fit(
        &self,
        rotation: Rotation3,
        points: &[Point3],
        settings: &RenderSettings,
        view: &View,
    ) -> Result<Camera, RenderError> {
        Camera::fit(rotation, points.iter(), settings.width, settings.height).ok_or_else(|| {
            RenderError::EmptyView {
                view: view.file_name(),
            }
        })
    }

    /// Where the human stands for the size view of object `i`: in the object's frame (facing
    /// the same way as the object), its feet level with the object's bottom, centred on the
    /// object's depth, the figure's +x side (its left hand) [`HUMAN_GAP_M`] from the object's
    /// local -x face.
    fn human_pose(&self, i: usize) -> Isometry3 {
        let object = &self.input.objects[i];
        let local = object.mesh.aabb();
        let offset = Vector3::new(
            local.min.x - HUMAN_GAP_M - HUMAN_HALF_WIDTH_M,
            0.5 * (local.min.y + local.max.y),
            local.min.z,
        );
        object.pose * Translation3::from(offset)
    }

    /// The top view's camera: straight down (Blender rotation (0, 0, 0): image up = +y),
    /// fitted to every object, floor and (cut) wall.
    fn top_camera(&self, settings: &RenderSettings, view: &View) -> Result<Camera, RenderError> {
        let mut points: Vec<Point3> = self.input.objects.iter().flat_map(object_points).collect();
        for floor in &self.input.floors {
            points.extend(floor.vertices().iter().copied());
        }
        for wall in &self.input.walls {
            let top = wall.base_z + settings.wall_cut_height;
            points.extend(
                wall.mesh
                    .vertices()
                    .iter()
                    .map(|v| Point3::new(v.x, v.y, v.z.min(top))),
            );
        }
        self.fit(Rotation3::identity(), &points, settings, view)
    }

    /// The camera, items and human of `view`.
    pub(crate) fn shot(&self, view: &View, settings: &RenderSettings) -> Result<Shot, RenderError> {
        let shot = match view {
            View::Front(id) => {
                let i = self.object(id)?;
                let rotation = self.object_camera_rotation(i, FRONT_TILT_DEG);
                let points: Vec<Point3> = object_points(&self.input.objects[i]).collect();
                Shot {
                    camera: self.fit(rotation, &points, settings, view)?,
                    items: self.object_items[i].clone().collect(),
                    human: None,
                    cut_walls: false,
                    cull_closed: true,
                }
            }
            View::Size(id) => {
                let i = self.object(id)?;
                let rotation = self.object_camera_rotation(i, SIZE_TILT_DEG);
                let human = self.human_pose(i);
                let mut points: Vec<Point3> = object_points(&self.input.objects[i]).collect();
                points.extend(
                    self.figure
                        .positions
                        .iter()
                        .map(|p| human * Point3::new(p[0], p[1], p[2])),
                );
                let mut items: Vec<usize> = self.object_items[i].clone().collect();
                items.push(self.human_item);
                Shot {
                    camera: self.fit(rotation, &points, settings, view)?,
                    items,
                    human: Some(human),
                    cut_walls: false,
                    cull_closed: true,
                }
            }
            View::Surroundings(id) => self.surroundings(self.object(id)?, settings, view)?,
            View::Top => Shot {
                camera: self.top_camera(settings, view)?,
                items: self.items_of(|o| o != Owner::Human),
                human: None,
                cut_walls: true,
                cull_closed: true,
            },
            View::TopOf(ids) => {
                let chosen = ids
                    .iter()
                    .map(|id| self.object(id))
                    .collect::<Result<Vec<_>, _>>()?;
                Shot {
                    camera: self.top_camera(settings, &View::Top)?,
                    items: self.items_of(|o| match o {
                        Owner::Object(i) => chosen.contains(&i),
                        Owner::Floor | Owner::Wall(_) => true,
                        Owner::Human => false,
                    }),
                    human: None,
                    cut_walls: true,
                    cull_closed: true,
                }
            }
            View::Custom {
                camera,
                objects,
                architecture,
            } => {
                let chosen = match objects {
                    Some(ids) => Some(
                        ids.iter()
                            .map(|id| self.object(id))
                            .collect::<Result<Vec<_>, _>>()?,
                    ),
                    None => None,
                };
                Shot {
                    camera: *camera,
                    items: self.items_of(|o| match o {
                        Owner::Object(i) => chosen.as_ref().is_none_or(|c| c.contains(&i)),
                        Owner::Floor | Owner::Wall(_) => *architecture,
                        Owner::Human => false,
                    }),
                    human: None,
                    cut_walls: false,
                    cull_closed: true,
                }
            }
        };
        Ok(shot)
    }

    /// The surroundings view of object `i` (see [`View::Surroundings`]).
    fn surroundings(&self, i: usize, settings: &RenderSettings, view: &View) -> Result<Shot, RenderError> {
        let objects = &self.input.objects;
        let object = &objects[i];
        let centre = object.world_aabb.center();
        // What stands on or hangs over the object: close, and above it.
        let close: Vec<usize> = (0..objects.len())
            .filter(|&j| j != i)
            .filter(|&j| {
                let other = &objects[j];
                let up = (other.world_aabb.center() - centre)
                    .try_normalize(1e-12)
                    .map_or(0.0, |d| d.z);
                object.world_aabb.distance_to_aabb(&other.world_aabb) < SURROUNDINGS_GAP_M
                    && up >= SURROUNDINGS_MIN_UP
            })
            .collect();
        let rotation = self.object_camera_rotation(i, FRONT_TILT_DEG);
        let mut points: Vec<Point3> = object_points(object).collect();
        for &j in &close {
            points.extend(object_points(&objects[j]));
        }
        let camera = self
            .fit(rotation, &points, settings, view)?
            .backed_off(SURROUNDINGS_BACK_OFF * object.world_aabb.extents().norm());

        // Rays from the camera to the object's 8 box corners.
        let rays: Vec<(Ray, Real)> = object
            .obb
            .corners()
            .iter()
            .filter_map(|corner| {
                let d = corner - camera.position;
                let len = d.norm();
                (len > 1e-9).then(|| (Ray::new(camera.position, d / len), len))
            })
            .collect();
        // A hit counts when it lies before the corner (by more than a tenth of a millimetre,
        // so that the corner's own surface does not count).
        let blocks = |mesh: &sceneeval_geom::Mesh, pose: &Isometry3, ray: &Ray, len: Real| {
            mesh.cast_ray(pose, ray, (len - 1e-4).max(0.0)).is_some()
        };
        let hidden_objects: Vec<usize> = (0..objects.len())
            .filter(|&j| j != i && !close.contains(&j))
            .filter(|&j| {
                let other = &objects[j];
                rays.iter()
                    .any(|(ray, len)| blocks(&other.mesh, &other.pose, ray, *len))
            })
            .collect();
        let identity = Isometry3::identity();
        let hidden_walls: Vec<usize> = (0..self.input.walls.len())
            .filter(|&w| {
                let mesh = &self.input.walls[w].mesh;
                rays.iter()
                    .filter(|(ray, len)| blocks(mesh, &identity, ray, *len))
                    .count()
                    > SURROUNDINGS_WALL_RAYS
            })
            .collect();
        tracing::debug!(
            object = %object.id,
            close = close.len(),
            hidden_objects = hidden_objects.len(),
            hidden_walls = hidden_walls.len(),
            "surroundings view"
        );
        Ok(Shot {
            camera,
            items: self.items_of(|o| match o {
                Owner::Object(j) => !hidden_objects.contains(&j),
                Owner::Wall(w) => !hidden_walls.contains(&w),
                Owner::Floor => true,
                Owner::Human => false,
            }),
            human: None,
            cut_walls: false,
            cull_closed: true,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_follow_the_reference() {
        assert_eq!(
            View::Front("idx0_fixture.bed".into()).file_name(),
            "front_idx0_fixture.bed.png"
        );
        assert_eq!(View::Size("x".into()).file_name(), "size_x.png");
        assert_eq!(View::Surroundings("x".into()).file_name(), "surroundings_x.png");
        assert_eq!(
            View::TopOf(vec!["a".into(), "b.c".into()]).file_name(),
            "top_a+b.c.png"
        );
        // Unsafe characters cannot escape the output folder or clash.
        assert_eq!(file_safe("../x"), "..%2Fx");
        assert_eq!(file_safe("a\\b:c%"), "a%5Cb%3Ac%25");
        assert_eq!(file_safe("t\u{0}"), "t%00");
        assert_eq!(file_safe("é"), "é");
    }

    #[test]
    fn kinds_parse_and_expand_in_file_order() {
        assert_eq!(
            "Surroundings".parse::<ViewKind>().unwrap(),
            ViewKind::Surroundings
        );
        assert!("side".parse::<ViewKind>().is_err());
        let views = View::standard(&[ViewKind::Top, ViewKind::Front, ViewKind::Size], ["a", "b"]);
        let names: Vec<String> = views.iter().map(View::file_name).collect();
        assert_eq!(
            names,
            [
                "front_a.png",
                "size_a.png",
                "front_b.png",
                "size_b.png",
                "top.png"
            ]
        );
    }
}
