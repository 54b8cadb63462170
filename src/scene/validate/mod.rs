//! `SceneDesc` (serde) to `Scene` (validated): every rejection names its JSON path.

use super::check::Check;
use super::desc::{
    CameraDesc, CoatingDesc, ConductorDesc, LightDesc, MaterialDesc, ObjectDesc, SceneDesc,
    Settings, TextureDesc, Triple,
};
use super::error::{
    bare_message, field_of_tagged, key_in_integrator, path_of, reword, with_missing_field,
};
use super::mesh_object::MeshLoader;
use super::{Accel, Camera, Light, LightKind, Material, Object, Scene, SceneError, Texture};
use crate::bsdf::{Coating, ComplexIor};
use crate::geometry::Shape;
use glam::DVec3;
use std::collections::HashMap;

mod settings;
pub use settings::{MAX_RR_DEPTH, MAX_SPP, check_rr_depth, check_settings};

pub(super) fn from_json(src: &str, load_mesh: MeshLoader) -> Result<Scene, SceneError> {
    let src = crate::input::strip_bom(src);
    super::scan::scan(src)?;
    let mut de = serde_json::Deserializer::from_str(src);
    let desc: SceneDesc = serde_path_to_error::deserialize(&mut de).map_err(|e| {
        let path = path_of(e.path());
        let inner = e.inner();
        let message = reword(bare_message(inner));
        // serde_json counts columns from 0 before the first character of a line.
        let at = (inner.line(), inner.column().max(1));
        let (path, at) = field_of_tagged(src, with_missing_field(path, &message), &message, at);
        let (path, message, at) = key_in_integrator(src, path, message, at);
        SceneError {
            path,
            line: Some(at.0),
            column: Some(at.1),
            message,
        }
    })?;
    de.end().map_err(|e| SceneError {
        path: String::new(),
        line: Some(e.line()),
        column: Some(e.column().max(1)),
        message: bare_message(&e),
    })?;
    validate(&desc, src, load_mesh)
}

/// Validate a parsed description, reading mesh files through `load_mesh`; `src` is used only
/// to locate errors (may be empty).
pub fn validate(desc: &SceneDesc, src: &str, load_mesh: MeshLoader) -> Result<Scene, SceneError> {
    let ck = Check { src };
    let camera = camera(&ck, &desc.camera)?;
    let background = ck.color("background", desc.background)?;
    let ambient = ck.color("ambient", desc.ambient)?;
    let mut materials = Vec::with_capacity(desc.materials.len());
    for (name, m) in &desc.materials {
        materials.push(material(&ck, name, m)?);
    }
    let index: HashMap<&str, usize> = (desc.materials.keys().enumerate())
        .map(|(i, k)| (k.as_str(), i))
        .collect();
    let mut objects = Vec::with_capacity(desc.objects.len());
    for (i, o) in desc.objects.iter().enumerate() {
        objects.push(object(&ck, &desc.materials, &index, i, o, load_mesh)?);
    }
    let mut lights = Vec::with_capacity(desc.lights.len());
    for (i, l) in desc.lights.iter().enumerate() {
        lights.push(light(&ck, i, l)?);
    }
    check_spheres(&ck, &camera, &objects)?;
    let settings = settings(&ck, &desc.settings)?;
    let accel = Accel::build(&objects);
    Ok(Scene {
        camera,
        background,
        ambient,
        materials,
        objects,
        lights,
        settings,
        accel,
    })
}

/// Largest sphere radius: the intersection test squares it.
pub const MAX_SPHERE_RADIUS: f64 = 1e150;

/// Refuse spheres the intersection test cannot resolve (issue 27: a ground sphere of radius
/// 1e100 vanished or rendered black). The test (Ray Tracing Gems ch. 7's stable form) squares
/// the radius, and a point near a sphere's surface is known only to about radius x 2^-52: a
/// camera closer to the surface than that (2^-44 of the larger of the radius and the camera's
/// distance to the centre, with headroom) sees it at a distance that is all rounding error.
fn check_spheres(ck: &Check, camera: &Camera, objects: &[Object]) -> Result<(), SceneError> {
    for (i, o) in objects.iter().enumerate() {
        let Shape::Sphere { center, radius } = o.shape else {
            continue;
        };
        let p = format!("objects[{i}].radius");
        if radius > MAX_SPHERE_RADIUS {
            return ck.fail(
                p,
                format!("{radius:e} is above the limit of 1e150 (the intersection test squares it); use a plane for an unbounded ground"),
            );
        }
        let dist = (camera.position - center).length();
        let gap = (dist - radius).abs();
        let resolution = dist.max(radius) * f64::from(2.0f32.powi(-44));
        if gap < resolution {
            return ck.fail(
                p,
                format!(
                    "{radius:e} is too large for this camera: the camera is {gap:.3e} from the sphere's surface, below what a 64-bit float resolves there ({resolution:.1e}, 2^-44 of its size); use a plane for a ground this large, or a smaller radius"
                ),
            );
        }
    }
    Ok(())
}

fn camera(ck: &Check, c: &CameraDesc) -> Result<Camera, SceneError> {
    let position = ck.vec("camera.position", c.position)?;
    let look_at = ck.vec("camera.look_at", c.look_at)?;
    let d = look_at - position;
    if !d.is_finite() {
        return ck.fail(
            "camera.look_at",
            "is so far from camera.position that their difference overflows a 64-bit float",
        );
    }
    // A distance beyond 1.3e154 squares to infinity: normalise it scaled (only then, so the
    // usual direction is unchanged bit for bit).
    let scaled = || (d / d.abs().max_element()).try_normalize();
    let Some(forward) = d
        .try_normalize()
        .or_else(|| scaled().filter(|_| d != DVec3::ZERO))
    else {
        return ck.fail("camera.look_at", "must differ from camera.position");
    };
    let up_hint = ck.direction("camera.up", c.up)?;
    let Some(right) = forward.cross(up_hint).try_normalize() else {
        return ck.fail("camera.up", "must not be parallel to the view direction");
    };
    let fov_y = ck.finite("camera.fov_y", c.fov_y)?;
    if !(fov_y > 0.0 && fov_y < 180.0) {
        return ck.fail(
            "camera.fov_y",
            format!("must be in (0, 180) degrees, got {fov_y}"),
        );
    }
    for (name, v) in [("width", c.width), ("height", c.height)] {
        if v == 0 || v > 65_536 {
            return ck.fail(
                format!("camera.{name}"),
                format!("must be in 1..=65536, got {v}"),
            );
        }
    }
    let aperture_radius = ck.finite("camera.aperture_radius", c.aperture_radius)?;
    if let Err(msg) = check_aperture(aperture_radius) {
        return ck.fail("camera.aperture_radius", msg);
    }
    let focus_distance = match c.focus_distance {
        Some(f) => {
            let f = ck.finite("camera.focus_distance", f)?;
            if let Err(msg) = check_focus(f) {
                return ck.fail("camera.focus_distance", msg);
            }
            f
        }
        None => (look_at - position).length(),
    };
    Ok(Camera {
        position,
        forward,
        right,
        up: right.cross(forward),
        fov_y,
        width: c.width,
        height: c.height,
        aperture_radius,
        focus_distance,
    })
}

/// `camera.aperture_radius` (and `--aperture`): a finite number >= 0.
pub fn check_aperture(r: f64) -> Result<f64, String> {
    if !(r.is_finite() && r >= 0.0) {
        Err(format!("must be a finite number >= 0, got {r}"))
    } else if r > MAX_LENS_RADIUS {
        Err(format!(
            "must be at most {MAX_LENS_RADIUS:e} (a lens point's distance from the focus point is squared when its ray is made), got {r:e}"
        ))
    } else {
        Ok(r)
    }
}

/// Largest thin-lens radius (`camera.aperture_radius`, `--aperture`).
pub const MAX_LENS_RADIUS: f64 = 1e150;

/// `camera.focus_distance` (and `--focus`): a finite number > 0.
pub fn check_focus(f: f64) -> Result<f64, String> {
    if f.is_finite() && f > 0.0 {
        Ok(f)
    } else {
        Err(format!("must be a finite number > 0, got {f}"))
    }
}

fn material(ck: &Check, name: &str, m: &MaterialDesc) -> Result<Material, SceneError> {
    let p = super::path::key("materials", name);
    let diffuse = diffuse(ck, &p, m.diffuse.as_ref())?;
    let shininess = ck.finite(&format!("{p}.shininess"), m.shininess)?;
    if shininess < 0.0 {
        return ck.fail(format!("{p}.shininess"), "must not be negative");
    }
    let roughness = alpha(ck, &p, "roughness", m.roughness)?;
    let roughness_v = match m.roughness_v {
        Some(v) => alpha(ck, &p, "roughness_v", v)?,
        None => roughness,
    };
    let tangent = match m.tangent {
        Some(t) => tangent(ck, &p, t)?,
        None => DVec3::X,
    };
    let (conductor, reflectivity) = match &m.conductor {
        None => (
            None,
            ck.color(&format!("{p}.reflectivity"), m.reflectivity)?,
        ),
        Some(c) => {
            if m.reflectivity != [0.0; 3] {
                return ck.fail(
                    format!("{p}.reflectivity"),
                    "a conductor's reflectance is its Fresnel: leave reflectivity out and tint \
                     it with conductor.scale",
                );
            }
            conductor(ck, &format!("{p}.conductor"), c)?
        }
    };
    let ior = match m.ior {
        Some(n) => Some(ck.positive(&format!("{p}.ior"), n)?),
        None => None,
    };
    let (coating, reflectivity) = match &m.coating {
        None => (None, reflectivity),
        Some(c) => coating(ck, &p, m, c, (roughness, roughness_v))?,
    };
    let thin = match &m.thin {
        None => None,
        Some(t) => Some(thin(ck, &p, m, t.ior)?),
    };
    Ok(Material {
        name: name.to_string(),
        diffuse,
        specular: ck.color(&format!("{p}.specular"), m.specular)?,
        shininess,
        reflectivity,
        transmissivity: ck.color(&format!("{p}.transmissivity"), m.transmissivity)?,
        ior,
        absorption: ck.color(&format!("{p}.absorption"), m.absorption)?,
        emission: ck.color(&format!("{p}.emission"), m.emission)?,
        roughness,
        roughness_v,
        tangent,
        distribution: m.distribution,
        conductor,
        coating,
        thin,
    })
}

/// The diffuse texture at `p`: black when absent, a colour, or a checker.
fn diffuse(ck: &Check, p: &str, d: Option<&TextureDesc>) -> Result<Texture, SceneError> {
    Ok(match d {
        None => Texture::Solid(DVec3::ZERO),
        Some(TextureDesc::Solid(c)) => Texture::Solid(ck.color(&format!("{p}.diffuse"), *c)?),
        Some(TextureDesc::Checker { checker }) => {
            let q = format!("{p}.diffuse.checker");
            Texture::Checker {
                even: ck.color(&format!("{q}.even"), checker.even)?,
                odd: ck.color(&format!("{q}.odd"), checker.odd)?,
                size: ck.positive(&format!("{q}.size"), checker.size)?,
            }
        }
    })
}

/// A microfacet alpha at `p.key`, in [0, 1].
fn alpha(ck: &Check, p: &str, key: &str, v: f64) -> Result<f64, SceneError> {
    let v = ck.finite(&format!("{p}.{key}"), v)?;
    if (0.0..=1.0).contains(&v) {
        Ok(v)
    } else {
        ck.fail(
            format!("{p}.{key}"),
            format!("must be in [0, 1] (the microfacet alpha), got {v}"),
        )
    }
}

/// The anisotropic lobes' tangent at `p`, normalised; not the zero vector.
fn tangent(ck: &Check, p: &str, t: [f64; 3]) -> Result<DVec3, SceneError> {
    let v = ck.vec(&format!("{p}.tangent"), t)?;
    if v.length_squared() == 0.0 {
        return ck.fail(format!("{p}.tangent"), "must not be the zero vector");
    }
    Ok(v.normalize())
}

/// The first `(condition, key, why)` whose condition holds, as an error at `p.key`.
fn refuse_first(ck: &Check, p: &str, clash: &[(bool, &str, &str)]) -> Result<(), SceneError> {
    match clash.iter().find(|c| c.0) {
        Some((_, key, why)) => ck.fail(format!("{p}.{key}"), *why),
        None => Ok(()),
    }
}

/// A thin sheet's index (at `p.thin.ior`); the fields a sheet cannot have are errors.
fn thin(ck: &Check, p: &str, m: &MaterialDesc, ior: f64) -> Result<f64, SceneError> {
    let clash = [
        (
            m.transmissivity == [0.0; 3],
            "transmissivity",
            "a thin sheet transmits: give its weight as transmissivity",
        ),
        (
            m.ior.is_some(),
            "ior",
            "a thin sheet bends no ray: give its index as thin.ior, not ior",
        ),
        (
            m.absorption != [0.0; 3],
            "absorption",
            "a thin sheet has no volume to absorb in",
        ),
        (
            m.roughness != 0.0 || m.roughness_v.is_some(),
            "roughness",
            "a thin sheet is smooth",
        ),
        (
            m.coating.is_some(),
            "coating",
            "a material is either coated or a thin sheet",
        ),
    ];
    refuse_first(ck, p, &clash)?;
    ck.positive(&format!("{p}.thin.ior"), ior)
}

/// A coating (at `p.coating`) and its tint, the material's `reflectivity`; the fields a
/// coated material cannot have are errors.
fn coating(
    ck: &Check,
    p: &str,
    m: &MaterialDesc,
    c: &CoatingDesc,
    (alpha_u, alpha_v): (f64, f64),
) -> Result<(Option<Coating>, DVec3), SceneError> {
    let clash = [
        (
            m.reflectivity != [0.0; 3],
            "reflectivity",
            "the coating's reflectance is its Fresnel: leave reflectivity out and tint it with coating.scale",
        ),
        (
            m.conductor.is_some(),
            "conductor",
            "a material is either coated or a conductor",
        ),
        (
            m.transmissivity != [0.0; 3],
            "transmissivity",
            "a coated material is opaque: its light goes to the diffuse base",
        ),
        (
            alpha_u != alpha_v,
            "roughness_v",
            "a coating is isotropic: give one roughness",
        ),
    ];
    refuse_first(ck, p, &clash)?;
    let eta = ck.positive(&format!("{p}.coating.ior"), c.ior)?;
    let scale = match c.scale {
        Some(s) => ck.color(&format!("{p}.coating.scale"), s)?,
        None => DVec3::ONE,
    };
    let rough = (alpha_u >= crate::bsdf::SMOOTH_ALPHA)
        .then(|| crate::bsdf::Microfacet::with(m.distribution, alpha_u, alpha_v));
    let coating = Coating {
        nonlinear: c.nonlinear,
        ..Coating::new(eta, rough)
    };
    Ok((Some(coating), scale))
}

/// A conductor's complex index and tint (the material's `reflectivity`).
fn conductor(
    ck: &Check,
    p: &str,
    c: &ConductorDesc,
) -> Result<(Option<ComplexIor>, DVec3), SceneError> {
    let ior = match (&c.metal, c.eta, c.k) {
        (Some(name), None, None) => ComplexIor::metal(name).map_or_else(
            || {
                let known: Vec<&str> = crate::bsdf::METALS.iter().map(|m| m.0).collect();
                ck.fail(
                    format!("{p}.metal"),
                    format!("unknown metal {name:?} (known: {})", known.join(", ")),
                )
            },
            Ok,
        )?,
        (None, Some(eta), Some(k)) => {
            let eta = ck.vec(&format!("{p}.eta"), eta)?;
            if eta.min_element() <= 0.0 {
                return ck.fail(format!("{p}.eta"), "must be positive in every channel");
            }
            ComplexIor {
                eta,
                k: ck.color(&format!("{p}.k"), k)?,
            }
        }
        _ => {
            return ck.fail(
                p.to_string(),
                "give either \"metal\" or both \"eta\" and \"k\"",
            );
        }
    };
    let scale = match c.scale {
        Some(s) => ck.color(&format!("{p}.scale"), s)?,
        None => DVec3::ONE,
    };
    Ok((Some(ior), scale))
}

fn object(
    ck: &Check,
    materials: &std::collections::BTreeMap<String, MaterialDesc>,
    index: &HashMap<&str, usize>,
    i: usize,
    o: &ObjectDesc,
    load_mesh: MeshLoader,
) -> Result<Object, SceneError> {
    let p = format!("objects[{i}]");
    let Some(&material) = index.get(o.material()) else {
        let known = super::suggest::closest(o.material(), materials.keys().map(String::as_str));
        return ck.fail(
            format!("{p}.material"),
            format!(
                "unknown material {} (defined: {known})",
                crate::input::quote(o.material()),
            ),
        );
    };
    let shape = match o {
        ObjectDesc::Sphere { center, radius, .. } => Shape::Sphere {
            center: ck.vec(&format!("{p}.center"), *center)?,
            radius: ck.positive(&format!("{p}.radius"), *radius)?,
        },
        ObjectDesc::Plane { point, normal, .. } => Shape::Plane {
            point: ck.vec(&format!("{p}.point"), *point)?,
            normal: ck.direction(&format!("{p}.normal"), *normal)?,
        },
        ObjectDesc::Triangle { vertices, .. } => triangle(ck, &p, vertices)?,
        ObjectDesc::Quad {
            corner,
            edge_u,
            edge_v,
            ..
        } => quad(ck, &p, *corner, *edge_u, *edge_v)?,
        ObjectDesc::Box { min, max, .. } => {
            let lo = ck.vec(&format!("{p}.min"), *min)?;
            let hi = ck.vec(&format!("{p}.max"), *max)?;
            if !lo.cmplt(hi).all() {
                return ck.fail(format!("{p}.max"), "must exceed min on every axis");
            }
            Shape::Box { min: lo, max: hi }
        }
        ObjectDesc::Mesh { .. } => super::mesh_object::shape(ck, &p, o, load_mesh)?,
        ObjectDesc::Trimesh { .. } => super::mesh_object::inline(ck, &p, o)?,
    };
    let name = o
        .name()
        .map_or_else(|| format!("{}#{i}", o.kind()), str::to_string);
    Ok(Object {
        name,
        shape,
        material,
    })
}

/// A triangle at `p` from its three vertices; refused when it has no area.
fn triangle(ck: &Check, p: &str, vertices: &[[f64; 3]; 3]) -> Result<Shape, SceneError> {
    let mut v = [DVec3::ZERO; 3];
    for (k, x) in vertices.iter().enumerate() {
        v[k] = ck.vec(&format!("{p}.vertices[{k}]"), *x)?;
    }
    let Some(normal) = (v[1] - v[0]).cross(v[2] - v[0]).try_normalize() else {
        return ck.fail(format!("{p}.vertices"), "degenerate triangle (zero area)");
    };
    Ok(Shape::Triangle {
        vertices: v,
        normal,
    })
}

/// A parallelogram at `p` from a corner and its two edges; refused when it has no area.
fn quad(
    ck: &Check,
    p: &str,
    corner: [f64; 3],
    edge_u: [f64; 3],
    edge_v: [f64; 3],
) -> Result<Shape, SceneError> {
    let a = ck.vec(&format!("{p}.corner"), corner)?;
    let u = ck.vec(&format!("{p}.edge_u"), edge_u)?;
    let v = ck.vec(&format!("{p}.edge_v"), edge_v)?;
    if u == DVec3::ZERO {
        return ck.fail(format!("{p}.edge_u"), "must not be zero");
    }
    if v == DVec3::ZERO {
        return ck.fail(format!("{p}.edge_v"), "must not be zero");
    }
    let Some(normal) = u.cross(v).try_normalize() else {
        return ck.fail(
            format!("{p}.edge_v"),
            "must not be parallel to edge_u (zero area)",
        );
    };
    Ok(Shape::Quad {
        vertices: [a, a + u, a + u + v, a + v],
        normal,
    })
}

fn light(ck: &Check, i: usize, l: &LightDesc) -> Result<Light, SceneError> {
    let p = format!("lights[{i}]");
    let (kind, name) = match l {
        LightDesc::Point {
            position,
            intensity,
            name,
        } => (
            LightKind::Point {
                position: ck.vec(&format!("{p}.position"), *position)?,
                intensity: ck.color(&format!("{p}.intensity"), *intensity)?,
                spot: None,
            },
            name,
        ),
        LightDesc::Spot {
            position,
            intensity,
            name,
            direction,
            look_at,
            cone_angle,
            falloff_angle,
            profile,
        } => {
            let position = ck.vec(&format!("{p}.position"), *position)?;
            let axis = spot_axis(ck, &p, position, (*direction, *look_at))?;
            let cone = (*cone_angle, *falloff_angle, *profile);
            (
                LightKind::Point {
                    position,
                    intensity: ck.color(&format!("{p}.intensity"), *intensity)?,
                    spot: Some(spot(ck, &p, axis, cone)?),
                },
                name,
            )
        }
        LightDesc::Directional {
            direction,
            irradiance,
            name,
        } => (
            LightKind::Directional {
                direction: ck.direction(&format!("{p}.direction"), *direction)?,
                irradiance: ck.color(&format!("{p}.irradiance"), *irradiance)?,
            },
            name,
        ),
    };
    Ok(Light {
        name: name.clone().unwrap_or_else(|| format!("light#{i}")),
        kind,
    })
}

/// A spot light's axis from `direction` or `look_at` (exactly one).
fn spot_axis(
    ck: &Check,
    p: &str,
    position: DVec3,
    (direction, look_at): (Option<Triple>, Option<Triple>),
) -> Result<DVec3, SceneError> {
    match (direction, look_at) {
        (Some(d), None) => ck.direction(&format!("{p}.direction"), d),
        (None, Some(t)) => {
            let target = ck.vec(&format!("{p}.look_at"), t)?;
            match (target - position).try_normalize() {
                Some(a) => Ok(a),
                None => ck.fail(format!("{p}.look_at"), "must differ from position"),
            }
        }
        (Some(_), Some(_)) => ck.fail(
            format!("{p}.look_at"),
            "give direction or look_at, not both",
        ),
        (None, None) => ck.fail(p.to_string(), "a spot light needs direction or look_at"),
    }
}

/// A spot light's cone about `axis`: its angles in degrees checked and converted to radians.
fn spot(
    ck: &Check,
    p: &str,
    axis: DVec3,
    (cone, falloff, profile): (f64, Option<f64>, crate::lights::SpotProfile),
) -> Result<crate::lights::Spot, SceneError> {
    if !(cone > 0.0 && cone < 180.0) {
        return ck.fail(format!("{p}.cone_angle"), "must be in (0, 180) degrees");
    }
    let falloff = falloff.unwrap_or(cone);
    if !(0.0..=cone).contains(&falloff) {
        return ck.fail(
            format!("{p}.falloff_angle"),
            "must be in [0, cone_angle] degrees",
        );
    }
    Ok(crate::lights::Spot {
        axis,
        cone: cone.to_radians(),
        falloff: falloff.to_radians(),
        profile,
    })
}

fn settings(ck: &Check, s: &Settings) -> Result<Settings, SceneError> {
    check_settings(s).or_else(|(path, msg)| ck.fail(ck.settings_key(&path), msg))
}

#[cfg(test)]
mod tests;
