//! glTF materials onto raytree's: the metallic-roughness model (glTF 2.0 Appendix B),
//! `KHR_materials_transmission`, `_ior`, `_volume`, `_emissive_strength` and `_unlit`, and
//! textures read as their mean.
//!
//! glTF's BRDF is `mix(dielectric, metal, metallic)`: the metal reflects with Schlick's Fresnel
//! of `F0 = baseColor`; the dielectric is a specular coat of `F0 = ((ior-1)/(ior+1))^2` (0.04 at
//! the default ior 1.5) over a Lambertian base (or, with transmission, a BTDF), the base
//! weighted by `1 - F`. Both share one GGX distribution of `alpha = roughness^2`. raytree has
//! a Lambert lobe, a constant mirror (`reflectivity`) or conductor Fresnel lobe (`conductor`),
//! and a dielectric interface (`transmissivity` + `ior`), all with one alpha, so
//! [`map`] writes:
//!
//! - `diffuse = baseColor (1 - metallic)(1 - transmission)(1 - F0)`: the coat's `1 - F` at
//!   normal incidence;
//! - without metal: the coat as a constant `reflectivity` of its `F0` (no rise towards
//!   grazing; energy is conserved);
//! - with metal: one conductor lobe of the blended `F0 = mix(F0_dielectric, baseColor,
//!   metallic)`: per channel the complex index whose exact Fresnel has that normal-incidence
//!   reflectance and is nearest Schlick's curve ([`index_for_f0`]);
//! - transmission with `KHR_materials_volume` (thickness > 0): a refracting dielectric of the
//!   ior tinted by baseColor, with Beer absorption `-ln(attenuationColor) /
//!   attenuationDistance`; without it glTF's surface is thin-walled: light passes straight
//!   through (`ior` 1) with weight `baseColor (1 - F0)`, the coat reflects as above;
//! - `emission = emissiveFactor * emissiveStrength` (radiance, emitted from the front side).

use crate::scene::desc::{ConductorDesc, MaterialDesc, TextureDesc, Triple};

/// A glTF material's parameters after textures were folded in (their means).
#[derive(Clone, Debug, PartialEq)]
pub struct Pbr {
    /// Linear base colour (RGB).
    pub base: Triple,
    /// `metallicFactor`.
    pub metallic: f64,
    /// `roughnessFactor` (perceptual; alpha is its square).
    pub roughness: f64,
    /// Emitted radiance (emissive factor times strength).
    pub emission: Triple,
    /// `KHR_materials_transmission` factor.
    pub transmission: f64,
    /// `KHR_materials_ior` (default 1.5).
    pub ior: f64,
    /// `KHR_materials_volume`: thickness factor, attenuation distance and colour.
    pub volume: Option<(f64, f64, Triple)>,
    /// `KHR_materials_unlit`.
    pub unlit: bool,
}

impl Default for Pbr {
    /// glTF's defaults (the material of a primitive without one).
    fn default() -> Self {
        Self {
            base: [1.0; 3],
            metallic: 1.0,
            roughness: 1.0,
            emission: [0.0; 3],
            transmission: 0.0,
            ior: 1.5,
            volume: None,
            unlit: false,
        }
    }
}

/// The real index whose normal-incidence Fresnel reflectance is `f0` (`f0` in [0, 1)).
#[must_use]
pub fn eta_of_f0(f0: f64) -> f64 {
    let s = f0.clamp(0.0, 1.0).sqrt().min(1.0 - 1e-6);
    (1.0 + s) / (1.0 - s)
}

/// The largest difference between the exact Fresnel of `eta + i k` and Schlick's
/// `f0 + (1 - f0)(1 - cos)^5` over 91 angles from 0 to 90 degrees.
#[must_use]
pub fn schlick_gap(eta: f64, k: f64, f0: f64) -> f64 {
    (0..=90)
        .map(|d| {
            let c = f64::from(d).to_radians().cos();
            let exact = crate::bsdf::fr_complex(c, eta, k);
            (exact - (f0 + (1.0 - f0) * (1.0 - c).powi(5))).abs()
        })
        .fold(0.0, f64::max)
}

/// A complex index `(eta, k)` whose normal-incidence reflectance is `f0` and whose exact
/// Fresnel follows Schlick's curve (glTF's) closely, with the largest difference: of the real
/// index `(1 + sqrt f0) / (1 - sqrt f0)` (a dielectric's curve, within 0.04 for `f0 <= 0.1`
/// but dipping before grazing for metals' `f0`, by up to 0.49) and pbrt-v4's
/// `eta = 1, k = 2 sqrt(f0) / sqrt(1 - f0)` (its conductor from a reflectance; within 0.11 for
/// `f0 >= 0.3`), the nearer.
#[must_use]
pub fn index_for_f0(f0: f64) -> (f64, f64, f64) {
    let f = f0.clamp(0.0, 0.9999);
    let real = (eta_of_f0(f), 0.0);
    let pbrt = (1.0, 2.0 * f.sqrt() / (1.0 - f).sqrt());
    let (a, b) = (
        schlick_gap(real.0, real.1, f),
        schlick_gap(pbrt.0, pbrt.1, f),
    );
    if a <= b {
        (real.0, real.1, a)
    } else {
        (pbrt.0, pbrt.1, b)
    }
}

fn fmt3(v: Triple) -> String {
    format!("[{:.4}, {:.4}, {:.4}]", v[0], v[1], v[2])
}

/// raytree's material for `p`, and what the mapping approximated (one sentence each).
#[must_use]
pub fn map(p: &Pbr) -> (MaterialDesc, Vec<String>) {
    if p.unlit {
        return unlit(p);
    }
    let m = p.metallic.clamp(0.0, 1.0);
    let t = p.transmission.clamp(0.0, 1.0);
    let alpha = p.roughness.clamp(0.0, 1.0).powi(2);
    let f0d = crate::formats::material_map::dielectric_f0(p.ior);
    let base = p.base;
    let mut out = MaterialDesc {
        roughness: alpha,
        emission: p.emission,
        ..MaterialDesc::default()
    };
    // The opaque dielectric part: a Lambert base under the coat.
    let wd = (1.0 - m) * (1.0 - t);
    if wd > 0.0 && base.iter().any(|&c| c > 0.0) {
        out.diffuse = Some(TextureDesc::Solid(scale(base, wd * (1.0 - f0d))));
    }
    let parts = Parts {
        m,
        wd,
        // The transmitting dielectric part.
        wt: (1.0 - m) * t,
        f0d,
        volume: p.volume.filter(|v| v.0 > 0.0),
    };
    // The reflection the Fresnel lobe carries: normal-incidence reflectance per channel and
    // the share of the surface it covers (the volume dielectric reflects for itself).
    let (spec, cover) = if parts.wt > 0.0 && parts.volume.is_some() {
        let cover = m + wd;
        let f = [0, 1, 2].map(|c| m * base[c] + wd * f0d);
        (f, cover)
    } else {
        ([0, 1, 2].map(|c| m * base[c] + (1.0 - m) * f0d), 1.0)
    };
    let mut notes = Vec::new();
    if parts.wt > 0.0 {
        transmission(p, &parts, &mut out, &mut notes);
    }
    if m > 0.0 {
        notes.push(conductor(&parts, spec, cover, &mut out));
    } else if spec.iter().any(|&c| c > 0.0) {
        out.reflectivity = spec;
        notes.push(format!(
            "the dielectric specular coat (F0 {f0d:.4} from ior {}) is a constant reflectivity \
             {:.4} over the diffuse base times 1 - F0: glTF's Schlick Fresnel rise towards \
             grazing is not modelled",
            p.ior, spec[0]
        ));
    }
    (out, notes)
}

/// The shares of a glTF material's parts, and what they have in common.
struct Parts {
    /// The metallic share (`metallicFactor`, clamped to [0, 1]).
    m: f64,
    /// The opaque dielectric share, `(1 - m)(1 - transmission)`.
    wd: f64,
    /// The transmitting dielectric share, `(1 - m) transmission`.
    wt: f64,
    /// The dielectric's normal-incidence reflectance, from the IOR.
    f0d: f64,
    /// `KHR_materials_volume` when it has a thickness.
    volume: Option<(f64, f64, Triple)>,
}

/// `v` times `k`, per channel.
fn scale(v: Triple, k: f64) -> Triple {
    v.map(|c| c * k)
}

/// `KHR_materials_unlit`: an emitter of the base colour that reflects nothing.
fn unlit(p: &Pbr) -> (MaterialDesc, Vec<String>) {
    let notes = vec![format!(
        "KHR_materials_unlit: an emitter of its base colour {} and no reflection (in raytree \
         it also lights the scene)",
        fmt3(p.base)
    )];
    (
        MaterialDesc {
            emission: p.base,
            ..MaterialDesc::default()
        },
        notes,
    )
}

/// The transmitting part of `p` into `out`: a refracting dielectric with Beer's law when it
/// has a volume, thin-walled (unrefracted) without.
fn transmission(p: &Pbr, parts: &Parts, out: &mut MaterialDesc, notes: &mut Vec<String>) {
    let (base, wt, f0d) = (p.base, parts.wt, parts.f0d);
    out.transmissivity = match parts.volume {
        Some(_) => scale(base, wt),
        None => scale(base, wt * (1.0 - f0d)),
    };
    if let Some((_, dist, color)) = parts.volume {
        out.ior = Some(p.ior);
        if dist.is_finite() && dist > 0.0 {
            out.absorption = color.map(|c| (-(c.max(1e-9)).ln() / dist).max(0.0));
            if color.iter().any(|&c| c < 1e-9) {
                notes.push(
                    "KHR_materials_volume: an attenuation colour of 0 is absorbed as 1e-9".into(),
                );
            }
        }
        if base.iter().any(|&c| c != 1.0) {
            notes.push(format!(
                "transmission: raytree's dielectric tints its Fresnel reflection by the base \
                 colour {} too (glTF tints only the transmitted light)",
                fmt3(base)
            ));
        }
    } else {
        out.ior = Some(1.0);
        notes.push(format!(
            "KHR_materials_transmission without KHR_materials_volume is thin-walled \
             (glTF): light passes straight through, unrefracted, with weight {} (base colour \
             times transmission times 1 - F0 at normal incidence)",
            fmt3(out.transmissivity)
        ));
    }
}

/// The metallic part into `out`: the conductor whose exact Fresnel has the normal-incidence
/// reflectance `spec / cover` over the share `cover`; returns its note.
fn conductor(parts: &Parts, spec: Triple, cover: f64, out: &mut MaterialDesc) -> String {
    let (m, f0d) = (parts.m, parts.f0d);
    let f = spec.map(|c| c / cover);
    let idx = f.map(index_for_f0);
    let (eta, k) = (idx.map(|i| i.0), idx.map(|i| i.1));
    let gap = idx.iter().map(|i| i.2).fold(0.0, f64::max);
    out.conductor = Some(ConductorDesc {
        metal: None,
        eta: Some(eta),
        k: Some(k),
        scale: (cover < 1.0).then_some([cover; 3]),
    });
    format!(
        "metallic {m}: glTF's Schlick Fresnel of F0 = mix({f0d:.4}, baseColor, metallic) = {} \
         is the exact Fresnel of the complex index eta {} + i k {}, which has that F0 and \
         differs from Schlick's curve by at most {gap:.3} (near grazing){}",
        fmt3(f),
        fmt3(eta),
        fmt3(k),
        if parts.wd > 0.0 {
            format!(
                "; the diffuse part is weighted by 1 - F0 = {:.4} at every angle (glTF: 1 - \
                 F, less at grazing)",
                1.0 - f0d
            )
        } else {
            String::new()
        }
    )
}

/// The sRGB transfer function's inverse (IEC 61966-2-1) of an 8-bit value, as a table.
fn srgb_table() -> [f64; 256] {
    std::array::from_fn(|i| {
        let c = i as f64 / 255.0;
        if c <= 0.040_45 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    })
}

/// What an image's pixels average to.
#[derive(Clone, Debug, PartialEq)]
pub enum Mean {
    /// Mean linear RGBA (colour channels sRGB-decoded when asked), and a description of the
    /// image (`PNG 4x4`).
    Decoded([f64; 4], String),
    /// Not decoded, and why.
    Skipped(String),
}

/// The mean linear RGBA of the encoded image `bytes`: PNG is decoded (within 16384 pixels a
/// side and 256 MiB of memory), colour channels through the sRGB curve when `srgb`; other
/// formats are named and skipped.
///
/// # Errors
/// A PNG that does not decode, or is larger than the bounds.
pub fn image_mean(bytes: &[u8], srgb: bool) -> Result<Mean, String> {
    let kind = if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        "PNG"
    } else if bytes.starts_with(&[0xFF, 0xD8, 0xFF]) {
        return Ok(Mean::Skipped("JPEG images are not decoded".into()));
    } else if bytes.len() >= 12 && &bytes[0..4] == b"RIFF" && &bytes[8..12] == b"WEBP" {
        return Ok(Mean::Skipped("WebP images are not decoded".into()));
    } else if bytes.starts_with(b"\xABKTX 20\xBB") {
        return Ok(Mean::Skipped("KTX2 images are not decoded".into()));
    } else {
        return Err("the image is not PNG, JPEG, WebP or KTX2".into());
    };
    let mut reader =
        image::ImageReader::with_format(std::io::Cursor::new(bytes), image::ImageFormat::Png);
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(16384);
    limits.max_image_height = Some(16384);
    limits.max_alloc = Some(256 << 20);
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| format!("cannot decode the {kind} image: {e}"))?;
    let (w, h) = (img.width(), img.height());
    let table = srgb_table();
    let mut sum = [0.0f64; 4];
    use image::GenericImageView;
    for (_, _, px) in img.pixels() {
        for (c, s) in sum.iter_mut().take(3).enumerate() {
            let v = px.0[c];
            *s += if srgb {
                table[usize::from(v)]
            } else {
                f64::from(v) / 255.0
            };
        }
        sum[3] += f64::from(px.0[3]) / 255.0;
    }
    let n = f64::from(w) * f64::from(h);
    if n == 0.0 {
        return Err(format!("the {kind} image has no pixels"));
    }
    Ok(Mean::Decoded(sum.map(|s| s / n), format!("{kind} {w}x{h}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matte_dielectric_is_lambert_under_a_constant_coat() {
        let (m, notes) = map(&Pbr {
            base: [0.5, 0.25, 1.0],
            metallic: 0.0,
            roughness: 0.5,
            ..Pbr::default()
        });
        let Some(TextureDesc::Solid(d)) = m.diffuse else {
            panic!("{m:?}")
        };
        assert!((d[0] - 0.5 * 0.96).abs() < 1e-12 && (d[2] - 0.96).abs() < 1e-12);
        assert!((m.reflectivity[1] - 0.04).abs() < 1e-12);
        assert_eq!(m.roughness, 0.25);
        assert!(m.conductor.is_none() && m.ior.is_none());
        assert!(notes[0].contains("constant reflectivity"), "{notes:?}");
    }

    #[test]
    fn a_metal_is_the_fresnel_of_its_base_colour() {
        let (m, notes) = map(&Pbr {
            base: [0.9, 0.6, 0.3],
            metallic: 1.0,
            roughness: 0.0,
            ..Pbr::default()
        });
        assert!(m.diffuse.is_none() && m.reflectivity == [0.0; 3]);
        let c = m.conductor.unwrap();
        let (eta, k) = (c.eta.unwrap(), c.k.unwrap());
        // The exact Fresnel at normal incidence of the index is the base colour, and its curve
        // is within 0.11 of Schlick's.
        for (i, want) in [0.9, 0.6, 0.3].into_iter().enumerate() {
            let f0 = crate::formats::material_map::conductor_f0(eta[i], k[i]);
            assert!((f0 - want).abs() < 1e-12, "{f0} {want}");
            assert!(schlick_gap(eta[i], k[i], want) < 0.11);
        }
        assert!(c.scale.is_none());
        assert!(notes[0].contains("Schlick"), "{notes:?}");
        // Half metal: F0 = mix(0.04, base, 0.5), diffuse (1 - 0.5) base (1 - 0.04).
        let (m, _) = map(&Pbr {
            base: [0.5; 3],
            metallic: 0.5,
            roughness: 1.0,
            ..Pbr::default()
        });
        let c = m.conductor.unwrap();
        let f0 = crate::formats::material_map::conductor_f0(c.eta.unwrap()[0], c.k.unwrap()[0]);
        assert!((f0 - (0.5 * 0.5 + 0.5 * 0.04)).abs() < 1e-12);
        let Some(TextureDesc::Solid(d)) = m.diffuse else {
            panic!()
        };
        assert!((d[0] - 0.5 * 0.5 * 0.96).abs() < 1e-12);
        assert_eq!(m.roughness, 1.0);
        // A base colour of 1 stays a finite index; low F0 takes the real index, high pbrt's.
        assert!(eta_of_f0(1.0).is_finite() && eta_of_f0(0.0) == 1.0);
        assert!(index_for_f0(1.0).2 < 0.01);
        assert_eq!(index_for_f0(0.04).1, 0.0);
        assert_eq!(index_for_f0(0.766).0, 1.0);
        // The dielectric curve dips before grazing for a metal's F0; pbrt's stays close.
        assert!(schlick_gap(eta_of_f0(0.766), 0.0, 0.766) > 0.4);
        assert!(index_for_f0(0.766).2 < 0.09);
    }

    #[test]
    fn transmission_is_thin_walled_unless_a_volume_is_given() {
        let glass = Pbr {
            metallic: 0.0,
            roughness: 0.0,
            transmission: 1.0,
            ior: 1.5,
            ..Pbr::default()
        };
        let (thin, notes) = map(&glass);
        assert_eq!(thin.ior, Some(1.0));
        assert!((thin.transmissivity[0] - 0.96).abs() < 1e-12);
        assert!((thin.reflectivity[0] - 0.04).abs() < 1e-12);
        assert!(thin.diffuse.is_none());
        assert!(notes.iter().any(|n| n.contains("thin-walled")), "{notes:?}");
        let (solid, notes) = map(&Pbr {
            volume: Some((1.0, 2.0, [0.5, 1.0, 1.0])),
            ior: 1.33,
            ..glass
        });
        assert_eq!(solid.ior, Some(1.33));
        assert_eq!(solid.transmissivity, [1.0; 3]);
        // The dielectric reflects by its own Fresnel: no second reflection lobe.
        assert_eq!(solid.reflectivity, [0.0; 3]);
        assert!((solid.absorption[0] - 2f64.ln() / 2.0).abs() < 1e-12);
        assert_eq!(solid.absorption[1], 0.0);
        assert!(notes.is_empty(), "{notes:?}");
    }

    #[test]
    fn emission_and_unlit() {
        let (m, _) = map(&Pbr {
            emission: [2.0, 4.0, 8.0],
            metallic: 0.0,
            ..Pbr::default()
        });
        assert_eq!(m.emission, [2.0, 4.0, 8.0]);
        let (u, notes) = map(&Pbr {
            base: [0.2, 0.3, 0.4],
            unlit: true,
            ..Pbr::default()
        });
        assert_eq!(u.emission, [0.2, 0.3, 0.4]);
        assert!(u.diffuse.is_none() && u.conductor.is_none());
        assert!(notes[0].contains("unlit"));
    }

    #[test]
    fn png_means_are_linear_and_other_images_are_named() {
        // A 2x1 RGBA PNG: one sRGB 255 white, one black; alpha 255 and 0.
        let mut png = Vec::new();
        image::ImageEncoder::write_image(
            image::codecs::png::PngEncoder::new(&mut png),
            &[255, 255, 255, 255, 0, 0, 0, 0],
            2,
            1,
            image::ExtendedColorType::Rgba8,
        )
        .unwrap();
        let Mean::Decoded(m, what) = image_mean(&png, true).unwrap() else {
            panic!()
        };
        assert_eq!(m, [0.5, 0.5, 0.5, 0.5]);
        assert_eq!(what, "PNG 2x1");
        // sRGB 128 is linear 0.2158.
        let mut png = Vec::new();
        image::ImageEncoder::write_image(
            image::codecs::png::PngEncoder::new(&mut png),
            &[128, 128, 128],
            1,
            1,
            image::ExtendedColorType::Rgb8,
        )
        .unwrap();
        let Mean::Decoded(m, _) = image_mean(&png, true).unwrap() else {
            panic!()
        };
        assert!((m[0] - 0.215_86).abs() < 1e-4, "{m:?}");
        let Mean::Decoded(m, _) = image_mean(&png, false).unwrap() else {
            panic!()
        };
        assert!((m[0] - 128.0 / 255.0).abs() < 1e-12);
        assert!(matches!(
            image_mean(&[0xFF, 0xD8, 0xFF, 0xE0], true),
            Ok(Mean::Skipped(_))
        ));
        assert!(image_mean(b"GIF89a", true).is_err());
        assert!(image_mean(b"\x89PNG\r\n\x1a\nbroken", true).is_err());
    }
}
