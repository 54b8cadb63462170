//! Mitsuba properties (`<float>`, `<rgb>`, `<transform>`, ...) of an object element.

use super::tree::El;
use crate::formats::FormatError;
use crate::formats::spectrum::{blackbody_rgb, sampled_rgb};
use crate::formats::xform::Xf;
use glam::{DMat4, DVec3};
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};

/// A colour and, when it is an approximation, why.
pub type Color = ([f64; 3], Option<String>);

/// The properties of one object element.
pub struct Props<'a> {
    by_name: HashMap<&'a str, &'a El>,
    ids: &'a HashMap<String, El>,
    used: RefCell<HashSet<String>>,
}

const PROPERTY_TAGS: [&str; 10] = [
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
    "texture",
];

impl<'a> Props<'a> {
    /// The named properties of `el` (named `<texture>`s and `<ref name=...>`s too).
    ///
    /// # Errors
    /// A property without a name, or a name given twice.
    pub fn new(el: &'a El, ids: &'a HashMap<String, El>) -> Result<Self, FormatError> {
        let mut by_name = HashMap::new();
        for c in &el.children {
            let named = PROPERTY_TAGS.contains(&c.tag.as_str())
                || (c.tag == "ref" && c.attr("name").is_some());
            if !named || (c.tag == "texture" && c.attr("name").is_none()) {
                continue;
            }
            let n = c.attr("name").ok_or_else(|| c.err("needs a name"))?;
            if by_name.insert(n, c).is_some() {
                return Err(c.err(format!("property {n:?} given twice")));
            }
        }
        Ok(Self {
            by_name,
            ids,
            used: RefCell::new(HashSet::new()),
        })
    }

    fn get(&self, name: &str) -> Option<&'a El> {
        let e = self.by_name.get(name).copied()?;
        self.used.borrow_mut().insert(name.to_string());
        Some(e)
    }

    /// The property elements nothing read, as labels.
    #[must_use]
    pub fn unused(&self) -> Vec<String> {
        let used = self.used.borrow();
        let mut v: Vec<String> = self
            .by_name
            .iter()
            .filter(|(k, _)| !used.contains(**k))
            .map(|(_, e)| e.label())
            .collect();
        v.sort();
        v
    }

    fn value(&self, e: &'a El) -> Result<&'a str, FormatError> {
        e.attr("value").ok_or_else(|| e.err("needs a value"))
    }

    /// A `<float>` (an `<integer>` is accepted too), or `default`.
    ///
    /// # Errors
    /// Another property type, or a value that is not a number.
    pub fn float(&self, name: &str, default: f64) -> Result<f64, FormatError> {
        match self.get(name) {
            None => Ok(default),
            Some(e) if e.tag == "float" => number(e, self.value(e)?),
            Some(e) if e.tag == "integer" => {
                let v = self.value(e)?;
                v.trim()
                    .parse::<i64>()
                    .map(|i| i as f64)
                    .map_err(|_| e.err(format!("{v:?} is not a whole number")))
            }
            Some(e) => Err(e.err("must be a <float>")),
        }
    }

    /// An `<integer>`, or `default`.
    ///
    /// # Errors
    /// Another type, or not a whole number.
    pub fn int(&self, name: &str, default: i64) -> Result<i64, FormatError> {
        match self.get(name) {
            None => Ok(default),
            Some(e) if e.tag == "integer" => self
                .value(e)?
                .trim()
                .parse()
                .map_err(|_| e.err("is not a whole number")),
            Some(e) => Err(e.err("must be an <integer>")),
        }
    }

    /// A `<boolean>`, or `default`.
    ///
    /// # Errors
    /// Another type, or neither true nor false.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, FormatError> {
        match self.get(name) {
            None => Ok(default),
            Some(e) if e.tag == "boolean" => match self.value(e)?.trim() {
                "true" => Ok(true),
                "false" => Ok(false),
                v => Err(e.err(format!("{v:?} is neither true nor false"))),
            },
            Some(e) => Err(e.err("must be a <boolean>")),
        }
    }

    /// A `<string>`.
    ///
    /// # Errors
    /// Another type.
    pub fn string(&self, name: &str) -> Result<Option<String>, FormatError> {
        match self.get(name) {
            None => Ok(None),
            Some(e) if e.tag == "string" => Ok(Some(self.value(e)?.to_string())),
            Some(e) => Err(e.err("must be a <string>")),
        }
    }

    /// A `<point>` or `<vector>`: `value="x, y, z"` or `x=` `y=` `z=` attributes.
    ///
    /// # Errors
    /// Another type, or bad numbers.
    pub fn point(&self, name: &str) -> Result<Option<DVec3>, FormatError> {
        match self.get(name) {
            None => Ok(None),
            Some(e) if e.tag == "point" || e.tag == "vector" => xyz(e, 0.0).map(Some),
            Some(e) => Err(e.err("must be a <point> or <vector>")),
        }
    }

    /// A colour: `<rgb>`, `<float>` (grey), `<spectrum>` (uniform value, wavelength:value
    /// pairs, or `type="blackbody"`), or a `<texture>` (its constant or mean colour, noted).
    ///
    /// # Errors
    /// Another type or bad numbers.
    pub fn color(&self, name: &str) -> Result<Option<Color>, FormatError> {
        let Some(mut e) = self.get(name) else {
            return Ok(None);
        };
        if e.tag == "ref" {
            let id = e.attr("id").ok_or_else(|| e.err("needs an id"))?;
            e = self
                .ids
                .get(id)
                .ok_or_else(|| e.err(format!("refers to undefined id {id:?}")))?;
        }
        Ok(Some(color_of(e, self.ids)?))
    }

    /// A `<transform>` (translate, rotate, scale, matrix, lookat, applied in order).
    ///
    /// # Errors
    /// Another type, or a malformed or singular step.
    pub fn transform(&self, name: &str) -> Result<Option<Xf>, FormatError> {
        match self.get(name) {
            None => Ok(None),
            Some(e) if e.tag == "transform" => transform(e).map(Some),
            Some(e) => Err(e.err("must be a <transform>")),
        }
    }
}

fn number(e: &El, v: &str) -> Result<f64, FormatError> {
    let x: f64 = v
        .trim()
        .parse()
        .map_err(|_| e.err(format!("{v:?} is not a number")))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(e.err("is not finite"))
    }
}

/// Numbers separated by commas and/or spaces.
fn numbers(e: &El, v: &str) -> Result<Vec<f64>, FormatError> {
    v.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| number(e, s))
        .collect()
}

/// `value="x, y, z"` (one number: all three) or `x`, `y`, `z` attributes (missing: `default`).
fn xyz(e: &El, default: f64) -> Result<DVec3, FormatError> {
    if let Some(v) = e.attr("value") {
        let n = numbers(e, v)?;
        return match n[..] {
            [a] => Ok(DVec3::splat(a)),
            [a, b, c] => Ok(DVec3::new(a, b, c)),
            _ => Err(e.err(format!("value {v:?} needs 1 or 3 numbers"))),
        };
    }
    let get = |k: &str| e.attr(k).map_or(Ok(default), |v| number(e, v));
    Ok(DVec3::new(get("x")?, get("y")?, get("z")?))
}

/// The colour of a colour-valued element (see [`Props::color`]).
pub fn color_of(e: &El, ids: &HashMap<String, El>) -> Result<Color, FormatError> {
    match e.tag.as_str() {
        "rgb" => {
            let v = e.attr("value").ok_or_else(|| e.err("needs a value"))?;
            match numbers(e, v)?[..] {
                [a] => Ok(([a; 3], None)),
                [r, g, b] => Ok(([r, g, b], None)),
                _ => Err(e.err(format!("value {v:?} needs 1 or 3 numbers"))),
            }
        }
        "float" => {
            let v = number(e, e.attr("value").ok_or_else(|| e.err("needs a value"))?)?;
            Ok(([v; 3], None))
        }
        "spectrum" | "blackbody" => spectrum(e, ids),
        "texture" => texture(e, ids),
        _ => Err(e.err("must be an <rgb>, <spectrum>, <float> or <texture>")),
    }
}

fn spectrum(e: &El, ids: &HashMap<String, El>) -> Result<Color, FormatError> {
    if e.tag == "blackbody" || e.attr("type") == Some("blackbody") {
        let t = match e.attr("temperature") {
            Some(t) => number(e, t.trim_end_matches('K'))?,
            None => {
                let p = Props::new(e, ids)?;
                p.float("temperature", 6504.0)?
            }
        };
        if t <= 0.0 {
            return Err(e.err("needs a temperature > 0"));
        }
        return Ok((
            blackbody_rgb(t),
            Some(format!(
                "blackbody {t} K converted to linear sRGB of luminance 1"
            )),
        ));
    }
    if e.attr("filename").is_some() {
        return Err(e.err("spectra read from files are not supported: give an <rgb>"));
    }
    let v = e.attr("value").ok_or_else(|| e.err("needs a value"))?;
    if !v.contains(':') {
        let x = number(e, v)?;
        return Ok(([x; 3], None));
    }
    let mut pairs = Vec::new();
    for item in v.split(',') {
        let (l, x) = item
            .split_once(':')
            .ok_or_else(|| e.err(format!("{item:?} is not wavelength:value")))?;
        pairs.push((number(e, l)?, number(e, x)?));
    }
    if pairs.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(e.err("wavelengths must increase"));
    }
    Ok((
        sampled_rgb(&pairs),
        Some("sampled spectrum integrated to linear sRGB".into()),
    ))
}

fn texture(e: &El, ids: &HashMap<String, El>) -> Result<Color, FormatError> {
    let ty = e.attr("type").unwrap_or("");
    let p = Props::new(e, ids)?;
    match ty {
        "checkerboard" => {
            let a = p.color("color0")?.map_or([0.4; 3], |c| c.0);
            let b = p.color("color1")?.map_or([0.2; 3], |c| c.0);
            let mean = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
            Ok((
                mean,
                Some(format!(
                    "checkerboard texture replaced by its mean colour {mean:?}"
                )),
            ))
        }
        _ => Ok((
            [0.5; 3],
            Some(format!("texture type {ty:?} not read: grey 0.5 used")),
        )),
    }
}

/// A `<transform>`'s matrix: each step left-multiplies the ones before it.
///
/// # Errors
/// An unknown step, bad numbers, a zero scale or axis, or a singular matrix.
pub fn transform(e: &El) -> Result<Xf, FormatError> {
    let mut x = Xf::IDENTITY;
    for s in &e.children {
        let step = match s.tag.as_str() {
            "translate" => Xf::translate(xyz(s, 0.0)?),
            "scale" => Xf::scale(xyz(s, 1.0)?).ok_or_else(|| s.err("a scale factor is zero"))?,
            "rotate" => {
                let angle = number(s, s.attr("angle").ok_or_else(|| s.err("needs an angle"))?)?;
                Xf::rotate(angle, xyz(s, 0.0)?).ok_or_else(|| s.err("the axis is zero"))?
            }
            "matrix" => {
                let v = numbers(s, s.attr("value").ok_or_else(|| s.err("needs a value"))?)?;
                let m = match v.len() {
                    16 => DMat4::from_cols_slice(&v).transpose(),
                    9 => {
                        let m3 = glam::DMat3::from_cols_slice(&v).transpose();
                        DMat4::from_mat3(m3)
                    }
                    n => return Err(s.err(format!("needs 16 (or 9) numbers, got {n}"))),
                };
                Xf::new(m).ok_or_else(|| s.err("the matrix is singular"))?
            }
            "lookat" => {
                let p = |k: &str| -> Result<DVec3, FormatError> {
                    let v = s.attr(k).ok_or_else(|| s.err(format!("needs {k}")))?;
                    match numbers(s, v)?[..] {
                        [a, b, c] => Ok(DVec3::new(a, b, c)),
                        _ => Err(s.err(format!("{k} needs 3 numbers"))),
                    }
                };
                let (o, t) = (p("origin")?, p("target")?);
                let up = if s.attr("up").is_some() {
                    p("up")?
                } else {
                    DVec3::Y
                };
                look_at(o, t, up).ok_or_else(|| {
                    s.err("origin and target coincide, or up is parallel to the view")
                })?
            }
            _ => return Err(s.err("unknown transform step")),
        };
        x = step.then(&x);
    }
    Ok(x)
}

/// Mitsuba's `look_at`: columns `left = normalize(up x dir)`, `up' = dir x left`, `dir`,
/// `origin` (world from camera).
fn look_at(origin: DVec3, target: DVec3, up: DVec3) -> Option<Xf> {
    let dir = (target - origin).try_normalize()?;
    let left = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(left);
    Some(Xf::frame(left, new_up, dir, origin))
}
