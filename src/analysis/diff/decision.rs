//! What a diff between stochastic settings needs (issue 32, item 16): the first *decision*
//! that differs (the sampled lobe, a Russian-roulette outcome, the dielectric split, which
//! rays a hit spawned) rather than the first number, since a changed value anywhere below
//! changes every radiance above it up to the camera ray; and the pixel difference with its
//! standard error, since two Monte Carlo estimates differ by noise alone.

use super::matched_children;
use crate::math::Rgb;
use crate::tree::{NodeId, RayKind, RayNode, RayTree};
use serde::Serialize;
use std::collections::VecDeque;

/// A sampling decision that differs between two matched rays.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DecisionChange {
    /// The sample (its index, as `raytree trace` numbers them).
    pub sample: u32,
    /// The ray in tree A.
    pub a: NodeId,
    /// The ray in tree B.
    pub b: NodeId,
    /// Their kind.
    pub kind: RayKind,
    /// Their depth.
    pub depth: u32,
    /// Which decision: `sampled lobe`, `path roulette`, `dielectric roulette`, `rays spawned`,
    /// `strategies` (the connections' `(s, t)` under light tracing and BDPT).
    pub decision: String,
    /// The decision in A, in words.
    pub in_a: String,
    /// The decision in B, in words.
    pub in_b: String,
}

/// The decisions recorded on ray `n`, each as (name, outcome to compare, outcome in words).
fn decisions(t: &RayTree, n: &RayNode) -> Vec<(&'static str, String, String)> {
    let mut out = Vec::new();
    let path = n.path.as_ref();
    if let Some(l) = path.and_then(|p| p.lobe) {
        out.push(("sampled lobe", l.name().to_string(), l.name().to_string()));
    } else if n.kind != RayKind::Shadow && n.kind != RayKind::Camera && path.is_some() {
        out.push(("sampled lobe", "none".into(), "none".into()));
    }
    let rr = match path.and_then(|p| p.roulette) {
        None => ("none".to_string(), "no roulette at this hit".to_string()),
        Some(r) if r.survived => (
            "survived".into(),
            format!("survived the roulette (probability {:.4})", r.probability),
        ),
        Some(r) => (
            "ended".into(),
            format!(
                "the roulette ended the path (survival probability {:.4})",
                r.probability
            ),
        ),
    };
    out.push(("path roulette", rr.0, rr.1));
    let split = match n.interface.as_ref().and_then(|i| i.roulette) {
        None => (
            "none".to_string(),
            "both rays traced (no split roulette)".to_string(),
        ),
        Some(s) => (
            s.ray().to_string(),
            format!(
                "followed the {} ray (probability {:.4})",
                s.ray(),
                s.probability
            ),
        ),
    };
    out.push(("dielectric roulette", split.0, split.1));
    let kids: Vec<&str> = n.children.iter().map(|c| t.node(*c).kind.name()).collect();
    let spawned = if kids.is_empty() {
        format!("no rays ({})", crate::text::end_text(n.end))
    } else {
        kids.join(", ")
    };
    out.push(("rays spawned", kids.join(","), spawned));
    // Light tracing and BDPT: the strategies (s, t) its connections made.
    let made: Vec<String> = n
        .children
        .iter()
        .filter_map(|c| t.node(*c).path.as_ref()?.strategy)
        .map(|[s, t]| format!("s={s} t={t}"))
        .collect();
    let words = if made.is_empty() {
        "no connection".to_string()
    } else {
        format!("connected by {}", made.join(", "))
    };
    out.push(("strategies", made.join(","), words));
    out
}

/// The first decision of `(na, nb)` that differs, if any.
fn first_changed(
    a: &RayTree,
    na: &RayNode,
    b: &RayTree,
    nb: &RayNode,
) -> Option<(String, String, String)> {
    let (da, db) = (decisions(a, na), decisions(b, nb));
    for (x, y) in da.iter().zip(&db) {
        if x.1 != y.1 {
            return Some((x.0.to_string(), x.2.clone(), y.2.clone()));
        }
    }
    None
}

/// For every sample both trees have (matched by position), the shallowest matched pair of
/// rays (breadth-first, then child order) whose decisions differ; samples in order.
#[must_use]
pub fn decision_changes(a: &RayTree, b: &RayTree) -> Vec<DecisionChange> {
    let mut out = Vec::new();
    for (sa, sb) in a.samples.iter().zip(&b.samples) {
        let mut queue = VecDeque::from([(sa.root, sb.root)]);
        while let Some((ia, ib)) = queue.pop_front() {
            let (na, nb) = (a.node(ia), b.node(ib));
            if let Some((decision, in_a, in_b)) = first_changed(a, na, b, nb) {
                out.push(DecisionChange {
                    sample: sa.index,
                    a: ia,
                    b: ib,
                    kind: na.kind,
                    depth: na.depth,
                    decision,
                    in_a,
                    in_b,
                });
                break;
            }
            queue.extend(
                matched_children(a, na, b, nb)
                    .into_iter()
                    .filter_map(|(x, y)| Some((x?, y?))),
            );
        }
    }
    out
}

/// The pixel difference `b - a` of two trees' sample means, with its standard error.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PixelDifference {
    /// Mean of B's samples minus mean of A's (the pixel values under a box filter).
    pub mean: Rgb,
    /// Standard error of `mean` per channel; `None` with fewer than 2 samples a side.
    pub std_error: Option<Rgb>,
    /// Whether the samples were paired by index (same count: the standard deviation of the
    /// per-sample differences over sqrt(n)); otherwise `sqrt(s_a^2/n_a + s_b^2/n_b)`.
    pub paired: bool,
    /// Samples in A and in B.
    pub samples: [usize; 2],
    /// Light tracing and BDPT: the light paths that splatted into the pixel in A and in B.
    /// Their part (the splats' sum over `splat_divisor`) is in `mean`, and its variance in
    /// `std_error` as that of independent light paths, each adding its splats here or nothing
    /// (`splat_part`); they are not paired.
    pub splat_paths: [usize; 2],
}

/// The splats' part of `t`'s pixel and its variance: with `N` light paths in the pass, path
/// `k` adds `c_k / d` (its splats here, over the divisor `d`), 0 for nearly all; the sum's
/// variance is `sum_k Var(c_k) / d^2`, about `sum_k c_k^2 / d^2` (the paths that missed add
/// 0, and the squared mean per path is negligible against its second moment). Also the number
/// of paths that landed.
fn splat_part(t: &RayTree) -> (Rgb, Rgb, usize) {
    let d = f64::from(t.splat_divisor.max(1));
    let mut per_path: Vec<(u64, Rgb)> = Vec::new();
    for s in &t.splats {
        match per_path.iter_mut().find(|p| p.0 == s.path) {
            Some(p) => p.1 += s.contribution,
            None => per_path.push((s.path, s.contribution)),
        }
    }
    let sum = per_path.iter().fold(Rgb::ZERO, |acc, p| acc + p.1 / d);
    let var = per_path.iter().fold(Rgb::ZERO, |acc, p| {
        let c = p.1 / d;
        acc + c * c
    });
    (sum, var, per_path.len())
}

/// Mean and unbiased variance of `x`, each sum scaled as it is added (so finite samples near
/// the largest double keep a finite mean).
fn mean_var(x: &[Rgb]) -> (Rgb, Option<Rgb>) {
    let n = x.len() as f64;
    let mean = x.iter().fold(Rgb::ZERO, |s, v| s + *v / n);
    if x.len() < 2 {
        return (mean, None);
    }
    let k = (n - 1.0).sqrt();
    let var = x.iter().fold(Rgb::ZERO, |s, v| {
        let d = (*v - mean) / k;
        s + d * d
    });
    (mean, Some(var))
}

/// `b - a` over the samples of both trees, and the light paths that splatted into them, with
/// its standard error (see [`PixelDifference`]).
#[must_use]
pub fn pixel_difference(a: &RayTree, b: &RayTree) -> PixelDifference {
    let ra: Vec<Rgb> = a.samples.iter().map(|s| s.radiance).collect();
    let rb: Vec<Rgb> = b.samples.iter().map(|s| s.radiance).collect();
    let samples = [ra.len(), rb.len()];
    let ((sa, va_splat, na), (sb, vb_splat, nb)) = (splat_part(a), splat_part(b));
    let splat_paths = [na, nb];
    // The camera samples' variance of the mean (paired or not), then the splats'.
    let (camera, var, paired) = if ra.len() == rb.len() && !ra.is_empty() {
        let d: Vec<Rgb> = rb.iter().zip(&ra).map(|(y, x)| *y - *x).collect();
        let (mean, var) = mean_var(&d);
        (mean, var.map(|v| v / d.len() as f64), true)
    } else {
        let ((ma, va), (mb, vb)) = (mean_var(&ra), mean_var(&rb));
        let var = match (va, vb) {
            (Some(va), Some(vb)) => Some(va / ra.len() as f64 + vb / rb.len() as f64),
            _ => None,
        };
        (mb - ma, var, false)
    };
    PixelDifference {
        mean: camera + (sb - sa),
        std_error: var.map(|v| (v + va_splat + vb_splat).map(f64::sqrt)),
        paired,
        samples,
        splat_paths,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;
    use crate::scene::IntegratorKind;
    use crate::trace_pixel;

    fn path_scene(rr_depth: u32) -> Scene {
        let mut s = Scene::default_scene();
        s.settings.integrator = IntegratorKind::Path;
        s.settings.spp = 16;
        s.settings.path.rr_depth = rr_depth;
        s
    }

    #[test]
    fn a_roulette_depth_first_differs_at_a_roulette_decision() {
        let a = trace_pixel(&path_scene(1), 300, 300).unwrap();
        let b = trace_pixel(&path_scene(8), 300, 300).unwrap();
        let d = decision_changes(&a, &b);
        assert!(!d.is_empty(), "some sample's decisions differ");
        let first = &d[0];
        assert_eq!(first.decision, "path roulette", "{first:?}");
        // Roulette from the first bounce on: played at the camera ray's hit in a, not in b.
        assert_eq!((first.kind, first.depth), (RayKind::Camera, 0), "{first:?}");
        assert!(first.in_b.contains("no roulette"), "{first:?}");
        // The same settings: no decision differs.
        assert!(decision_changes(&a, &a.clone()).is_empty());
    }

    #[test]
    fn the_pixel_difference_has_a_paired_standard_error() {
        let a = trace_pixel(&path_scene(1), 300, 300).unwrap();
        let b = trace_pixel(&path_scene(8), 300, 300).unwrap();
        let p = pixel_difference(&a, &b);
        assert!(p.paired && p.samples == [16, 16]);
        let se = p.std_error.unwrap();
        assert!(se.is_finite() && se.min_element() >= 0.0);
        // By hand: the per-sample differences' spread over sqrt(16).
        let d: Vec<f64> = a
            .samples
            .iter()
            .zip(&b.samples)
            .map(|(x, y)| y.radiance.x - x.radiance.x)
            .collect();
        let m = d.iter().sum::<f64>() / 16.0;
        let v = d.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 15.0;
        assert!((p.mean.x - m).abs() < 1e-12);
        assert!((se.x - (v / 16.0).sqrt()).abs() < 1e-12);
        // A tree against itself: no difference and no spread.
        let z = pixel_difference(&a, &a);
        assert_eq!((z.mean, z.std_error), (Rgb::ZERO, Some(Rgb::ZERO)));
        // Finite samples near the largest double: a finite mean and error.
        let mut big = a.clone();
        for s in &mut big.samples {
            s.radiance = Rgb::splat(1.19e308);
        }
        big.samples[0].radiance = Rgb::splat(-1.19e308);
        let o = pixel_difference(&a, &big);
        assert!(o.mean.is_finite(), "{:?}", o.mean);
    }

    /// Under light tracing the pixel is the sample mean plus the splats over the divisor: the
    /// difference is that of the pixels, and the splats' spread widens its error.
    #[test]
    fn the_pixel_difference_counts_the_splats() {
        let mut s = Scene::from_json(include_str!("../../../fixtures/caustic.json")).unwrap();
        s.camera = s.camera.with_size(48, 36);
        s.settings.integrator = IntegratorKind::Light;
        s.settings.spp = 4;
        let a = trace_pixel(&s, 20, 26).unwrap();
        s.settings.seed = 7;
        let b = trace_pixel(&s, 20, 26).unwrap();
        assert!(!a.splats.is_empty() && !b.splats.is_empty());
        let p = pixel_difference(&a, &b);
        let want = b.radiance - a.radiance;
        assert!(
            (p.mean - want).abs().max_element() < 1e-12,
            "{} {want}",
            p.mean
        );
        assert!(p.splat_paths[0] > 0 && p.splat_paths[1] > 0, "{p:?}");
        let (_, var, n) = splat_part(&a);
        assert_eq!(n, p.splat_paths[0]);
        assert!(var.max_element() > 0.0);
        let camera_only = {
            let (mut x, mut y) = (a.clone(), b.clone());
            x.splats.clear();
            y.splats.clear();
            pixel_difference(&x, &y).std_error.unwrap()
        };
        assert!(p.std_error.unwrap().min_element() >= camera_only.min_element());
        assert!((p.std_error.unwrap() - camera_only).max_element() > 0.0);
    }
}
