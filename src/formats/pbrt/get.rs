//! Typed reads of a directive's parameters: a parameter of the wrong type, size or value is an
//! error at its position naming the directive.

use super::params::{Param, Params, Values};
use crate::formats::spectrum::{blackbody_rgb, sampled_rgb};
use crate::formats::{FormatError, material_map};
use crate::scene::desc::Triple;
use glam::DVec3;
use std::collections::HashMap;

/// A pbrt texture reduced to what raytree can use: a constant colour, and whether that is an
/// approximation (and of what).
#[derive(Clone, Debug)]
pub struct Tex {
    /// The colour (or the mean of a procedural pattern).
    pub rgb: Triple,
    /// Why this is only an approximation.
    pub note: Option<String>,
}

/// A directive's parameters with what is needed to report errors.
pub struct Ctx<'a> {
    /// The file.
    pub file: &'a str,
    /// The directive as written (`Shape "sphere"`), for messages.
    pub what: String,
    /// The parameters.
    pub params: &'a Params,
    /// Named textures.
    pub textures: &'a HashMap<String, Tex>,
}

/// What a spectrum parameter is, which decides how a named or blackbody spectrum converts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An albedo in [0, 1].
    Albedo,
    /// Emitted radiance or intensity.
    Light,
    /// A conductor's `eta` or `k` (named metal spectra allowed).
    Index,
}

impl Ctx<'_> {
    /// An error at `p`.
    pub fn err(&self, p: &Param, msg: impl std::fmt::Display) -> FormatError {
        FormatError {
            file: self.file.to_string(),
            line: p.line,
            column: p.column,
            message: format!("{}: \"{} {}\" {msg}", self.what, p.ty, p.name),
        }
    }

    fn typed(&self, name: &str, types: &[&str]) -> Result<Option<&Param>, FormatError> {
        match self.params.get(name) {
            Some(p) if !types.contains(&p.ty.as_str()) => {
                Err(self.err(p, format!("must be of type {}", types.join(" or "))))
            }
            other => Ok(other),
        }
    }

    fn nums(&self, name: &str, types: &[&str]) -> Result<Option<(&Param, &[f64])>, FormatError> {
        match self.typed(name, types)? {
            None => Ok(None),
            Some(p) => match &p.values {
                Values::Nums(v) => Ok(Some((p, v))),
                _ => Err(self.err(p, "must be numbers")),
            },
        }
    }

    /// One float, or `default`.
    ///
    /// # Errors
    /// Wrong type or count.
    pub fn float(&self, name: &str, default: f64) -> Result<f64, FormatError> {
        match self.nums(name, &["float"])? {
            None => Ok(default),
            Some((_, [v])) => Ok(*v),
            Some((p, _)) => Err(self.err(p, "must be one number")),
        }
    }

    /// One integer, or `default`.
    ///
    /// # Errors
    /// Wrong type or count, or not a whole number.
    pub fn int(&self, name: &str, default: i64) -> Result<i64, FormatError> {
        match self.nums(name, &["integer"])? {
            None => Ok(default),
            Some((p, [v])) if v.fract() != 0.0 || v.abs() > 1e15 => {
                Err(self.err(p, "must be a whole number"))
            }
            Some((_, [v])) => Ok(*v as i64),
            Some((p, _)) => Err(self.err(p, "must be one number")),
        }
    }

    /// Integers (`indices`).
    ///
    /// # Errors
    /// Wrong type, or a value that is not a whole number in `0..2^32`.
    pub fn indices(&self, name: &str) -> Result<Option<Vec<u32>>, FormatError> {
        let Some((p, v)) = self.nums(name, &["integer"])? else {
            return Ok(None);
        };
        v.iter()
            .map(|&x| {
                if x.fract() == 0.0 && (0.0..4_294_967_296.0).contains(&x) {
                    Ok(x as u32)
                } else {
                    Err(self.err(p, format!("holds {x}, not a vertex index")))
                }
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// Points, vectors or normals (`types`), in threes.
    ///
    /// # Errors
    /// Wrong type, or a count that is not a multiple of 3.
    pub fn points(&self, name: &str, types: &[&str]) -> Result<Option<Vec<DVec3>>, FormatError> {
        let Some((p, v)) = self.nums(name, types)? else {
            return Ok(None);
        };
        if v.len() % 3 != 0 {
            return Err(self.err(p, format!("has {} numbers, not a multiple of 3", v.len())));
        }
        Ok(Some(
            v.chunks(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect(),
        ))
    }

    /// One point (`from`, `to`).
    ///
    /// # Errors
    /// Wrong type or count.
    pub fn point(&self, name: &str, default: DVec3) -> Result<DVec3, FormatError> {
        match self.points(
            name,
            &["point3", "point", "vector3", "vector", "normal", "normal3"],
        )? {
            None => Ok(default),
            Some(v) if v.len() == 1 => Ok(v[0]),
            Some(_) => Err(self.err(self.params.get(name).expect("read"), "must be one point")),
        }
    }

    /// One boolean, or `default`.
    ///
    /// # Errors
    /// Wrong type or count.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, FormatError> {
        match self.typed(name, &["bool"])? {
            None => Ok(default),
            Some(p) => match &p.values {
                Values::Bools(b) if b.len() == 1 => Ok(b[0]),
                _ => Err(self.err(p, "must be one boolean")),
            },
        }
    }

    /// One string.
    ///
    /// # Errors
    /// Wrong type or count.
    pub fn string(&self, name: &str) -> Result<Option<String>, FormatError> {
        match self.typed(name, &["string"])? {
            None => Ok(None),
            Some(p) => match &p.values {
                Values::Strs(s) if s.len() == 1 => Ok(Some(s[0].clone())),
                _ => Err(self.err(p, "must be one string")),
            },
        }
    }

    /// A colour-valued parameter as RGB: `rgb`, `blackbody` (luminance-normalised as pbrt-v4
    /// does for lights), a named metal spectrum (for `Kind::Index`), a sampled `spectrum`, a
    /// single `float` (grey), or a `texture` (its constant colour or mean, with a note).
    /// Returns the colour and a note when it is an approximation.
    ///
    /// # Errors
    /// A wrong type or count, an unknown named spectrum or texture.
    pub fn color(
        &self,
        name: &str,
        kind: Kind,
    ) -> Result<Option<(Triple, Option<String>)>, FormatError> {
        let Some(p) = self.params.get(name) else {
            return Ok(None);
        };
        let nums = |n: usize| match &p.values {
            Values::Nums(v) if v.len() == n || n == 0 => Ok(v.clone()),
            _ => Err(self.err(p, format!("must be {n} numbers"))),
        };
        let out = match p.ty.as_str() {
            "rgb" | "color" => {
                let v = nums(3)?;
                ([v[0], v[1], v[2]], None)
            }
            "float" => {
                let v = nums(1)?;
                ([v[0]; 3], None)
            }
            "blackbody" => {
                let t = nums(1)?[0];
                if t.is_nan() || t <= 0.0 {
                    return Err(self.err(p, "needs a temperature > 0 kelvin"));
                }
                (
                    blackbody_rgb(t),
                    Some(format!(
                        "blackbody {t} K converted to linear sRGB of luminance 1"
                    )),
                )
            }
            "spectrum" => self.spectrum(p, kind)?,
            "texture" => {
                let Values::Strs(s) = &p.values else {
                    unreachable!()
                };
                let [t] = &s[..] else {
                    return Err(self.err(p, "must name one texture"));
                };
                let tex = self
                    .textures
                    .get(t)
                    .ok_or_else(|| self.err(p, format!("names an undefined texture {t:?}")))?;
                (tex.rgb, tex.note.clone())
            }
            _ => return Err(self.err(p, "must be of type rgb, spectrum, blackbody or texture")),
        };
        Ok(Some(out))
    }

    fn spectrum(&self, p: &Param, kind: Kind) -> Result<(Triple, Option<String>), FormatError> {
        match &p.values {
            Values::Strs(s) => {
                let n = s.first().map_or("", String::as_str);
                let metal = n
                    .strip_prefix("metal-")
                    .and_then(|r| r.rsplit_once('-'))
                    .and_then(|(m, part)| Some((material_map::metal(m)?, part)));
                let rgb = || {
                    Some(format!(
                        "spectrum {n:?} taken as raytree's RGB projection of the tabulated \
                         spectrum (docs/materials.md)"
                    ))
                };
                match (kind, metal) {
                    (Kind::Index, Some(((eta, _), "eta"))) => Ok((eta, rgb())),
                    (Kind::Index, Some(((_, k), "k"))) => Ok((k, rgb())),
                    _ => match glass(n) {
                        Some(v) => Ok(([v; 3], Some(format!("spectrum {n:?} taken as {v}")))),
                        None => Err(self.err(p, format!("names an unknown spectrum {n:?}"))),
                    },
                }
            }
            Values::Nums(v) if v.len() >= 2 && v.len() % 2 == 0 => {
                let pairs: Vec<(f64, f64)> = v.chunks(2).map(|c| (c[0], c[1])).collect();
                if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
                    return Err(self.err(p, "wavelengths must increase"));
                }
                Ok((
                    sampled_rgb(&pairs),
                    Some("sampled spectrum integrated to linear sRGB".into()),
                ))
            }
            _ => Err(self.err(p, "must be wavelength-value pairs or a spectrum name")),
        }
    }
}

/// The index of a glass pbrt-v4 names (`glass-BK7`): its value at the sodium d line (587.6 nm)
/// from the manufacturers' data sheets (Schott N-BK7, N-BAF10, N-FK51A, N-LASF9).
fn glass(name: &str) -> Option<f64> {
    Some(match name {
        "glass-BK7" => 1.5168,
        "glass-BAF10" => 1.6700,
        "glass-FK51A" => 1.4866,
        "glass-LASF9" => 1.8503,
        _ => return None,
    })
}
