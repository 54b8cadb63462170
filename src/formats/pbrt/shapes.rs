//! pbrt-v4 materials and shapes.

use super::get::Kind;
use super::lex::{Tok, Token};
use super::params::Params;
use super::scene::{Gs, State, ctx, err_at};
use crate::formats::build::{Surface, disk_triangles};
use crate::formats::{FormatError, material_map as mm, ply, relative_to};
use crate::scene::desc::MaterialDesc;
use glam::DVec3;

/// Subdivisions per side of a bilinear patch that is not a parallelogram.
const PATCH_GRID: u32 = 8;

impl State<'_> {
    /// A material directive's description (notes recorded at `t`).
    pub(super) fn material(
        &mut self,
        file: &str,
        t: &Token,
        kind: &str,
        p: &Params,
    ) -> Result<MaterialDesc, FormatError> {
        let what = format!("Material \"{kind}\"");
        let c = ctx(file, &what, p, &self.textures);
        let mut notes: Vec<String> = Vec::new();
        let color = |notes: &mut Vec<String>,
                     name: &str,
                     kind: Kind,
                     default: [f64; 3]|
         -> Result<[f64; 3], FormatError> {
            Ok(match c.color(name, kind)? {
                Some((v, n)) => {
                    notes.extend(n);
                    v
                }
                None => default,
            })
        };
        let remap = c.bool("remaproughness", true)?;
        // alpha_v of an anisotropic material, set by `rough`.
        let alpha_v = std::cell::Cell::new(None);
        let rough = |notes: &mut Vec<String>| -> Result<f64, FormatError> {
            let r = c.float("roughness", 0.0)?;
            let u = c.float("uroughness", r)?;
            let v = c.float("vroughness", r)?;
            let (a, v, n) = mm::anisotropic(mm::pbrt_alpha(u, remap), mm::pbrt_alpha(v, remap));
            notes.extend(n);
            alpha_v.set(v);
            Ok(a)
        };
        let eta = |notes: &mut Vec<String>| -> Result<f64, FormatError> {
            Ok(match c.color("eta", Kind::Albedo)? {
                Some((v, n)) => {
                    notes.extend(n);
                    v[1]
                }
                None => 1.5,
            })
        };
        let (mut desc, note) = match kind {
            "diffuse" => (mm::diffuse(color(&mut notes, "reflectance", Kind::Albedo, [0.5; 3])?), None),
            "dielectric" => {
                let e = eta(&mut notes)?;
                let a = rough(&mut notes)?;
                mm::dielectric(e, a)
            }
            "thindielectric" => mm::thin_dielectric(eta(&mut notes)?),
            "conductor" | "coatedconductor" => {
                if kind == "coatedconductor" {
                    notes.push("coatedconductor: its coating is left out".into());
                }
                let a = rough(&mut notes)?;
                let (ename, kname) = if kind == "conductor" { ("eta", "k") } else { ("conductor.eta", "conductor.k") };
                if let Some((r, n)) = c.color("reflectance", Kind::Albedo)? {
                    notes.extend(n);
                    mm::conductor_reflectance(r, a)
                } else {
                    let (cu_eta, cu_k) = mm::metal("Cu").expect("copper is tabulated");
                    let e = color(&mut notes, ename, Kind::Index, cu_eta)?;
                    let k = color(&mut notes, kname, Kind::Index, cu_k)?;
                    mm::conductor(e, k, a, [1.0; 3])
                }
            }
            "coateddiffuse" => {
                let r = color(&mut notes, "reflectance", Kind::Albedo, [0.5; 3])?;
                let a = rough(&mut notes)?;
                let _ = c.float("thickness", 0.01)?;
                let note = "pbrt-v4's coateddiffuse (a random walk through a dielectric \
                            layer over the base) mapped to raytree's coating with \
                            inter-reflections tinted by the base (Mitsuba's nonlinear plastic, \
                            the walk's expectation without its maxdepth cut): the layer's \
                            medium (thickness, albedo, g) is not modelled, and pbrt's walk at \
                            its default thickness 0.01 and maxdepth 10 renders 4-13% darker \
                            (docs/materials.md)";
                let eta = eta(&mut notes)?;
                mm::coated_diffuse(r, eta, a, [1.0; 3], true, Some(note.into()))
            }
            "interface" => (
                MaterialDesc { transmissivity: [1.0; 3], ior: Some(1.0), ..MaterialDesc::default() },
                Some("interface material (a medium boundary) made fully transmissive without refraction".into()),
            ),
            "diffusetransmission" => {
                let r = color(&mut notes, "reflectance", Kind::Albedo, [0.25; 3])?;
                (mm::diffuse(r), Some("diffusetransmission: only its diffuse reflection is kept".into()))
            }
            _ => (mm::diffuse([0.5; 3]), Some(format!("{what} is not supported: grey diffuse 0.5 used"))),
        };
        notes.extend(note);
        desc.roughness_v = alpha_v.get();
        for n in notes {
            self.b.note(file, t.line, format!("{what}: {n}"));
        }
        let ignored: Vec<String> = p
            .unused()
            .into_iter()
            .filter(|u| !u.ends_with(" type\""))
            .collect();
        if !ignored.is_empty() {
            self.b.note(
                file,
                t.line,
                format!("{what}: ignored {}", ignored.join(", ")),
            );
        }
        Ok(desc)
    }

    /// The surface (material with the current area light's emission) for a shape.
    fn surface(&mut self, gs: &Gs) -> Surface {
        let (name, mut desc) = gs.material.clone();
        let name = match &gs.area {
            None => self.b.material(&name, desc),
            Some(a) => {
                desc.emission = a.l;
                self.b.material(&format!("{name}+light"), desc)
            }
        };
        Surface {
            material: name,
            name: None,
            flip: gs.reverse,
        }
    }

    /// `Shape "kind" params` under the graphics state `gs`.
    pub(super) fn shape_with(
        &mut self,
        file: &str,
        line: usize,
        column: usize,
        kind: &str,
        p: &Params,
        gs: &Gs,
    ) -> Result<(), FormatError> {
        let t = Token {
            tok: Tok::Word("Shape".into()),
            line,
            column,
        };
        let what = format!("Shape \"{kind}\"");
        let m = gs
            .ctm
            .affine()
            .ok_or_else(|| err_at(file, &t, format!("{what}: projective transform")))?;
        let s = self.surface(gs);
        let fail = |e: String| err_at(file, &t, format!("{what}: {e}"));
        let c = ctx(file, &what, p, &self.textures);
        if c.string("alpha")?.is_some() || c.float("alpha", 1.0)? != 1.0 {
            self.b
                .note(file, line, format!("{what}: alpha (cut-out) ignored"));
        }
        let c = ctx(file, &what, p, &self.textures);
        match kind {
            "sphere" => {
                let r = c.float("radius", 1.0)?;
                let partial = c.float("zmin", -r)? != -r
                    || c.float("zmax", r)? != r
                    || c.float("phimax", 360.0)? != 360.0;
                if partial {
                    self.b.note(
                        file,
                        line,
                        format!("{what}: a partial sphere (zmin, zmax or phimax) is drawn whole"),
                    );
                }
                if let Some(n) = self.b.sphere(DVec3::ZERO, r, &m, &s).map_err(fail)? {
                    self.b.note(file, line, format!("{what}: {n}"));
                }
            }
            "trianglemesh" | "loopsubdiv" => {
                let pos = c
                    .points("P", &["point3", "point"])?
                    .ok_or_else(|| fail("needs \"point3 P\"".into()))?;
                let idx = match c.indices("indices")? {
                    Some(v) => v,
                    None if pos.len() == 3 => vec![0, 1, 2],
                    None => return Err(fail("needs \"integer indices\"".into())),
                };
                if idx.len() % 3 != 0 {
                    return Err(fail(format!("{} indices, not a multiple of 3", idx.len())));
                }
                let n = c.points("N", &["normal", "normal3"])?;
                if kind == "loopsubdiv" {
                    self.b.note(
                        file,
                        line,
                        format!("{what}: its control mesh is used unsubdivided"),
                    );
                    let _ = c.int("levels", 3)?;
                }
                for extra in ["uv", "S", "faceIndices"] {
                    if p.get(extra).is_some() {
                        self.b.note(
                            file,
                            line,
                            format!("{what}: \"{extra}\" not used by raytree"),
                        );
                    }
                }
                let tris: Vec<[u32; 3]> = idx.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
                self.b
                    .mesh(&pos, &tris, n.as_deref(), &m, &s)
                    .map_err(fail)?;
            }
            "plymesh" => {
                let f = c
                    .string("filename")?
                    .ok_or_else(|| fail("needs \"string filename\"".into()))?;
                if p.get("displacement").is_some() {
                    self.b
                        .note(file, line, format!("{what}: displacement ignored"));
                }
                let path = relative_to(file, &f);
                let bytes = self.read(file, &t, &path, &what)?;
                let mesh = ply::parse(&bytes, self.vertex_limit())
                    .map_err(|e| fail(format!("{f}: {e}")))?;
                if mesh.has_uv {
                    self.b.note(
                        file,
                        line,
                        format!("{what}: {f}: texture coordinates not used by raytree"),
                    );
                }
                self.b
                    .mesh(
                        &mesh.positions,
                        &mesh.triangles,
                        mesh.normals.as_deref(),
                        &m,
                        &s,
                    )
                    .map_err(|e| fail(format!("{f}: {e}")))?;
            }
            "bilinearmesh" => {
                let pos = c
                    .points("P", &["point3", "point"])?
                    .ok_or_else(|| fail("needs \"point3 P\"".into()))?;
                let idx = match c.indices("indices")? {
                    Some(v) => v,
                    None if pos.len() == 4 => vec![0, 1, 2, 3],
                    None => return Err(fail("needs \"integer indices\"".into())),
                };
                if idx.len() % 4 != 0 {
                    return Err(fail(format!("{} indices, not a multiple of 4", idx.len())));
                }
                if c.points("N", &["normal", "normal3"])?.is_some() {
                    self.b
                        .note(file, line, format!("{what}: \"N\" not used (flat patches)"));
                }
                if let Some(&bad) = idx.iter().find(|&&k| k as usize >= pos.len()) {
                    return Err(fail(format!(
                        "vertex index {bad} out of range ({} vertices)",
                        pos.len()
                    )));
                }
                for q in idx.chunks(4) {
                    self.patch(
                        [q[0], q[1], q[2], q[3]].map(|k| pos[k as usize]),
                        &m,
                        &s,
                        file,
                        line,
                    )
                    .map_err(fail)?;
                }
            }
            "disk" => {
                let h = c.float("height", 0.0)?;
                let r = c.float("radius", 1.0)?;
                let ri = c.float("innerradius", 0.0)?;
                if c.float("phimax", 360.0)? != 360.0 {
                    self.b
                        .note(file, line, format!("{what}: phimax ignored (a whole disk)"));
                }
                if !(r > 0.0 && ri >= 0.0 && ri < r) {
                    return Err(fail("needs radius > innerradius >= 0".into()));
                }
                let (pos, tris) = disk_triangles(r, ri, h);
                self.b.note(
                    file,
                    line,
                    format!("{what}: tessellated into {} triangles", tris.len()),
                );
                self.b.mesh(&pos, &tris, None, &m, &s).map_err(fail)?;
            }
            "cylinder" | "curve" | "cone" | "paraboloid" | "hyperboloid" => {
                self.b.note(
                    file,
                    line,
                    format!("{what} is not supported by raytree: left out"),
                );
                return Ok(());
            }
            _ => return Err(fail("unknown shape".into())),
        }
        self.unused(file, &t, &what, p);
        Ok(())
    }

    /// A bilinear patch `p00, p10, p01, p11`: a quad when it is a parallelogram (exact),
    /// otherwise a grid of triangles (noted).
    fn patch(
        &mut self,
        [p00, p10, p01, p11]: [DVec3; 4],
        m: &glam::DAffine3,
        s: &Surface,
        file: &str,
        line: usize,
    ) -> Result<(), String> {
        let (u, v) = (p10 - p00, p01 - p00);
        let size = u.length().max(v.length());
        if (p11 - p10 - v).length() <= 1e-12 * size {
            self.b.quad(p00, u, v, m, s);
            return Ok(());
        }
        let n = PATCH_GRID;
        let at = |i: u32, j: u32| {
            let (a, b) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            p00.lerp(p10, a).lerp(p01.lerp(p11, a), b)
        };
        let pos: Vec<DVec3> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| at(i, j)))
            .collect();
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        self.b.note(
            file,
            line,
            format!(
                "Shape \"bilinearmesh\": a curved patch tessellated into {} triangles",
                tris.len()
            ),
        );
        self.b.mesh(&pos, &tris, None, m, s)
    }
}
