//! Shading normals at a hit, and the rule that keeps refraction and reflection consistent.
//!
//! The rule (documented in `docs/mesh.md`): the geometric normal `ng` decides which side the
//! ray is on (entering or leaving, the media stack) and the offset side of every secondary
//! ray. The interpolated shading normal `ns` is used for lighting, the mirror direction and
//! Snell/Fresnel only while it is consistent with `ng`; at a hit where it is not, the whole
//! hit (cos_i, Fresnel, reflection and refraction) uses `ng` instead. Consistent means:
//! 1. `ns` faces the same side as `ng` (`ns . ng > 0`);
//! 2. the ray arrives from the front of `ns` (`-d . ns > 0`);
//! 3. the mirror direction about `ns` leaves on the incident side of `ng`;
//! 4. the refracted direction about `ns`, if any, continues to the far side of `ng`
//!    (checked by the tracer, which knows n1 and n2; see [`refraction_consistent`]).
//!
//! Without this, a smooth-shaded glass surface seen at grazing angles would send reflected
//! rays into the surface and refracted rays out of it while the media stack believes the
//! opposite, and the recorded tree would contradict itself.

use crate::math::reflect;
use glam::DVec3;

/// The normal to shade with, oriented to the incident side: `ns_outward` when it passes checks
/// 1-3, else `n` (the geometric normal already oriented to the incident side). `entering` says
/// whether `n` is the outward normal.
#[must_use]
pub fn shading_normal(d: DVec3, n: DVec3, ns_outward: DVec3, entering: bool) -> DVec3 {
    let ns = if entering { ns_outward } else { -ns_outward };
    let consistent = ns.dot(n) > 0.0 && -d.dot(ns) > 0.0 && reflect(d, ns).dot(n) > 0.0;
    if consistent { ns } else { n }
}

/// Check 4: a refracted direction must continue to the far side of the geometric normal `n`
/// (oriented to the incident side).
#[must_use]
pub fn refraction_consistent(n: DVec3, refracted: DVec3) -> bool {
    refracted.dot(n) < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flipped_shading_normal_falls_back_to_geometric() {
        let n = DVec3::Y;
        let d = DVec3::new(1.0, -1.0, 0.0).normalize();
        // Shading normal facing the other way than the geometric one.
        assert_eq!(shading_normal(d, n, -DVec3::Y, true), n);
        // Leaving: the outward normal is -n; a consistent outward ns flips to the incident side.
        let tilt = DVec3::new(0.1, -1.0, 0.0).normalize();
        assert_eq!(shading_normal(d, n, tilt, false), -tilt);
    }

    #[test]
    fn grazing_ray_behind_the_shading_normal_falls_back() {
        let n = DVec3::Y;
        // A ray grazing at 5 degrees, shading normal tilted 20 degrees towards it.
        let d = DVec3::new(5f64.to_radians().cos(), -5f64.to_radians().sin(), 0.0);
        let ns = DVec3::new(20f64.to_radians().sin(), 20f64.to_radians().cos(), 0.0);
        assert!(-d.dot(ns) < 0.0);
        assert_eq!(shading_normal(d, n, ns, true), n);
        // Tilted 3 degrees towards it: the ray is in front of ns, but the mirror direction
        // about ns would go below the geometric surface.
        let ns = DVec3::new(3f64.to_radians().sin(), 3f64.to_radians().cos(), 0.0);
        assert!(-d.dot(ns) > 0.0);
        assert!(reflect(d, ns).dot(n) <= 0.0);
        assert_eq!(shading_normal(d, n, ns, true), n);
        // A mild tilt at a steep angle is kept.
        let d = DVec3::new(0.3, -1.0, 0.0).normalize();
        assert_eq!(shading_normal(d, n, ns, true), ns);
    }

    #[test]
    fn refraction_side_check() {
        assert!(refraction_consistent(DVec3::Y, -DVec3::Y));
        assert!(!refraction_consistent(DVec3::Y, DVec3::new(1.0, 0.01, 0.0)));
    }
}
