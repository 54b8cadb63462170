//! How a scene's ray tree grows with `max_depth` (issue 18), and what the bounded-error cut
//! saves on a small sample of pixels.
//!
//! **The model.** A Whitted tree (the lecture's `trace`) spawns at each hit a reflected ray
//! (reflectivity > 0, or Fresnel/TIR reflection at a transmissive surface) and a refracted ray
//! (transmissive, unless TIR). Only hits on *specular* objects (reflective or transmissive)
//! have children, so the tree's shape follows the walks between specular objects. A *state* is
//! "a ray arrives at object `j` from its outside (or from its inside)"; each child of that hit
//! (reflected: stays on the side it came from; refracted: crosses to the other side) leaves
//! into a *region* and can arrive at the states of that region: inside a closed object
//! (sphere, box, plane as a half-space) its own inside and the objects nested in it; outside,
//! the objects that share its region ("siblings"). A convex object cannot be hit again from
//! its outside by a ray that leaves it outward; a mesh may be (it is treated as non-convex and
//! one-sided-less).
//!
//! A hit *branches* when both children are spawned at once: a transmissive material with a
//! Fresnel model (reflection and refraction at every hit except TIR) or with reflectivity too.
//! With `fresnel: none` and no reflectivity a transmissive hit has one child (refracted, or
//! reflected under TIR). Then, on the graph of states:
//!
//! - **exponential**: some state branches and *both* its children can come back to it (they
//!   lead into its strongly connected component): the number of rays can double every few
//!   bounces, `2^depth` up to constants;
//! - **polynomial** of degree `d`: cycles exist but no such state; a path passes through at
//!   most `d` cyclic components, each a chain along which one child at most stays (degree 1:
//!   facing mirrors, internal reflection in one convex glass: rays per camera ray grow
//!   linearly with `max_depth`);
//! - **bounded**: no cycle (or no recursion): the tree's size does not depend on `max_depth`
//!   beyond the longest acyclic walk.
//!
//! The test is conservative, in the direction of warning: it ignores occlusion and facing
//! (two siblings "can see each other" whenever they share a region), intersecting objects
//! that are not nested are treated as siblings, and whether a branch carries any weight is
//! left to the measured figures ([`cut_savings`]). It is geometric possibility, not a count.

use crate::effects::EffectPlan;
use crate::geometry::Shape;
use crate::math::FresnelModel;
use crate::scene::{Material, Scene, Settings};
use crate::trace::bound::effective_min_weight;
use crate::trace::{NoopRecorder, RayCounts};
use glam::DVec3;

/// How the number of rays per camera ray grows with `max_depth`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Growth {
    /// Independent of `max_depth` beyond a fixed number of bounces.
    Bounded,
    /// As `max_depth^degree` (degree 1: linear).
    Polynomial(u32),
    /// As `2^max_depth` up to constants.
    Exponential,
}

/// The growth verdict with the reasons, one per line.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TreeGrowth {
    /// The verdict.
    pub growth: Growth,
    /// Why: the objects and relations that make it so (empty when bounded by having no
    /// specular object).
    pub reasons: Vec<String>,
}

impl Growth {
    /// One word: "bounded", "linear", "polynomial (degree d)", "exponential".
    #[must_use]
    pub fn word(&self) -> String {
        match self {
            Growth::Bounded => "bounded".to_string(),
            Growth::Polynomial(1) => "linear".to_string(),
            Growth::Polynomial(d) => format!("polynomial (degree {d})"),
            Growth::Exponential => "exponential".to_string(),
        }
    }
}

impl TreeGrowth {
    /// A one-line summary, e.g. "exponential: the tree can grow as 2^depth".
    #[must_use]
    pub fn summary(&self) -> String {
        match self.growth {
            Growth::Bounded => "bounded: the ray tree does not grow with max depth".to_string(),
            Growth::Polynomial(1) => {
                "linear: rays per camera ray can grow linearly with max depth (no split ray can \
                 come back)"
                    .to_string()
            }
            Growth::Polynomial(d) => format!(
                "polynomial: rays per camera ray can grow as max_depth^{d} (chains of cycles, \
                 no split ray can come back)"
            ),
            Growth::Exponential => {
                "exponential: the ray tree can grow as 2^depth (both rays of a split can come \
                 back to split again)"
                    .to_string()
            }
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Outside,
    Inside,
}

/// The closed solid an object bounds, if any (planes: the half-space behind the normal).
fn closed(shape: &Shape) -> bool {
    matches!(
        shape,
        Shape::Sphere { .. } | Shape::Box { .. } | Shape::Plane { .. }
    )
}

/// Whether `p` is strictly inside the solid of `shape`.
fn point_inside(shape: &Shape, p: DVec3) -> bool {
    match *shape {
        Shape::Sphere { center, radius } => (p - center).length() < radius,
        Shape::Box { min, max } => p.cmpgt(min).all() && p.cmplt(max).all(),
        Shape::Plane { point, normal } => (p - point).dot(normal) < 0.0,
        Shape::Triangle { .. } | Shape::Quad { .. } | Shape::Mesh(_) => false,
    }
}

/// Whether object `b`'s bounds lie strictly inside object `a`'s solid.
fn contains(a: &Shape, b: &Shape) -> bool {
    if !closed(a) {
        return false;
    }
    let Some((lo, hi)) = b.bounds() else {
        return false;
    };
    (0..8).all(|i| {
        let c = DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        point_inside(a, c)
    })
}

fn volume(shape: &Shape) -> f64 {
    shape.bounds().map_or(f64::INFINITY, |(lo, hi)| {
        let d = hi - lo;
        d.x * d.y * d.z
    })
}

/// Whether a hit on `m` spawns two rays at once: transmissive with a Fresnel model (reflection
/// and refraction except under TIR) or with reflectivity. A rough material (`trace::glossy`)
/// draws one ray per rough lobe below a path's first rough hit (which fans out
/// `glossy_samples` rays once, a constant factor), so it branches only with both lobes.
fn branches(scene: &Scene, m: &Material) -> bool {
    if m.is_rough() {
        return m.is_transmissive() && m.reflectivity.max_element() > 0.0;
    }
    m.is_transmissive()
        && (scene.settings.fresnel != FresnelModel::None || m.reflectivity.max_element() > 0.0)
}

/// Region a ray is in: the world (`None`) or inside object `k`.
type Region = Option<usize>;

struct Graph<'a> {
    scene: &'a Scene,
    /// Specular objects (indices into `scene.objects`).
    specular: Vec<usize>,
    /// Innermost container of each object.
    parent: Vec<Region>,
    /// States: (object, side).
    states: Vec<(usize, Side)>,
    /// Per state, its children: each a list of successor states. One entry for a hit with one
    /// child (or alternatives), two for a branching hit.
    children: Vec<Vec<Vec<usize>>>,
    branching: Vec<bool>,
}

impl<'a> Graph<'a> {
    fn new(scene: &'a Scene) -> Self {
        let objs = &scene.objects;
        let mat = |j: usize| scene.material_of(j);
        let specular: Vec<usize> = (0..objs.len())
            .filter(|&j| mat(j).is_transmissive() || mat(j).reflectivity.max_element() > 0.0)
            .collect();
        // Only specular objects' regions matter (non-specular ones have no state).
        let parent: Vec<Region> = (0..objs.len())
            .map(|j| {
                if !specular.contains(&j) {
                    return None;
                }
                (0..objs.len())
                    .filter(|&k| k != j && contains(&objs[k].shape, &objs[j].shape))
                    .min_by(|&a, &b| volume(&objs[a].shape).total_cmp(&volume(&objs[b].shape)))
            })
            .collect();
        let mut states = Vec::new();
        for &j in &specular {
            states.push((j, Side::Outside));
            if closed(&objs[j].shape) && mat(j).is_transmissive() {
                states.push((j, Side::Inside));
            }
        }
        let mut g = Self {
            scene,
            specular,
            parent,
            states,
            children: Vec::new(),
            branching: Vec::new(),
        };
        for i in 0..g.states.len() {
            let (j, side) = g.states[i];
            let m = mat(j);
            let other = match side {
                Side::Outside => Side::Inside,
                Side::Inside => Side::Outside,
            };
            let reflected = g.arrivals(j, side);
            let (kids, branch) = if m.is_transmissive() {
                let refracted = g.arrivals(j, other);
                if branches(scene, m) {
                    (vec![reflected, refracted], true)
                } else {
                    // One child per hit: refracted, or reflected under TIR.
                    let mut both = reflected;
                    both.extend(refracted);
                    both.sort_unstable();
                    both.dedup();
                    (vec![both], false)
                }
            } else {
                (vec![reflected], false)
            };
            g.children.push(kids);
            g.branching.push(branch);
        }
        g
    }

    fn state(&self, j: usize, side: Side) -> Option<usize> {
        self.states.iter().position(|&s| s == (j, side))
    }

    /// States a ray leaving object `j` into its `side` can arrive at.
    fn arrivals(&self, j: usize, side: Side) -> Vec<usize> {
        let objs = &self.scene.objects;
        let region: Region = match side {
            Side::Inside if closed(&objs[j].shape) => Some(j),
            // Open shapes have no inside: both sides are the object's own region.
            _ => self.parent[j],
        };
        let mut out = Vec::new();
        if let Some(k) = region
            && let Some(s) = self.state(k, Side::Inside)
        {
            out.push(s);
        }
        for &m in &self.specular {
            if self.parent[m] != region {
                continue;
            }
            // A convex object is not hit again from outside by a ray that leaves it outward.
            if m == j && !matches!(objs[j].shape, Shape::Mesh(_)) {
                continue;
            }
            if let Some(s) = self.state(m, Side::Outside) {
                out.push(s);
            }
        }
        out
    }

    /// Strongly connected components (Tarjan), as a component id per state.
    fn components(&self) -> Vec<usize> {
        struct Tarjan<'g> {
            succ: &'g [Vec<Vec<usize>>],
            index: Vec<usize>,
            low: Vec<usize>,
            on: Vec<bool>,
            stack: Vec<usize>,
            comp: Vec<usize>,
            next: usize,
            ncomp: usize,
        }
        impl Tarjan<'_> {
            fn visit(&mut self, v: usize) {
                self.index[v] = self.next;
                self.low[v] = self.next;
                self.next += 1;
                self.stack.push(v);
                self.on[v] = true;
                let succ = self.succ;
                for &w in succ[v].iter().flatten() {
                    if self.index[w] == usize::MAX {
                        self.visit(w);
                        self.low[v] = self.low[v].min(self.low[w]);
                    } else if self.on[w] {
                        self.low[v] = self.low[v].min(self.index[w]);
                    }
                }
                if self.low[v] == self.index[v] {
                    while let Some(w) = self.stack.pop() {
                        self.on[w] = false;
                        self.comp[w] = self.ncomp;
                        if w == v {
                            break;
                        }
                    }
                    self.ncomp += 1;
                }
            }
        }
        let n = self.states.len();
        let mut t = Tarjan {
            succ: &self.children,
            index: vec![usize::MAX; n],
            low: vec![0; n],
            on: vec![false; n],
            stack: Vec::new(),
            comp: vec![usize::MAX; n],
            next: 0,
            ncomp: 0,
        };
        for v in 0..n {
            if t.index[v] == usize::MAX {
                t.visit(v);
            }
        }
        t.comp
    }

    fn describe(&self, state: usize) -> String {
        let (j, side) = self.states[state];
        let name = &self.scene.objects[j].name;
        match side {
            Side::Outside => name.clone(),
            Side::Inside => format!("{name} (inside)"),
        }
    }
}

/// Scenes with more specular objects than this are not analysed pair by pair (the graph has
/// up to `2n` states and `n^2` edges); the verdict is then "exponential", conservatively.
pub const MAX_ANALYSED: usize = 256;

/// How the ray tree of `scene` (with its settings) can grow with `max_depth`, and why.
#[must_use]
pub fn tree_growth(scene: &Scene) -> TreeGrowth {
    let plan = EffectPlan::for_scene(scene);
    if !plan.recursion {
        return TreeGrowth {
            growth: Growth::Bounded,
            reasons: vec![if scene.settings.max_depth == 0 {
                "no recursion: max_depth 0".to_string()
            } else {
                "no recursion: nothing reflects or refracts".to_string()
            }],
        };
    }
    let specular = scene
        .objects
        .iter()
        .map(|o| &scene.materials[o.material])
        .filter(|m| m.is_transmissive() || m.reflectivity.max_element() > 0.0)
        .count();
    if specular > MAX_ANALYSED {
        // Without a split every hit has one child: the tree is a chain of at most max_depth.
        let splits = scene.used_materials().any(|m| branches(scene, m));
        return TreeGrowth {
            growth: if splits {
                Growth::Exponential
            } else {
                Growth::Polynomial(1)
            },
            reasons: vec![format!(
                "{specular} reflective or transmissive objects: more than {MAX_ANALYSED}, not \
                 analysed pair by pair ({})",
                if splits {
                    "some hit splits in two: assumed exponential"
                } else {
                    "no hit splits in two: each tree is a chain, at most linear"
                }
            )],
        };
    }
    let g = Graph::new(scene);
    let comp = g.components();
    let n = g.states.len();
    let in_comp = |v: usize, c: usize| comp[v] == c;
    // A component is cyclic when some edge stays inside it (a self-loop included).
    let cyclic = |c: usize| {
        (0..n).any(|v| in_comp(v, c) && g.children[v].iter().flatten().any(|&w| in_comp(w, c)))
    };
    let mut reasons = Vec::new();
    // Exponential: a branching state both of whose children can come back.
    for v in (0..n).filter(|&v| g.branching[v]) {
        let back: Vec<Vec<usize>> = g.children[v]
            .iter()
            .map(|kids| {
                kids.iter()
                    .copied()
                    .filter(|&w| in_comp(w, comp[v]))
                    .collect()
            })
            .collect();
        let (j, _) = g.states[v];
        let named = reasons
            .iter()
            .any(|r: &String| r.starts_with(&format!("a ray at {}", g.scene.objects[j].name)));
        if back.iter().all(|b| !b.is_empty()) && !named {
            let via = |b: &[usize]| {
                b.iter()
                    .map(|&w| g.describe(w))
                    .collect::<Vec<_>>()
                    .join(" or ")
            };
            reasons.push(format!(
                "a ray at {} splits in two, and both can come back: the reflected ray via {}, the \
                 refracted ray via {}",
                g.describe(v),
                via(&back[0]),
                via(&back[1])
            ));
        }
    }
    reasons.extend(relations(&g, &comp, &cyclic));
    if reasons.iter().any(|r| r.starts_with("a ray at")) {
        return TreeGrowth {
            growth: Growth::Exponential,
            reasons,
        };
    }
    // Polynomial degree: along the condensation, a cyclic component multiplies what follows
    // it when it is left by one child of a split whose other child can stay (a new subtree at
    // every turn of the cycle); otherwise sizes add.
    let ncomp = comp.iter().copied().max().map_or(0, |m| m + 1);
    let mut memo: Vec<Option<u32>> = vec![None; ncomp];
    fn degree_of(
        c: usize,
        g: &Graph,
        comp: &[usize],
        cyclic: &dyn Fn(usize) -> bool,
        memo: &mut Vec<Option<u32>>,
    ) -> u32 {
        if let Some(d) = memo[c] {
            return d;
        }
        let here = cyclic(c);
        let mut best = u32::from(here);
        for v in (0..comp.len()).filter(|&v| comp[v] == c) {
            for (i, kid) in g.children[v].iter().enumerate() {
                let sibling_stays = g.branching[v]
                    && g.children[v]
                        .iter()
                        .enumerate()
                        .any(|(k, other)| k != i && other.iter().any(|&w| comp[w] == c));
                for &w in kid.iter().filter(|&&w| comp[w] != c) {
                    let after = degree_of(comp[w], g, comp, cyclic, memo);
                    best = best.max(after + u32::from(here && sibling_stays));
                }
            }
        }
        memo[c] = Some(best);
        best
    }
    let degree = (0..ncomp)
        .map(|c| degree_of(c, &g, &comp, &cyclic, &mut memo))
        .max()
        .unwrap_or(0);
    TreeGrowth {
        growth: if degree == 0 {
            Growth::Bounded
        } else {
            Growth::Polynomial(degree)
        },
        reasons,
    }
}

/// The relations behind each cyclic component: nesting, mutual visibility, internal reflection.
fn relations(g: &Graph, comp: &[usize], cyclic: &dyn Fn(usize) -> bool) -> Vec<String> {
    let objs = &g.scene.objects;
    let mat = |j: usize| g.scene.material_of(j);
    let kind = |j: usize| {
        if mat(j).is_transmissive() {
            "dielectric"
        } else {
            "mirror"
        }
    };
    let mut out = Vec::new();
    let n = g.states.len();
    for v in 0..n {
        if !cyclic(comp[v]) {
            continue;
        }
        let (j, side) = g.states[v];
        for &w in g.children[v].iter().flatten() {
            if comp[w] != comp[v] {
                continue;
            }
            let (k, wside) = g.states[w];
            if j == k && side != wside {
                continue; // entering or leaving the object: not a relation
            }
            let line = if j == k && side == Side::Inside && wside == Side::Inside {
                format!(
                    "{} ({}): internal reflection keeps rays inside it",
                    objs[j].name,
                    kind(j)
                )
            } else if j == k {
                format!("{} ({}, non-convex) can see itself", objs[j].name, kind(j))
            } else if g.parent[j] == Some(k) || g.parent[k] == Some(j) {
                let (inner, outer) = if g.parent[j] == Some(k) {
                    (j, k)
                } else {
                    (k, j)
                };
                format!(
                    "nested: {} ({}) is inside {} ({})",
                    objs[inner].name,
                    kind(inner),
                    objs[outer].name,
                    kind(outer)
                )
            } else if kind(j) == "mirror" && kind(k) == "mirror" {
                let (a, b) = (j.min(k), j.max(k));
                format!(
                    "facing mirrors: {} and {} can see each other",
                    objs[a].name, objs[b].name
                )
            } else {
                let (a, b) = (j.min(k), j.max(k));
                format!(
                    "{} ({}) and {} ({}) can see each other",
                    objs[a].name,
                    kind(a),
                    objs[b].name,
                    kind(b)
                )
            };
            if !out.contains(&line) {
                out.push(line);
            }
        }
    }
    out
}

/// Rays of the default (automatic `min_weight`) tree against the exhaustive one on a grid of
/// pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutSavings {
    /// Grid columns and rows (pixel centres of equal cells, one sample each).
    pub grid: [u32; 2],
    /// The automatic cut used.
    pub min_weight: f64,
    /// Rays of every kind with the cut.
    pub cut_rays: u64,
    /// Rays of every kind with `min_weight` 0 (bounded per sample by `settings.max_rays`).
    pub exhaustive_rays: u64,
    /// Samples of the exhaustive run that reached `max_rays` (then `exhaustive_rays` is a
    /// lower bound).
    pub budget_samples: u64,
}

impl CutSavings {
    /// `exhaustive_rays / cut_rays`.
    #[must_use]
    pub fn ratio(&self) -> f64 {
        self.exhaustive_rays as f64 / self.cut_rays.max(1) as f64
    }

    /// "the automatic cut traces N rays where the exhaustive tree would trace M (x fewer) on a
    /// 16x9 sample".
    #[must_use]
    pub fn sentence(&self) -> String {
        let at_least = if self.budget_samples > 0 {
            "at least "
        } else {
            ""
        };
        let budget = if self.budget_samples > 0 {
            format!(
                "; {} samples reached the ray budget max_rays",
                self.budget_samples
            )
        } else {
            String::new()
        };
        let ratio = self.ratio();
        let fewer = if ratio < 1.05 && self.budget_samples == 0 {
            "no saving".to_string()
        } else {
            format!("{at_least}{ratio:.1}x fewer")
        };
        format!(
            "the automatic cut (min_weight {:.2e}) traces {} rays where the exhaustive tree \
             would trace {at_least}{} ({fewer}) on a {}x{} sample of pixel centres{budget}",
            self.min_weight, self.cut_rays, self.exhaustive_rays, self.grid[0], self.grid[1]
        )
    }
}

/// The pixels of a `cols x rows` grid over a `w x h` image: the centre pixel of each cell.
#[must_use]
pub fn grid_pixels(w: u32, h: u32, cols: u32, rows: u32) -> Vec<(u32, u32)> {
    let cell = |i: u32, n: u32, len: u32| {
        ((2 * u64::from(i) + 1) * u64::from(len) / (2 * u64::from(n))).min(u64::from(len) - 1)
            as u32
    };
    if w == 0 || h == 0 {
        return Vec::new();
    }
    (0..rows)
        .flat_map(|r| (0..cols).map(move |c| (cell(c, cols, w), cell(r, rows, h))))
        .collect()
}

/// Trace the grid's pixels (one sample at each centre) with the scene's automatic cut and with
/// the exhaustive tree, and count the rays. `min_weight` set in the scene is ignored: the
/// question is what the default saves. `cancelled` is polled between pixels; `None` if it said
/// so.
#[must_use]
pub fn cut_savings(
    scene: &Scene,
    cols: u32,
    rows: u32,
    cancelled: &dyn Fn() -> bool,
) -> Option<CutSavings> {
    let with = |min_weight| Scene {
        settings: Settings {
            min_weight,
            spp: 1,
            ..scene.settings
        },
        ..scene.clone()
    };
    let (cut, full) = (with(None), with(Some(0.0)));
    let pixels = grid_pixels(scene.camera.width, scene.camera.height, cols, rows);
    let count = |s: &Scene| {
        let tracer = crate::trace::Tracer::new(s);
        let mut counts = RayCounts::default();
        for &(x, y) in &pixels {
            if cancelled() {
                return None;
            }
            crate::render::render_pixel_with(&tracer, x, y, &mut NoopRecorder, &mut counts, |_| {});
        }
        Some(counts)
    };
    let a = count(&cut)?;
    let b = count(&full)?;
    Some(CutSavings {
        grid: [cols, rows],
        min_weight: effective_min_weight(&cut),
        cut_rays: a.total(),
        exhaustive_rays: b.total(),
        budget_samples: b.budget_samples,
    })
}

#[cfg(test)]
mod tests;
