//! pbrt-v4 and Mitsuba 3 materials mapped onto raytree's material (`diffuse`, `reflectivity`,
//! `transmissivity`, `ior`, `roughness` as microfacet alpha, `roughness_v`, `distribution`,
//! `conductor`, `emission`; `docs/materials.md`). One function per material, each returning the
//! description and, where the mapping is approximate, the sentence a [`super::Note`] carries;
//! replace a function when the material model learns the real thing.

use crate::scene::desc::{CoatingDesc, ConductorDesc, MaterialDesc, TextureDesc, ThinDesc, Triple};

/// A mapped material and what its mapping approximated.
pub type Mapped = (MaterialDesc, Option<String>);

/// Lambertian reflectance `r` (pbrt `diffuse`, Mitsuba `diffuse`): exact.
#[must_use]
pub fn diffuse(r: Triple) -> MaterialDesc {
    MaterialDesc {
        diffuse: Some(TextureDesc::Solid(r)),
        ..MaterialDesc::default()
    }
}

/// A GGX alpha clamped to raytree's `[0, 1]`, with a note when it had to be.
fn alpha(a: f64) -> (f64, Option<String>) {
    if a > 1.0 {
        (1.0, Some(format!("roughness alpha {a} clamped to 1")))
    } else {
        (a.max(0.0), None)
    }
}

/// A smooth or GGX-rough dielectric interface of relative index `eta` (pbrt `dielectric`,
/// Mitsuba `dielectric` / `roughdielectric`): exact Fresnel reflection and refraction.
#[must_use]
pub fn dielectric(eta: f64, a: f64) -> Mapped {
    let (roughness, note) = alpha(a);
    (
        MaterialDesc {
            transmissivity: [1.0; 3],
            ior: Some(eta),
            roughness,
            ..MaterialDesc::default()
        },
        note,
    )
}

/// Normal-incidence Fresnel reflectance of a dielectric of relative index `eta`:
/// `((eta - 1) / (eta + 1))^2` (pbrt-v4, section 9.3.2).
#[must_use]
pub fn dielectric_f0(eta: f64) -> f64 {
    ((eta - 1.0) / (eta + 1.0)).powi(2)
}

/// Normal-incidence reflectance of a conductor with complex index `eta + i k`:
/// `((n - 1)^2 + k^2) / ((n + 1)^2 + k^2)` (pbrt-v4 `FrComplex` at `cos theta = 1`, section
/// 9.3.6; Born and Wolf, *Principles of Optics*, section 14.2).
#[must_use]
pub fn conductor_f0(n: f64, k: f64) -> f64 {
    ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k)
}

/// A conductor with complex index `eta + i k` per channel, its Fresnel tinted by `scale`
/// (pbrt `conductor`, Mitsuba `conductor` / `roughconductor`): raytree's conductor, the exact
/// Fresnel of the complex index (`bsdf::fr_complex`). An `eta`, `k` pair that is one of
/// raytree's named metals ([`crate::bsdf::METALS`]) is written by its name.
#[must_use]
pub fn conductor(eta: Triple, k: Triple, a: f64, scale: Triple) -> Mapped {
    let (roughness, note) = alpha(a);
    let named = crate::bsdf::METALS
        .iter()
        .find(|m| m.1 == eta && m.2 == k)
        .map(|m| m.0.to_string());
    let conductor = ConductorDesc {
        eta: named.is_none().then_some(eta),
        k: named.is_none().then_some(k),
        metal: named,
        scale: (scale != [1.0; 3]).then_some(scale),
    };
    (
        MaterialDesc {
            conductor: Some(conductor),
            roughness,
            ..MaterialDesc::default()
        },
        note,
    )
}

/// pbrt-v4's conductor given by its normal-incidence `reflectance` instead of `eta` and `k`:
/// pbrt-v4 (`ConductorMaterial`) makes it the complex index `eta = 1`, `k = 2 sqrt(r) /
/// sqrt(1 - r)` (`r` clamped to 0.9999), whose normal-incidence reflectance is `r`; the same
/// index here, so the Fresnel is pbrt's.
#[must_use]
pub fn conductor_reflectance(r: Triple, a: f64) -> Mapped {
    let k = r.map(|c| {
        let c = c.clamp(0.0, 0.9999);
        2.0 * c.sqrt() / (1.0 - c).sqrt()
    });
    conductor([1.0; 3], k, a, [1.0; 3])
}

/// A perfect mirror scaled by `r` (Mitsuba `conductor` with `material="none"`): exact.
#[must_use]
pub fn mirror(r: Triple, a: f64) -> Mapped {
    let (roughness, note) = alpha(a);
    (
        MaterialDesc {
            reflectivity: r,
            roughness,
            ..MaterialDesc::default()
        },
        note,
    )
}

/// A thin dielectric sheet of index `eta` (Mitsuba and pbrt `thindielectric`): raytree's
/// thin sheet, exactly (reflectance `2R / (1 + R)` of the angle's Fresnel, the rest straight
/// through; [`crate::bsdf::Lobe::ThinDielectric`]).
#[must_use]
pub fn thin_dielectric(eta: f64) -> Mapped {
    (
        MaterialDesc {
            transmissivity: [1.0; 3],
            thin: Some(ThinDesc { ior: eta }),
            ..MaterialDesc::default()
        },
        None,
    )
}

/// A diffuse base under a dielectric coating of index `eta`, tinted `specular` (Mitsuba
/// `plastic` / `roughplastic`, pbrt `coateddiffuse`): raytree's coated material
/// ([`crate::bsdf::Coating`], the model of Mitsuba's plastic), exact for Mitsuba apart from
/// its `F_dr` fits (docs/materials.md); `nonlinear` tints the inter-reflections by the base.
/// `note` says what the caller's format differs in.
#[must_use]
pub fn coated_diffuse(
    base: Triple,
    eta: f64,
    a: f64,
    specular: Triple,
    nonlinear: bool,
    note: Option<String>,
) -> Mapped {
    let (roughness, clamp) = alpha(a);
    let notes: Vec<String> = note.into_iter().chain(clamp).collect();
    (
        MaterialDesc {
            diffuse: Some(TextureDesc::Solid(base)),
            roughness,
            coating: Some(CoatingDesc {
                ior: eta,
                scale: (specular != [1.0; 3]).then_some(specular),
                nonlinear,
            }),
            ..MaterialDesc::default()
        },
        (!notes.is_empty()).then(|| notes.join("; ")),
    )
}

/// pbrt-v4's roughness to alpha: `sqrt(roughness)` when `remaproughness` is true (its
/// default; `TrowbridgeReitzDistribution::RoughnessToAlpha`), else the value itself.
#[must_use]
pub fn pbrt_alpha(roughness: f64, remap: bool) -> f64 {
    if remap {
        roughness.max(0.0).sqrt()
    } else {
        roughness
    }
}

/// Roughness `(u, v)` along the two tangents: raytree's `roughness` and, when they differ,
/// `roughness_v` (both clamped to `[0, 1]`), with a note when they differ: raytree's first
/// tangent is the world x axis projected onto the surface, not the file's `dpdu`.
#[must_use]
pub fn anisotropic(u: f64, v: f64) -> (f64, Option<f64>, Option<String>) {
    if u == v {
        (u, None, None)
    } else {
        (
            u,
            Some(v.clamp(0.0, 1.0)),
            Some(format!(
                "anisotropic roughness ({u}, {v}): alpha_u follows raytree's tangent, the world x \
                 axis projected onto the surface (the file's surface parametrisation, dpdu, is \
                 not available)"
            )),
        )
    }
}

/// RGB complex index `(eta, k)` of a named metal: pbrt-v4's `metal-<X>-eta` / `-k` and
/// Mitsuba's `material` names. Ag, Al, Au and Cu are raytree's named metals
/// ([`crate::bsdf::METALS`]: pbrt-v4's tabulated spectra projected to linear sRGB under D65);
/// Cr, which raytree does not name, is the Tungsten renderer's `ComplexIorData.hpp` value (the
/// same measured data sampled to RGB).
#[must_use]
pub fn metal(name: &str) -> Option<(Triple, Triple)> {
    if let Some(m) = crate::bsdf::METALS.iter().find(|m| m.0 == name) {
        return Some((m.1, m.2));
    }
    Some(match name {
        "Cr" => (
            [4.369_682_866_3, 2.916_702_489_2, 1.654_700_541_3],
            [5.206_433_795_6, 4.231_364_527_7, 3.754_946_793_3],
        ),
        _ => return None,
    })
}

/// Index of refraction of a material Mitsuba names (`int_ior="bk7"`), from Mitsuba 3's
/// documented table of refractive indices.
#[must_use]
pub fn named_ior(name: &str) -> Option<f64> {
    Some(match name {
        "vacuum" => 1.0,
        "helium" => 1.000_036,
        "hydrogen" => 1.000_132,
        "air" => 1.000_277,
        "carbon dioxide" => 1.000_449,
        "water" => 1.333,
        "acetone" => 1.36,
        "ethanol" => 1.361,
        "carbon tetrachloride" => 1.461,
        "glycerol" => 1.4729,
        "benzene" => 1.501,
        "silicone oil" => 1.520_45,
        "bromine" => 1.661,
        "water ice" => 1.31,
        "fused quartz" => 1.458,
        "pyrex" => 1.470,
        "acrylic glass" => 1.49,
        "polypropylene" => 1.49,
        "bk7" => 1.5046,
        "sodium chloride" => 1.544,
        "amber" => 1.55,
        "pet" => 1.575,
        "diamond" => 2.419,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conductor_fresnel_at_normal_incidence_is_the_closed_form() {
        // k = 0 is the dielectric's ((n-1)/(n+1))^2.
        assert!((conductor_f0(1.5, 0.0) - 0.04).abs() < 1e-15);
        // A perfect conductor (k -> inf) reflects everything.
        assert!(conductor_f0(0.2, 1e8) > 1.0 - 1e-12);
        // Silver reflects > 90 % in every channel, copper far less in blue than red.
        let (eta, k) = metal("Ag").unwrap();
        assert!((0..3).all(|c| conductor_f0(eta[c], k[c]) > 0.9));
        let (eta, k) = metal("Cu").unwrap();
        let r = [0, 1, 2].map(|c| conductor_f0(eta[c], k[c]));
        assert!(r[0] > 0.9 && r[2] < 0.65, "{r:?}");
    }

    #[test]
    fn conductors_are_raytree_conductors_named_when_they_can_be() {
        // A named metal's index is written by its name, exactly, without a note.
        let (eta, k) = metal("Au").unwrap();
        let (m, note) = conductor(eta, k, 0.2, [1.0; 3]);
        let c = m.conductor.unwrap();
        assert_eq!(c.metal.as_deref(), Some("Au"));
        assert!(c.eta.is_none() && c.k.is_none() && c.scale.is_none());
        assert!(note.is_none() && m.reflectivity == [0.0; 3] && m.roughness == 0.2);
        // Chromium is not named in raytree: its index, tinted.
        let (eta, k) = metal("Cr").unwrap();
        let c = conductor(eta, k, 0.0, [0.5; 3]).0.conductor.unwrap();
        assert_eq!((c.eta, c.k, c.scale), (Some(eta), Some(k), Some([0.5; 3])));
        // pbrt's reflectance form: eta 1, k = 2 sqrt(r) / sqrt(1 - r) has F(0) = r.
        let c = conductor_reflectance([0.25, 0.5, 1.0], 0.0)
            .0
            .conductor
            .unwrap();
        let (eta, k) = (c.eta.unwrap(), c.k.unwrap());
        for (i, r) in [0.25, 0.5, 0.9999].into_iter().enumerate() {
            assert!((conductor_f0(eta[i], k[i]) - r).abs() < 1e-12);
        }
        assert_eq!(anisotropic(0.1, 0.1), (0.1, None, None));
        let (u, v, n) = anisotropic(0.1, 0.3);
        assert_eq!((u, v), (0.1, Some(0.3)));
        assert!(n.unwrap().contains("dpdu"));
    }

    #[test]
    fn coatings_and_thin_sheets_conserve_energy() {
        let (m, n) = coated_diffuse([0.5; 3], 1.5, 0.0, [1.0; 3], false, None);
        assert_eq!(n, None);
        assert_eq!(m.reflectivity, [0.0; 3]);
        let c = m.coating.expect("a coating");
        assert_eq!((c.ior, c.scale), (1.5, None));
        assert!(matches!(
            m.diffuse,
            Some(TextureDesc::Solid([0.5, 0.5, 0.5]))
        ));
        let (m, n) = coated_diffuse([0.5; 3], 1.5, 2.0, [0.5; 3], true, Some("x".into()));
        let c = m.coating.unwrap();
        assert_eq!((c.scale, c.nonlinear), (Some([0.5; 3]), true));
        assert!(n.unwrap().starts_with("x; roughness alpha 2 clamped"));
        let (t, n) = thin_dielectric(1.5);
        assert_eq!((t.transmissivity, t.ior, n), ([1.0; 3], None, None));
        assert_eq!(t.thin.unwrap().ior, 1.5);
        assert_eq!(pbrt_alpha(0.25, true), 0.5);
        assert_eq!(pbrt_alpha(0.25, false), 0.25);
        assert_eq!(dielectric(1.5, 3.0).0.roughness, 1.0);
        assert_eq!(named_ior("bk7"), Some(1.5046));
    }
}
