//! Warps from the unit square to the domains Monte Carlo needs, each with its pdf.
//!
//! Sources: pbrt-v4 `src/pbrt/util/sampling.h` (`SampleUniformDiskConcentric`,
//! `SampleCosineHemisphere`, `SampleUniformCone`, `SampleUniformTriangle`), Nori's
//! `src/warp.cpp`, Shirley and Chiu 1997 ("A Low Distortion Map Between Disk and Square").
//! Directions are in a local frame with `z` the axis (normal or cone axis).

use glam::{DVec2, DVec3};
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI};

/// Shirley-Chiu concentric map from `[0, 1)^2` to the unit disk (pbrt-v4
/// `SampleUniformDiskConcentric`); uniform in area, pdf [`concentric_disk_pdf`].
#[must_use]
pub fn square_to_concentric_disk(u: DVec2) -> DVec2 {
    let o = 2.0 * u - DVec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return DVec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    r * DVec2::new(theta.cos(), theta.sin())
}

/// Area pdf of [`square_to_concentric_disk`]: `1 / pi` inside the unit disk, 0 outside.
#[must_use]
pub fn concentric_disk_pdf(p: DVec2) -> f64 {
    if p.length_squared() <= 1.0 {
        FRAC_1_PI
    } else {
        0.0
    }
}

/// Cosine-weighted hemisphere around `+z` by Malley's method (the concentric disk lifted);
/// pdf [`cosine_hemisphere_pdf`].
#[must_use]
pub fn square_to_cosine_hemisphere(u: DVec2) -> DVec3 {
    let d = square_to_concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    DVec3::new(d.x, d.y, z)
}

/// Solid-angle pdf `cos(theta) / pi` of [`square_to_cosine_hemisphere`] (0 below the horizon).
#[must_use]
pub fn cosine_hemisphere_pdf(w: DVec3) -> f64 {
    if w.z > 0.0 { w.z * FRAC_1_PI } else { 0.0 }
}

/// Uniform sphere (pbrt-v4 `SampleUniformSphere`); pdf `1 / (4 pi)`.
#[must_use]
pub fn square_to_uniform_sphere(u: DVec2) -> DVec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// `1 - cos(theta_max)` computed without cancellation from `sin^2(theta_max)` when the cone is
/// narrow (a far, small light: `1 - cos` would round to 0 and the pdf to infinity).
#[must_use]
pub fn one_minus_cos(cos_max: f64, sin2_max: f64) -> f64 {
    if cos_max > 0.5 {
        sin2_max / (1.0 + cos_max)
    } else {
        1.0 - cos_max
    }
}

/// Uniform directions in the cone of half-angle `theta_max` around `+z`, given as
/// `cos_max = cos(theta_max)` and `sin2_max = sin^2(theta_max)` (both, so that narrow cones
/// keep their precision; pbrt-v4 `SampleUniformCone`, and its `Sphere::Sample` for the
/// `sin2` form). Solid-angle pdf [`uniform_cone_pdf`].
#[must_use]
pub fn square_to_uniform_cone(u: DVec2, cos_max: f64, sin2_max: f64) -> DVec3 {
    // cos(theta) = 1 - u (1 - cos_max), sin^2 = 1 - cos^2 written as (1-cos)(1+cos).
    let one_minus = u.x * one_minus_cos(cos_max, sin2_max);
    let cos = 1.0 - one_minus;
    let sin = (one_minus * (2.0 - one_minus)).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    DVec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// Solid-angle pdf of [`square_to_uniform_cone`]: `1 / (2 pi (1 - cos_max))` inside the cone.
#[must_use]
pub fn uniform_cone_pdf(w: DVec3, cos_max: f64, sin2_max: f64) -> f64 {
    if w.z >= cos_max {
        1.0 / (2.0 * PI * one_minus_cos(cos_max, sin2_max))
    } else {
        0.0
    }
}

/// Barycentrics `(b0, b1, b2)` uniform over a triangle (pbrt-v3 `UniformSampleTriangle`, the
/// square-root warp; Osada et al. 2002); area pdf `1 / area`.
#[must_use]
pub fn square_to_triangle_barycentrics(u: DVec2) -> DVec3 {
    let s = u.x.sqrt();
    let b0 = 1.0 - s;
    let b1 = u.y * s;
    DVec3::new(b0, b1, (1.0 - b0 - b1).max(0.0))
}

/// An orthonormal basis `(s, t)` completing unit `n` to a right-handed frame (Duff et al. 2017,
/// "Building an Orthonormal Basis, Revisited"; pbrt-v4 `CoordinateSystem`).
#[must_use]
pub fn orthonormal_basis(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}
