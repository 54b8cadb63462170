//! `raytree compare A B`: error metrics of two images and a false-colour error map.

use super::args::CompareArgs;
use super::output::{Pending, encode_rgb8_png, read_image};
use anyhow::{Result, bail};
use raytree::analysis::cost::{compare, error_map};

/// Print RMSE, max error and the share of pixels off by more than 1/255; optionally write the
/// error map (black = equal, through red and yellow to white = the scale or more).
pub fn run(a: &CompareArgs) -> Result<()> {
    let pending = a.map.as_deref().map(Pending::create).transpose()?;
    let (ia, ib) = (read_image(&a.a)?, read_image(&a.b)?);
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
    println!(
        "RMSE {:.6e}  max error {:.6}  pixels off by more than 1/255: {:.3}%",
        m.rmse,
        m.max,
        m.off_8bit * 100.0
    );
    if let Some(p) = pending {
        let errs = error_map(&ia, &ib).expect("same size");
        let scale = a.scale.unwrap_or(m.max).max(f64::MIN_POSITIVE);
        let rgb: Vec<u8> = errs.iter().flat_map(|e| heat(e / scale)).collect();
        p.commit(&encode_rgb8_png(&rgb, ia.width, ia.height)?)?;
        println!(
            "wrote {} (full scale = {scale:.4})",
            a.map.as_ref().expect("map").display()
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
