//! The pbrt-v4 interpreter: graphics state and directives.

use super::get::{Ctx, Kind, Tex};
use super::lex::{Tok, Token, tokens};
use super::params::Params;
use crate::formats::build::{Builder, CameraSpec};
use crate::formats::xform::Xf;
use crate::formats::{Converted, FormatError, Limits, Resolver, material_map as mm, relative_to};
use crate::lights::SpotProfile;
use crate::scene::desc::{FilterDesc, MaterialDesc, Triple};
use glam::{DAffine3, DMat4, DVec3};
use std::collections::HashMap;

/// An area light attached to the shapes that follow.
#[derive(Clone, Debug)]
pub struct Area {
    /// Emitted radiance (times `scale`).
    pub l: Triple,
}

/// pbrt's graphics state.
#[derive(Clone, Debug)]
pub struct Gs {
    /// Current transformation matrix.
    pub ctm: Xf,
    /// `ReverseOrientation` in effect.
    pub reverse: bool,
    /// Current material: its name in the converted scene and description.
    pub material: (String, MaterialDesc),
    /// Current area light.
    pub area: Option<Area>,
}

/// A shape recorded inside `ObjectBegin`/`ObjectEnd`, replayed by `ObjectInstance`.
#[derive(Clone, Debug)]
pub struct Recorded {
    pub kind: String,
    pub params: Params,
    pub gs: Gs,
    pub file: String,
    pub line: usize,
    pub column: usize,
}

/// The camera directive, resolved at `WorldBegin` (the film size may follow it).
struct CameraDef {
    world_from_camera: Xf,
    fov: f64,
    lens: f64,
    focus: f64,
    file: String,
    line: usize,
}

/// The interpreter's state.
pub struct State<'r> {
    pub b: Builder,
    res: &'r mut dyn Resolver,
    limits: Limits,
    files: usize,
    pub gs: Gs,
    stack: Vec<Gs>,
    named: HashMap<String, MaterialDesc>,
    coords: HashMap<String, Xf>,
    pub textures: HashMap<String, Tex>,
    objects: HashMap<String, Vec<Recorded>>,
    current_object: Option<(String, Vec<Recorded>)>,
    camera: Option<CameraDef>,
    film: (u32, u32),
    world: bool,
    open: Vec<String>,
    /// `ActiveTransform EndTime`: transforms go to the (unused) end time only.
    end_only: bool,
}

/// An error at a token.
pub fn err_at(file: &str, t: &Token, msg: impl Into<String>) -> FormatError {
    FormatError {
        file: file.to_string(),
        line: t.line,
        column: t.column,
        message: msg.into(),
    }
}

impl<'r> State<'r> {
    pub fn new(res: &'r mut dyn Resolver, limits: Limits) -> Self {
        let mut b = Builder::new(limits.vertices);
        // pbrt-v4's defaults: 16 samples, maxdepth 5, a Gaussian filter of radius 1.5.
        b.settings.spp = 16;
        b.settings.max_depth = 4;
        b.settings.filter = FilterDesc::Gaussian {
            sigma: 0.5,
            radius: Some(1.5),
        };
        Self {
            b,
            res,
            limits,
            files: 0,
            gs: Gs {
                ctm: Xf::IDENTITY,
                reverse: false,
                material: ("diffuse".into(), mm::diffuse([0.5; 3])),
                area: None,
            },
            stack: Vec::new(),
            named: HashMap::new(),
            coords: HashMap::new(),
            textures: HashMap::new(),
            objects: HashMap::new(),
            current_object: None,
            camera: None,
            film: (1280, 720),
            world: false,
            open: Vec::new(),
            end_only: false,
        }
    }

    /// Interpret the file `file` with contents `bytes` at include depth `depth`.
    pub fn run_file(&mut self, file: &str, bytes: &[u8], depth: usize) -> Result<(), FormatError> {
        let src = crate::formats::text(file, bytes)?;
        let toks = tokens(src).map_err(|(line, column, message)| FormatError {
            file: file.to_string(),
            line,
            column,
            message,
        })?;
        self.open.push(file.to_string());
        let mut i = 0;
        while i < toks.len() {
            self.directive(file, &toks, &mut i, depth)?;
        }
        self.open.pop();
        Ok(())
    }

    fn include(
        &mut self,
        file: &str,
        t: &Token,
        name: &str,
        depth: usize,
    ) -> Result<(), FormatError> {
        let path = relative_to(file, name);
        if depth + 1 > self.limits.include_depth {
            return Err(err_at(
                file,
                t,
                format!(
                    "Include {name:?}: nested deeper than {} files",
                    self.limits.include_depth
                ),
            ));
        }
        if self.open.contains(&path) {
            return Err(err_at(
                file,
                t,
                format!(
                    "Include {name:?}: include cycle ({})",
                    self.open.join(" -> ")
                ),
            ));
        }
        let bytes = self.read(file, t, &path, "Include")?;
        self.run_file(&path, &bytes, depth + 1)
    }

    /// Read `path` through the resolver, counting files.
    pub fn read(
        &mut self,
        file: &str,
        t: &Token,
        path: &str,
        what: &str,
    ) -> Result<Vec<u8>, FormatError> {
        self.files += 1;
        if self.files > self.limits.files {
            return Err(err_at(
                file,
                t,
                format!("{what}: more than {} files read", self.limits.files),
            ));
        }
        self.res
            .read(path)
            .map_err(|e| err_at(file, t, format!("{what} {path:?}: {e}")))
    }

    /// The vertex limit.
    pub fn vertex_limit(&self) -> usize {
        self.limits.vertices
    }

    fn directive(
        &mut self,
        file: &str,
        toks: &[Token],
        i: &mut usize,
        depth: usize,
    ) -> Result<(), FormatError> {
        let t = &toks[*i];
        let Tok::Word(name) = &t.tok else {
            return Err(err_at(
                file,
                t,
                format!("expected a directive, got {:?}", t.tok),
            ));
        };
        *i += 1;
        let name = name.as_str();
        if self.transform(file, t, name, toks, i)? {
            return Ok(());
        }
        match name {
            "AttributeBegin" | "TransformBegin" => self.stack.push(self.gs.clone()),
            "AttributeEnd" | "TransformEnd" => self.attribute_end(file, t, name)?,
            "ReverseOrientation" => self.gs.reverse = !self.gs.reverse,
            "WorldBegin" => self.world_begin(file, t)?,
            "WorldEnd" => {}
            "CoordinateSystem" => {
                let n = string_arg(file, toks, i, name)?;
                self.coords.insert(n, self.gs.ctm);
            }
            "CoordSysTransform" => {
                let n = string_arg(file, toks, i, name)?;
                self.gs.ctm = *self.coords.get(&n).ok_or_else(|| {
                    err_at(
                        file,
                        t,
                        format!("CoordSysTransform: unknown coordinate system {n:?}"),
                    )
                })?;
            }
            "Include" | "Import" => {
                let n = string_arg(file, toks, i, name)?;
                self.include(file, t, &n, depth)?;
            }
            "ObjectBegin" => {
                let n = string_arg(file, toks, i, name)?;
                self.object_begin(file, t, n)?;
            }
            "ObjectEnd" => self.object_end(file, t)?,
            "ObjectInstance" => {
                let n = string_arg(file, toks, i, name)?;
                self.object_instance(file, t, &n)?;
            }
            "NamedMaterial" => {
                let n = string_arg(file, toks, i, name)?;
                let m = self.named.get(&n).cloned().ok_or_else(|| {
                    err_at(file, t, format!("NamedMaterial: undefined material {n:?}"))
                })?;
                self.gs.material = (n, m);
            }
            _ => return self.with_params(file, t, name, toks, i),
        }
        Ok(())
    }

    /// `AttributeEnd` or `TransformEnd` (`name`): the graphics state, or only its transform,
    /// of the matching begin.
    fn attribute_end(&mut self, file: &str, t: &Token, name: &str) -> Result<(), FormatError> {
        let g = self
            .stack
            .pop()
            .ok_or_else(|| err_at(file, t, format!("{name} without a matching begin")))?;
        if name == "TransformEnd" {
            self.gs.ctm = g.ctm;
        } else {
            self.gs = g;
        }
        Ok(())
    }

    /// `ObjectBegin "n"`: shapes are recorded, not placed, until `ObjectEnd`.
    fn object_begin(&mut self, file: &str, t: &Token, n: String) -> Result<(), FormatError> {
        if self.current_object.is_some() {
            return Err(err_at(file, t, "ObjectBegin inside another ObjectBegin"));
        }
        self.stack.push(self.gs.clone());
        self.current_object = Some((n, Vec::new()));
        Ok(())
    }

    /// `ObjectEnd`: the recorded shapes become the object, the graphics state is restored.
    fn object_end(&mut self, file: &str, t: &Token) -> Result<(), FormatError> {
        let (n, shapes) = self
            .current_object
            .take()
            .ok_or_else(|| err_at(file, t, "ObjectEnd without ObjectBegin"))?;
        self.gs = self
            .stack
            .pop()
            .ok_or_else(|| err_at(file, t, "ObjectEnd without ObjectBegin"))?;
        self.objects.insert(n, shapes);
        Ok(())
    }

    /// `ObjectInstance "n"`: the object's shapes under the current transform.
    fn object_instance(&mut self, file: &str, t: &Token, n: &str) -> Result<(), FormatError> {
        let shapes = self
            .objects
            .get(n)
            .cloned()
            .ok_or_else(|| err_at(file, t, format!("ObjectInstance: unknown object {n:?}")))?;
        let instance = self.gs.ctm;
        for r in shapes {
            let mut gs = r.gs.clone();
            gs.ctm = instance.then(&r.gs.ctm);
            self.shape_with(&r.file, r.line, r.column, &r.kind, &r.params, &gs)?;
        }
        Ok(())
    }

    /// Directives of the form `Name "type" params`.
    fn with_params(
        &mut self,
        file: &str,
        t: &Token,
        name: &str,
        toks: &[Token],
        i: &mut usize,
    ) -> Result<(), FormatError> {
        let known = super::DIRECTIVES.contains(&name) || name == "TransformTimes";
        if !known {
            return Err(err_at(file, t, format!("unknown directive {name:?}")));
        }
        let kind = match name {
            "Texture" => return self.texture_directive(file, t, toks, i),
            "TransformTimes" => {
                numbers(file, toks, i, name, 2)?;
                self.b.note(
                    file,
                    t.line,
                    "TransformTimes ignored: raytree has no motion blur",
                );
                return Ok(());
            }
            "ActiveTransform" | "MediumInterface" | "ColorSpace" => {
                return self.untyped_state(file, t, name, toks, i);
            }
            _ => string_arg(file, toks, i, name)?,
        };
        let params = Params::parse(toks, i).map_err(|(l, c, m)| FormatError {
            file: file.into(),
            line: l,
            column: c,
            message: format!("{name} \"{kind}\": {m}"),
        })?;
        let what = format!("{name} \"{kind}\"");
        match name {
            "Camera" => self.camera(file, t, &kind, &params)?,
            "Film" => self.film(file, t, &kind, &params)?,
            "Sampler" => self.sampler(file, t, &kind, &params)?,
            "Integrator" => self.integrator(file, t, &kind, &params)?,
            "PixelFilter" => self.filter(file, t, &kind, &params)?,
            "Material" => {
                let m = self.material(file, t, &kind, &params)?;
                self.gs.material = (format!("{kind}-{}", t.line), m);
                // `material` names its unused parameters itself.
                return Ok(());
            }
            "MakeNamedMaterial" => {
                let ty = ctx(file, &what, &params, &self.textures)
                    .string("type")?
                    .ok_or_else(|| err_at(file, t, format!("{what}: needs \"string type\"")))?;
                let m = self.material(file, t, &ty, &params)?;
                self.named.insert(kind, m);
                return Ok(());
            }
            "AreaLightSource" => self.area(file, t, &kind, &params)?,
            "LightSource" => self.light(file, t, &kind, &params)?,
            "Shape" => return self.shape(file, t, kind, params),
            "Attribute" | "Accelerator" | "Option" | "MakeNamedMedium" => {
                self.b.note(file, t.line, format!("{what} ignored"));
            }
            _ => return Err(err_at(file, t, format!("{name} is not supported"))),
        }
        self.unused(file, t, &what, &params);
        Ok(())
    }

    /// `Texture "name" "type" "class" params`.
    fn texture_directive(
        &mut self,
        file: &str,
        t: &Token,
        toks: &[Token],
        i: &mut usize,
    ) -> Result<(), FormatError> {
        let name = "Texture";
        let n = string_arg(file, toks, i, name)?;
        let _ty = string_arg(file, toks, i, name)?;
        let class = string_arg(file, toks, i, name)?;
        let params = Params::parse(toks, i).map_err(|(l, c, m)| FormatError {
            file: file.into(),
            line: l,
            column: c,
            message: format!("{name}: {m}"),
        })?;
        self.texture(file, t, &n, &class, &params)
    }

    /// `ActiveTransform`, `MediumInterface` or `ColorSpace` (`name`) and its argument: only
    /// `ActiveTransform EndTime` changes what follows, the others are noted.
    fn untyped_state(
        &mut self,
        file: &str,
        t: &Token,
        name: &str,
        toks: &[Token],
        i: &mut usize,
    ) -> Result<(), FormatError> {
        let w = match &toks.get(*i).map(|x| &x.tok) {
            Some(Tok::Word(w) | Tok::Str(w)) => w.clone(),
            _ => return Err(err_at(file, t, format!("{name} needs an argument"))),
        };
        *i += 1;
        if name == "MediumInterface" && matches!(toks.get(*i).map(|x| &x.tok), Some(Tok::Str(_))) {
            *i += 1;
        }
        if name == "ActiveTransform" {
            // Only the start-time transformation is used (no motion blur).
            self.end_only = w == "EndTime";
            if w != "EndTime" {
                return Ok(());
            }
        }
        self.b.note(file, t.line, format!("{name} {w} ignored (raytree has no motion blur, participating media or colour spaces other than linear sRGB)"));
        Ok(())
    }

    /// `Sampler "kind"`: its samples per pixel (raytree draws its own points).
    fn sampler(
        &mut self,
        file: &str,
        t: &Token,
        kind: &str,
        params: &Params,
    ) -> Result<(), FormatError> {
        let what = format!("Sampler \"{kind}\"");
        let spp = ctx(file, &what, params, &self.textures).int("pixelsamples", 16)?;
        self.b.settings.spp = u32::try_from(spp).ok().filter(|&s| s > 0).ok_or_else(|| {
            err_at(
                file,
                t,
                format!("{what}: pixelsamples must be > 0, got {spp}"),
            )
        })?;
        if !matches!(kind, "sobol" | "zsobol" | "paddedsobol") {
            self.b.note(file, t.line, format!("{what}: raytree draws its own sample points (Sobol); the image converges to the same result"));
        }
        Ok(())
    }

    /// `Shape "kind" params`: recorded inside `ObjectBegin`, placed otherwise.
    fn shape(
        &mut self,
        file: &str,
        t: &Token,
        kind: String,
        params: Params,
    ) -> Result<(), FormatError> {
        if let Some((_, shapes)) = &mut self.current_object {
            shapes.push(Recorded {
                kind,
                params,
                gs: self.gs.clone(),
                file: file.into(),
                line: t.line,
                column: t.column,
            });
            return Ok(());
        }
        let gs = self.gs.clone();
        self.shape_with(file, t.line, t.column, &kind, &params, &gs)
    }

    /// A note naming the parameters a directive did not read.
    pub fn unused(&mut self, file: &str, t: &Token, what: &str, params: &Params) {
        let u = params.unused();
        if !u.is_empty() {
            self.b
                .note(file, t.line, format!("{what}: ignored {}", u.join(", ")));
        }
    }

    /// Transform directives; `Ok(false)` when `name` is not one.
    fn transform(
        &mut self,
        file: &str,
        t: &Token,
        name: &str,
        toks: &[Token],
        i: &mut usize,
    ) -> Result<bool, FormatError> {
        let bad = |what: &str| err_at(file, t, format!("{name}: {what}"));
        let x = match name {
            "Identity" => {
                if !self.end_only {
                    self.gs.ctm = Xf::IDENTITY;
                }
                return Ok(true);
            }
            "Translate" => {
                let v = numbers(file, toks, i, name, 3)?;
                Xf::translate(DVec3::new(v[0], v[1], v[2]))
            }
            "Scale" => {
                let v = numbers(file, toks, i, name, 3)?;
                Xf::scale(DVec3::new(v[0], v[1], v[2]))
                    .ok_or_else(|| bad("a scale factor is zero"))?
            }
            "Rotate" => {
                let v = numbers(file, toks, i, name, 4)?;
                Xf::rotate(v[0], DVec3::new(v[1], v[2], v[3]))
                    .ok_or_else(|| bad("the axis is zero"))?
            }
            "LookAt" => {
                let v = numbers(file, toks, i, name, 9)?;
                look_at(
                    DVec3::new(v[0], v[1], v[2]),
                    DVec3::new(v[3], v[4], v[5]),
                    DVec3::new(v[6], v[7], v[8]),
                )
                .ok_or_else(|| {
                    bad("eye and target coincide, or up is parallel to the view direction")
                })?
            }
            "Transform" | "ConcatTransform" => {
                let v = numbers(file, toks, i, name, 16)?;
                let m = DMat4::from_cols_slice(&v);
                let x = Xf::new(m).ok_or_else(|| bad("the matrix is singular"))?;
                if name == "Transform" {
                    if !self.end_only {
                        self.gs.ctm = x;
                    }
                    return Ok(true);
                }
                x
            }
            _ => return Ok(false),
        };
        if !self.end_only {
            self.gs.ctm = self.gs.ctm.then(&x);
        }
        Ok(true)
    }

    fn world_begin(&mut self, file: &str, t: &Token) -> Result<(), FormatError> {
        if self.world {
            return Err(err_at(file, t, "WorldBegin twice"));
        }
        self.world = true;
        let (w, h) = self.film;
        let cam = match self.camera.take() {
            Some(c) => c,
            None => {
                self.b.note(file, t.line, "no Camera before WorldBegin: pbrt's default perspective camera (fov 90) at the origin, looking along +z");
                CameraDef {
                    world_from_camera: self.gs.ctm.inverse(),
                    fov: 90.0,
                    lens: 0.0,
                    focus: 1e6,
                    file: file.into(),
                    line: t.line,
                }
            }
        };
        let m = cam
            .world_from_camera
            .affine()
            .ok_or_else(|| err_at(file, t, "the camera transform is projective"))?;
        // pbrt's fov spans the shorter image axis; raytree's is vertical.
        let half = (cam.fov.to_radians() / 2.0).tan();
        let fov_y = if w < h {
            2.0 * (half * f64::from(h) / f64::from(w)).atan().to_degrees()
        } else {
            cam.fov
        };
        let spec = CameraSpec {
            position: m.transform_point3(DVec3::ZERO),
            forward: m.transform_vector3(DVec3::Z),
            up: m.transform_vector3(DVec3::Y),
            right: m.transform_vector3(DVec3::X),
            fov_y,
            width: w,
            height: h,
            aperture: cam.lens,
            focus: Some(cam.focus),
        };
        if !spec.forward.is_finite() || spec.forward.length() == 0.0 {
            return Err(err_at(file, t, "the camera transform is degenerate"));
        }
        self.b.set_camera(&spec, &cam.file, cam.line);
        self.coords.insert("world".into(), Xf::IDENTITY);
        self.gs.ctm = Xf::IDENTITY;
        self.gs.reverse = false;
        Ok(())
    }

    fn camera(&mut self, file: &str, t: &Token, kind: &str, p: &Params) -> Result<(), FormatError> {
        let what = format!("Camera \"{kind}\"");
        if kind != "perspective" {
            return Err(err_at(
                file,
                t,
                format!("{what} is not supported (only \"perspective\")"),
            ));
        }
        let c = ctx(file, &what, p, &self.textures);
        let fov = c.float("fov", 90.0)?;
        let lens = c.float("lensradius", 0.0)?;
        let focus = c.float("focaldistance", 1e6)?;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(err_at(
                file,
                t,
                format!("{what}: fov must be in (0, 180), got {fov}"),
            ));
        }
        if lens < 0.0 || focus <= 0.0 {
            return Err(err_at(
                file,
                t,
                format!("{what}: lensradius must be >= 0 and focaldistance > 0"),
            ));
        }
        self.coords.insert("camera".into(), self.gs.ctm.inverse());
        self.camera = Some(CameraDef {
            world_from_camera: self.gs.ctm.inverse(),
            fov,
            lens,
            focus,
            file: file.into(),
            line: t.line,
        });
        Ok(())
    }

    fn film(&mut self, file: &str, t: &Token, kind: &str, p: &Params) -> Result<(), FormatError> {
        let what = format!("Film \"{kind}\"");
        if kind != "rgb" {
            self.b.note(
                file,
                t.line,
                format!("{what}: raytree's film is linear RGB"),
            );
        }
        let c = ctx(file, &what, p, &self.textures);
        let (w, h) = (c.int("xresolution", 1280)?, c.int("yresolution", 720)?);
        for (n, v) in [("xresolution", w), ("yresolution", h)] {
            if !(1..=65_536).contains(&v) {
                return Err(err_at(
                    file,
                    t,
                    format!("{what}: {n} must be in 1..=65536, got {v}"),
                ));
            }
        }
        let _ = c.string("filename")?;
        self.film = (w as u32, h as u32);
        Ok(())
    }

    fn integrator(
        &mut self,
        file: &str,
        t: &Token,
        kind: &str,
        p: &Params,
    ) -> Result<(), FormatError> {
        let what = format!("Integrator \"{kind}\"");
        let depth = ctx(file, &what, p, &self.textures).int("maxdepth", 5)?;
        if !matches!(kind, "path" | "volpath") {
            self.b.note(
                file,
                t.line,
                format!("{what}: raytree's path tracer is used instead"),
            );
        }
        // pbrt's maxdepth counts bounces (1 = direct light only); raytree's max_depth counts
        // bounces after the first hit (0 = direct light only).
        if depth < 1 {
            self.b.note(file, t.line, format!("{what}: maxdepth {depth} (emitters only) is not expressible; raytree renders direct light (max_depth 0)"));
        }
        self.b.settings.max_depth = u32::try_from((depth - 1).clamp(0, 1024)).expect("clamped");
        Ok(())
    }

    fn filter(&mut self, file: &str, t: &Token, kind: &str, p: &Params) -> Result<(), FormatError> {
        let what = format!("PixelFilter \"{kind}\"");
        let c = ctx(file, &what, p, &self.textures);
        let positive = |v: f64, n: &str| {
            if v > 0.0 {
                Ok(v)
            } else {
                Err(err_at(file, t, format!("{what}: {n} must be > 0")))
            }
        };
        self.b.settings.filter = match kind {
            "box" => {
                let r = c.float("xradius", 0.5)?.max(c.float("yradius", 0.5)?);
                if r != 0.5 {
                    self.b.note(
                        file,
                        t.line,
                        format!("{what}: radius {r}: raytree's box spans one pixel"),
                    );
                }
                FilterDesc::Box {}
            }
            "triangle" => FilterDesc::Tent {
                radius: positive(
                    c.float("xradius", 2.0)?.max(c.float("yradius", 2.0)?),
                    "radius",
                )?,
            },
            "gaussian" => {
                let sigma = positive(c.float("sigma", 0.5)?, "sigma")?;
                let radius = positive(
                    c.float("xradius", 1.5)?.max(c.float("yradius", 1.5)?),
                    "radius",
                )?;
                self.b.note(file, t.line, format!("{what}: pbrt subtracts the Gaussian's value at the radius; raytree samples the plain truncated Gaussian (sigma {sigma}, radius {radius})"));
                FilterDesc::Gaussian {
                    sigma,
                    radius: Some(radius),
                }
            }
            _ => {
                self.b.note(
                    file,
                    t.line,
                    format!("{what}: not supported, raytree's box filter used"),
                );
                FilterDesc::Box {}
            }
        };
        Ok(())
    }

    fn area(&mut self, file: &str, t: &Token, kind: &str, p: &Params) -> Result<(), FormatError> {
        let what = format!("AreaLightSource \"{kind}\"");
        if kind != "diffuse" {
            return Err(err_at(
                file,
                t,
                format!("{what} is not supported (only \"diffuse\")"),
            ));
        }
        let c = ctx(file, &what, p, &self.textures);
        let (l, note) = c.color("L", Kind::Light)?.unwrap_or(([1.0; 3], None));
        let scale = c.float("scale", 1.0)?;
        let two = c.bool("twosided", false)?;
        if let Some(n) = note {
            self.b.note(file, t.line, format!("{what}: {n}"));
        }
        if two {
            self.b.note(
                file,
                t.line,
                format!("{what}: two-sided emission: raytree emits from the front side only"),
            );
        }
        self.gs.area = Some(Area {
            l: l.map(|x| x * scale),
        });
        Ok(())
    }

    fn light(&mut self, file: &str, t: &Token, kind: &str, p: &Params) -> Result<(), FormatError> {
        let what = format!("LightSource \"{kind}\"");
        let m = self
            .gs
            .ctm
            .affine()
            .ok_or_else(|| err_at(file, t, format!("{what}: projective transform")))?;
        let c = ctx(file, &what, p, &self.textures);
        let scale = c.float("scale", 1.0)?;
        let key = if kind == "point" || kind == "spot" || kind == "goniometric" {
            "I"
        } else {
            "L"
        };
        let (rgb, note) = c.color(key, Kind::Light)?.unwrap_or(([1.0; 3], None));
        // pbrt-v4 divides `scale` by the spectrum's luminance (`SpectrumToPhotometric`, which
        // its film multiplies back: a no-op in RGB) and, given a target `power` (point, spot)
        // or `illuminance` (distant, infinite), multiplies by it over the light's k_e.
        let target = c.float(light_target(kind), -1.0)?;
        let gain = Gain { scale, target };
        let from = c.point("from", DVec3::ZERO)?;
        let to = c.point("to", DVec3::Z)?;
        let file_name = c.string("filename")?;
        if let Some(n) = note {
            self.b.note(file, t.line, format!("{what}: {n}"));
        }
        match kind {
            "point" => {
                let k = gain.of(4.0 * std::f64::consts::PI);
                self.b
                    .point_light(m.transform_point3(from), rgb.map(|x| x * k));
            }
            "spot" => {
                let l = LightAt {
                    file,
                    t,
                    what,
                    p,
                    m,
                };
                self.spot_light(&l, (from, to), rgb, gain)?;
            }
            "distant" => {
                let l = LightAt {
                    file,
                    t,
                    what,
                    p,
                    m,
                };
                self.distant_light(&l, to - from, rgb, gain)?;
            }
            "infinite" => {
                // A constant environment of radiance L gives a surface facing up E = pi L.
                let rgb = rgb.map(|x| x * gain.of(std::f64::consts::PI));
                if let Some(f) = file_name {
                    self.b.note(file, t.line, format!("{what}: environment map {f:?} not read; its L times scale ({rgb:?}) is used as the constant background radiance"));
                }
                self.b.background = rgb;
            }
            _ => {
                return Err(err_at(
                    file,
                    t,
                    format!("{what} is not supported (point, spot, distant, infinite)"),
                ));
            }
        }
        Ok(())
    }

    /// `LightSource "spot"` from `from` towards `to`, of intensity `rgb` before `gain`.
    fn spot_light(
        &mut self,
        l: &LightAt,
        (from, to): (DVec3, DVec3),
        rgb: [f64; 3],
        gain: Gain,
    ) -> Result<(), FormatError> {
        let (file, t, what, m) = (l.file, l.t, &l.what, &l.m);
        let c = ctx(file, what, l.p, &self.textures);
        let cone = c.float("coneangle", 30.0)?;
        let delta = c.float("conedelta", 5.0)?;
        let rgb = rgb.map(|x| x * gain.of(spot_k_e(cone, delta)));
        // pbrt-v4 `SpotLight`: cosFalloffStart = cos(coneangle - conedelta), so the
        // falloff starts |coneangle - conedelta| from the axis; its smoothstep needs
        // that inside the cone.
        let falloff = (cone - delta).abs();
        if !(cone > 0.0 && cone < 180.0) {
            return Err(err_at(
                file,
                t,
                format!("{what}: \"coneangle\" {cone} is not in (0, 180) degrees"),
            ));
        }
        if falloff.is_nan() || falloff > cone {
            return Err(err_at(
                file,
                t,
                format!("{what}: \"conedelta\" {delta} is not in [0, 2 coneangle]"),
            ));
        }
        let axis = m.transform_vector3(to - from);
        if axis.try_normalize().is_none() {
            return Err(err_at(file, t, format!("{what}: from and to coincide")));
        }
        let at = (m.transform_point3(from), axis);
        self.b
            .spot_light(at, rgb, (cone, falloff), SpotProfile::Smoothstep);
        Ok(())
    }

    /// `LightSource "distant"` along `dir` (light space), of radiance `rgb` before `gain`.
    fn distant_light(
        &mut self,
        l: &LightAt,
        dir: DVec3,
        rgb: [f64; 3],
        gain: Gain,
    ) -> Result<(), FormatError> {
        let target = gain.target;
        let (file, t, what) = (l.file, l.t, &l.what);
        let d = l.m.transform_vector3(dir);
        if d.try_normalize().is_none() {
            return Err(err_at(file, t, format!("{what}: from and to coincide")));
        }
        if target > 0.0 {
            // pbrt-v4 divides by -w.y of the light-space direction here, which its
            // author calls a bug (mmp/pbrt-v4 issue 130): raytree takes the
            // illuminance on a surface facing the light, which is what it means.
            self.b.note(file, t.line, format!("{what}: \"illuminance\" {target} is taken on a surface facing the light (pbrt-v4 divides by -w.y of the light-space direction, its issue 130, so its image may differ)"));
        }
        self.b.directional_light(d, rgb.map(|x| x * gain.of(1.0)));
        Ok(())
    }

    fn texture(
        &mut self,
        file: &str,
        t: &Token,
        name: &str,
        class: &str,
        p: &Params,
    ) -> Result<(), FormatError> {
        let what = format!("Texture \"{name}\" \"{class}\"");
        let c = ctx(file, &what, p, &self.textures);
        let tex = match class {
            "constant" => Tex {
                rgb: c.color("value", Kind::Albedo)?.map_or([1.0; 3], |v| v.0),
                note: None,
            },
            "checkerboard" => {
                let a = c.color("tex1", Kind::Albedo)?.map_or([1.0; 3], |v| v.0);
                let b = c.color("tex2", Kind::Albedo)?.map_or([0.0; 3], |v| v.0);
                let mean = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
                Tex {
                    rgb: mean,
                    note: Some(format!(
                        "checkerboard texture {name:?} replaced by its mean colour {mean:?}"
                    )),
                }
            }
            "scale" => {
                let a = c.color("tex", Kind::Albedo)?.map_or([1.0; 3], |v| v.0);
                let s = c.color("scale", Kind::Albedo)?.map_or([1.0; 3], |v| v.0);
                Tex {
                    rgb: [0, 1, 2].map(|k| a[k] * s[k]),
                    note: None,
                }
            }
            _ => Tex {
                rgb: [0.5; 3],
                note: Some(format!(
                    "texture {name:?} ({class}) not read: grey 0.5 used"
                )),
            },
        };
        if class == "constant" || class == "scale" {
            self.unused(file, t, &what, p);
        }
        self.textures.insert(name.to_string(), tex);
        Ok(())
    }

    /// The converted scene.
    pub fn finish(self, file: &str) -> Result<Converted, FormatError> {
        if let Some((n, _)) = &self.current_object {
            return Err(FormatError {
                file: file.into(),
                line: 0,
                column: 0,
                message: format!("ObjectBegin {n:?} is never ended"),
            });
        }
        let world = self.world;
        let (desc, notes) = self.b.finish().ok_or_else(|| FormatError {
            file: file.into(),
            line: 0,
            column: 0,
            message: if world {
                "no camera".into()
            } else {
                "no WorldBegin: the file describes no scene".into()
            },
        })?;
        Ok(Converted { desc, notes })
    }
}

/// Typed access to `params` of the directive `what`.
pub fn ctx<'a>(
    file: &'a str,
    what: &str,
    params: &'a Params,
    textures: &'a HashMap<String, Tex>,
) -> Ctx<'a> {
    Ctx {
        file,
        what: what.to_string(),
        params,
        textures,
    }
}

/// A `LightSource` being converted: where it is written, its name in messages, its
/// parameters and its light-to-world transform.
struct LightAt<'a> {
    file: &'a str,
    t: &'a Token,
    /// `LightSource "kind"`.
    what: String,
    p: &'a Params,
    /// Light to world.
    m: DAffine3,
}

/// pbrt-v4's factor on a light's spectrum: `scale`, times a target `power` or `illuminance`
/// (`target`, -1 when not given) over the light's `k_e`.
#[derive(Clone, Copy)]
struct Gain {
    scale: f64,
    target: f64,
}

impl Gain {
    /// The factor for a light whose `k_e` (power or illuminance per unit of spectrum) is `k_e`.
    fn of(self, k_e: f64) -> f64 {
        self.scale
            * if self.target > 0.0 {
                self.target / k_e
            } else {
                1.0
            }
    }
}

/// pbrt's `LookAt` as camera-from-world (with its exact inverse): pbrt-v4 `LookAt()`, whose
/// camera space has `right = normalize(cross(normalize(up), dir))` as +x (left-handed).
fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> Option<Xf> {
    let dir = (target - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(dir).try_normalize()?;
    let new_up = dir.cross(right);
    Some(Xf::frame(right, new_up, dir, eye).inverse())
}

/// `n` numbers, bare or in one bracketed list.
pub fn numbers(
    file: &str,
    toks: &[Token],
    i: &mut usize,
    name: &str,
    n: usize,
) -> Result<Vec<f64>, FormatError> {
    let start = toks.get(i.saturating_sub(1)).cloned();
    let bracket = matches!(toks.get(*i).map(|t| &t.tok), Some(Tok::Open));
    if bracket {
        *i += 1;
    }
    let mut v = Vec::with_capacity(n);
    while v.len() < n {
        match toks.get(*i) {
            Some(Token {
                tok: Tok::Num(x), ..
            }) => v.push(*x),
            Some(t) => {
                return Err(err_at(
                    file,
                    t,
                    format!(
                        "{name}: expected {n} numbers, got {:?} after {}",
                        t.tok,
                        v.len()
                    ),
                ));
            }
            None => {
                return Err(err_at(
                    file,
                    start.as_ref().expect("a directive"),
                    format!(
                        "{name}: expected {n} numbers, the file ends after {}",
                        v.len()
                    ),
                ));
            }
        }
        *i += 1;
    }
    if bracket {
        match toks.get(*i) {
            Some(Token {
                tok: Tok::Close, ..
            }) => *i += 1,
            Some(t) => {
                return Err(err_at(
                    file,
                    t,
                    format!("{name}: expected ] after {n} numbers"),
                ));
            }
            None => {
                return Err(err_at(
                    file,
                    start.as_ref().expect("a directive"),
                    format!("{name}: missing ]"),
                ));
            }
        }
    }
    Ok(v)
}

/// One quoted string argument.
pub fn string_arg(
    file: &str,
    toks: &[Token],
    i: &mut usize,
    name: &str,
) -> Result<String, FormatError> {
    match toks.get(*i) {
        Some(Token {
            tok: Tok::Str(s), ..
        }) => {
            *i += 1;
            Ok(s.clone())
        }
        Some(t) => Err(err_at(
            file,
            t,
            format!("{name}: expected a quoted string, got {:?}", t.tok),
        )),
        None => Err(err_at(
            file,
            &toks[toks.len() - 1],
            format!("{name}: expected a quoted string, the file ends"),
        )),
    }
}

/// The parameter that sets a pbrt-v4 light's brightness in photometric terms: `power` (lm) for
/// lights at a point, `illuminance` (lx) for distant and infinite ones (pbrt-v4's
/// `lights.cpp`, each light's `Create`).
fn light_target(kind: &str) -> &'static str {
    match kind {
        "distant" | "infinite" => "illuminance",
        _ => "power",
    }
}

/// pbrt-v4's `k_e` of a spot light (`SpotLight::Create`): its solid angle with the falloff
/// ramp counted half, 2 pi ((1 - cos start) + (cos start - cos end) / 2), for `coneangle` and
/// `conedelta` in degrees. pbrt's own expression, not the exact flux of its smoothstep, so
/// that a `power` gives the intensity pbrt gives.
fn spot_k_e(cone: f64, delta: f64) -> f64 {
    let end = cone.to_radians().cos();
    let start = (cone - delta).to_radians().cos();
    2.0 * std::f64::consts::PI * ((1.0 - start) + (start - end) / 2.0)
}
