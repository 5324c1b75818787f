//! Rooms from an outline, in code.

use sceneeval_geom::{Point2, Polygon2, Real};

use super::{Ceiling, Floor, Opening, OpeningKind, Room, WallSpec};
use crate::{Element, RoomId, SceneError};

/// Builds a room from a floor outline, with one wall per edge (wall `i` from point `i` to
/// point `i + 1`, wrapping) and doors and windows by wall index.
///
/// ```
/// use sceneeval_scene::{OpeningKind, RoomBuilder};
/// use sceneeval_geom::Point2;
///
/// let room = RoomBuilder::rectangle("bedroom", Point2::new(0.0, 0.0), Point2::new(4.0, 5.0))
///     .wall_height(2.8)
///     .wall_thickness(0.1)
///     .door(0, [1.0, 1.9], [0.0, 2.1])
///     .window(2, [1.0, 2.5], [0.9, 2.0])
///     .build()
///     .unwrap();
/// assert_eq!(room.walls().len(), 4);
/// // Wall 0 runs along y = 0 from x = 0 to x = 4; the room is on its +y side.
/// assert_eq!(room.walls()[0].inward_normal(), sceneeval_geom::Vector2::new(0.0, 1.0));
/// assert_eq!(room.ceiling_z(), Some(2.8));
/// ```
#[derive(Debug, Clone)]
pub struct RoomBuilder {
    id: RoomId,
    kind: Option<String>,
    outline: Vec<Point2>,
    floor_z: Real,
    height: Real,
    thickness: Real,
    openings: Vec<(usize, OpeningKind, [Real; 2], [Real; 2])>,
    ceiling: bool,
}

impl RoomBuilder {
    /// A room whose floor is `outline` (either winding). Defaults: floor at z = 0, walls 2.8 m
    /// high and 0.1 m thick, no openings, ceiling implied by the walls.
    pub fn polygon(id: impl Into<RoomId>, outline: Vec<Point2>) -> Self {
        RoomBuilder {
            id: id.into(),
            kind: None,
            outline,
            floor_z: 0.0,
            height: 2.8,
            thickness: 0.1,
            openings: Vec::new(),
            ceiling: false,
        }
    }

    /// An axis-aligned rectangular room (counter-clockwise from `min`: wall 0 runs along
    /// `y = min.y` toward +x, then +x side, then `y = max.y`, then `x = min.x`).
    pub fn rectangle(id: impl Into<RoomId>, min: Point2, max: Point2) -> Self {
        RoomBuilder::polygon(
            id,
            vec![min, Point2::new(max.x, min.y), max, Point2::new(min.x, max.y)],
        )
    }

    /// Sets the room type (e.g. `bedroom`).
    pub fn kind(mut self, kind: impl Into<String>) -> Self {
        self.kind = Some(kind.into());
        self
    }

    /// Sets the floor height (world z).
    pub fn floor_z(mut self, z: Real) -> Self {
        self.floor_z = z;
        self
    }

    /// Sets every wall's height.
    pub fn wall_height(mut self, h: Real) -> Self {
        self.height = h;
        self
    }

    /// Sets every wall's thickness.
    pub fn wall_thickness(mut self, t: Real) -> Self {
        self.thickness = t;
        self
    }

    /// Adds an explicit ceiling over the floor outline at the top of the walls.
    pub fn with_ceiling(mut self) -> Self {
        self.ceiling = true;
        self
    }

    /// Adds a door in wall `wall` (see [`Opening`] for the coordinates).
    pub fn door(mut self, wall: usize, along: [Real; 2], height: [Real; 2]) -> Self {
        self.openings.push((wall, OpeningKind::Door, along, height));
        self
    }

    /// Adds a window in wall `wall`.
    pub fn window(mut self, wall: usize, along: [Real; 2], height: [Real; 2]) -> Self {
        self.openings.push((wall, OpeningKind::Window, along, height));
        self
    }

    /// Builds the room. Wall ids are `<room>_wall_<i>`, opening ids `<wall>_<door|window>_<k>`,
    /// the floor id `floor_<room>`.
    pub fn build(self) -> Result<Room, SceneError> {
        let room = self.id.to_string();
        let floor = Polygon2::new(self.outline).map_err(|source| SceneError::Geometry {
            element: Box::new(Element::Floor {
                room: self.id.clone(),
            }),
            source,
        })?;
        let n = floor.len();
        let mut walls: Vec<WallSpec> = (0..n)
            .map(|i| {
                let (a, b) = floor.edge(i);
                WallSpec::new(
                    format!("{room}_wall_{i}"),
                    a,
                    b,
                    self.floor_z,
                    self.height,
                    self.thickness,
                )
            })
            .collect();
        for (wall, kind, along, height) in self.openings {
            let w = walls.get_mut(wall).ok_or(SceneError::NoSuchWall {
                room: room.clone(),
                index: wall,
                count: n,
            })?;
            let k = w.openings.iter().filter(|o| o.kind == kind).count();
            let id = format!("{}_{}_{k}", w.id, kind.name());
            w.openings.push(Opening::new(id, kind, along, height));
        }
        let ceiling = self.ceiling.then(|| Ceiling {
            id: format!("ceiling_{room}"),
            polygon: floor.clone(),
            z: self.floor_z + self.height,
        });
        let floor = Floor {
            id: format!("floor_{room}"),
            polygon: floor,
            z: self.floor_z,
        };
        let built = Room::new(self.id, floor, walls, ceiling)?;
        Ok(match self.kind {
            Some(k) => built.with_kind(k),
            None => built,
        })
    }
}
