//! Mitsuba objects: sensor, integrator, shapes, BSDFs, emitters.

use super::props::Props;
use super::tree::{El, Reader};
use crate::formats::build::{Builder, CameraSpec, Surface, disk_triangles};
use crate::formats::xform::Xf;
use crate::formats::{Converted, FormatError, Limits, material_map as mm, ply};
use crate::lights::SpotProfile;
use crate::scene::desc::{FilterDesc, MaterialDesc};
use glam::{DAffine3, DVec3};
use std::collections::HashMap;
use std::rc::Rc;

/// `el` itself, or the element its `<ref id>` names.
fn deref<'a>(ids: &'a HashMap<String, El>, el: &'a El) -> Result<&'a El, FormatError> {
    if el.tag != "ref" {
        return Ok(el);
    }
    let id = el.attr("id").ok_or_else(|| el.err("needs an id"))?;
    ids.get(id)
        .ok_or_else(|| el.err(format!("refers to undefined id {id:?}")))
}

/// The index of refraction `name` of `el`: a number, or a named material's.
fn ior(el: &El, p: &Props, name: &str, default: f64) -> Result<f64, FormatError> {
    match p.string(name) {
        Ok(Some(s)) => {
            mm::named_ior(&s).ok_or_else(|| el.err(format!("{name}: unknown material {s:?}")))
        }
        Ok(None) => p.float(name, default),
        Err(_) => p.float(name, default),
    }
}

/// A BSDF's properties being read, with the notes they raise (those of its colours and
/// those of its roughness, kept apart: they are reported in that order).
struct BsdfReader<'a, 'p> {
    el: &'a El,
    p: &'a Props<'p>,
    /// A rough variant (`rough...`): `alpha` reads a roughness.
    rough: bool,
    /// Notes of the colours read.
    notes: Vec<String>,
    /// Notes of the roughness.
    a_notes: Vec<String>,
    /// alpha_v of an anisotropic roughness, set by `alpha`.
    alpha_v: Option<f64>,
    /// The Beckmann distribution, set by `alpha`.
    beckmann: bool,
}

impl BsdfReader<'_, '_> {
    /// The colour `name`, or `default`.
    fn color(&mut self, name: &str, default: [f64; 3]) -> Result<[f64; 3], FormatError> {
        Ok(match self.p.color(name)? {
            Some((c, n)) => {
                self.notes.extend(n);
                c
            }
            None => default,
        })
    }

    /// alpha_u of a rough BSDF (0 for a smooth one), with its distribution.
    fn alpha(&mut self) -> Result<f64, FormatError> {
        if !self.rough {
            return Ok(0.0);
        }
        let p = self.p;
        let a = p.float("alpha", 0.1)?;
        let (a, v, n) = mm::anisotropic(p.float("alpha_u", a)?, p.float("alpha_v", a)?);
        self.a_notes.extend(n);
        self.alpha_v = v;
        let dist = p
            .string("distribution")?
            .unwrap_or_else(|| "beckmann".into());
        match dist.as_str() {
            "ggx" => Ok(a),
            "beckmann" => {
                self.beckmann = true;
                Ok(a)
            }
            d => Err(self.el.err(format!("unknown distribution {d:?}"))),
        }
    }

    /// `conductor` or `roughconductor`: from `eta` and `k`, a named metal, or a mirror.
    fn conductor(&mut self) -> Result<mm::Mapped, FormatError> {
        let p = self.p;
        let a = self.alpha()?;
        let scale = self.color("specular_reflectance", [1.0; 3])?;
        let material = p.string("material")?.unwrap_or_else(|| "none".into());
        Ok(if p.color("eta")?.is_some() || p.color("k")?.is_some() {
            mm::conductor(
                self.color("eta", [0.0; 3])?,
                self.color("k", [1.0; 3])?,
                a,
                scale,
            )
        } else if material == "none" {
            mm::mirror(scale, a)
        } else {
            let (e, k) = mm::metal(&material).ok_or_else(|| self.el.err(format!("unknown conductor material {material:?} (raytree knows Ag, Al, Au, Cr, Cu, none)")))?;
            mm::conductor(e, k, a, scale)
        })
    }
}

/// A sensor's field of view in degrees (`fov`, or from `focal_length` on a 36 x 24 mm film
/// along the diagonal) and the axis it is measured along (`fov_axis`).
fn sensor_fov(el: &El, p: &Props) -> Result<(f64, String), FormatError> {
    let fov = match p.float("fov", -1.0)? {
        f if f > 0.0 => f,
        _ => {
            // Mitsuba: focal_length on a 36 x 24 mm film, along the diagonal.
            let s = p.string("focal_length")?.unwrap_or_else(|| "50mm".into());
            let f: f64 = s
                .trim_end_matches("mm")
                .parse()
                .map_err(|_| el.err(format!("bad focal_length {s:?}")))?;
            2.0 * ((36f64.hypot(24.0)) / (2.0 * f)).atan().to_degrees()
        }
    };
    let axis = p.string("fov_axis")?.unwrap_or_else(|| {
        if p.string("focal_length").ok().flatten().is_some() {
            "diagonal".into()
        } else {
            "x".into()
        }
    });
    Ok((fov, axis))
}

/// The vertical field of view of a `w` x `h` image whose field of view `fov` is measured
/// along `axis`: the given one when that axis is vertical, else from its tangent.
fn vertical_fov(el: &El, fov: f64, axis: &str, (w, h): (u32, u32)) -> Result<f64, FormatError> {
    let half = (fov.to_radians() / 2.0).tan();
    let (wf, hf) = (f64::from(w), f64::from(h));
    // The vertical field of view: the given one when fov_axis is vertical, else from tan.
    let vertical = match axis {
        "x" => false,
        "y" => true,
        "smaller" => w >= h,
        "larger" => w <= h,
        "diagonal" => false,
        _ => return Err(el.err(format!("unknown fov_axis {axis:?}"))),
    };
    Ok(if vertical {
        fov
    } else {
        let tan_y = if axis == "diagonal" {
            half * hf / wf.hypot(hf)
        } else {
            half * hf / wf
        };
        2.0 * tan_y.atan().to_degrees()
    })
}

/// Converter state.
pub struct State<'r> {
    reader: Reader<'r>,
    b: Builder,
    limits: Limits,
    next_material: usize,
    /// Materials already made from BSDFs with an id (a `<ref>` reuses them).
    by_id: HashMap<String, String>,
}

impl<'r> State<'r> {
    pub fn new(reader: Reader<'r>, limits: Limits) -> Self {
        let mut b = Builder::new(limits.vertices);
        // Mitsuba 3's defaults: 4 samples (independent sampler), unbounded depth, Gaussian
        // reconstruction filter (stddev 0.5, radius 4 stddev).
        b.settings.spp = 4;
        b.settings.filter = FilterDesc::Gaussian {
            sigma: 0.5,
            radius: Some(2.0),
        };
        Self {
            reader,
            b,
            limits,
            next_material: 0,
            by_id: HashMap::new(),
        }
    }

    fn ids(&self) -> Rc<HashMap<String, El>> {
        Rc::clone(&self.reader.ids)
    }

    fn unused(&mut self, el: &El, p: &Props) {
        let u = p.unused();
        if !u.is_empty() {
            self.b.note(
                &el.file,
                el.line,
                format!("{}: ignored {}", el.label(), u.join(", ")),
            );
        }
    }

    /// The whole `<scene>`: the sensor first (its handedness decides the world mirror), then
    /// everything else in order.
    pub fn scene(&mut self, root: &El) -> Result<(), FormatError> {
        let sensors: Vec<&El> = root.children.iter().filter(|c| c.tag == "sensor").collect();
        match sensors.as_slice() {
            [] => return Err(root.err("no <sensor>: the scene has no camera")),
            [s, rest @ ..] => {
                if let Some(extra) = rest.first() {
                    self.b.note(
                        &extra.file,
                        extra.line,
                        "more than one <sensor>: the first is used",
                    );
                }
                self.sensor(s)?;
            }
        }
        for c in &root.children {
            match c.tag.as_str() {
                "sensor" => {}
                "integrator" => self.integrator(c)?,
                "shape" => self.shape(c)?,
                // A named area emitter is a definition: it lights the shapes that <ref> it.
                "emitter" if c.attr("type") == Some("area") && c.attr("id").is_some() => {}
                "emitter" => {
                    self.emitter(c, None)?;
                }
                "bsdf" | "texture" | "spectrum" | "rgb" => {}
                "medium" | "phase" => self.b.note(
                    &c.file,
                    c.line,
                    format!(
                        "{}: participating media are not supported: left out",
                        c.label()
                    ),
                ),
                "ref" => return Err(c.err("a <ref> at the top level refers to nothing")),
                _ => return Err(c.err("unknown element")),
            }
        }
        Ok(())
    }

    fn sensor(&mut self, el: &El) -> Result<(), FormatError> {
        let ty = el.attr("type").unwrap_or("");
        if ty != "perspective" && ty != "thinlens" {
            return Err(el.err("only perspective and thinlens sensors are supported"));
        }
        let ids = self.ids();
        let p = Props::new(el, &ids)?;
        let to_world = p.transform("to_world")?.unwrap_or(Xf::IDENTITY);
        let (fov, axis) = sensor_fov(el, &p)?;
        let (aperture, focus) = (
            p.float("aperture_radius", 0.0)?,
            p.float("focus_distance", 0.0)?,
        );
        if ty == "thinlens" && (aperture <= 0.0 || focus <= 0.0) {
            return Err(el.err("thinlens needs aperture_radius > 0 and focus_distance > 0"));
        }
        self.note_clipping(el, &p)?;
        self.unused(el, &p);
        let (w, h, spp) = self.film_and_sampler(el)?;
        let fov_y = vertical_fov(el, fov, &axis, (w, h))?;
        let m = to_world
            .affine()
            .ok_or_else(|| el.err("projective to_world"))?;
        let spec = CameraSpec {
            position: m.transform_point3(DVec3::ZERO),
            forward: m.transform_vector3(DVec3::Z),
            up: m.transform_vector3(DVec3::Y),
            // Mitsuba's camera +x is image-left.
            right: -m.transform_vector3(DVec3::X),
            fov_y,
            width: w,
            height: h,
            aperture: if ty == "thinlens" { aperture } else { 0.0 },
            focus: (ty == "thinlens").then_some(focus),
        };
        if !(spec.fov_y > 0.0 && spec.fov_y < 180.0) {
            return Err(el.err(format!(
                "the vertical field of view {} is not in (0, 180)",
                spec.fov_y
            )));
        }
        self.b.settings.spp = spp;
        self.b.set_camera(&spec, &el.file, el.line);
        Ok(())
    }

    /// Mitsuba's near and far clipping planes: noted unless they are its defaults.
    fn note_clipping(&mut self, el: &El, p: &Props) -> Result<(), FormatError> {
        for (k, default) in [("near_clip", 1e-2), ("far_clip", 1e4)] {
            let v = p.float(k, default)?;
            if v != default {
                self.b.note(
                    &el.file,
                    el.line,
                    format!(
                        "{}: {k} {v}: raytree does not clip camera rays (surfaces nearer or \
                         farther are seen)",
                        el.label()
                    ),
                );
            }
        }
        Ok(())
    }

    fn film_and_sampler(&mut self, sensor: &El) -> Result<(u32, u32, u32), FormatError> {
        let (mut w, mut h, mut spp) = (768, 576, 4);
        for c in &sensor.children {
            let ids = self.ids();
            let c = deref(&ids, c)?;
            match c.tag.as_str() {
                "film" => {
                    let ids = self.ids();
                    let p = Props::new(c, &ids)?;
                    let (fw, fh) = (p.int("width", 768)?, p.int("height", 576)?);
                    for k in ["file_format", "pixel_format", "component_format"] {
                        let _ = p.string(k)?;
                    }
                    let _ = p.bool("sample_border", false)?;
                    for (n, v) in [("width", fw), ("height", fh)] {
                        if !(1..=65_536).contains(&v) {
                            return Err(c.err(format!("{n} must be in 1..=65536, got {v}")));
                        }
                    }
                    self.unused(c, &p);
                    (w, h) = (fw as u32, fh as u32);
                    for f in c.children.iter().filter(|f| f.tag == "rfilter") {
                        self.rfilter(f)?;
                    }
                }
                "sampler" => {
                    let ids = self.ids();
                    let p = Props::new(c, &ids)?;
                    let n = p.int("sample_count", 4)?;
                    spp = u32::try_from(n)
                        .ok()
                        .filter(|&n| n > 0)
                        .ok_or_else(|| c.err(format!("sample_count must be > 0, got {n}")))?;
                    let _ = p.int("seed", 0)?;
                    self.unused(c, &p);
                    if !matches!(
                        c.attr("type"),
                        Some(
                            "independent"
                                | "stratified"
                                | "multijitter"
                                | "ldsampler"
                                | "orthogonal"
                        )
                    ) {
                        self.b.note(
                            &c.file,
                            c.line,
                            format!("{}: unknown sampler type", c.label()),
                        );
                    }
                }
                _ => {}
            }
        }
        Ok((w, h, spp))
    }

    fn rfilter(&mut self, el: &El) -> Result<(), FormatError> {
        let ids = self.ids();
        let p = Props::new(el, &ids)?;
        self.b.settings.filter = match el.attr("type").unwrap_or("") {
            "box" => FilterDesc::Box {},
            "tent" => FilterDesc::Tent {
                radius: p.float("radius", 1.0)?,
            },
            "gaussian" => {
                let s = p.float("stddev", 0.5)?;
                FilterDesc::Gaussian {
                    sigma: s,
                    radius: Some(4.0 * s),
                }
            }
            _ => {
                self.b.note(
                    &el.file,
                    el.line,
                    format!("{}: not supported, box filter used", el.label()),
                );
                FilterDesc::Box {}
            }
        };
        self.unused(el, &p);
        Ok(())
    }

    fn integrator(&mut self, el: &El) -> Result<(), FormatError> {
        let ty = el.attr("type").unwrap_or("");
        let ids = self.ids();
        let p = Props::new(el, &ids)?;
        let depth = p.int("max_depth", -1)?;
        let _ = p.int("rr_depth", 5)?;
        let _ = p.bool("hide_emitters", false)?;
        self.unused(el, &p);
        if !matches!(ty, "path" | "volpath" | "volpathmis" | "direct") {
            self.b.note(
                &el.file,
                el.line,
                format!("{}: raytree's path tracer is used instead", el.label()),
            );
        }
        // Mitsuba's max_depth counts path segments (1 = emitters seen directly, 2 = direct
        // light); raytree's counts bounces after the first hit (0 = direct light).
        self.b.settings.max_depth = match (ty, depth) {
            ("direct", _) => 0,
            (_, -1) => {
                self.b.note(&el.file, el.line, "max_depth -1 (unbounded): raytree stops at depth 64, Russian roulette ends paths long before");
                64
            }
            (_, d) if d < 2 => {
                self.b.note(&el.file, el.line, format!("max_depth {d} shows emitters only, which raytree cannot express: direct light (max_depth 0) used"));
                0
            }
            (_, d) => u32::try_from((d - 2).min(1024)).expect("bounded"),
        };
        Ok(())
    }

    /// A BSDF element as a material name in the converted scene.
    fn bsdf(&mut self, el: &El, two_sided: bool, id: Option<&str>) -> Result<String, FormatError> {
        let ids = self.ids();
        let el = deref(&ids, el)?;
        let id = id.or(el.attr("id"));
        if let Some(name) = id.and_then(|i| self.by_id.get(i)) {
            return Ok(name.clone());
        }
        let name = self.bsdf_new(el, two_sided, id)?;
        if let Some(i) = id {
            self.by_id.insert(i.to_string(), name.clone());
        }
        Ok(name)
    }

    fn bsdf_new(
        &mut self,
        el: &El,
        two_sided: bool,
        id: Option<&str>,
    ) -> Result<String, FormatError> {
        let ty = el.attr("type").unwrap_or("");
        if ty == "twosided" || matches!(ty, "mask" | "bumpmap" | "normalmap" | "blendbsdf") {
            if ty != "twosided" {
                self.b.note(
                    &el.file,
                    el.line,
                    format!("{}: approximated by its (first) nested BSDF", el.label()),
                );
            }
            let inner = el
                .children
                .iter()
                .find(|c| c.tag == "bsdf" || c.tag == "ref")
                .ok_or_else(|| el.err("needs a nested <bsdf>"))?;
            return self.bsdf_new(deref(&self.ids(), inner)?, true, id);
        }
        let ids = self.ids();
        let p = Props::new(el, &ids)?;
        let (desc, note) = self.material_of(el, &p)?;
        if let Some(n) = note {
            self.b
                .note(&el.file, el.line, format!("{}: {n}", el.label()));
        }
        let one_sided = !matches!(ty, "dielectric" | "roughdielectric" | "thindielectric");
        if one_sided && !two_sided {
            self.b.note(&el.file, el.line, format!("{}: Mitsuba shades only the front of a BSDF not wrapped in twosided; raytree shades both sides", el.label()));
        }
        self.unused(el, &p);
        let name = id.map_or_else(
            || {
                self.next_material += 1;
                format!("{ty}-{}", self.next_material)
            },
            str::to_string,
        );
        Ok(self.b.material(&name, desc))
    }

    fn material_of(&mut self, el: &El, p: &Props) -> Result<mm::Mapped, FormatError> {
        let ty = el.attr("type").unwrap_or("");
        // Mitsuba's default interior: BK7 glass, polypropylene (1.49) under plastics.
        let int_default = if ty.ends_with("plastic") {
            1.49
        } else {
            1.5046
        };
        let eta = ior(el, p, "int_ior", int_default)? / ior(el, p, "ext_ior", 1.000_277)?;
        let rough = ty.starts_with("rough");
        let mut r = BsdfReader {
            el,
            p,
            rough,
            notes: Vec::new(),
            a_notes: Vec::new(),
            alpha_v: None,
            beckmann: false,
        };
        let (mut desc, note) = match ty {
            "diffuse" => (mm::diffuse(r.color("reflectance", [0.5; 3])?), None),
            "dielectric" | "roughdielectric" => mm::dielectric(eta, r.alpha()?),
            "thindielectric" => mm::thin_dielectric(eta),
            "conductor" | "roughconductor" => r.conductor()?,
            "plastic" | "roughplastic" => {
                let a = r.alpha()?;
                let base = r.color("diffuse_reflectance", [0.5; 3])?;
                let spec = r.color("specular_reflectance", [1.0; 3])?;
                let nonlinear = p.bool("nonlinear", false)?;
                mm::coated_diffuse(base, eta, a, spec, nonlinear, None)
            }
            _ => (
                mm::diffuse([0.5; 3]),
                Some(format!(
                    "BSDF type {ty:?} is not supported: grey diffuse 0.5 used"
                )),
            ),
        };
        let mut notes = r.notes;
        notes.extend(r.a_notes);
        notes.extend(note);
        if rough {
            desc.roughness_v = r.alpha_v;
            if r.beckmann {
                desc.distribution = crate::bsdf::Distribution::Beckmann;
            }
        }
        Ok((desc, (!notes.is_empty()).then(|| notes.join("; "))))
    }

    fn shape(&mut self, el: &El) -> Result<(), FormatError> {
        let ty = el.attr("type").unwrap_or("");
        let ids = self.ids();
        let p = Props::new(el, &ids)?;
        let to_world = p.transform("to_world")?.unwrap_or(Xf::IDENTITY);
        let m = to_world
            .affine()
            .ok_or_else(|| el.err("projective to_world"))?;
        let flip = p.bool("flip_normals", false)?;
        let face_normals = p.bool("face_normals", false)?;
        let mut material = None;
        let mut emission = None;
        for c in &el.children {
            let ids = self.ids();
            let d = deref(&ids, c)?;
            match d.tag.as_str() {
                "bsdf" if material.is_none() => material = Some(self.bsdf(c, false, None)?),
                "bsdf" => return Err(c.err("a shape takes one <bsdf>")),
                "emitter" => emission = Some(self.emitter(d, Some(el))?),
                _ => {}
            }
        }
        let base = match material {
            Some(m) => m,
            None => self.b.material("default-diffuse", mm::diffuse([0.5; 3])),
        };
        let material = match emission.flatten() {
            None => base,
            Some(l) => {
                let mut d: MaterialDesc = self.b.materials[&base].clone();
                d.emission = l;
                self.b.material(&format!("{base}+light"), d)
            }
        };
        let s = Surface {
            material,
            name: el.attr("id").map(str::to_string),
            flip,
        };
        let fail = |e: String| el.err(e);
        match ty {
            "rectangle" => self.b.quad(DVec3::new(-1.0, -1.0, 0.0), 2.0 * DVec3::X, 2.0 * DVec3::Y, &m, &s),
            "cube" => self.b.cube(-DVec3::ONE, DVec3::ONE, &m, &s).map_err(fail)?,
            "sphere" => {
                let c = p.point("center")?.unwrap_or(DVec3::ZERO);
                let r = p.float("radius", 1.0)?;
                if let Some(n) = self.b.sphere(c, r, &m, &s).map_err(fail)? {
                    self.b.note(&el.file, el.line, format!("{}: {n}", el.label()));
                }
            }
            "disk" => {
                let (pos, tris) = disk_triangles(1.0, 0.0, 0.0);
                self.b.note(&el.file, el.line, format!("{}: tessellated into {} triangles", el.label(), tris.len()));
                self.b.mesh(&pos, &tris, None, &m, &s).map_err(fail)?;
            }
            "obj" | "ply" => self.mesh_file(el, &p, ty, &m, &s, face_normals)?,
            "serialized" => return Err(el.err("serialized meshes are not supported: convert them to PLY (mitsuba's own tools or Blender)")),
            _ => return Err(el.err("unsupported shape type")),
        }
        self.unused(el, &p);
        Ok(())
    }

    fn mesh_file(
        &mut self,
        el: &El,
        p: &Props,
        ty: &str,
        m: &DAffine3,
        s: &Surface,
        face_normals: bool,
    ) -> Result<(), FormatError> {
        let f = p
            .string("filename")?
            .ok_or_else(|| el.err("needs a filename"))?;
        let (path, bytes) = self.reader.resource(el, &f)?;
        let (pos, tris, normals) = if ty == "ply" {
            let mesh = ply::parse(&bytes, self.limits.vertices)
                .map_err(|e| el.err(format!("{f}: {e}")))?;
            (mesh.positions, mesh.triangles, mesh.normals)
        } else {
            let text = crate::formats::text(&path, &bytes)?;
            let d = crate::mesh::parse_obj(text)
                .map_err(|e| el.err(format!("{f}:{}: {}", e.line, e.message)))?;
            super::super::build::unify_obj(&d)
        };
        let normals = match (normals, face_normals) {
            (_, true) => None,
            (Some(n), false) => Some(n),
            (None, false) => {
                self.b.note(&el.file, el.line, format!("{}: {f} has no normals: smoothed with angle-weighted vertex normals, as Mitsuba does", el.label()));
                Some(super::super::build::vertex_normals(&pos, &tris))
            }
        };
        self.b
            .mesh(&pos, &tris, normals.as_deref(), m, s)
            .map_err(|e| el.err(format!("{f}: {e}")))
    }

    /// An emitter; inside a shape (`shape` given) only `area`, whose radiance is returned.
    fn emitter(&mut self, el: &El, shape: Option<&El>) -> Result<Option<[f64; 3]>, FormatError> {
        let ty = el.attr("type").unwrap_or("");
        let ids = self.ids();
        let p = Props::new(el, &ids)?;
        let key = match ty {
            "point" | "spot" => "intensity",
            "directional" => "irradiance",
            _ => "radiance",
        };
        let (rgb, note) = p.color(key)?.unwrap_or(([1.0; 3], None));
        if let Some(n) = note {
            self.b
                .note(&el.file, el.line, format!("{}: {n}", el.label()));
        }
        let scale = p.float("scale", 1.0)?;
        let rgb = rgb.map(|c| c * scale);
        let to_world = p.transform("to_world")?.unwrap_or(Xf::IDENTITY);
        let m = to_world
            .affine()
            .ok_or_else(|| el.err("projective to_world"))?;
        let out = match (ty, shape) {
            ("area", Some(_)) => Some(rgb),
            ("area", None) => {
                return Err(el.err(
                    "an area emitter must be inside a <shape> (or named by an id and \
                     referenced from one)",
                ));
            }
            (_, Some(_)) => return Err(el.err("only area emitters can be attached to a shape")),
            ("point", None) => {
                let pos = p.point("position")?.unwrap_or(DVec3::ZERO);
                self.b.point_light(m.transform_point3(pos), rgb);
                None
            }
            ("spot", None) => {
                // Mitsuba 3 `spot`: at to_world's origin, along its +z; full intensity within
                // `beam_width`, linear in the angle to zero at `cutoff_angle`.
                let cutoff = p.float("cutoff_angle", 20.0)?;
                let beam = p.float("beam_width", cutoff * 0.75)?;
                if !(cutoff > 0.0 && cutoff < 180.0) {
                    return Err(el.err(format!("cutoff_angle {cutoff} is not in (0, 180) degrees")));
                }
                if !(0.0..=cutoff).contains(&beam) {
                    return Err(el.err(format!("beam_width {beam} is not in [0, cutoff_angle]")));
                }
                let Some(axis) = m.transform_vector3(DVec3::Z).try_normalize() else {
                    return Err(el.err("to_world is singular"));
                };
                let at = (m.transform_point3(DVec3::ZERO), axis);
                self.b
                    .spot_light(at, rgb, (cutoff, beam), SpotProfile::Linear);
                None
            }
            ("directional", None) => {
                let d = p.point("direction")?.unwrap_or(DVec3::Z);
                let d = m.transform_vector3(d);
                if d.try_normalize().is_none() {
                    return Err(el.err("zero direction"));
                }
                self.b.directional_light(d, rgb);
                None
            }
            ("constant", None) => {
                self.b.background = rgb;
                None
            }
            ("envmap", None) => {
                let _ = p.string("filename")?;
                self.b.note(
                    &el.file,
                    el.line,
                    format!("{}: environment map not read: black background", el.label()),
                );
                None
            }
            _ => return Err(el.err("unsupported emitter type")),
        };
        self.unused(el, &p);
        Ok(out)
    }

    /// The converted scene.
    pub fn finish(self, file: &str) -> Result<Converted, FormatError> {
        let (desc, notes) = self.b.finish().ok_or_else(|| FormatError {
            file: file.into(),
            line: 0,
            column: 0,
            message: "no camera".into(),
        })?;
        Ok(Converted { desc, notes })
    }
}
