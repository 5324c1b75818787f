//! Perspective cameras as the reference sets them up in Blender: a 35 mm lens on a 36 mm
//! sensor, Blender's camera axes (looking along local -z, image up = local +y), Euler angles,
//! and Blender's "camera to selected" fit.

use sceneeval_geom::na::{Matrix4, Unit};
use sceneeval_geom::{Point2, Point3, Real, Rotation3, Vector3};

use crate::RenderError;

/// The reference's lens (Blender's default camera): 35 mm.
pub const LENS_MM: Real = 35.0;
/// Blender's default sensor width: 36 mm (fitted to the longer image side).
pub const SENSOR_MM: Real = 36.0;
/// Distance of the near clipping plane in metres (the far plane is at infinity).
pub const NEAR_M: Real = 0.005;

/// A perspective camera.
///
/// Axes follow Blender: the camera looks along its local **-z**, the image's up is local
/// **+y** and its right local **+x**; `rotation` maps camera axes to world axes. The field of
/// view comes from the lens and sensor with Blender's automatic sensor fit: the sensor width
/// spans the longer image side.
///
/// ```
/// use sceneeval_render::Camera;
/// use sceneeval_geom::{Point3, Vector3};
/// // Two metres above the origin, looking straight down (Blender rotation (0, 0, 0)).
/// let cam = Camera::looking_at(Point3::new(0.0, 0.0, 2.0), Point3::origin(), Vector3::y()).unwrap();
/// // A point 0.5 m to the right of the centre, 2 m away: tan = 0.25 against the half field of
/// // view tan = 18 / 35, so it lands 0.25 / (18 / 35) = 0.4861 of the half-width right of the
/// // centre of a 100-pixel image: x = 50 + 50 * 0.4861 = 74.31.
/// let px = cam.project(&Point3::new(0.5, 0.0, 0.0), 100, 100).unwrap();
/// assert!((px.x - 74.3056).abs() < 1e-3 && (px.y - 50.0).abs() < 1e-9);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// The camera's position in the world.
    pub position: Point3,
    /// `world_from_camera` rotation (camera looks along its local -z).
    pub rotation: Rotation3,
    /// Focal length in millimetres.
    pub lens_mm: Real,
    /// Sensor width in millimetres.
    pub sensor_mm: Real,
}

impl Camera {
    /// A camera at `position` with rotation `rotation` and the reference's lens.
    pub fn new(position: Point3, rotation: Rotation3) -> Camera {
        Camera {
            position,
            rotation,
            lens_mm: LENS_MM,
            sensor_mm: SENSOR_MM,
        }
    }

    /// A camera at `eye` looking at `target`, with `up` (projected) as the image's up.
    ///
    /// # Errors
    /// [`RenderError::BadCamera`] when `eye == target`, `up` is parallel to the view direction
    /// or anything is not finite.
    pub fn looking_at(eye: Point3, target: Point3, up: Vector3) -> Result<Camera, RenderError> {
        let forward = target - eye;
        let back = -forward;
        let right = up.cross(&back);
        let (Some(back), Some(right)) = (Unit::try_new(back, 1e-12), Unit::try_new(right, 1e-12)) else {
            return Err(RenderError::BadCamera {
                reason: "the eye equals the target or the up vector is parallel to the view".into(),
            });
        };
        let up = back.cross(&right);
        let m = sceneeval_geom::Matrix3::from_columns(&[right.into_inner(), up, back.into_inner()]);
        let cam = Camera::new(eye, Rotation3::from_matrix_unchecked(m));
        cam.check()?;
        Ok(cam)
    }

    /// The rotation of a Blender object with XYZ Euler angles `(x, y, z)` in radians:
    /// `Rz(z) * Ry(y) * Rx(x)`.
    pub fn euler_xyz(x: Real, y: Real, z: Real) -> Rotation3 {
        Rotation3::from_axis_angle(&Vector3::z_axis(), z)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), y)
            * Rotation3::from_axis_angle(&Vector3::x_axis(), x)
    }

    /// The XYZ Euler angles `(x, y, z)` Blender reports for a rotation (of the two solutions,
    /// the one with the smaller sum of absolute angles, as `mat3_normalized_to_eul` picks).
    pub fn euler_of(rotation: &Rotation3) -> (Real, Real, Real) {
        let m = rotation.matrix();
        let cy = m[(0, 0)].hypot(m[(1, 0)]);
        let (a, b) = if cy > 16.0 * f64::from(f32::EPSILON) {
            (
                (
                    m[(2, 1)].atan2(m[(2, 2)]),
                    (-m[(2, 0)]).atan2(cy),
                    m[(1, 0)].atan2(m[(0, 0)]),
                ),
                (
                    (-m[(2, 1)]).atan2(-m[(2, 2)]),
                    (-m[(2, 0)]).atan2(-cy),
                    (-m[(1, 0)]).atan2(-m[(0, 0)]),
                ),
            )
        } else {
            let e = ((-m[(1, 2)]).atan2(m[(1, 1)]), (-m[(2, 0)]).atan2(cy), 0.0);
            (e, e)
        };
        let sum = |e: &(Real, Real, Real)| e.0.abs() + e.1.abs() + e.2.abs();
        if sum(&a) <= sum(&b) { a } else { b }
    }

    /// The camera's viewing direction (its local -z) in the world.
    pub fn forward(&self) -> Vector3 {
        self.rotation * -Vector3::z()
    }

    /// The image's up direction (local +y) in the world.
    pub fn up(&self) -> Vector3 {
        self.rotation * Vector3::y()
    }

    /// The image's right direction (local +x) in the world.
    pub fn right(&self) -> Vector3 {
        self.rotation * Vector3::x()
    }

    /// Tangents of the half field of view `(horizontal, vertical)` for an image of
    /// `width x height` pixels (Blender's automatic sensor fit).
    pub fn half_fov_tangents(&self, width: u32, height: u32) -> (Real, Real) {
        let t = 0.5 * self.sensor_mm / self.lens_mm;
        let (w, h) = (Real::from(width.max(1)), Real::from(height.max(1)));
        if w >= h { (t, t * h / w) } else { (t * w / h, t) }
    }

    /// Moves a camera of rotation `rotation` so that every point of `points` is in the frame
    /// of a `width x height` image and the points' extent touches the frame on the tighter
    /// axis, centred on both: Blender's "camera to selected"
    /// (`BKE_camera_view_frame_fit_to_coords` without shift). `None` without points.
    pub fn fit<'a>(
        rotation: Rotation3,
        points: impl IntoIterator<Item = &'a Point3>,
        width: u32,
        height: u32,
    ) -> Option<Camera> {
        let probe = Camera::new(Point3::origin(), rotation);
        let (tx, ty) = probe.half_fov_tangents(width, height);
        let (r, u, f) = (probe.right(), probe.up(), probe.forward());
        // In camera-aligned coordinates (a right, b up, d forward), a point is inside the
        // horizontal frame of a camera at (ca, cd) when |a - ca| <= tx (d - cd). The tightest
        // camera satisfies ca - tx cd = max(a - tx d) and -ca - tx cd = max(-a - tx d).
        let mut bounds = [Real::NEG_INFINITY; 4];
        let mut any = false;
        for p in points {
            let (a, b, d) = (p.coords.dot(&r), p.coords.dot(&u), p.coords.dot(&f));
            bounds[0] = bounds[0].max(a - tx * d);
            bounds[1] = bounds[1].max(-a - tx * d);
            bounds[2] = bounds[2].max(b - ty * d);
            bounds[3] = bounds[3].max(-b - ty * d);
            any = true;
        }
        if !any || !bounds.iter().all(|v| v.is_finite()) {
            return None;
        }
        let ca = 0.5 * (bounds[0] - bounds[1]);
        let cd_x = -0.5 * (bounds[0] + bounds[1]) / tx;
        let cb = 0.5 * (bounds[2] - bounds[3]);
        let cd_y = -0.5 * (bounds[2] + bounds[3]) / ty;
        // The camera sits on both fitted lines; the one further back frames everything.
        let cd = cd_x.min(cd_y);
        Some(Camera::new(Point3::from(r * ca + u * cb + f * cd), rotation))
    }

    /// This camera moved `distance` metres backwards along its viewing direction.
    pub fn backed_off(&self, distance: Real) -> Camera {
        Camera {
            position: self.position - self.forward() * distance,
            ..*self
        }
    }

    /// The pixel position (x right, y down, pixel centres at half-integers, `(0, 0)` the
    /// top-left corner of the image) of the world point `p` in a `width x height` image;
    /// `None` when `p` is not in front of the camera.
    pub fn project(&self, p: &Point3, width: u32, height: u32) -> Option<Point2> {
        let q = self.rotation.inverse() * (p - self.position);
        let depth = -q.z;
        if depth <= 0.0 {
            return None;
        }
        let (tx, ty) = self.half_fov_tangents(width, height);
        let nx = q.x / (depth * tx);
        let ny = q.y / (depth * ty);
        Some(Point2::new(
            0.5 * (nx + 1.0) * Real::from(width),
            0.5 * (1.0 - ny) * Real::from(height),
        ))
    }

    /// The clip-from-world matrix for wgpu: reversed depth with an infinite far plane (depth 1
    /// at [`NEAR_M`], tending to 0 far away), which keeps 32-bit float depth precise at every
    /// distance.
    pub(crate) fn clip_from_world(&self, width: u32, height: u32) -> Matrix4<Real> {
        let (tx, ty) = self.half_fov_tangents(width, height);
        let r_inv = self.rotation.inverse();
        let t = -(r_inv * self.position.coords);
        let mut view = Matrix4::identity();
        view.fixed_view_mut::<3, 3>(0, 0).copy_from(r_inv.matrix());
        view.fixed_view_mut::<3, 1>(0, 3).copy_from(&t);
        #[rustfmt::skip]
        let proj = Matrix4::new(
            1.0 / tx, 0.0,      0.0,  0.0,
            0.0,      1.0 / ty, 0.0,  0.0,
            0.0,      0.0,      0.0,  NEAR_M,
            0.0,      0.0,      -1.0, 0.0,
        );
        proj * view
    }

    /// Checks that the camera can be used.
    pub(crate) fn check(&self) -> Result<(), RenderError> {
        let finite = self.position.iter().all(|v| v.is_finite())
            && self.rotation.matrix().iter().all(|v| v.is_finite());
        if !finite {
            return Err(RenderError::BadCamera {
                reason: "position or rotation is not finite".into(),
            });
        }
        let orthonormal = (self.rotation.matrix().transpose() * self.rotation.matrix()
            - sceneeval_geom::Matrix3::identity())
        .norm()
            < 1e-6;
        if !orthonormal {
            return Err(RenderError::BadCamera {
                reason: "the rotation is not orthonormal".into(),
            });
        }
        if !(self.lens_mm.is_finite()
            && self.lens_mm > 0.0
            && self.sensor_mm.is_finite()
            && self.sensor_mm > 0.0)
        {
            return Err(RenderError::BadCamera {
                reason: format!("lens {} mm, sensor {} mm", self.lens_mm, self.sensor_mm),
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_3};

    #[test]
    fn blender_euler_60_degrees_looks_forward_and_down() {
        // Rx(60 deg): -z goes to (0, sin 60, -cos 60) = (0, 0.866, -0.5), i.e. along +y and 30
        // degrees below the horizon.
        let cam = Camera::new(Point3::origin(), Camera::euler_xyz(FRAC_PI_3, 0.0, 0.0));
        let f = cam.forward();
        assert!((f - Vector3::new(0.0, 0.75f64.sqrt(), -0.5)).norm() < 1e-15);
        assert!((cam.right() - Vector3::x()).norm() < 1e-15);
        // Turned by yaw 90 deg (Rz(90) maps +y to -x) it looks along -x and down.
        let turned = Camera::new(Point3::origin(), Camera::euler_xyz(FRAC_PI_3, 0.0, FRAC_PI_2));
        assert!((turned.forward() - Vector3::new(-(0.75f64.sqrt()), 0.0, -0.5)).norm() < 1e-15);
    }

    #[test]
    fn euler_round_trip_picks_the_small_solution() {
        for (x, y, z) in [(0.0, 0.0, 1.0), (0.3, -0.2, 2.5), (-1.0, 0.4, -3.0)] {
            let (a, b, c) = Camera::euler_of(&Camera::euler_xyz(x, y, z));
            assert!((a - x).abs() < 1e-12 && (b - y).abs() < 1e-12 && (c - z).abs() < 1e-12);
        }
    }

    #[test]
    fn fit_centres_and_touches_the_tighter_axis() {
        // Looking straight down at a 4 x 2 m rectangle at z = 0 centred at (1, 2): the
        // horizontal half-width 2 m needs a distance 2 / (18 / 35) = 3.8889 m, the vertical
        // half-height 1 m only 1 / (18 / 35) on a square image: the camera is at
        // (1, 2, 3.8889).
        let pts = [
            Point3::new(-1.0, 1.0, 0.0),
            Point3::new(3.0, 1.0, 0.0),
            Point3::new(3.0, 3.0, 0.0),
            Point3::new(-1.0, 3.0, 0.0),
        ];
        let cam = Camera::fit(Rotation3::identity(), pts.iter(), 64, 64).unwrap();
        assert!((cam.position - Point3::new(1.0, 2.0, 2.0 * 35.0 / 18.0)).norm() < 1e-12);
        // The corners land on the left and right edges.
        let p = cam.project(&pts[0], 64, 64).unwrap();
        assert!(p.x.abs() < 1e-9, "{p}");
        assert!((p.y - 48.0).abs() < 1e-9, "{p}");
        assert!(Camera::fit(Rotation3::identity(), [].iter(), 64, 64).is_none());
    }

    #[test]
    fn wide_images_widen_the_horizontal_view() {
        let cam = Camera::new(Point3::origin(), Rotation3::identity());
        let (tx, ty) = cam.half_fov_tangents(200, 100);
        assert!((tx - 18.0 / 35.0).abs() < 1e-15 && (ty - 9.0 / 35.0).abs() < 1e-15);
        let (tx, ty) = cam.half_fov_tangents(100, 200);
        assert!((tx - 9.0 / 35.0).abs() < 1e-15 && (ty - 18.0 / 35.0).abs() < 1e-15);
    }

    #[test]
    fn clip_matrix_agrees_with_projection() {
        let cam = Camera::looking_at(
            Point3::new(1.0, -3.0, 2.0),
            Point3::new(0.5, 0.5, 0.3),
            Vector3::z(),
        )
        .unwrap();
        let p = Point3::new(0.7, 0.2, 0.9);
        let c = cam.clip_from_world(80, 60) * p.to_homogeneous();
        let ndc = (c.x / c.w, c.y / c.w, c.z / c.w);
        let px = cam.project(&p, 80, 60).unwrap();
        assert!((0.5 * (ndc.0 + 1.0) * 80.0 - px.x).abs() < 1e-9);
        assert!((0.5 * (1.0 - ndc.1) * 60.0 - px.y).abs() < 1e-9);
        // Reversed depth: NEAR / distance along the view axis.
        let depth = (p - cam.position).dot(&cam.forward());
        assert!((ndc.2 - NEAR_M / depth).abs() < 1e-12);
    }
}
