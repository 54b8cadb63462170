//! Materials: what a surface is made of, as the scene file describes it (diffuse texture,
//! Blinn-Phong highlight, mirror and dielectric weights, index, absorption, emission, roughness,
//! microfacet distribution, conductor index) and the lobes it turns into (`super::Bsdf`).

use crate::math::Rgb;
use glam::DVec3;

/// A diffuse albedo.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// Constant.
    Solid(Rgb),
    /// World-space 3D checkerboard.
    Checker {
        /// Even cells.
        even: Rgb,
        /// Odd cells.
        odd: Rgb,
        /// Cell size.
        size: f64,
    },
}

impl Texture {
    /// The albedo at world point `p`.
    #[must_use]
    pub fn at(&self, p: DVec3) -> Rgb {
        match *self {
            Texture::Solid(c) => c,
            Texture::Checker { even, odd, size } => {
                // A tiny bias keeps points exactly on a cell boundary (a floor at y = 0) stable.
                let c = ((p / size) + 1e-9).floor();
                if (c.x + c.y + c.z).rem_euclid(2.0) == 0.0 {
                    even
                } else {
                    odd
                }
            }
        }
    }

    /// Whether the albedo is zero everywhere.
    #[must_use]
    pub fn is_black(&self) -> bool {
        match *self {
            Texture::Solid(c) => c == Rgb::ZERO,
            Texture::Checker { even, odd, .. } => even == Rgb::ZERO && odd == Rgb::ZERO,
        }
    }
}

/// The lecture's general material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Name in the scene file.
    pub name: String,
    /// Diffuse albedo.
    pub diffuse: Texture,
    /// Blinn-Phong specular colour.
    pub specular: Rgb,
    /// Blinn-Phong exponent.
    pub shininess: f64,
    /// Mirror reflectivity.
    pub reflectivity: Rgb,
    /// Transmissivity.
    pub transmissivity: Rgb,
    /// Index of refraction; `None` means index-matched to the surrounding medium.
    pub ior: Option<f64>,
    /// Beer's law coefficients inside the object.
    pub absorption: Rgb,
    /// Emitted radiance (outer side).
    pub emission: Rgb,
    /// GGX alpha of the `reflectivity` and `transmissivity` lobes, in [0, 1] (0: smooth; below
    /// [`crate::bsdf::SMOOTH_ALPHA`] the lobes are traced as smooth).
    pub roughness: f64,
    /// Alpha along the second tangent (equal to `roughness` for an isotropic lobe).
    pub roughness_v: f64,
    /// The world direction the first tangent follows where the lobe is anisotropic.
    pub tangent: DVec3,
    /// GGX or Beckmann.
    pub distribution: crate::bsdf::Distribution,
    /// A conductor's complex index: the `reflectivity` lobe's reflectance is then
    /// `reflectivity * F_conductor(cos)` per channel (`reflectivity` is the tint, at most the
    /// reflectance, so every bound on it still holds).
    pub conductor: Option<crate::bsdf::ComplexIor>,
    /// A dielectric coating over the diffuse base (plastic): `reflectivity` is then the
    /// coating's tint and the base is seen through it ([`crate::bsdf::Lobe::Plastic`]).
    pub coating: Option<crate::bsdf::Coating>,
    /// A thin dielectric sheet of this index over the medium around it: the transmissive lobe
    /// is [`crate::bsdf::Lobe::ThinDielectric`] (the material's own `ior` is then `None`: the
    /// sheet bends no ray).
    pub thin: Option<f64>,
}

impl Material {
    /// The factor a coating puts on the diffuse base's `albedo / pi` for light from cosine
    /// `cos_i` seen at cosine `cos_o` ([`crate::bsdf::Coating::base_factor`]); 1 without one.
    #[must_use]
    #[inline]
    pub fn base_factor(&self, cos_i: f64, cos_o: f64) -> f64 {
        self.coating
            .map_or(1.0, |c| c.base_factor(cos_i.abs(), cos_o.abs()))
    }

    /// Whether the material transmits light.
    #[must_use]
    pub fn is_transmissive(&self) -> bool {
        self.transmissivity != Rgb::ZERO
    }

    /// Whether the material has a rough (GGX) lobe: a roughness of at least
    /// [`crate::bsdf::SMOOTH_ALPHA`] on a nonzero `reflectivity` or `transmissivity`.
    #[must_use]
    pub fn is_rough(&self) -> bool {
        self.roughness.max(self.roughness_v) >= crate::bsdf::SMOOTH_ALPHA
            && (self.reflectivity != Rgb::ZERO || self.is_transmissive())
    }

    /// Whether the rough lobes are anisotropic (`roughness_v` differs from `roughness`), which
    /// makes the shading frame follow [`Material::tangent`].
    #[must_use]
    pub fn is_anisotropic(&self) -> bool {
        self.roughness_v != self.roughness
    }

    /// The microfacet distribution of the rough lobes (alphas clamped to at least
    /// [`crate::bsdf::SMOOTH_ALPHA`]).
    #[must_use]
    pub fn microfacet(&self) -> crate::bsdf::Microfacet {
        crate::bsdf::Microfacet::with(self.distribution, self.roughness, self.roughness_v)
    }

    /// The lobe of the `reflectivity` term: a mirror of constant weight, a conductor with
    /// Fresnel, or a coating's reflection alone (its dielectric Fresnel, no base); GGX/Beckmann
    /// rough where `rough`.
    #[must_use]
    pub fn reflection_lobe(&self, rough: bool) -> crate::bsdf::Lobe {
        use crate::bsdf::Lobe;
        let weight = self.reflectivity;
        if let Some(coating) = self.coating {
            return Lobe::Plastic {
                diffuse: Rgb::ZERO,
                specular: weight,
                coating,
                dist: self.microfacet(),
            };
        }
        match (self.conductor, rough) {
            (None, false) => Lobe::Mirror { weight },
            (None, true) => Lobe::RoughMirror {
                weight,
                dist: self.microfacet(),
            },
            (Some(ior), false) => Lobe::Conductor { weight, ior },
            (Some(ior), true) => Lobe::RoughConductor {
                weight,
                ior,
                dist: self.microfacet(),
            },
        }
    }
}
