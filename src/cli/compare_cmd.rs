//! `raytree compare A B`: error metrics of two images and a false-colour error map.

use super::args::CompareArgs;
use super::output::{Inputs, Pending, encode_rgb8_png, read_image};
use super::say::sayln;
use anyhow::{Result, bail};
use raytree::Image;
use raytree::analysis::cost::{compare, error_map};
use std::path::Path;

/// Print RMSE, max error and the share of pixels off by more than 1/255; optionally write the
/// error map (black = equal, through red and yellow to white = the scale or more).
pub fn run(a: &CompareArgs) -> Result<()> {
    if let Some(m) = &a.map {
        let png = m
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if !png {
            bail!(
                "cannot write {}: the error map must end in .png",
                m.display()
            );
        }
    }
    if let Some(s) = a.scale
        && !(s.is_finite() && s > 0.0)
    {
        bail!(
            "--scale {}: the map's full scale must be a finite number > 0",
            raytree::text::num(s, 4)
        );
    }
    let inputs = Inputs::new([a.a.as_path(), a.b.as_path()]);
    let pending = a
        .map
        .as_deref()
        .map(|m| Pending::create(m, &inputs))
        .transpose()?;
    let (ia, ib) = (read_image(&a.a)?, read_image(&a.b)?);
    finite(&ia, &a.a)?;
    finite(&ib, &a.b)?;
    let Some(m) = compare(&ia, &ib) else {
        bail!(
            "cannot compare {} ({}x{}) with {} ({}x{}): sizes differ",
            a.a.display(),
            ia.width,
            ia.height,
            a.b.display(),
            ib.width,
            ib.height
        );
    };
    sayln!(
        "RMSE {:.6e}  max error {:.6}  pixels off by more than 1/255: {:.3}%",
        m.rmse,
        m.max,
        m.off_8bit * 100.0
    )?;
    if let Some(p) = pending {
        let errs = error_map(&ia, &ib).expect("same size");
        let scale = a.scale.unwrap_or(m.max).max(f64::MIN_POSITIVE);
        let rgb: Vec<u8> = errs.iter().flat_map(|e| heat(e / scale)).collect();
        p.commit(&encode_rgb8_png(&rgb, ia.width, ia.height)?)?;
        sayln!(
            "wrote {} (full scale = {scale:.4})",
            a.map.as_ref().expect("map").display()
        )?;
    }
    Ok(())
}

/// Refuse an image with NaN or infinite values: no error metric of it is a number.
fn finite(img: &Image, path: &Path) -> Result<()> {
    let bad = img.pixels.iter().filter(|p| !p.is_finite()).count();
    if let Some(i) = img.pixels.iter().position(|p| !p.is_finite()) {
        let w = img.width.max(1) as usize;
        bail!(
            "cannot compare {}: {bad} pixels are not finite (not a number or infinite), the first at {},{}",
            path.display(),
            i % w,
            i / w
        );
    }
    Ok(())
}

/// Black-body style ramp: 0 black, 1/3 red, 2/3 yellow, 1 white.
fn heat(v: f64) -> [u8; 3] {
    let v = if v.is_finite() {
        v.clamp(0.0, 1.0)
    } else {
        1.0
    };
    let ch = |x: f64| ((x * 3.0).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    [ch(v), ch(v - 1.0 / 3.0), ch(v - 2.0 / 3.0)]
}
