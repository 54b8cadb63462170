//! Unit tests of the firefly explanation on hand-built trees.

use super::*;
use crate::analysis::hand_tree::{HandTree, grey_samples};
use crate::math::Rgb;

/// Nine dim samples (0.1) and one built by `last`.
fn with_one(last: impl FnOnce(&mut HandTree, NodeId)) -> RayTree {
    let mut h = HandTree::new();
    for _ in 0..9 {
        let r = h.sample();
        h.shadow(r, "C<RD>L", 1.0, 1.0, Rgb::splat(0.1));
    }
    let r = h.sample();
    last(&mut h, r);
    h.finish()
}

#[test]
fn even_samples_are_no_fireflies() {
    let t = grey_samples(&[0.5, 0.6, 0.4, 0.5]);
    assert!((0..4).all(|s| explain(&t, s).is_none() && !is_firefly(&t, s)));
    // Ten times the median exactly is not above it.
    let t = grey_samples(&[0.1, 0.1, 1.0]);
    assert!(!is_firefly(&t, 2));
}

#[test]
fn a_caustic_blames_the_diffuse_bounce() {
    let mut bounce = NodeId(0);
    let t = with_one(|h, r| {
        h.shadow(r, "C<RD>L", 1.0, 1.0, Rgb::ZERO);
        bounce = h.bounce(
            r,
            LobeKind::Diffuse,
            "C<RD>",
            Some(0.06),
            0.7,
            None,
            Rgb::ZERO,
        );
        let a = h.bounce(
            bounce,
            LobeKind::SpecularTransmission,
            "C<RD><TS>",
            None,
            1.0,
            None,
            Rgb::ZERO,
        );
        h.bounce(
            a,
            LobeKind::SpecularTransmission,
            "C<RD><TS><TS>L",
            None,
            1.0,
            None,
            Rgb::splat(35.0),
        );
    });
    let f = explain(&t, 9).expect("a firefly");
    assert_eq!(f.node, bounce);
    assert_eq!(
        f.cause,
        Cause::Caustic {
            pdf: Some(0.06),
            lobe: LobeKind::Diffuse,
            weight: Some(0.7),
            events: 1,
        }
    );
    assert_eq!(f.lpe, "C<RD><TS><TS>L");
    assert!((f.ratio() - 350.0).abs() < 1e-9, "{}", f.ratio());
    // Issue 32: the pdf of the sample is ordinary; the event is what is rare (1 of 10).
    let text = f.sentence();
    assert!(text.contains("caustic"), "{text}");
    assert!(!text.contains("rare sample"), "{text}");
    assert!(text.contains("f cos/pdf = 0.7000, pdf 0.0600"), "{text}");
    assert!(text.contains("1 of the pixel's 10 samples"), "{text}");
    assert_eq!(f.roulette_gain, 1.0);
    assert!(!text.contains("roulette"), "{text}");
    // The dim samples are not.
    assert!(explain(&t, 0).is_none());
}

#[test]
fn roulette_survival_is_blamed_when_it_is_the_largest_factor() {
    let mut cont = NodeId(0);
    let t = with_one(|h, r| {
        cont = h.bounce(
            r,
            LobeKind::Diffuse,
            "C<RD>",
            Some(0.3),
            0.7,
            Some(0.05),
            Rgb::ZERO,
        );
        h.shadow(cont, "C<RD><RD>L", 1.0, 1.0, Rgb::splat(5.0));
    });
    let f = explain(&t, 9).expect("a firefly");
    assert_eq!(f.node, cont);
    assert_eq!(f.cause, Cause::Roulette { q: 0.05 });
    assert!((f.roulette_gain - 20.0).abs() < 1e-9, "{}", f.roulette_gain);
}

#[test]
fn a_small_light_pdf_is_blamed() {
    let mut sh = NodeId(0);
    let t = with_one(|h, r| {
        sh = h.shadow(r, "C<RD>L", 0.002, 0.95, Rgb::splat(5.0));
    });
    let f = explain(&t, 9).expect("a firefly");
    assert_eq!(f.node, sh);
    let Cause::LightSample { pdf, factor, .. } = f.cause else {
        panic!("{:?}", f.cause)
    };
    assert_eq!(pdf, 0.002);
    assert!((factor - 0.2 * 0.95 / 0.002).abs() < 1e-9);
}

#[test]
fn emission_found_by_a_bsdf_sample_with_mis_near_one() {
    let mut b = NodeId(0);
    let t = with_one(|h, r| {
        b = h.bounce(
            r,
            LobeKind::Diffuse,
            "C<RD>L",
            Some(0.01),
            0.7,
            None,
            Rgb::splat(4.0),
        );
    });
    let f = explain(&t, 9).expect("a firefly");
    assert_eq!(f.node, b);
    assert_eq!(
        f.cause,
        Cause::BsdfEmission {
            mis: 1.0,
            pdf: Some(0.01)
        }
    );
}

#[test]
fn a_nan_sample_is_no_firefly() {
    let t = grey_samples(&[f64::NAN, 0.1, 0.1]);
    assert!(explain(&t, 0).is_none() && !is_firefly(&t, 0));
    assert_eq!(typical(&t), Some((0.1, true)));
}

#[test]
fn a_black_median_compares_with_the_mean() {
    let t = grey_samples(&[0.0; 15].iter().chain(&[3.0]).copied().collect::<Vec<_>>());
    let (typ, by_median) = typical(&t).unwrap();
    assert!(!by_median);
    assert!((typ - 3.0 / 16.0).abs() < 1e-12);
    assert!(is_firefly(&t, 15));
}
