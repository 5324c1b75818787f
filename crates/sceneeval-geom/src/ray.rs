use crate::{GeomError, Point3, Real, Vector3};

/// A half-line `origin + t * dir`, `t >= 0`. The direction need not be unit length; times of
/// impact returned by queries are in units of `dir`'s length (metres when `dir` is unit).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Ray {
    /// Start point.
    pub origin: Point3,
    /// Direction.
    pub dir: Vector3,
}

impl Ray {
    /// A ray from `origin` along `dir`.
    #[inline]
    pub const fn new(origin: Point3, dir: Vector3) -> Self {
        Ray { origin, dir }
    }

    /// The point at parameter `t`.
    #[inline]
    pub fn point_at(&self, t: Real) -> Point3 {
        self.origin + self.dir * t
    }
}

/// An oriented plane `{p : normal . p = offset}` with a unit normal.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Plane {
    /// Unit normal; the positive side is where it points.
    pub normal: Vector3,
    /// Signed distance of the plane from the origin along `normal`.
    pub offset: Real,
}

impl Plane {
    /// The plane through `point` with normal `normal` (normalised here).
    pub fn from_point_normal(point: &Point3, normal: &Vector3) -> Result<Self, GeomError> {
        let n = normal
            .try_normalize(0.0)
            .ok_or(GeomError::ZeroDirection { what: "plane normal" })?;
        if !point.iter().all(|v| v.is_finite()) || !n.iter().all(|v| v.is_finite()) {
            return Err(GeomError::NonFinite { what: "plane" });
        }
        Ok(Plane {
            normal: n,
            offset: n.dot(&point.coords),
        })
    }

    /// Signed distance of `p` from the plane (positive on the normal's side).
    #[inline]
    pub fn signed_distance(&self, p: &Point3) -> Real {
        self.normal.dot(&p.coords) - self.offset
    }

    /// The orthogonal projection of `p` onto the plane.
    #[inline]
    pub fn project(&self, p: &Point3) -> Point3 {
        p - self.normal * self.signed_distance(p)
    }

    /// The parameter `t >= 0` at which `ray` crosses the plane, if it does.
    pub fn intersect_ray(&self, ray: &Ray) -> Option<Real> {
        let denom = self.normal.dot(&ray.dir);
        if denom == 0.0 {
            return None;
        }
        let t = -self.signed_distance(&ray.origin) / denom;
        (t >= 0.0 && t.is_finite()).then_some(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plane_distance_projection_and_ray() {
        let plane =
            Plane::from_point_normal(&Point3::new(0.0, 0.0, 2.0), &Vector3::new(0.0, 0.0, 5.0)).unwrap();
        assert_eq!(plane.signed_distance(&Point3::new(1.0, 1.0, 3.0)), 1.0);
        assert_eq!(
            plane.project(&Point3::new(1.0, 1.0, 3.0)),
            Point3::new(1.0, 1.0, 2.0)
        );
        let down = Ray::new(Point3::new(0.5, 0.5, 5.0), -Vector3::z());
        assert_eq!(plane.intersect_ray(&down), Some(3.0));
        assert_eq!(down.point_at(3.0), Point3::new(0.5, 0.5, 2.0));
        let up = Ray::new(Point3::new(0.5, 0.5, 5.0), Vector3::z());
        assert_eq!(plane.intersect_ray(&up), None);
        let parallel = Ray::new(Point3::origin(), Vector3::x());
        assert_eq!(plane.intersect_ray(&parallel), None);
        assert!(Plane::from_point_normal(&Point3::origin(), &Vector3::zeros()).is_err());
    }
}
