//! `raytree compare A B`: error metrics of two images, the mean signed difference with its 95 %
//! interval (`raytree::analysis::bias`), and a signed (or, with `--abs`, unsigned) error map
//! with a legend; all over the whole image or `--region`.

use super::args::CompareArgs;
use super::compare_map::{abs_map, signed_map};
use super::output::{Inputs, Pending, read_image};
use super::say::sayln;
use anyhow::{Result, bail};
use raytree::Image;
use raytree::analysis::bias::{Region, SignedDifference, signed_difference};
use raytree::analysis::cost::compare;
use raytree::text::sci;
use std::path::Path;

/// Print RMSE, max error, the share of pixels off by more than 1/255 and the mean signed
/// difference A - B per channel with its 95 % interval; optionally write the error map.
pub fn run(a: &CompareArgs) -> Result<()> {
    check_map_flags(a)?;
    let inputs = Inputs::new([a.a.as_path(), a.b.as_path()]);
    let pending = a
        .map
        .as_deref()
        .map(|m| Pending::create(m, &inputs))
        .transpose()?;
    let (ia, ib) = read_pair(a)?;
    let region = match &a.region {
        Some(s) => Region::parse(s, ia.width, ia.height)
            .map_err(|e| anyhow::anyhow!("--region {s:?}: {e}"))?,
        None => Region::whole(ia.width, ia.height),
    };
    let (ca, cb) = (region.crop(&ia), region.crop(&ib));
    let m = compare(&ca, &cb).expect("same size, not empty");
    let d = signed_difference(&ia, &ib, region).expect("same size, region inside");
    let interval_ok = d.blocks < 2 || d.half_width.iter().all(|v| v.is_finite());
    if !(m.rmse.is_finite()
        && m.max.is_finite()
        && d.mean.iter().all(|v| v.is_finite())
        && interval_ok)
    {
        bail!(
            "cannot compare {} with {}: a difference of their values is not finite (they are finite, but too large to subtract)",
            a.a.display(),
            a.b.display()
        );
    }
    let mut text = String::new();
    if a.region.is_some() {
        let (w, h) = region.size();
        text += &format!(
            "region {},{} to {},{} (x1, y1 exclusive): {w}x{h} of {}x{} pixels\n",
            region.x0, region.y0, region.x1, region.y1, ia.width, ia.height
        );
    }
    text += &format!(
        "RMSE {}  max error {:.6}  pixels off by more than 1/255: {:.3}%\n",
        sci(m.rmse, Some(6)),
        m.max,
        m.off_8bit * 100.0
    );
    text += &bias_text(&d);
    let map = match &pending {
        Some(_) => {
            let made = if a.abs {
                abs_map(&ca, &cb, a.scale)?
            } else {
                signed_map(&ca, &cb, a.scale)?
            };
            Some(made)
        }
        None => None,
    };
    sayln!("{}", text.trim_end())?;
    if let (Some(p), Some((png, scale))) = (pending, map) {
        p.commit(&png)?;
        sayln!(
            "wrote {} ({}, full scale = {})",
            a.map.as_ref().expect("map").display(),
            if a.abs {
                "largest channel |A - B|: black 0, white the scale"
            } else {
                "luminance A - B: blue A darker, grey equal, red A brighter"
            },
            scale.map_or("0 (the images are equal here)".to_string(), |s| sci(
                s,
                Some(4)
            ))
        )?;
    }
    Ok(())
}

/// The error map must be a PNG and its full scale (`--scale`) a finite number > 0.
fn check_map_flags(a: &CompareArgs) -> Result<()> {
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
    Ok(())
}

/// Images A and B, both finite and of the same size.
fn read_pair(a: &CompareArgs) -> Result<(Image, Image)> {
    let (ia, ib) = (read_image(&a.a)?, read_image(&a.b)?);
    finite(&ia, &a.a)?;
    finite(&ib, &a.b)?;
    if (ia.width, ia.height) != (ib.width, ib.height) {
        bail!(
            "cannot compare {} ({}x{}) with {} ({}x{}): sizes differ",
            a.a.display(),
            ia.width,
            ia.height,
            a.b.display(),
            ib.width,
            ib.height
        );
    }
    Ok((ia, ib))
}

/// The mean signed difference per channel with its interval, and whether it is beyond the
/// noise (the interval excludes 0).
fn bias_text(d: &SignedDifference) -> String {
    let from = if d.block == 1 {
        format!(
            "{} single pixels (the region has too few {}x{} blocks)",
            d.blocks,
            raytree::analysis::bias::BLOCK,
            raytree::analysis::bias::BLOCK
        )
    } else {
        format!("{} block means of {}x{} pixels", d.blocks, d.block, d.block)
    };
    let mut s = format!("mean signed difference A - B, 95% interval from {from}:\n");
    for (c, name) in ["R", "G", "B"].into_iter().enumerate() {
        let (m, h) = (d.mean[c], d.half_width[c]);
        if !h.is_finite() {
            s += &format!(
                "  {name} {}  (no interval from a single pixel)\n",
                sci(m, Some(3))
            );
            continue;
        }
        let verdict = if d.significant(c) {
            "beyond the noise"
        } else {
            "within the noise"
        };
        s += &format!(
            "  {name} {:+.3e}  [{:+.3e}, {:+.3e}]  {verdict}\n",
            m,
            m - h,
            m + h
        );
    }
    s
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
