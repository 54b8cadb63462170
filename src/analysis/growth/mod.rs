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
use crate::scene::Scene;

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

/// What the rays of a scene rendered by the path integrator do instead of a tree, or `None`
/// under the Whitted integrator. The growth verdict ([`tree_growth`]) and the cut
/// ([`cut_savings`]) describe the Whitted integrator's tree: a path-traced sample never splits.
#[must_use]
pub fn path_note(scene: &Scene) -> Option<String> {
    (scene.settings.integrator == crate::scene::IntegratorKind::Path).then(|| {
        format!(
            "path integrator: each sample is one path, a continuation ray and a light sample \
             at each bounce, so its rays grow at most linearly with max depth (Russian \
             roulette from bounce {}); no split, no cut. The tree below is that of \
             --integrator whitted",
            scene.settings.path.rr_depth
        )
    })
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
        return not_analysed(scene, specular);
    }
    let g = Graph::new(scene);
    let comp = g.components();
    let n = g.states.len();
    // A component is cyclic when some edge stays inside it (a self-loop included).
    let cyclic = |c: usize| {
        (0..n).any(|v| comp[v] == c && g.children[v].iter().flatten().any(|&w| comp[w] == c))
    };
    let mut reasons = split_reasons(&g, &comp);
    reasons.extend(relations(&g, &comp, &cyclic));
    if reasons.iter().any(|r| r.starts_with("a ray at")) {
        return TreeGrowth {
            growth: Growth::Exponential,
            reasons,
        };
    }
    let degree = polynomial_degree(&g, &comp, &cyclic);
    TreeGrowth {
        growth: if degree == 0 {
            Growth::Bounded
        } else {
            Growth::Polynomial(degree)
        },
        reasons,
    }
}

/// The verdict for a scene with `specular` (more than [`MAX_ANALYSED`]) reflective or
/// transmissive objects: exponential if some hit splits, else linear.
fn not_analysed(scene: &Scene, specular: usize) -> TreeGrowth {
    // Without a split every hit has one child: the tree is a chain of at most max_depth.
    let splits = scene.used_materials().any(|m| branches(scene, m));
    TreeGrowth {
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
    }
}

/// Exponential growth: a branching state both of whose children can come back (into its
/// component `comp`), one reason per object.
fn split_reasons(g: &Graph, comp: &[usize]) -> Vec<String> {
    let mut reasons = Vec::new();
    for v in (0..g.states.len()).filter(|&v| g.branching[v]) {
        let back: Vec<Vec<usize>> = g.children[v]
            .iter()
            .map(|kids| {
                kids.iter()
                    .copied()
                    .filter(|&w| comp[w] == comp[v])
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
    reasons
}

/// The polynomial degree: along the condensation, a cyclic component multiplies what follows
/// it when it is left by one child of a split whose other child can stay (a new subtree at
/// every turn of the cycle); otherwise sizes add.
fn polynomial_degree(g: &Graph, comp: &[usize], cyclic: &dyn Fn(usize) -> bool) -> u32 {
    let ncomp = comp.iter().copied().max().map_or(0, |m| m + 1);
    let mut memo: Vec<Option<u32>> = vec![None; ncomp];
    (0..ncomp)
        .map(|c| degree_of(c, g, comp, cyclic, &mut memo))
        .max()
        .unwrap_or(0)
}

/// The degree of component `c` and what follows it (memoised in `memo`).
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

mod graph;
mod savings;

use graph::{Graph, Side, branches};
pub use savings::{CutSavings, cut_savings, grid_pixels};

#[cfg(test)]
mod tests;
