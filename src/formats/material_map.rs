//! pbrt-v4 and Mitsuba 3 materials mapped onto raytree's material (`diffuse`, `reflectivity`,
//! `transmissivity`, `ior`, `roughness` as GGX alpha, `emission`). One function per material,
//! each returning the description and, where the mapping is approximate, the sentence a
//! [`super::Note`] carries; replace a function when the material model learns the real thing.

use crate::scene::desc::{MaterialDesc, TextureDesc, Triple};

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

/// A conductor with complex index `eta + i k` per channel (pbrt `conductor`, Mitsuba
/// `conductor` / `roughconductor`): raytree's mirror with its normal-incidence reflectance,
/// constant over angle (the exact Fresnel rises towards 1 at grazing angles).
#[must_use]
pub fn conductor(eta: Triple, k: Triple, a: f64) -> Mapped {
    let r = [0, 1, 2].map(|c| conductor_f0(eta[c], k[c]));
    let (roughness, clamp) = alpha(a);
    let note = format!(
        "conductor (eta {eta:?}, k {k:?}) approximated by a mirror of constant reflectivity \
         [{:.4}, {:.4}, {:.4}], its normal-incidence Fresnel ((n-1)^2+k^2)/((n+1)^2+k^2); \
         grazing angles reflect less than they should{}",
        r[0],
        r[1],
        r[2],
        clamp.map_or(String::new(), |c| format!("; {c}"))
    );
    (
        MaterialDesc {
            reflectivity: r,
            roughness,
            ..MaterialDesc::default()
        },
        Some(note),
    )
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

/// A thin dielectric sheet of index `eta` (Mitsuba `thindielectric`): the sheet's total
/// reflectance at normal incidence, `R' = 2 R / (1 + R)` with `R` the single interface's
/// (Mitsuba 3 `thindielectric`, summing the inter-reflections), as a constant mirror, and the
/// rest passed straight through (`ior` 1).
#[must_use]
pub fn thin_dielectric(eta: f64) -> Mapped {
    let r = dielectric_f0(eta);
    let r = 2.0 * r / (1.0 + r);
    (
        MaterialDesc {
            reflectivity: [r; 3],
            transmissivity: [1.0 - r; 3],
            ior: Some(1.0),
            ..MaterialDesc::default()
        },
        Some(format!(
            "thin dielectric (eta {eta}) approximated by a constant reflectivity {r:.4} (its \
             normal-incidence value 2R/(1+R)) and transmissivity {:.4} without refraction",
            1.0 - r
        )),
    )
}

/// A diffuse base under a dielectric coating of index `eta` (pbrt `coateddiffuse`, Mitsuba
/// `plastic` / `roughplastic`): the coating as a constant mirror of its normal-incidence
/// reflectance `F0`, the base's albedo scaled by `1 - F0`. Neither pbrt's stochastic layered
/// model nor Mitsuba's internal-reflection term is reproduced.
#[must_use]
pub fn coated_diffuse(base: Triple, eta: f64, a: f64, specular: f64) -> Mapped {
    let f0 = dielectric_f0(eta) * specular;
    let (roughness, clamp) = alpha(a);
    let note = format!(
        "coated diffuse (eta {eta}) approximated by a constant coat reflectivity {f0:.4} (the \
         coating's normal-incidence Fresnel) over the diffuse base times {:.4}; the coating's \
         angular Fresnel and internal reflections are not modelled{}",
        1.0 - f0,
        clamp.map_or(String::new(), |c| format!("; {c}"))
    );
    (
        MaterialDesc {
            diffuse: Some(TextureDesc::Solid(base.map(|c| c * (1.0 - f0)))),
            reflectivity: [f0; 3],
            roughness,
            ..MaterialDesc::default()
        },
        Some(note),
    )
}

/// A Beckmann alpha used as raytree's GGX alpha (Mitsuba's rough BSDFs default to Beckmann):
/// the same alpha, so the lobes have the same width near their peak, GGX's tails are longer.
#[must_use]
pub fn beckmann_as_ggx(a: f64) -> (f64, String) {
    (
        a,
        format!(
            "Beckmann microfacets (alpha {a}) approximated by GGX with the same alpha (GGX has \
             longer tails)"
        ),
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

/// Anisotropic roughness `(u, v)` on raytree's isotropic GGX: the geometric mean, with a note
/// when they differ.
#[must_use]
pub fn isotropic(u: f64, v: f64) -> (f64, Option<String>) {
    if u == v {
        (u, None)
    } else {
        let a = (u * v).max(0.0).sqrt();
        (
            a,
            Some(format!(
                "anisotropic roughness ({u}, {v}) approximated by isotropic alpha {a:.4} (their \
                 geometric mean)"
            )),
        )
    }
}

/// RGB complex index `(eta, k)` of a named metal: pbrt-v4's `metal-<X>-eta` / `-k` and
/// Mitsuba's `material` names. Values: Tungsten renderer, `ComplexIorData.hpp` (measured
/// spectra integrated to linear sRGB), the table Mitsuba's and pbrt's spectra also come from.
#[must_use]
pub fn metal(name: &str) -> Option<(Triple, Triple)> {
    Some(match name {
        "Ag" => (
            [0.155_264_648_9, 0.116_723_296_5, 0.138_380_695_9],
            [4.828_343_322_4, 3.122_245_927_8, 2.146_950_445_5],
        ),
        "Al" => (
            [1.657_459_959_5, 0.880_368_957_9, 0.521_228_734_6],
            [9.223_869_199_6, 6.269_523_247_7, 4.837_001_228_1],
        ),
        "Au" => (
            [0.143_118_955_7, 0.374_957_043_2, 1.442_478_557_1],
            [3.983_160_424_7, 2.385_720_747_8, 1.603_215_289_9],
        ),
        "Cr" => (
            [4.369_682_866_3, 2.916_702_489_2, 1.654_700_541_3],
            [5.206_433_795_6, 4.231_364_527_7, 3.754_946_793_3],
        ),
        "Cu" => (
            [0.200_437_697_0, 0.924_033_430_4, 1.102_211_952_7],
            [3.912_948_503_3, 2.452_847_701_5, 2.142_187_955_2],
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
        let (m, note) = conductor(eta, k, 0.0);
        assert!(
            m.reflectivity.iter().all(|&r| r > 0.9),
            "{:?}",
            m.reflectivity
        );
        assert!(note.unwrap().contains("normal-incidence"));
        let (eta, k) = metal("Cu").unwrap();
        let r = [0, 1, 2].map(|c| conductor_f0(eta[c], k[c]));
        assert!(r[0] > 0.9 && r[2] < 0.65, "{r:?}");
    }

    #[test]
    fn coatings_and_thin_sheets_conserve_energy() {
        let (m, _) = coated_diffuse([0.5; 3], 1.5, 0.0, 1.0);
        assert!((m.reflectivity[0] - 0.04).abs() < 1e-15);
        let Some(TextureDesc::Solid(d)) = m.diffuse else {
            panic!()
        };
        assert!((d[0] - 0.48).abs() < 1e-15);
        let (t, _) = thin_dielectric(1.5);
        // 2R/(1+R) with R = 0.04.
        assert!((t.reflectivity[0] - 0.08 / 1.04).abs() < 1e-15);
        assert!((t.reflectivity[0] + t.transmissivity[0] - 1.0).abs() < 1e-15);
        assert_eq!(pbrt_alpha(0.25, true), 0.5);
        assert_eq!(pbrt_alpha(0.25, false), 0.25);
        assert_eq!(dielectric(1.5, 3.0).0.roughness, 1.0);
        assert_eq!(isotropic(0.04, 0.01).0, 0.02);
        assert_eq!(named_ior("bk7"), Some(1.5046));
    }
}
