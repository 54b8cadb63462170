//! pbrt-v4 materials and shapes.

use super::get::{Ctx, Kind};
use super::lex::{Tok, Token};
use super::params::Params;
use super::scene::{Gs, State, ctx, err_at};
use crate::formats::build::{Surface, disk_triangles};
use crate::formats::{FormatError, material_map as mm, ply, relative_to};
use crate::scene::desc::MaterialDesc;
use glam::{DAffine3, DVec3};

/// Subdivisions per side of a bilinear patch that is not a parallelogram.
const PATCH_GRID: u32 = 8;

/// A material directive's parameters being read, with the notes they raise, in order.
struct MatReader<'a> {
    c: Ctx<'a>,
    /// `remaproughness`.
    remap: bool,
    notes: Vec<String>,
    /// alpha_v of an anisotropic material, set by `rough`.
    alpha_v: Option<f64>,
}

impl MatReader<'_> {
    /// The colour `name` of `kind`, or `default`.
    fn color(
        &mut self,
        name: &str,
        kind: Kind,
        default: [f64; 3],
    ) -> Result<[f64; 3], FormatError> {
        Ok(match self.c.color(name, kind)? {
            Some((v, n)) => {
                self.notes.extend(n);
                v
            }
            None => default,
        })
    }

    /// alpha_u from `roughness`, `uroughness` and `vroughness` (alpha_v kept for the end).
    fn rough(&mut self) -> Result<f64, FormatError> {
        let c = &self.c;
        let r = c.float("roughness", 0.0)?;
        let u = c.float("uroughness", r)?;
        let v = c.float("vroughness", r)?;
        let (a, v, n) =
            mm::anisotropic(mm::pbrt_alpha(u, self.remap), mm::pbrt_alpha(v, self.remap));
        self.notes.extend(n);
        self.alpha_v = v;
        Ok(a)
    }

    /// The (green) `eta`, 1.5 by default.
    fn eta(&mut self) -> Result<f64, FormatError> {
        Ok(match self.c.color("eta", Kind::Albedo)? {
            Some((v, n)) => {
                self.notes.extend(n);
                v[1]
            }
            None => 1.5,
        })
    }

    /// The description of material `kind`, and a note (the caller prefixes the directive).
    fn desc(&mut self, kind: &str) -> Result<(MaterialDesc, Option<String>), FormatError> {
        Ok(match kind {
            "diffuse" => (mm::diffuse(self.color("reflectance", Kind::Albedo, [0.5; 3])?), None),
            "dielectric" => {
                let e = self.eta()?;
                let a = self.rough()?;
                mm::dielectric(e, a)
            }
            "thindielectric" => mm::thin_dielectric(self.eta()?),
            "conductor" | "coatedconductor" => self.conductor(kind)?,
            "coateddiffuse" => self.coated_diffuse()?,
            "interface" => (
                MaterialDesc { transmissivity: [1.0; 3], ior: Some(1.0), ..MaterialDesc::default() },
                Some("interface material (a medium boundary) made fully transmissive without refraction".into()),
            ),
            "diffusetransmission" => {
                let r = self.color("reflectance", Kind::Albedo, [0.25; 3])?;
                (mm::diffuse(r), Some("diffusetransmission: only its diffuse reflection is kept".into()))
            }
            // As the caller prints it: `Material "measured": not supported by raytree: ...`.
            _ => (mm::diffuse([0.5; 3]), Some("not supported by raytree: grey diffuse 0.5 used".into())),
        })
    }

    /// `conductor` or `coatedconductor` (its coating left out): from a reflectance, or from
    /// `eta` and `k` (copper's by default).
    fn conductor(&mut self, kind: &str) -> Result<(MaterialDesc, Option<String>), FormatError> {
        if kind == "coatedconductor" {
            self.notes
                .push("coatedconductor: its coating is left out".into());
        }
        let a = self.rough()?;
        let (ename, kname) = if kind == "conductor" {
            ("eta", "k")
        } else {
            ("conductor.eta", "conductor.k")
        };
        Ok(
            if let Some((r, n)) = self.c.color("reflectance", Kind::Albedo)? {
                self.notes.extend(n);
                mm::conductor_reflectance(r, a)
            } else {
                let (cu_eta, cu_k) = mm::metal("Cu").expect("copper is tabulated");
                let e = self.color(ename, Kind::Index, cu_eta)?;
                let k = self.color(kname, Kind::Index, cu_k)?;
                mm::conductor(e, k, a, [1.0; 3])
            },
        )
    }

    /// `coateddiffuse`, as raytree's coating over a diffuse base.
    fn coated_diffuse(&mut self) -> Result<(MaterialDesc, Option<String>), FormatError> {
        let r = self.color("reflectance", Kind::Albedo, [0.5; 3])?;
        let a = self.rough()?;
        let _ = self.c.float("thickness", 0.01)?;
        let note = "pbrt-v4's coateddiffuse (a random walk through a dielectric \
                    layer over the base) mapped to raytree's coating with \
                    inter-reflections tinted by the base (Mitsuba's nonlinear plastic, \
                    the walk's expectation without its maxdepth cut): the layer's \
                    medium (thickness, albedo, g) is not modelled, and pbrt's walk at \
                    its default thickness 0.01 and maxdepth 10 renders 4-13% darker \
                    (docs/materials.md)";
        let eta = self.eta()?;
        Ok(mm::coated_diffuse(
            r,
            eta,
            a,
            [1.0; 3],
            true,
            Some(note.into()),
        ))
    }
}

/// One `Shape` directive being converted: where it is written, its name in messages, its
/// parameters, its placement and its surface.
struct ShapeAt<'p> {
    file: &'p str,
    /// The directive's position (its word `Shape`).
    t: Token,
    /// `Shape "kind"`.
    what: String,
    p: &'p Params,
    /// Object to world.
    m: DAffine3,
    s: Surface,
}

impl ShapeAt<'_> {
    /// The error `e` at the directive.
    fn fail(&self, e: impl std::fmt::Display) -> FormatError {
        err_at(self.file, &self.t, format!("{}: {e}", self.what))
    }
}

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
        let remap = c.bool("remaproughness", true)?;
        let mut r = MatReader {
            c,
            remap,
            notes: Vec::new(),
            alpha_v: None,
        };
        let (mut desc, note) = r.desc(kind)?;
        let mut notes = r.notes;
        notes.extend(note);
        desc.roughness_v = r.alpha_v;
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
        let sh = ShapeAt {
            file,
            t,
            what,
            p,
            m,
            s,
        };
        let c = ctx(file, &sh.what, p, &self.textures);
        if c.string("alpha")?.is_some() || c.float("alpha", 1.0)? != 1.0 {
            self.b
                .note(file, line, format!("{}: alpha (cut-out) ignored", sh.what));
        }
        match kind {
            "sphere" => self.sphere_shape(&sh)?,
            "trianglemesh" | "loopsubdiv" => self.triangle_mesh(&sh, kind == "loopsubdiv")?,
            "plymesh" => self.ply_mesh(&sh)?,
            "bilinearmesh" => self.bilinear_mesh(&sh)?,
            "disk" => self.disk(&sh)?,
            "cylinder" | "curve" | "cone" | "paraboloid" | "hyperboloid" => {
                self.b.note(
                    file,
                    line,
                    format!("{} is not supported by raytree: left out", sh.what),
                );
                return Ok(());
            }
            _ => return Err(sh.fail("unknown shape")),
        }
        self.unused(file, &sh.t, &sh.what, p);
        Ok(())
    }

    /// `Shape "sphere"` (a partial one drawn whole).
    fn sphere_shape(&mut self, sh: &ShapeAt) -> Result<(), FormatError> {
        let (file, line, what) = (sh.file, sh.t.line, &sh.what);
        let c = ctx(file, what, sh.p, &self.textures);
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
        if let Some(n) = self
            .b
            .sphere(DVec3::ZERO, r, &sh.m, &sh.s)
            .map_err(|e| sh.fail(e))?
        {
            self.b.note(file, line, format!("{what}: {n}"));
        }
        Ok(())
    }

    /// `Shape "trianglemesh"`, or `"loopsubdiv"` (`subdiv`: its control mesh, unsubdivided).
    fn triangle_mesh(&mut self, sh: &ShapeAt, subdiv: bool) -> Result<(), FormatError> {
        let (file, line, what) = (sh.file, sh.t.line, &sh.what);
        let c = ctx(file, what, sh.p, &self.textures);
        let pos = c
            .points("P", &["point3", "point"])?
            .ok_or_else(|| sh.fail("needs \"point3 P\""))?;
        let idx = match c.indices("indices")? {
            Some(v) => v,
            None if pos.len() == 3 => vec![0, 1, 2],
            None => return Err(sh.fail("needs \"integer indices\"")),
        };
        if idx.len() % 3 != 0 {
            return Err(sh.fail(format!("{} indices, not a multiple of 3", idx.len())));
        }
        let n = c.points("N", &["normal", "normal3"])?;
        if subdiv {
            self.b.note(
                file,
                line,
                format!("{what}: its control mesh is used unsubdivided"),
            );
            let _ = c.int("levels", 3)?;
        }
        for extra in ["uv", "S", "faceIndices"] {
            if sh.p.get(extra).is_some() {
                self.b.note(
                    file,
                    line,
                    format!("{what}: \"{extra}\" not used by raytree"),
                );
            }
        }
        let tris: Vec<[u32; 3]> = idx.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        self.b
            .mesh(&pos, &tris, n.as_deref(), &sh.m, &sh.s)
            .map_err(|e| sh.fail(e))
    }

    /// `Shape "plymesh"`: the PLY file it names.
    fn ply_mesh(&mut self, sh: &ShapeAt) -> Result<(), FormatError> {
        let (file, line, what) = (sh.file, sh.t.line, &sh.what);
        let c = ctx(file, what, sh.p, &self.textures);
        let f = c
            .string("filename")?
            .ok_or_else(|| sh.fail("needs \"string filename\""))?;
        if sh.p.get("displacement").is_some() {
            self.b
                .note(file, line, format!("{what}: displacement ignored"));
        }
        let path = relative_to(file, &f);
        let bytes = self.read(file, &sh.t, &path, what)?;
        let mesh =
            ply::parse(&bytes, self.vertex_limit()).map_err(|e| sh.fail(format!("{f}: {e}")))?;
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
                &sh.m,
                &sh.s,
            )
            .map_err(|e| sh.fail(format!("{f}: {e}")))
    }

    /// `Shape "bilinearmesh"`: each patch a quad or a grid of triangles.
    fn bilinear_mesh(&mut self, sh: &ShapeAt) -> Result<(), FormatError> {
        let (file, line, what) = (sh.file, sh.t.line, &sh.what);
        let c = ctx(file, what, sh.p, &self.textures);
        let pos = c
            .points("P", &["point3", "point"])?
            .ok_or_else(|| sh.fail("needs \"point3 P\""))?;
        let idx = match c.indices("indices")? {
            Some(v) => v,
            None if pos.len() == 4 => vec![0, 1, 2, 3],
            None => return Err(sh.fail("needs \"integer indices\"")),
        };
        if idx.len() % 4 != 0 {
            return Err(sh.fail(format!("{} indices, not a multiple of 4", idx.len())));
        }
        if c.points("N", &["normal", "normal3"])?.is_some() {
            self.b
                .note(file, line, format!("{what}: \"N\" not used (flat patches)"));
        }
        if let Some(&bad) = idx.iter().find(|&&k| k as usize >= pos.len()) {
            return Err(sh.fail(format!(
                "vertex index {bad} out of range ({} vertices)",
                pos.len()
            )));
        }
        for q in idx.chunks(4) {
            self.patch(
                [q[0], q[1], q[2], q[3]].map(|k| pos[k as usize]),
                &sh.m,
                &sh.s,
                file,
                line,
            )
            .map_err(|e| sh.fail(e))?;
        }
        Ok(())
    }

    /// `Shape "disk"`, tessellated (a whole disk).
    fn disk(&mut self, sh: &ShapeAt) -> Result<(), FormatError> {
        let (file, line, what) = (sh.file, sh.t.line, &sh.what);
        let c = ctx(file, what, sh.p, &self.textures);
        let h = c.float("height", 0.0)?;
        let r = c.float("radius", 1.0)?;
        let ri = c.float("innerradius", 0.0)?;
        if c.float("phimax", 360.0)? != 360.0 {
            self.b
                .note(file, line, format!("{what}: phimax ignored (a whole disk)"));
        }
        if !(r > 0.0 && ri >= 0.0 && ri < r) {
            return Err(sh.fail("needs radius > innerradius >= 0"));
        }
        let (pos, tris) = disk_triangles(r, ri, h);
        self.b.note(
            file,
            line,
            format!("{what}: tessellated into {} triangles", tris.len()),
        );
        self.b
            .mesh(&pos, &tris, None, &sh.m, &sh.s)
            .map_err(|e| sh.fail(e))
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
