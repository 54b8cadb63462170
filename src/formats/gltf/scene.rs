//! The node hierarchy, cameras, punctual lights and meshes of the chosen scene.

use super::data::Data;
use super::material::{self as mat, Mean, Pbr};
use crate::formats::build::{Builder, CameraSpec, Surface};
use crate::formats::{Converted, FormatError, Limits};
use crate::lights::SpotProfile;
use crate::scene::desc::LightDesc;
use ::gltf::json::validation::Checked;
use ::gltf::json::{Node, Root};
use glam::{DAffine3, DMat4, DQuat, DVec3, DVec4};
use std::collections::HashMap;

/// Samples per pixel of a converted glTF scene (the file has no render settings).
pub const SPP: u32 = 16;
/// The longer side of the image (the file gives at most an aspect ratio).
pub const IMAGE_SIDE: u32 = 640;

/// One primitive, decoded in object space.
struct Prim {
    positions: Vec<DVec3>,
    tris: Vec<[u32; 3]>,
    normals: Option<Vec<DVec3>>,
    material: Option<usize>,
}

/// Converter state.
pub struct State<'a, 'r> {
    d: Data<'a, 'r>,
    b: Builder,
    /// Decoded meshes by index (a mesh several nodes instance is read once).
    meshes: HashMap<usize, std::rc::Rc<Vec<Option<Prim>>>>,
    /// Material names by glTF index (`None`: the default material).
    materials: HashMap<Option<usize>, String>,
}

/// A number written in the JSON as the `f32` the crate parsed it into, back as the decimal that
/// was written (the shortest that round-trips: `3.4`, not `3.4000000953674316`).
pub(crate) fn dec(x: f32) -> f64 {
    if x.is_finite() {
        x.to_string().parse().unwrap_or(f64::from(x))
    } else {
        f64::from(x)
    }
}

/// The local transform of `node` (matrix, or translation * rotation * scale).
fn local(node: &Node) -> Result<DMat4, String> {
    if let Some(m) = node.matrix {
        if m.iter().any(|x| !x.is_finite()) {
            return Err("matrix: a value is not a finite number".into());
        }
        let m = DMat4::from_cols_array(&m.map(dec));
        if m.row(3) != DVec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(format!(
                "matrix: the last row is {:?}, not [0, 0, 0, 1] (glTF matrices are affine)",
                m.row(3).to_array()
            ));
        }
        return Ok(m);
    }
    let t = node.translation.unwrap_or([0.0; 3]).map(dec);
    let r = node
        .rotation
        .as_ref()
        .map_or([0.0, 0.0, 0.0, 1.0], |q| q.0)
        .map(dec);
    let s = node.scale.unwrap_or([1.0; 3]).map(dec);
    for (name, v) in [
        ("translation", &t[..]),
        ("rotation", &r[..]),
        ("scale", &s[..]),
    ] {
        if v.iter().any(|x| !x.is_finite()) {
            return Err(format!("{name}: a value is not a finite number"));
        }
    }
    let q = DQuat::from_array(r);
    let len = q.length();
    if len < 1e-6 {
        return Err("rotation: a zero quaternion".into());
    }
    Ok(DMat4::from_scale_rotation_translation(
        DVec3::from(s),
        q / len,
        DVec3::from(t),
    ))
}

impl<'a, 'r> State<'a, 'r> {
    pub fn new(d: Data<'a, 'r>, limits: Limits) -> Self {
        let mut b = Builder::new(limits.vertices);
        b.settings.spp = SPP;
        Self {
            d,
            b,
            meshes: HashMap::new(),
            materials: HashMap::new(),
        }
    }

    fn root(&self) -> &'a Root {
        self.d.root
    }

    fn note(&mut self, path: &str, message: impl std::fmt::Display) {
        let file = self.d.file.clone();
        self.b.note(&file, 0, format!("{path}: {message}"));
    }

    fn err(&self, path: &str, message: impl std::fmt::Display) -> FormatError {
        self.d.err(path, message)
    }

    /// The whole conversion.
    pub fn run(mut self) -> Result<Converted, FormatError> {
        let root = self.root();
        let scene = self.scene_index()?;
        let (instances, cameras, lights) = self.walk(scene)?;
        // Meshes are decoded first: the default camera frames them.
        for &(_, mesh, _) in &instances {
            self.decode_mesh(mesh)?;
        }
        match cameras.first() {
            Some(&(node, cam, w)) => {
                if cameras.len() > 1 {
                    self.note(
                        &format!("nodes[{node}]"),
                        format!(
                            "{} cameras in the scene: the first (cameras[{cam}]) is used",
                            cameras.len()
                        ),
                    );
                }
                self.camera(node, cam, &w)?;
            }
            None => self.default_camera(&instances, scene)?,
        }
        for &(node, light, w) in &lights {
            self.light(node, light, &w)?;
        }
        if !lights.is_empty() {
            self.note(
                "extensions.KHR_lights_punctual",
                "photometric units taken 1:1: a light of I candela is raytree intensity I and \
                 one of E lux irradiance E (so emissive radiance and lights keep the ratio glTF \
                 viewers without exposure give them)",
            );
        }
        for &(node, mesh, w) in &instances {
            self.place(node, mesh, &w)?;
        }
        let single_sided = root.materials.iter().filter(|m| !m.double_sided).count();
        if single_sided > 0 && !instances.is_empty() {
            self.note(
                "materials",
                format!(
                    "{single_sided} material(s) with doubleSided false: glTF culls their back \
                     faces when rasterising, raytree shades both sides"
                ),
            );
        }
        let file = self.d.file.clone();
        let (desc, notes) = self
            .b
            .finish()
            .ok_or_else(|| super::err(&file, "", "no camera"))?;
        Ok(Converted { desc, notes })
    }

    /// The index of the scene to convert (the default, or the first), after noting the
    /// extensions that are not read and the animations that are not played.
    fn scene_index(&mut self) -> Result<usize, FormatError> {
        let root = self.root();
        for (i, name) in root.extensions_used.iter().enumerate() {
            if !super::SUPPORTED_EXTENSIONS.contains(&name.as_str()) {
                self.note(
                    &format!("extensionsUsed[{i}]"),
                    format!("{name} is not read: what it adds is left out"),
                );
            }
        }
        if !root.animations.is_empty() {
            self.note(
                "animations",
                format!(
                    "{} animation(s) not played: the nodes' static transforms are used",
                    root.animations.len()
                ),
            );
        }
        Ok(match root.scene {
            Some(s) => s.value(),
            None if root.scenes.is_empty() => {
                return Err(self.err("scenes", "the file has no scene (only assets)"));
            }
            None => {
                if root.scenes.len() > 1 {
                    self.note(
                        "scene",
                        format!(
                            "no default scene among {}: scenes[0] is used",
                            root.scenes.len()
                        ),
                    );
                }
                0
            }
        })
    }

    /// The nodes of scene `s`, depth first without recursion: mesh instances, cameras and
    /// lights with their global transforms.
    #[allow(clippy::type_complexity)]
    fn walk(
        &mut self,
        s: usize,
    ) -> Result<
        (
            Vec<(usize, usize, DMat4)>,
            Vec<(usize, usize, DMat4)>,
            Vec<(usize, usize, DMat4)>,
        ),
        FormatError,
    > {
        let root = self.root();
        let mut seen = vec![false; root.nodes.len()];
        let (mut meshes, mut cameras, mut lights) = (Vec::new(), Vec::new(), Vec::new());
        let mut stack: Vec<(usize, DMat4)> = root.scenes[s]
            .nodes
            .iter()
            .rev()
            .map(|n| (n.value(), DMat4::IDENTITY))
            .collect();
        while let Some((n, parent)) = stack.pop() {
            let path = format!("nodes[{n}]");
            if std::mem::replace(&mut seen[n], true) {
                return Err(self.err(
                    &path,
                    "reached twice: the node hierarchy must be a tree (a node has one parent \
                     and a scene lists roots only)",
                ));
            }
            let node = &root.nodes[n];
            let m = local(node).map_err(|e| self.err(&path, e))?;
            let world = parent * m;
            if let Some(mesh) = node.mesh {
                meshes.push((n, mesh.value(), world));
                if node.skin.is_some() {
                    self.note(
                        &format!("{path}.skin"),
                        "skinning is not applied: the mesh is placed by the node's transform in \
                         its bind pose",
                    );
                }
                let morph = root.meshes[mesh.value()]
                    .primitives
                    .iter()
                    .any(|p| p.targets.as_ref().is_some_and(|t| !t.is_empty()));
                if morph {
                    self.note(
                        &format!("meshes[{}]", mesh.value()),
                        "morph targets are not applied: the base shape is used",
                    );
                }
            }
            if let Some(c) = node.camera {
                cameras.push((n, c.value(), world));
            }
            if let Some(l) = node
                .extensions
                .as_ref()
                .and_then(|e| e.khr_lights_punctual.as_ref())
            {
                lights.push((n, l.light.value(), world));
            }
            if let Some(ext) = &node.extensions {
                for k in ext.others.keys() {
                    self.note(&format!("{path}.extensions.{k}"), "not read");
                }
            }
            if let Some(children) = &node.children {
                for c in children.iter().rev() {
                    stack.push((c.value(), world));
                }
            }
        }
        Ok((meshes, cameras, lights))
    }

    /// The camera of node `node` (camera `cam`) under global transform `w`.
    fn camera(&mut self, node: usize, cam: usize, w: &DMat4) -> Result<(), FormatError> {
        let root = self.root();
        let path = format!("cameras[{cam}]");
        let c = &root.cameras[cam];
        let Some(p) = c.perspective.as_ref() else {
            return Err(self.err(
                &path,
                "an orthographic camera: raytree's camera is a pinhole (or thin lens)",
            ));
        };
        let yfov = dec(p.yfov);
        if !(yfov > 0.0 && yfov < std::f64::consts::PI) {
            return Err(self.err(
                &format!("{path}.perspective.yfov"),
                format!("{yfov} radians is not in (0, pi)"),
            ));
        }
        let (width, height) = match p.aspect_ratio.map(dec) {
            Some(a) if a.is_finite() && a > 0.0 => {
                let (w, h) = if a >= 1.0 {
                    (f64::from(IMAGE_SIDE), f64::from(IMAGE_SIDE) / a)
                } else {
                    (f64::from(IMAGE_SIDE) * a, f64::from(IMAGE_SIDE))
                };
                (w.round().max(1.0) as u32, h.round().max(1.0) as u32)
            }
            Some(a) => {
                return Err(self.err(
                    &format!("{path}.perspective.aspectRatio"),
                    format!("{a} is not a finite number > 0"),
                ));
            }
            None => {
                self.note(
                    &format!("{path}.perspective"),
                    "no aspectRatio (the viewport's): raytree renders 640x480",
                );
                (IMAGE_SIDE, IMAGE_SIDE * 3 / 4)
            }
        };
        let a = DAffine3::from_mat4(*w);
        let spec = CameraSpec {
            position: a.transform_point3(DVec3::ZERO),
            forward: a.transform_vector3(-DVec3::Z),
            up: a.transform_vector3(DVec3::Y),
            right: a.transform_vector3(DVec3::X),
            fov_y: yfov.to_degrees(),
            width,
            height,
            aperture: 0.0,
            focus: None,
        };
        let npath = format!("nodes[{node}]");
        if spec.forward.length() < 1e-12
            || spec.up.length() < 1e-12
            || spec.forward.cross(spec.up).length() < 1e-12 * spec.forward.length()
        {
            return Err(self.err(&npath, "the camera's transform is singular"));
        }
        let before = self.b.notes.len();
        let file = self.d.file.clone();
        self.b.set_camera(&spec, &file, 0);
        for n in &mut self.b.notes[before..] {
            n.message = format!("{npath}: {}", n.message);
        }
        Ok(())
    }

    /// No camera: one on the +z side (glTF's front) looking at the centre of the geometry's
    /// bounds, far enough for its bounding sphere to fill a 45-degree vertical field of view.
    fn default_camera(
        &mut self,
        instances: &[(usize, usize, DMat4)],
        scene: usize,
    ) -> Result<(), FormatError> {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &(_, mesh, w) in instances {
            let a = DAffine3::from_mat4(w);
            for p in self.meshes[&mesh].iter().flatten() {
                for &v in &p.positions {
                    let v = a.transform_point3(v);
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        if !lo.cmple(hi).all() {
            return Err(self.err(
                &format!("scenes[{scene}]"),
                "no camera and no geometry: nothing to render",
            ));
        }
        let center = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-9);
        let fov: f64 = 45.0;
        let dist = radius / (fov.to_radians() / 2.0).sin();
        let spec = CameraSpec {
            position: center + DVec3::new(0.0, 0.0, dist),
            forward: -DVec3::Z,
            up: DVec3::Y,
            right: DVec3::X,
            fov_y: fov,
            width: IMAGE_SIDE,
            height: IMAGE_SIDE * 3 / 4,
            aperture: 0.0,
            focus: None,
        };
        let file = self.d.file.clone();
        self.b.set_camera(&spec, &file, 0);
        self.note(
            &format!("scenes[{scene}]"),
            format!(
                "no camera: raytree's default looks along -z at the centre {:?} of the geometry \
                 from {:.4} away (45 degrees vertical field of view, 640x480)",
                center.to_array(),
                dist
            ),
        );
        Ok(())
    }

    /// Light `l` on node `node` under `w`.
    fn light(&mut self, node: usize, l: usize, w: &DMat4) -> Result<(), FormatError> {
        use ::gltf::json::extensions::scene::khr_lights_punctual::Type;
        let root = self.root();
        let path = format!("extensions.KHR_lights_punctual.lights[{l}]");
        let Some(light) = root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|k| k.lights.get(l))
        else {
            return Err(self.err(
                &format!("nodes[{node}].extensions.KHR_lights_punctual.light"),
                format!("light {l} does not exist"),
            ));
        };
        let power = self.light_power(light, &path)?;
        let a = DAffine3::from_mat4(*w);
        if let Some(r) = light.range {
            self.note(
                &format!("{path}.range"),
                format!("range {r} ignored: raytree's lights fall off as 1/r^2 without a cut-off"),
            );
        }
        let Checked::Valid(ty) = light.type_ else {
            return Err(self.err(&format!("{path}.type"), "unknown light type"));
        };
        match ty {
            Type::Point | Type::Spot => {
                let p = a.transform_point3(DVec3::ZERO);
                if !p.is_finite() {
                    return Err(self.err(
                        &format!("nodes[{node}]"),
                        "the light's position is not finite",
                    ));
                }
                if ty == Type::Spot {
                    let cone = self.spot_cone(&path, light.spot.as_ref())?;
                    // KHR_lights_punctual: a spot light points along the node's -z.
                    let Some(axis) = a.transform_vector3(-DVec3::Z).try_normalize() else {
                        return Err(self.err(
                            &format!("nodes[{node}]"),
                            "the spot light's transform is singular",
                        ));
                    };
                    self.b.spot_light((p, axis), power, cone, SpotProfile::Gltf);
                } else {
                    self.b.point_light(p, power);
                }
            }
            Type::Directional => {
                let Some(d) = a.transform_vector3(-DVec3::Z).try_normalize() else {
                    return Err(self.err(
                        &format!("nodes[{node}]"),
                        "the directional light's transform is singular",
                    ));
                };
                self.b.directional_light(d, power);
            }
        }
        let label = light.name.clone().or_else(|| root.nodes[node].name.clone());
        if let Some(
            LightDesc::Point { name, .. }
            | LightDesc::Spot { name, .. }
            | LightDesc::Directional { name, .. },
        ) = self.b.lights.last_mut()
        {
            *name = label;
        }
        Ok(())
    }

    /// The colour times the intensity of `light` at `path`, each checked finite and >= 0.
    fn light_power(
        &self,
        light: &::gltf::json::extensions::scene::khr_lights_punctual::Light,
        path: &str,
    ) -> Result<[f64; 3], FormatError> {
        let color = light.color.map(dec);
        let intensity = dec(light.intensity);
        if color.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
            return Err(self.err(
                &format!("{path}.color"),
                "every component must be a finite number >= 0",
            ));
        }
        if !(intensity.is_finite() && intensity >= 0.0) {
            return Err(self.err(
                &format!("{path}.intensity"),
                format!("{intensity} is not a finite number >= 0"),
            ));
        }
        Ok(color.map(|c| c * intensity))
    }

    /// A spot light's (outer, inner) cone half-angles in degrees: glTF's `outerConeAngle`
    /// (default pi/4) and `innerConeAngle` (default 0), with `0 <= inner < outer <= pi/2` as
    /// the extension requires.
    fn spot_cone(
        &self,
        path: &str,
        spot: Option<&::gltf::json::extensions::scene::khr_lights_punctual::Spot>,
    ) -> Result<(f64, f64), FormatError> {
        let (inner, outer) = spot.map_or((0.0, std::f64::consts::FRAC_PI_4), |s| {
            (dec(s.inner_cone_angle), dec(s.outer_cone_angle))
        });
        if !(outer > 0.0 && outer <= std::f64::consts::FRAC_PI_2) {
            return Err(self.err(
                &format!("{path}.spot.outerConeAngle"),
                format!("{outer} is not in (0, pi/2]"),
            ));
        }
        if !(inner >= 0.0 && inner < outer) {
            return Err(self.err(
                &format!("{path}.spot.innerConeAngle"),
                format!("{inner} is not in [0, outerConeAngle)"),
            ));
        }
        Ok((outer.to_degrees(), inner.to_degrees()))
    }

    /// Read every primitive of mesh `m` (once).
    fn decode_mesh(&mut self, m: usize) -> Result<(), FormatError> {
        if self.meshes.contains_key(&m) {
            return Ok(());
        }
        let root = self.root();
        let mut prims = Vec::new();
        for (j, p) in root.meshes[m].primitives.iter().enumerate() {
            prims.push(self.decode_primitive(m, j, p)?);
        }
        self.meshes.insert(m, std::rc::Rc::new(prims));
        Ok(())
    }

    fn decode_primitive(
        &mut self,
        m: usize,
        j: usize,
        p: &::gltf::json::mesh::Primitive,
    ) -> Result<Option<Prim>, FormatError> {
        use ::gltf::json::mesh::Semantic;
        let path = format!("meshes[{m}].primitives[{j}]");
        let mode = self.surface_mode(p, &path)?;
        let Some(pos) = p.attributes.get(&Checked::Valid(Semantic::Positions)) else {
            self.note(&path, "no POSITION attribute: left out (as glTF says)");
            return Ok(None);
        };
        let positions: Vec<DVec3> = self.d.accessor(pos.value(), "POSITION", false)?;
        let n = positions.len();
        let normals = self.normals(p, &path, n)?;
        for key in p.attributes.keys() {
            if let Checked::Valid(Semantic::Colors(c)) = key {
                self.note(
                    &format!("{path}.attributes.COLOR_{c}"),
                    "vertex colours are not read (raytree has none): the material's colour is \
                     used alone",
                );
            }
        }
        let index_list: Vec<u32> = match p.indices {
            Some(a) => {
                let v: Vec<u32> = self.d.accessor(a.value(), "indices", true)?;
                if let Some((k, x)) = v.iter().enumerate().find(|&(_, &x)| x as usize >= n) {
                    return Err(self.err(
                        &format!("accessors[{}]", a.value()),
                        format!("index {k} is {x}, out of range for the {n} vertices of {path}"),
                    ));
                }
                v
            }
            None => (0..n as u32).collect(),
        };
        let tris: Vec<[u32; 3]> = self
            .triangles(mode, index_list, &path)?
            .into_iter()
            .filter(|t| {
                let [a, b, c] = t.map(|i| positions[i as usize]);
                (b - a).cross(c - a).length_squared() > 0.0
            })
            .collect();
        if tris.is_empty() {
            self.note(&path, "no triangle with area: left out");
            return Ok(None);
        }
        Ok(Some(Prim {
            positions,
            tris,
            normals,
            material: p.material.map(|x| x.value()),
        }))
    }

    /// The mode of primitive `p` at `path`, refused unless it has triangles.
    fn surface_mode(
        &self,
        p: &::gltf::json::mesh::Primitive,
        path: &str,
    ) -> Result<::gltf::json::mesh::Mode, FormatError> {
        use ::gltf::json::mesh::Mode;
        let Checked::Valid(mode) = p.mode else {
            return Err(self.err(&format!("{path}.mode"), "unknown primitive mode"));
        };
        let mode_name = match mode {
            Mode::Points => "POINTS",
            Mode::Lines => "LINES",
            Mode::LineLoop => "LINE_LOOP",
            Mode::LineStrip => "LINE_STRIP",
            Mode::Triangles => "TRIANGLES",
            Mode::TriangleStrip => "TRIANGLE_STRIP",
            Mode::TriangleFan => "TRIANGLE_FAN",
        };
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Err(self.err(
                &format!("{path}.mode"),
                format!(
                    "{mode_name}: points and lines have no area, raytree renders surfaces only"
                ),
            ));
        }
        Ok(mode)
    }

    /// The `n` vertex normals of primitive `p` at `path`, or `None` (flat normals) when it
    /// has none or one of them is zero (noted).
    fn normals(
        &mut self,
        p: &::gltf::json::mesh::Primitive,
        path: &str,
        n: usize,
    ) -> Result<Option<Vec<DVec3>>, FormatError> {
        use ::gltf::json::mesh::Semantic;
        let normals = match p.attributes.get(&Checked::Valid(Semantic::Normals)) {
            None => None,
            Some(a) => {
                let ns: Vec<DVec3> = self.d.accessor(a.value(), "NORMAL", false)?;
                if ns.len() != n {
                    return Err(self.err(
                        &format!("{path}.attributes.NORMAL"),
                        format!(
                            "{} normals for {n} positions (attributes must have one count)",
                            ns.len()
                        ),
                    ));
                }
                Some(ns)
            }
        };
        if let Some(ns) = &normals
            && let Some(k) = ns.iter().position(|v| v.length() < 1e-12)
        {
            self.note(
                &format!("{path}.attributes.NORMAL"),
                format!("normal {k} is zero: the primitive is shaded with flat normals"),
            );
            return Ok(None);
        }
        Ok(normals)
    }

    /// The triangles of `index_list` under `mode` (strips alternate their winding, fans share
    /// their first vertex), degenerate ones included.
    fn triangles(
        &self,
        mode: ::gltf::json::mesh::Mode,
        index_list: Vec<u32>,
        path: &str,
    ) -> Result<Vec<[u32; 3]>, FormatError> {
        use ::gltf::json::mesh::Mode;
        Ok(match mode {
            Mode::TriangleStrip => (2..index_list.len())
                .map(|i| {
                    let (a, b, c) = (index_list[i - 2], index_list[i - 1], index_list[i]);
                    if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
                })
                .collect(),
            Mode::TriangleFan => (2..index_list.len())
                .map(|i| [index_list[0], index_list[i - 1], index_list[i]])
                .collect(),
            _ => {
                if !index_list.len().is_multiple_of(3) {
                    return Err(self.err(
                        path,
                        format!(
                            "{} indices (vertices) is not a multiple of 3 for TRIANGLES",
                            index_list.len()
                        ),
                    ));
                }
                index_list
                    .chunks_exact(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect()
            }
        })
    }

    /// Place mesh `m` of node `node` under `w`.
    fn place(&mut self, node: usize, m: usize, w: &DMat4) -> Result<(), FormatError> {
        let root = self.root();
        let a = DAffine3::from_mat4(*w);
        let det = a.matrix3.determinant();
        if !(det.is_finite() && det.abs() > 1e-300) {
            self.note(
                &format!("nodes[{node}]"),
                format!("a singular transform (a zero scale): meshes[{m}] has no area, left out"),
            );
            return Ok(());
        }
        let prims = std::rc::Rc::clone(&self.meshes[&m]);
        let label = root.nodes[node]
            .name
            .clone()
            .or_else(|| root.meshes[m].name.clone())
            .unwrap_or_else(|| format!("mesh{m}"));
        let count = prims.len();
        for (j, p) in prims.iter().enumerate() {
            let Some(p) = p else { continue };
            let material = self.material(p.material)?;
            let name = if count > 1 {
                format!("{label}/{j}")
            } else {
                label.clone()
            };
            let s = Surface {
                material,
                name: Some(name),
                flip: false,
            };
            self.b
                .mesh(&p.positions, &p.tris, p.normals.as_deref(), &a, &s)
                .map_err(|e| {
                    super::err(
                        &self.d.file,
                        &format!("nodes[{node}] meshes[{m}].primitives[{j}]"),
                        e,
                    )
                })?;
        }
        Ok(())
    }

    /// The raytree material name of glTF material `index` (made once).
    fn material(&mut self, index: Option<usize>) -> Result<String, FormatError> {
        if let Some(n) = self.materials.get(&index) {
            return Ok(n.clone());
        }
        let (pbr, name) = match index {
            None => {
                self.note(
                    "meshes",
                    "a primitive without a material: glTF's default material (white, \
                     metallic 1, roughness 1)",
                );
                (Pbr::default(), "default".to_string())
            }
            Some(i) => self.read_material(i)?,
        };
        let path = index.map_or("meshes".to_string(), |i| format!("materials[{i}]"));
        let (desc, notes) = mat::map(&pbr);
        for n in notes {
            self.note(&path, n);
        }
        let name = self.b.material(&name, desc);
        self.materials.insert(index, name.clone());
        Ok(name)
    }

    /// The parameters of material `i` with its textures' means folded in, and its name.
    fn read_material(&mut self, i: usize) -> Result<(Pbr, String), FormatError> {
        let root = self.root();
        let m = &root.materials[i];
        let path = format!("materials[{i}]");
        let pmp = format!("{path}.pbrMetallicRoughness");
        let (mut pbr, alpha) = self.textured_factors(m, &path, &pmp)?;
        self.note_unread_maps(m, &path, alpha);
        for (k, v) in [
            ("metallicFactor", pbr.metallic),
            ("roughnessFactor", pbr.roughness),
        ] {
            if !(v.is_finite() && (0.0..=1.0).contains(&v)) {
                return Err(self.err(&format!("{pmp}.{k}"), format!("{v} is not in [0, 1]")));
            }
        }
        if pbr.base.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
            return Err(self.err(
                &format!("{pmp}.baseColorFactor"),
                "every component must be a finite number >= 0",
            ));
        }
        if let Some(ext) = &m.extensions {
            self.material_extensions(ext, &path, &mut pbr)?;
        }
        if pbr.emission.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
            return Err(self.err(
                &format!("{path}.emissiveFactor"),
                "every component must be a finite number >= 0",
            ));
        }
        if pbr.emission.iter().any(|&c| c > 0.0) && m.double_sided {
            self.note(
                &format!("{path}.doubleSided"),
                "an emissive double-sided material: raytree emits from the front side only",
            );
        }
        let name = m.name.clone().unwrap_or_else(|| format!("material{i}"));
        Ok((pbr, name))
    }

    /// Material `m`'s factors with the means of its base colour, metallic-roughness and
    /// emissive textures folded in, and its alpha (`pmp`: the path of its
    /// `pbrMetallicRoughness`).
    fn textured_factors(
        &mut self,
        m: &::gltf::json::Material,
        path: &str,
        pmp: &str,
    ) -> Result<(Pbr, f64), FormatError> {
        let pm = &m.pbr_metallic_roughness;
        let bc = pm.base_color_factor.0.map(dec);
        let mut pbr = Pbr {
            base: [bc[0], bc[1], bc[2]],
            metallic: dec(pm.metallic_factor.0),
            roughness: dec(pm.roughness_factor.0),
            emission: m.emissive_factor.0.map(dec),
            ..Pbr::default()
        };
        let mut alpha = bc[3];
        if let Some(t) = &pm.base_color_texture {
            let tp = format!("{pmp}.baseColorTexture");
            if let Some(mean) = self.texture(t.index.value(), true, &tp, "baseColorFactor")? {
                for (b, m) in pbr.base.iter_mut().zip(mean) {
                    *b *= m;
                }
                alpha *= mean[3];
            }
        }
        if let Some(t) = &pm.metallic_roughness_texture {
            let tp = format!("{pmp}.metallicRoughnessTexture");
            if let Some(mean) = self.texture(
                t.index.value(),
                false,
                &tp,
                "metallicFactor and roughnessFactor",
            )? {
                pbr.roughness *= mean[1];
                pbr.metallic *= mean[2];
            }
        }
        if let Some(t) = &m.emissive_texture {
            let tp = format!("{path}.emissiveTexture");
            if let Some(mean) = self.texture(t.index.value(), true, &tp, "emissiveFactor")? {
                for (e, m) in pbr.emission.iter_mut().zip(mean) {
                    *e *= m;
                }
            }
        }
        Ok((pbr, alpha))
    }

    /// Notes for what material `m` has that raytree does not read: normal and occlusion
    /// maps, alpha masks and blending (`alpha`: the base colour's, texture included).
    fn note_unread_maps(&mut self, m: &::gltf::json::Material, path: &str, alpha: f64) {
        use ::gltf::json::material::AlphaMode;
        if let Some(t) = &m.normal_texture {
            self.note(
                &format!("{path}.normalTexture"),
                format!(
                    "textures[{}] ignored: raytree has no normal mapping (the geometric or \
                     vertex normals shade)",
                    t.index.value()
                ),
            );
        }
        if let Some(t) = &m.occlusion_texture {
            self.note(
                &format!("{path}.occlusionTexture"),
                format!(
                    "textures[{}] ignored: baked ambient occlusion (raytree traces occlusion)",
                    t.index.value()
                ),
            );
        }
        match m.alpha_mode {
            Checked::Valid(AlphaMode::Mask) => self.note(
                &format!("{path}.alphaMode"),
                "MASK: cut-outs are not supported, the surface is opaque",
            ),
            Checked::Valid(AlphaMode::Blend) if alpha < 1.0 => self.note(
                &format!("{path}.alphaMode"),
                format!("BLEND with alpha {alpha:.4}: treated as opaque"),
            ),
            _ => {}
        }
    }

    /// The material extensions `ext` of the material at `path` folded into `pbr`, in the
    /// order they are checked: emissive strength, IOR, transmission, volume, then the others
    /// (unlit is read, the rest noted).
    fn material_extensions(
        &mut self,
        ext: &::gltf::json::extensions::material::Material,
        path: &str,
        pbr: &mut Pbr,
    ) -> Result<(), FormatError> {
        if let Some(s) = &ext.emissive_strength {
            let k = dec(s.emissive_strength.0);
            if !(k.is_finite() && k >= 0.0) {
                return Err(self.err(
                    &format!("{path}.extensions.KHR_materials_emissive_strength"),
                    format!("emissiveStrength {k} is not a finite number >= 0"),
                ));
            }
            pbr.emission = pbr.emission.map(|c| c * k);
        }
        if let Some(ior) = &ext.ior {
            let v = dec(ior.ior.0);
            if !(v.is_finite() && v >= 1.0) {
                return Err(self.err(
                    &format!("{path}.extensions.KHR_materials_ior.ior"),
                    format!("{v} is not a finite number >= 1"),
                ));
            }
            pbr.ior = v;
        }
        if let Some(t) = &ext.transmission {
            pbr.transmission = self.transmission(t, path)?;
        }
        if let Some(v) = &ext.volume {
            pbr.volume = Some(self.volume(v, path)?);
        }
        for k in ext.others.keys() {
            if k == "KHR_materials_unlit" {
                pbr.unlit = true;
            } else {
                self.note(
                    &format!("{path}.extensions.{k}"),
                    "not read: the material is mapped without it",
                );
            }
        }
        Ok(())
    }

    /// `KHR_materials_transmission` of the material at `path`: its factor, times its
    /// texture's mean red.
    fn transmission(
        &mut self,
        t: &::gltf::json::extensions::material::Transmission,
        path: &str,
    ) -> Result<f64, FormatError> {
        let ep = format!("{path}.extensions.KHR_materials_transmission");
        let mut transmission = dec(t.transmission_factor.0);
        if !(transmission.is_finite() && (0.0..=1.0).contains(&transmission)) {
            return Err(self.err(
                &format!("{ep}.transmissionFactor"),
                format!("{transmission} is not in [0, 1]"),
            ));
        }
        if let Some(tt) = &t.transmission_texture {
            let tp = format!("{ep}.transmissionTexture");
            if let Some(mean) = self.texture(tt.index.value(), false, &tp, "transmissionFactor")? {
                transmission *= mean[0];
            }
        }
        Ok(transmission)
    }

    /// `KHR_materials_volume` of the material at `path`: thickness (times its texture's mean
    /// green), attenuation distance and colour.
    fn volume(
        &mut self,
        v: &::gltf::json::extensions::material::Volume,
        path: &str,
    ) -> Result<(f64, f64, [f64; 3]), FormatError> {
        let ep = format!("{path}.extensions.KHR_materials_volume");
        let mut thickness = dec(v.thickness_factor.0);
        let dist = dec(v.attenuation_distance.0);
        let color = v.attenuation_color.0.map(dec);
        if !(thickness.is_finite() && thickness >= 0.0) {
            return Err(self.err(
                &format!("{ep}.thicknessFactor"),
                format!("{thickness} is not a finite number >= 0"),
            ));
        }
        if dist.is_nan() || dist <= 0.0 || color.iter().any(|c| !(0.0..=1.0).contains(c)) {
            return Err(self.err(
                &ep,
                "attenuationDistance must be > 0 and attenuationColor in [0, 1]",
            ));
        }
        if let Some(tt) = &v.thickness_texture {
            let tp = format!("{ep}.thicknessTexture");
            if let Some(mean) = self.texture(tt.index.value(), false, &tp, "thicknessFactor")? {
                thickness *= mean[1];
            }
        }
        if thickness > 0.0 {
            self.note(
                &format!("{ep}.thicknessFactor"),
                "the thickness (a rasteriser's hint) is not used: raytree traces the mesh's \
                 actual volume",
            );
        }
        Ok((thickness, dist, color))
    }

    /// The mean linear RGBA of texture `t` at `path` (sRGB-decoded when `srgb`), noted; `None`
    /// (noted too) when its image is in a format that is not decoded, so `factor` is used
    /// alone.
    fn texture(
        &mut self,
        t: usize,
        srgb: bool,
        path: &str,
        factor: &str,
    ) -> Result<Option<[f64; 4]>, FormatError> {
        let root = self.root();
        let Some(tex) = root.textures.get(t) else {
            return Err(self.err(path, format!("textures[{t}] does not exist")));
        };
        let img = tex.source.value();
        let bytes = self.d.image(img)?;
        let mean =
            mat::image_mean(&bytes, srgb).map_err(|e| self.err(&format!("images[{img}]"), e))?;
        Ok(match mean {
            Mean::Decoded(m, what) => {
                self.note(
                    path,
                    format!(
                        "textures[{t}] (images[{img}], {what}) read as its mean {} (linear{}), \
                         times {factor}: raytree's materials are not textured",
                        if srgb {
                            format!("colour [{:.4}, {:.4}, {:.4}]", m[0], m[1], m[2])
                        } else {
                            format!("[{:.4}, {:.4}, {:.4}]", m[0], m[1], m[2])
                        },
                        if srgb { ", decoded from sRGB" } else { "" }
                    ),
                );
                Some(m)
            }
            Mean::Skipped(why) => {
                self.note(
                    path,
                    format!("textures[{t}] (images[{img}]): {why}: {factor} alone is used"),
                );
                None
            }
        })
    }
}
