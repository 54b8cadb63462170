//! The local shading frame: `z` is the (outward) shading normal, so `cos(theta) = w.z`.

use crate::sampling::warp::orthonormal_basis;
use glam::DVec3;

/// An orthonormal frame `(s, t, n)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub s: DVec3,
    /// Second tangent.
    pub t: DVec3,
    /// Normal (local `z`).
    pub n: DVec3,
}

impl Frame {
    /// The frame around unit normal `n` (Duff et al. 2017).
    #[must_use]
    pub fn from_normal(n: DVec3) -> Self {
        let (s, t) = orthonormal_basis(n);
        Self { s, t, n }
    }

    /// The frame around unit normal `n` whose first tangent `s` is `tangent` projected into the
    /// tangent plane (`t = n x s`, right-handed like [`Frame::from_normal`]); where `tangent` is
    /// parallel to `n`, the frame of [`Frame::from_normal`].
    #[must_use]
    pub fn from_normal_tangent(n: DVec3, tangent: DVec3) -> Self {
        match (tangent - tangent.dot(n) * n).try_normalize() {
            Some(s) if s.dot(n).abs() < 1e-9 => Self {
                s,
                t: n.cross(s),
                n,
            },
            _ => Self::from_normal(n),
        }
    }

    /// World direction to local coordinates.
    #[must_use]
    pub fn to_local(&self, w: DVec3) -> DVec3 {
        DVec3::new(w.dot(self.s), w.dot(self.t), w.dot(self.n))
    }

    /// Local direction to world coordinates.
    #[must_use]
    pub fn to_world(&self, w: DVec3) -> DVec3 {
        w.x * self.s + w.y * self.t + w.z * self.n
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_is_identity() {
        let f = Frame::from_normal(DVec3::new(0.3, -0.5, 0.8).normalize());
        let w = DVec3::new(-0.2, 0.9, 0.1).normalize();
        assert!((f.to_world(f.to_local(w)) - w).length() < 1e-14);
        assert!((f.to_local(f.n) - DVec3::Z).length() < 1e-14);
    }

    #[test]
    fn a_tangent_frame_follows_the_tangent_and_keeps_handedness() {
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        let f = Frame::from_normal_tangent(n, DVec3::X);
        assert!(f.s.dot(n).abs() < 1e-15 && f.s.x > 0.9);
        assert!((f.s.cross(f.t) - n).length() < 1e-14);
        let d = Frame::from_normal(n);
        assert!((d.s.cross(d.t) - n).length() < 1e-14);
        // Parallel tangent: the default frame.
        assert_eq!(
            Frame::from_normal_tangent(DVec3::X, DVec3::X),
            Frame::from_normal(DVec3::X)
        );
    }
}
