//! 4x4 transforms kept with their inverses, as pbrt-v4 keeps them (`Transform` holds `m` and
//! `mInv`), so a camera placed by `LookAt` gets its exact world position back instead of a
//! numerically inverted one.

use glam::{DAffine3, DMat3, DMat4, DVec3, DVec4};

/// A transform and its inverse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Xf {
    /// The matrix (column vectors: `p' = m p`).
    pub m: DMat4,
    /// Its inverse.
    pub inv: DMat4,
}

impl Default for Xf {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Xf {
    /// The identity.
    pub const IDENTITY: Xf = Xf {
        m: DMat4::IDENTITY,
        inv: DMat4::IDENTITY,
    };

    /// A general matrix; `None` if it is singular or not finite.
    #[must_use]
    pub fn new(m: DMat4) -> Option<Xf> {
        let det = m.determinant();
        if !m.is_finite() || det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = m.inverse();
        inv.is_finite().then_some(Xf { m, inv })
    }

    /// Translation by `t`.
    #[must_use]
    pub fn translate(t: DVec3) -> Xf {
        Xf {
            m: DMat4::from_translation(t),
            inv: DMat4::from_translation(-t),
        }
    }

    /// Scale by `s` per axis; `None` when a factor is zero or not finite.
    #[must_use]
    pub fn scale(s: DVec3) -> Option<Xf> {
        (s.is_finite() && s.cmpne(DVec3::ZERO).all()).then(|| Xf {
            m: DMat4::from_scale(s),
            inv: DMat4::from_scale(s.recip()),
        })
    }

    /// Rotation by `deg` degrees about `axis` (right-handed, as pbrt's `Rotate` and Mitsuba's
    /// `<rotate>`); `None` for a zero axis.
    #[must_use]
    pub fn rotate(deg: f64, axis: DVec3) -> Option<Xf> {
        let axis = axis.try_normalize()?;
        let m = DMat4::from_axis_angle(axis, deg.to_radians());
        m.is_finite().then(|| Xf {
            m,
            inv: m.transpose(),
        })
    }

    /// The frame whose columns are `x, y, z` at `origin` (world from local) with its inverse;
    /// `x, y, z` must be orthonormal.
    #[must_use]
    pub fn frame(x: DVec3, y: DVec3, z: DVec3, origin: DVec3) -> Xf {
        let m = DMat4::from_cols(
            x.extend(0.0),
            y.extend(0.0),
            z.extend(0.0),
            origin.extend(1.0),
        );
        let r = DMat3::from_cols(x, y, z).transpose();
        let inv = DMat4::from_cols(
            r.x_axis.extend(0.0),
            r.y_axis.extend(0.0),
            r.z_axis.extend(0.0),
            (-(r * origin)).extend(1.0),
        );
        Xf { m, inv }
    }

    /// `self * other` (apply `other` first).
    #[must_use]
    pub fn then(&self, other: &Xf) -> Xf {
        Xf {
            m: self.m * other.m,
            inv: other.inv * self.inv,
        }
    }

    /// The inverse transform.
    #[must_use]
    pub fn inverse(&self) -> Xf {
        Xf {
            m: self.inv,
            inv: self.m,
        }
    }

    /// The affine part, `None` for a projective matrix (bottom row not `0 0 0 1`).
    #[must_use]
    pub fn affine(&self) -> Option<DAffine3> {
        (self.m.row(3) == DVec4::new(0.0, 0.0, 0.0, 1.0)).then(|| DAffine3::from_mat4(self.m))
    }

    /// Whether the transform changes handedness (negative determinant of its linear part).
    #[must_use]
    pub fn swaps_handedness(&self) -> bool {
        DMat3::from_mat4(self.m).determinant() < 0.0
    }
}

/// How `m`'s linear part is a similarity (rotation or reflection times a uniform scale):
/// `Some(scale)` when its columns are orthogonal with equal lengths to a relative 1e-9.
#[must_use]
pub fn similarity_scale(m: &DMat3) -> Option<f64> {
    let (a, b, c) = (m.x_axis, m.y_axis, m.z_axis);
    let s = a.length();
    let tol = 1e-9 * s;
    let same = |v: DVec3| (v.length() - s).abs() <= tol;
    let orth = |u: DVec3, v: DVec3| u.dot(v).abs() <= tol * s;
    (s > 0.0 && same(b) && same(c) && orth(a, b) && orth(a, c) && orth(b, c)).then_some(s)
}

/// Whether `m` maps the coordinate axes onto coordinate axes without permuting them (a per-axis
/// scale, signs allowed): what keeps an axis-aligned box a box.
#[must_use]
pub fn is_axis_scale(m: &DMat3) -> bool {
    m.x_axis.y == 0.0
        && m.x_axis.z == 0.0
        && m.y_axis.x == 0.0
        && m.y_axis.z == 0.0
        && m.z_axis.x == 0.0
        && m.z_axis.y == 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverses_compose_and_stay_exact() {
        let t = Xf::translate(DVec3::new(1.0, 2.0, 3.0));
        let s = Xf::scale(DVec3::new(-1.0, 1.0, 1.0)).unwrap();
        let r = Xf::rotate(90.0, DVec3::Z).unwrap();
        let all = t.then(&s).then(&r);
        let id = all.m * all.inv;
        assert!(id.abs_diff_eq(DMat4::IDENTITY, 1e-12));
        assert!(s.swaps_handedness() && !r.swaps_handedness());
        // A right-handed rotation of +90 degrees about z takes x to y.
        let x = r.affine().unwrap().transform_vector3(DVec3::X);
        assert!(x.abs_diff_eq(DVec3::Y, 1e-15));
        assert!(Xf::scale(DVec3::new(0.0, 1.0, 1.0)).is_none());
        assert!(Xf::new(DMat4::ZERO).is_none());
    }

    #[test]
    fn frames_invert_exactly_and_similarities_are_recognised() {
        let f = Xf::frame(DVec3::X, DVec3::Z, -DVec3::Y, DVec3::new(0.0, 1.0, 3.4));
        assert_eq!(
            f.inv.transform_point3(DVec3::new(0.0, 1.0, 3.4)),
            DVec3::ZERO
        );
        assert_eq!(
            similarity_scale(&(DMat3::from_rotation_y(0.3) * 2.0)),
            Some(2.0)
        );
        assert!((similarity_scale(&DMat3::from_diagonal(DVec3::new(-2.0, 2.0, 2.0)))).is_some());
        assert_eq!(
            similarity_scale(&DMat3::from_diagonal(DVec3::new(1.0, 2.0, 1.0))),
            None
        );
        assert!(is_axis_scale(&DMat3::from_diagonal(DVec3::new(
            1.0, -2.0, 3.0
        ))));
        assert!(!is_axis_scale(&DMat3::from_rotation_x(0.1)));
    }
}
